// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Inputs shared by the io and tools tests: a folder in the METRIC layout
/// (SPEC §8) and images of a checkerboard whose corner pixels are known.

#include <Eigen/Geometry>
#include <cstdio>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

#include "handeye/core/transform.h"
#include "support/test_support.h"

namespace handeye::test {

/// T_base_ee of METRIC pose `index` (any integer): full-precision rotations.
inline Eigen::Isometry3d MetricPose(int index) {
  return MakeTransformFromRotationVector(
      Eigen::Vector3d(0.1 * index, -0.05 * index + 0.3, 0.2 + 0.03 * index),
      Eigen::Vector3d(0.4 + 0.01 * index, -0.1 * index, 0.9 - 0.02 * index));
}

/// Ground-truth T_base_cam of METRIC camera k.
inline Eigen::Isometry3d MetricCamera(int k) {
  return MakeTransformFromRotationVector(Eigen::Vector3d(2.0, -0.4 * k, 0.3),
                                         Eigen::Vector3d(-1.2 * k, 1.9, 1.15));
}

/// A 4×4 as the original tool writes it: 4 lines, `sep` between values.
inline std::string MatrixText(const Eigen::Matrix4d& M, const std::string& sep) {
  std::string text;
  char buf[64];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buf, sizeof(buf), "%.18e", M(r, c));
      text += (c ? sep : "") + std::string(buf);
    }
    text += "\n";
  }
  return text;
}

inline void WriteGrayPng(const std::string& path, int width, int height) {
  WriteText(path, "");  // creates the folders
  if (!cv::imwrite(path, cv::Mat(height, width, CV_8UC1, cv::Scalar(128))))
    throw std::runtime_error("cannot write " + path);
}

/// A METRIC folder: 2 cameras (64×48 images), checkerboard number_of_rows 4,
/// number_of_columns 3, size 0.05. camera1 has images 0001..0003 (png, pose
/// files space-separated, distortion), camera2 has 0002 (png), 0003 (jpg),
/// 0004 (tiff) with comma-separated pose files and no distortion. With
/// `with_gt`, GT/gt_cam1.csv and GT/gt_cam2.csv.
inline void WriteMetricFolder(const std::string& dir, int calibration_setup, bool with_gt) {
  WriteText(dir + "/CalibrationInfo.yaml",
            "# Number of cameras you want to calibrate\n"
            "number_of_cameras: 2\n"
            "camera_folder_prefix: camera\n"
            "pattern_type: checkerboard\n"
            "\n"
            "number_of_rows: 4\n"
            "number_of_columns: 3\n"
            "size: 0.05   # metres\n"
            "resize_factor: 1\n"
            "visual_error: 1\n"
            "calibration_setup: " +
                std::to_string(calibration_setup) + "\n");
  WriteText(dir + "/camera1/intrinsic_pars_file.yaml",
            "fx: 1360.5206198852188\nfy: 1362.5943706855635\ncx: 31.5\ncy: 23.25\n"
            "has_dist_coeff: 1\n"
            "dist_k0: -0.01\ndist_k1: 0.2\ndist_px: 0.003\ndist_py: -0.0002\n"
            "dist_k2: -1.3\ndist_k3: 0.01\ndist_k4: 0.02\ndist_k5: 0.03\n"
            "img_width: 64\nimg_height: 48\n");
  WriteText(dir + "/camera2/intrinsic_pars_file.yaml",
            "fx: 800\nfy: 801.5\ncx: 32\ncy: 24\nhas_dist_coeff: 0\n"
            "dist_k0: 0\ndist_k1: 0\ndist_px: 0\ndist_py: 0\ndist_k2: 0\ndist_k3: 0\n"
            "dist_k4: 0\ndist_k5: 0\nimg_width: 64.0\nimg_height: 48\n");
  for (int i = 1; i <= 3; ++i) {
    char stem[16];
    std::snprintf(stem, sizeof(stem), "%04d", i);
    WriteGrayPng(dir + "/camera1/image/" + stem + ".png", 64, 48);
    WriteText(dir + "/camera1/pose/" + stem + ".csv", MatrixText(MetricPose(i).matrix(), " "));
  }
  WriteText(dir + "/camera1/image/notes.txt", "not an image\n");
  const char* camera2_images[] = {"0002.png", "0003.jpg", "0004.tiff"};
  for (int i = 2; i <= 4; ++i) {
    const std::string name = camera2_images[i - 2];
    WriteGrayPng(dir + "/camera2/image/" + name, 64, 48);
    WriteText(dir + "/camera2/pose/" + name.substr(0, 4) + ".csv",
              MatrixText(MetricPose(i).matrix(), ", "));
  }
  if (with_gt) {
    for (int k = 1; k <= 2; ++k)
      WriteText(dir + "/GT/gt_cam" + std::to_string(k) + ".csv",
                MatrixText(MetricCamera(k).matrix(), " "));
  }
}

/// A fronto-parallel checkerboard of cols × rows inner corners, `square_px`
/// pixels per square, seen by a camera whose axes are the target's (the
/// printed face towards the camera, SPEC §4): target +x is image right, +y
/// image down, and the square on the -x, -y side of corner (0, 0) is black.
/// Corner (i, j) is at pixel CornerPixel(...) (pixel centres at integers).
inline cv::Mat DrawBoard(int cols, int rows, int square_px, int x0, int y0, int width, int height) {
  cv::Mat image(height, width, CV_8UC1, cv::Scalar(225));
  for (int b = -1; b <= rows - 1; ++b)
    for (int a = -1; a <= cols - 1; ++a)
      if ((a + b + 2) % 2 == 0)
        cv::rectangle(image, cv::Rect(x0 + a * square_px, y0 + b * square_px, square_px, square_px),
                      cv::Scalar(25), cv::FILLED);
  // A little optical blur, as a real lens gives; symmetric, so corners stay put.
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.8);
  return image;
}

/// Where DrawBoard puts corner (i, j): between pixel x0 + i·s − 1 and x0 + i·s.
inline Eigen::Vector2d CornerPixel(int i, int j, int square_px, int x0, int y0) {
  return Eigen::Vector2d(x0 + i * square_px - 0.5, y0 + j * square_px - 0.5);
}

}  // namespace handeye::test
