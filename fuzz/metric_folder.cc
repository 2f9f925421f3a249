// SPDX-License-Identifier: GPL-2.0-or-later
// ImportMetricFolder on a valid two-camera METRIC folder (SPEC §8) with one
// of its files replaced by the input; the input's first byte picks which:
// CalibrationInfo.yaml, an intrinsic_pars_file.yaml, a pose file or a
// ground-truth file.
#include <filesystem>

#include "fuzz_support.h"
#include "handeye/io/metric_import.h"

namespace {

const char kInfo[] =
    "number_of_cameras: 2\ncamera_folder_prefix: camera\npattern_type: checkerboard\n"
    "number_of_rows: 4\nnumber_of_columns: 3\nsize: 0.05\nresize_factor: 1\nvisual_error: 1\n"
    "calibration_setup: 1\n";
const char kIntrinsics[] =
    "fx: 800\nfy: 800\ncx: 320\ncy: 240\nhas_dist_coeff: 1\ndist_k0: 1e-08\ndist_k1: 0\n"
    "dist_px: 0\ndist_py: 0\ndist_k2: 0\ndist_k3: 0\ndist_k4: 0\ndist_k5: 0\nimg_width: 640\n"
    "img_height: 480\n";
const char kPose[] = "1 0 0 0.1\n0 1 0 0.2\n0 0 1 0.3\n0 0 0 1\n";

const char* const kFiles[] = {"CalibrationInfo.yaml", "camera1/intrinsic_pars_file.yaml",
                              "camera2/pose/0001.csv", "GT/gt_cam2.csv"};

void Write(const std::string& path, const std::string& text) {
  handeye::fuzz::WriteFile(path, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

std::string ValidText(const std::string& file) {
  if (file == "CalibrationInfo.yaml") return kInfo;
  if (file.find("intrinsic_pars_file") != std::string::npos) return kIntrinsics;
  return kPose;
}

// Lays the valid folder out once; later calls put back only the file the
// previous input replaced (writing all eleven each time was most of a run).
std::string ValidFolder() {
  const std::string root = handeye::fuzz::WorkDir() + "/metric";
  static const bool made = [&] {
    for (const char* camera : {"camera1", "camera2"}) {
      std::filesystem::create_directories(root + "/" + camera + "/image");
      std::filesystem::create_directories(root + "/" + camera + "/pose");
      for (const char* id : {"0001", "0002"}) Write(root + "/" + camera + "/image/" + id + ".png", "");
    }
    std::filesystem::create_directories(root + "/GT");
    Write(root + "/CalibrationInfo.yaml", kInfo);
    for (const char* camera : {"camera1", "camera2"}) {
      Write(root + "/" + camera + "/intrinsic_pars_file.yaml", kIntrinsics);
      for (const char* id : {"0001", "0002"}) Write(root + "/" + camera + "/pose/" + id + ".csv", kPose);
    }
    for (const char* gt : {"gt_cam1.csv", "gt_cam2.csv"}) Write(root + "/GT/" + gt, kPose);
    return true;
  }();
  (void)made;
  return root;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string root = ValidFolder();
  const std::string file = kFiles[data[0] % (sizeof kFiles / sizeof kFiles[0])];
  handeye::fuzz::WriteFile(root + "/" + file, data + 1, size - 1);
  handeye::fuzz::ExpectInputErrorsOnly([&] { handeye::ImportMetricFolder(root); });
  Write(root + "/" + file, ValidText(file));
  return 0;
}
