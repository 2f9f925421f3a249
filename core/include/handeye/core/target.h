// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Calibration target geometry: the interface every target type implements.
///
/// Target frame: the printed face lies in the plane z = 0; points have ids
/// that detectors report. The face is seen from the -z side: a camera looking
/// at the print has the target's +z axis pointing away from it (as with
/// OpenCV's calibration boards), so a target seen from +z shows its back.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "handeye/core/target_spec.h"

namespace handeye {

/// One detectable point of a target.
struct TargetPoint {
  int id = 0;                  ///< unique within the target
  Eigen::Vector3d p_target;    ///< position in the target frame, metres (z = 0)
};

/// A calibration target. Implementations are immutable and thread-safe.
class Target {
 public:
  virtual ~Target() = default;

  /// `target.type` of SPEC §4, e.g. "checkerboard".
  virtual std::string Type() const = 0;
  /// The parameters it was made from (written back to observation files).
  virtual const TargetSpec& Spec() const = 0;
  /// Every detectable point, ordered by id.
  virtual const std::vector<TargetPoint>& Points() const = 0;

  /// The printed sheet in the target plane, metres, including its white
  /// margin: what a renderer draws and an outline shows.
  virtual Eigen::AlignedBox2d Extent() const = 0;
  /// Reflectance of the printed face at (x, y) in the target plane (metres):
  /// 0 black … 1 white. Defined on Extent(); point sampling, the renderer
  /// supersamples for anti-aliasing.
  virtual double Albedo(double x_m, double y_m) const = 0;

  /// Warnings a user should see about this target (e.g. a board that is
  /// 180°-ambiguous). Empty when none.
  virtual std::vector<std::string> Warnings() const { return {}; }

  /// Position of the point with `id`, or nullptr if no such point.
  const TargetPoint* FindPoint(int id) const;
};

}  // namespace handeye
