// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Sub-pixel corner refinement and small geometry helpers shared by the
// target detectors (checkerboard, ChArUco, AprilGrid). Internal to the
// detectors library.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <vector>

namespace handeye::internal {

/// 3×3 Sobel gradients (CV_32F) of a region of an 8-bit grey image: the
/// gradient at image pixel (x, y) is at row y − origin.y, column x − origin.x.
struct Gradients {
  cv::Mat gx, gy;
  cv::Point origin;
};
/// The gradients over `region` (clipped to the image; outside the image the
/// border pixels are repeated).
Gradients SobelGradients(const cv::Mat& gray, const cv::Rect& region);

/// The detectors' one X-junction (saddle point) refiner, for checkerboard and
/// ChArUco corners. Refines the junction near `guess` (pixels, centre of the
/// top-left pixel at (0, 0), SPEC §2) from the image's gradients. Every edge
/// through the junction has its gradient orthogonal to (p − c), so c solves
/// Σ w(p) g gᵀ (p − c) = 0 over a window with Gaussian weights (σ = half the
/// window), iterated on the image's own pixel grid: unlike cv::cornerSubPix
/// it does not resample the window at the sub-pixel estimate, which on
/// rendered boards halved the error (0.019 → 0.010 px for 40 px squares
/// without noise). The window is the ellipse {c + W u : |u| ≤ 1}: on a
/// checkerboard a disc up to the nearest grid line; on a coded target the
/// image of a disc on the target under the local map, so that a foreshortened
/// view keeps other edges (marker and tag borders, bits) out of it in every
/// direction; they would pull the estimate. Pixels outside `gradients` count
/// as flat. nullopt when the gradients do not pin a point down (the smaller
/// eigenvalue of Σ w g gᵀ under 2 % of the larger: one edge direction only,
/// or flat paper) or the estimate leaves `max_shift_px` of the guess. The
/// checkerboard's refiner used to accept down to a ratio of about 1e-6; on
/// the detector tests and bench the stricter test changed no corner.
std::optional<Eigen::Vector2d> RefineXCorner(const Gradients& gradients,
                                             const Eigen::Vector2d& guess,
                                             const Eigen::Matrix2d& window, double max_shift_px);

/// The same on `gray` (8-bit), with the gradients of just the pixels the
/// window can reach. `keep(x, y)`, when given, leaves out pixels it rejects
/// (e.g. those on a marker next to the corner, so the window can reach along
/// the edges past it).
std::optional<Eigen::Vector2d> RefineXCorner(const cv::Mat& gray, const Eigen::Vector2d& guess,
                                             const Eigen::Matrix2d& window, double max_shift_px,
                                             const std::function<bool(int x, int y)>& keep = {});

/// A straight edge n·p = c (|n| = 1), pixels.
struct EdgeLine {
  Eigen::Vector2d normal;
  double offset = 0;
};

/// Fits the straight edge that runs from about `from` to about `to` (pixels,
/// SPEC §2), continued `extend_px` beyond both ends, to the image gradients in
/// a band of ±`half_width_px` around it: the gradient-squared-weighted line
/// through the band's pixels, re-centred until it settles. Pixels within
/// `skip_px` of either end are left out (another edge crosses there). The
/// band must hold no other edge parallel to this one. nullopt when the band
/// has (almost) no gradient or leaves the image.
std::optional<EdgeLine> FitEdge(const cv::Mat& gray, const Eigen::Vector2d& from,
                                const Eigen::Vector2d& to, double extend_px, double skip_px,
                                double half_width_px);

/// Where two edges cross; nullopt when they are (nearly) parallel.
std::optional<Eigen::Vector2d> Intersect(const EdgeLine& a, const EdgeLine& b);

/// Whether `points` (target-plane coordinates, metres) span a plane: the
/// largest distance of a point from their best-fit line is at least
/// `min_spread_m`. Collinear points do not fix a camera pose.
bool SpansPlane(const std::vector<Eigen::Vector2d>& points, double min_spread_m);

/// Homography (3×3, h33 = 1 scale free) from ≥ 4 point pairs by normalised
/// DLT; nullopt when degenerate.
std::optional<Eigen::Matrix3d> FitHomography(const std::vector<Eigen::Vector2d>& from,
                                             const std::vector<Eigen::Vector2d>& to);
/// The same least-squares solution through the 9×9 normal equations of the
/// normalised DLT: several times faster on a few points, for scoring many
/// candidates (internal::PlaceCornersBySquares); points that do not fix H
/// are refused more readily (a second eigenvalue under 1e-12 of the largest,
/// a singular value ratio of 1e-6).
std::optional<Eigen::Matrix3d> FitHomographyFast(const std::vector<Eigen::Vector2d>& from,
                                                 const std::vector<Eigen::Vector2d>& to);

/// Grey level of `gray` (8-bit) at a sub-pixel position (bilinear; clamped
/// at the border).
double Bilinear(const cv::Mat& gray, double x, double y);

/// Pearson correlation of two samples of one length; nullopt when either
/// is constant.
std::optional<double> Pearson(const std::vector<double>& a, const std::vector<double>& b);

/// H applied to a point (with the perspective division).
inline Eigen::Vector2d ApplyHomography(const Eigen::Matrix3d& H, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = H * p.homogeneous();
  return q.hnormalized();
}

}  // namespace handeye::internal
