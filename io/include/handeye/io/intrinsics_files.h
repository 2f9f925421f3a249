// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Camera intrinsics from the files calibration tools write, so a dataset can
/// reference them by path instead of copying numbers:
///
/// - `opencv`: an OpenCV FileStorage file (YAML, XML or JSON, as written by
///   OpenCV's calibration sample) with `camera_matrix` (3×3) and
///   `distortion_coefficients` (1×N or N×1, N = 0, 4, 5, 8, 12 or 14), and
///   optionally `image_width`, `image_height`. A YAML file without the
///   `%YAML:1.0` header OpenCV wants is read all the same.
/// - `ros`: a ROS `camera_info` as the calibration file that
///   camera_calibration / camera_info_manager write (`image_width`,
///   `image_height`, `camera_matrix: {rows, cols, data}`, `distortion_model`,
///   `distortion_coefficients: {rows, cols, data}`) or as the message that
///   `ros2 topic echo` prints (`width`, `height`, `k` / `K`, `d` / `D`,
///   `distortion_model`). Models `plumb_bob` (5 coefficients) and
///   `rational_polynomial` (8); both are OpenCV's order.
/// - `kalibr`: a Kalibr camchain (`camchain.yaml`) and one of its cameras by
///   name: `cam0: {camera_model: pinhole, intrinsics: [fu, fv, pu, pv],
///   distortion_model: radtan, distortion_coeffs: [k1, k2, r1, r2],
///   resolution: [w, h]}`. radtan's r1, r2 are OpenCV's p1, p2.
///
/// All three use OpenCV's pixel convention (the centre of the top-left pixel
/// is (0, 0), SPEC §2), so no offset is applied. A camera matrix with skew or
/// a last row other than [0 0 1] is rejected (the model has no skew).
///
/// In a dataset (SPEC §4) a camera gives `intrinsics_file` instead of
/// `intrinsics` and `distortion`:
/// `{"name": "cam0", "intrinsics_file": {"path": "calib/cam0.yaml", "format": "ros"}}`
/// with `"camera": "cam0"` added for `kalibr`. The path is relative to the
/// dataset's folder; `image_size` may be left out when the file states it,
/// and must agree with it when both do.

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace handeye {

/// The file formats above.
enum class IntrinsicsFileFormat { kOpenCv, kRos, kKalibr };
/// "opencv" / "ros" / "kalibr".
const char* IntrinsicsFileFormatName(IntrinsicsFileFormat format);
/// Parses a format name; nullopt if unknown.
std::optional<IntrinsicsFileFormat> ParseIntrinsicsFileFormat(const std::string& name);

/// Intrinsics as read from a file, in pixels.
struct FileIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  /// OpenCV's order (k1, k2, p1, p2, k3, …); empty for no distortion.
  std::vector<double> distortion;
  /// [width, height] in pixels when the file states it.
  std::optional<std::array<int, 2>> image_size;
};

/// Reads intrinsics from `path`. `camera` names the camera inside a Kalibr
/// camchain and must be empty for the other formats. Throws InputError naming
/// the file, the key inside it (as a path such as `/cam0/intrinsics`) and what
/// was expected.
FileIntrinsics ReadIntrinsicsFile(const std::string& path, IntrinsicsFileFormat format,
                                  const std::string& camera = "");

}  // namespace handeye
