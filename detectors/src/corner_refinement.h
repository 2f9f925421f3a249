// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Sub-pixel corner refinement and small geometry helpers shared by the coded
// target detectors (ChArUco, AprilGrid). Internal to the detectors library.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <vector>

namespace handeye::internal {

/// Refines an X junction near `guess` (pixels, centre of the top-left pixel at
/// (0, 0), SPEC §2) in an 8-bit grey image. Every edge through the junction
/// has its gradient orthogonal to (p − c), so c solves
/// Σ w(p) g gᵀ (p − c) = 0 over a window with Gaussian weights, iterated on
/// the image's own pixel grid (no resampling). The window is the ellipse
/// {c + W u : |u| ≤ 1}: the image of a disc on the target under the local
/// map, so that a foreshortened view keeps other edges (marker and tag
/// borders, bits) out of it in every direction; they would pull the estimate.
/// nullopt when the gradients do not pin a point down or the estimate leaves
/// `max_shift_px` of the guess.
/// `keep(x, y)`, when given, leaves out pixels it rejects (e.g. those on a
/// marker next to the corner, so the window can reach along the edges past it).
std::optional<Eigen::Vector2d> RefineXCorner(const cv::Mat& gray, const Eigen::Vector2d& guess,
                                             const Eigen::Matrix2d& window, double max_shift_px,
                                             const std::function<bool(int x, int y)>& keep = {});

/// The same with a round window of `radius_px`.
inline std::optional<Eigen::Vector2d> RefineXCorner(const cv::Mat& gray,
                                                    const Eigen::Vector2d& guess, double radius_px,
                                                    double max_shift_px) {
  return RefineXCorner(gray, guess, radius_px * Eigen::Matrix2d::Identity(), max_shift_px);
}

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

/// H applied to a point (with the perspective division).
inline Eigen::Vector2d ApplyHomography(const Eigen::Matrix3d& H, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = H * p.homogeneous();
  return q.hnormalized();
}

}  // namespace handeye::internal
