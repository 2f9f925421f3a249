// SPDX-License-Identifier: GPL-2.0-or-later
// The frame-explicit readings of a CalibrationResult (calibration.h).
#include <stdexcept>
#include <string>

#include "handeye/core/calibration.h"

namespace handeye {
namespace {

/// Throws when `result` is not of `setup`, naming what to read instead.
void RequireSetup(const CalibrationResult& result, Setup setup, const char* asked,
                  const char* instead) {
  if (result.setup == setup) return;
  throw std::logic_error(std::string(asked) + ": this result is " + SetupName(result.setup) +
                         ", where it has no meaning; read " + instead);
}

const CameraResult& Calibrated(const CalibrationResult& result, const std::string& camera) {
  for (const CameraResult& c : result.cameras) {
    if (c.name != camera) continue;
    if (!c.calibrated) throw std::out_of_range("camera '" + camera + "' was not calibrated");
    return c;
  }
  throw std::out_of_range("the result has no camera '" + camera + "'");
}

}  // namespace

Eigen::Isometry3d CalibrationResult::T_base_cam(const std::string& camera) const {
  RequireSetup(*this, Setup::kEyeToHand, "T_base_cam",
               "T_ee_cam (the camera rides on the flange), or T_base_cam_at(camera, T_base_ee)");
  return Calibrated(*this, camera).T_cam;
}

Eigen::Isometry3d CalibrationResult::T_ee_cam(const std::string& camera) const {
  RequireSetup(*this, Setup::kEyeInHand, "T_ee_cam",
               "T_base_cam (the camera is fixed in the cell)");
  return Calibrated(*this, camera).T_cam;
}

Eigen::Isometry3d CalibrationResult::T_ee_target() const {
  RequireSetup(*this, Setup::kEyeToHand, "T_ee_target",
               "T_base_target (the target is fixed in the cell)");
  return T_target;
}

Eigen::Isometry3d CalibrationResult::T_base_target() const {
  RequireSetup(*this, Setup::kEyeInHand, "T_base_target",
               "T_ee_target (the robot holds the target)");
  return T_target;
}

Eigen::Isometry3d CalibrationResult::T_base_cam_at(const std::string& camera,
                                                   const Eigen::Isometry3d& T_base_ee) const {
  const Eigen::Isometry3d& T_mount_cam = Calibrated(*this, camera).T_cam;
  return setup == Setup::kEyeToHand ? T_mount_cam : T_base_ee * T_mount_cam;
}

}  // namespace handeye
