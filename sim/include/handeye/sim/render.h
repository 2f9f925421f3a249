// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Off-screen rendering of a target as a camera sees it: per-pixel ray
/// casting through the camera's distortion model with supersampling, then
/// blur, sensor noise and a cluttered background.

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <opencv2/core/mat.hpp>
#include <string>

#include "handeye/core/camera.h"
#include "handeye/core/target.h"

namespace handeye {

/// How RenderView() draws (optics, sensor, background).
struct RenderOptions {
  /// Samples per pixel along each axis where the target is seen (n×n, one in
  /// each cell of an n×n split of the pixel). Keep it even: with n odd a
  /// sample lies at the pixel centre, and a board edge running exactly through
  /// pixel centres (e.g. a corner placed at an integer pixel) would be drawn
  /// shifted by a fraction of a pixel.
  int supersampling = 6;
  /// Gaussian blur σ in pixels (optics), 0 for none.
  double blur_sigma_px = 0.7;
  /// Sensor noise σ in grey levels.
  double noise_sigma = 2.0;
  /// Grey levels of the target's black and white print.
  double black_level = 25.0;
  double white_level = 225.0;
  /// Draw a cluttered background (otherwise flat, of `background_level`:
  /// mid grey, or as white as the print for a sheet on a white surface).
  bool clutter = true;
  double background_level = 128.0;
  /// A see-through (glass) target: seen from behind, its pattern shows
  /// mirrored. Otherwise a printed sheet, whose back is plain.
  bool see_through = false;
  /// `handeye simulate`, WriteSimulation() and DetectSimulated(): render every
  /// camera at every pose, as a real capture does (targets out of view, edge-on
  /// or from behind included); false renders only the views the truth counts.
  bool every_view = true;
  std::uint64_t seed = 1;
  /// A camera whose optics and sensor differ from the cell's (a cheaper or
  /// more distant camera, a lens out of focus): the blur σ (px) and sensor
  /// noise σ (grey levels) it renders with.
  struct CameraQuality {
    double blur_sigma_px = 0;
    double noise_sigma = 0;
  };
  /// By camera name: WriteSimulation() and DetectSimulated() render these
  /// cameras with their own quality instead of their share of blur_sigma_px
  /// and noise_sigma.
  std::map<std::string, CameraQuality> camera_quality;

  /// False, with the reason in `*why`, when a value is out of its domain.
  bool Check(std::string* why) const;
};

/// 8-bit grey image (camera.height × camera.width) of `target` at pose
/// T_cam_target. The printed face is seen from the target's -z side; from
/// the +z side the sheet shows its plain back, or with `see_through` the
/// pattern mirrored.
cv::Mat RenderView(const Camera& camera, const Target& target,
                   const Eigen::Isometry3d& T_cam_target, const RenderOptions& options);

}  // namespace handeye
