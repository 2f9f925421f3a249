// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Rendered views of coded targets (ChArUco, AprilGrid) with ground truth, and
// the scoring of a detector against it: which corners a detector can be
// asked to find, how many it found, how far off, and how many ids were wrong.

#include <Eigen/Geometry>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <random>
#include <string>
#include <vector>

#include "handeye/core/camera.h"
#include "handeye/core/charuco.h"
#include "handeye/core/target.h"
#include "handeye/detectors/detector.h"
#include "handeye/sim/render.h"

namespace handeye::test {

/// The fiducial (marker or tag) corners that identify point `id`, in the
/// target frame: a point can only be found when they are all in view.
using IdentifyingCorners = std::function<std::vector<Eigen::Vector3d>(int id)>;

/// How views are drawn at random.
struct ViewSampling {
  /// Size of the fiducial (marker or tag edge, metres) and the range of its
  /// size in the image, pixels, when seen face-on at the image centre.
  double feature_m = 0;
  double min_feature_px = 20, max_feature_px = 60;
  double max_tilt_deg = 45;
  /// Fiducials at least this size (shortest side and width, pixels) count as
  /// expected when scoring; the requirement's 20 px.
  double expected_feature_px = 20;
  /// Where the sheet's centre lands, as a fraction of the image beyond its
  /// border: 0 keeps it inside, 0.5 lets half the sheet leave the image.
  double centre_beyond_border = 0.0;
};

/// T_cam_target for a random view of `target` (printed face towards the camera).
Eigen::Isometry3d RandomView(const Camera& camera, const Target& target,
                             const ViewSampling& sampling, std::mt19937_64* rng);

/// T_cam_target with the sheet's centre on the ray through pixel (u, v) at
/// `distance_m`, turned by `spin_rad` about its normal and tilted by
/// `tilt_rad` about the camera's x axis.
Eigen::Isometry3d ViewAt(const Camera& camera, const Target& target, double u, double v,
                         double distance_m, double spin_rad, double tilt_rad);

/// A ChArUco corner is identified by the corners of its two markers.
IdentifyingCorners CharucoMarkers(const CharucoTarget& board);

/// Tallies over views.
struct Score {
  int expected = 0;        ///< points whose fiducials are ≥ min size and fully in view
  int found = 0;           ///< of those, reported with the right id
  int wrong = 0;           ///< reported points farther than the wrong-id threshold from their truth
  int views = 0;           ///< views scored
  int views_detected = 0;  ///< views where the detector returned a detection
  std::vector<double> errors_px;  ///< distance to truth of every correctly identified point
  double Rate() const { return expected ? static_cast<double>(found) / expected : 0.0; }
  double MeanError() const;
  std::string Summary() const;
};

/// Scores one detection (or none) of a view against the truth. A point is
/// expected when it and every identifying corner project at least
/// `border_px` inside the image and each fiducial is at least `min_feature_px`
/// along its shortest side and across its narrowest width. A reported point
/// counts as a wrong id when it lies farther than `wrong_px` from its true
/// projection. A view with fewer than `min_points` expected points expects
/// none (the detector's `min_corners` rejects it by design).
void ScoreView(const Camera& camera, const Target& target, const Eigen::Isometry3d& T_cam_target,
               const IdentifyingCorners& identifying, const std::optional<Detection>& detection,
               double min_feature_px, double border_px, double wrong_px, int min_points,
               Score* score);

/// Renders, detects and scores `count` random views (seeded by `seed`).
Score RenderAndScore(const Camera& camera, const Target& target, const Detector& detector,
                     const IdentifyingCorners& identifying, const ViewSampling& sampling,
                     const RenderOptions& render, int count, std::uint64_t seed, double border_px,
                     double wrong_px, int min_points);

/// A pinhole camera without distortion looking along +z.
Camera PinholeCamera(int width, int height, double fx);

}  // namespace handeye::test
