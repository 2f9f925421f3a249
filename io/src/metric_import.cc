// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/metric_import.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/detectors/registry.h"
#include "text_file.h"

namespace handeye {
namespace {

namespace fs = std::filesystem;

// Pose files with the same stem in different camera folders record the same
// robot pose. The published METRIC folders store one copy per camera, and the
// copies differ by up to 13 µm and 0.0036° (rounding in the authors' export),
// so copies within these bounds are one pose (their mean); beyond them the
// records disagree for real and each camera keeps its own (SPEC §8).
constexpr double kSamePoseTolerance_m = 1e-4;     // 0.1 mm
constexpr double kSamePoseTolerance_rad = 0.01 * M_PI / 180.0;  // 0.01°

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A whole-string number (what strtod accepts, nothing after it); nullopt otherwise.
std::optional<double> ParseNumber(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return x;
}

/// A METRIC YAML file: flat `key: value` lines (the original tool reads
/// them with cv::FileStorage, without a `%YAML` header), parsed with
/// yaml-cpp. Values are read as the original tool's numbers and strings;
/// nested values are refused. Messages name the file, the key and its line.
class FlatYaml {
 public:
  explicit FlatYaml(const fs::path& path) : path_(path.string()) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      throw InputError(path_, "", "file does not exist (METRIC folder layout, SPEC §8)");
    const std::string text = internal::ReadTextFile(path_, "a YAML file");
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::ParserException& e) {
      throw InputError(path_, "", "line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
    } catch (const YAML::Exception& e) {
      throw InputError(path_, "", std::string("not readable as YAML: ") + e.what());
    }
    if (root.IsNull()) return;  // no keys: each one asked for is missing
    if (!root.IsMap()) {
      // The line where the document starts, as the user wrote it.
      std::istringstream lines(text);
      std::string first;
      for (int i = 0; i <= root.Mark().line && std::getline(lines, first);) ++i;
      throw InputError(path_, "",
                       "line " + std::to_string(root.Mark().line + 1) + ": expected 'key: value' lines, got '" +
                           Trim(first) + "'");
    }
    for (const auto& member : root) {
      const int line = member.first.Mark().line + 1;
      if (!member.first.IsScalar() || !(member.second.IsScalar() || member.second.IsNull()))
        throw InputError(path_, member.first.IsScalar() ? "/" + member.first.Scalar() : "",
                         "line " + std::to_string(line) +
                             ": nested YAML is not supported; expected flat 'key: value' lines");
      const std::string& key = member.first.Scalar();
      const std::string value = member.second.IsNull() ? "" : member.second.Scalar();
      const auto [it, inserted] = values_.emplace(key, Entry{value, line});
      if (!inserted)
        throw InputError(path_, "/" + key,
                         "duplicate key on line " + std::to_string(line) + " (also on line " +
                             std::to_string(it->second.line) + ")");
    }
  }

  const std::string& path() const { return path_; }

  std::string String(const std::string& key) const {
    const Entry& e = Require(key, "a non-empty string");
    if (e.text.empty()) throw Fail(key, e, "a non-empty string");
    return e.text;
  }

  double Number(const std::string& key) const {
    const Entry& e = Require(key, "a number");
    const auto x = ParseNumber(e.text);
    if (!x || !std::isfinite(*x)) throw Fail(key, e, "a finite number");
    return *x;
  }

  double Positive(const std::string& key) const {
    const double x = Number(key);
    if (!(x > 0)) throw Fail(key, values_.at(key), "a positive number");
    return x;
  }

  int Int(const std::string& key, int min_value, int max_value) const {
    const std::string expected =
        "an integer between " + std::to_string(min_value) + " and " + std::to_string(max_value);
    const Entry& e = Require(key, expected);
    const auto x = ParseNumber(e.text);  // "4" and "4.0" alike
    if (!x || *x != std::floor(*x) || *x < min_value || *x > max_value)
      throw Fail(key, e, expected);
    return static_cast<int>(*x);
  }

  bool Flag(const std::string& key) const {
    const Entry& e = Require(key, "0 or 1");
    const std::string v = Lower(e.text);
    if (v == "1" || v == "true") return true;
    if (v == "0" || v == "false") return false;
    throw Fail(key, e, "0 or 1 (or true / false)");
  }

 private:
  struct Entry {
    std::string text;
    int line = 0;
  };

  const Entry& Require(const std::string& key, const std::string& expected) const {
    auto it = values_.find(key);
    if (it == values_.end())
      throw InputError(path_, "/" + key, "missing key; expected " + expected);
    return it->second;
  }

  InputError Fail(const std::string& key, const Entry& e, const std::string& expected) const {
    return InputError(
        path_, "/" + key,
        "expected " + expected + ", got '" + e.text + "' (line " + std::to_string(e.line) + ")");
  }

  std::string path_;
  std::map<std::string, Entry> values_;
};

/// A 4×4 matrix written as 4 lines of 4 numbers, separated by spaces or by
/// commas (blank lines ignored).
Eigen::Matrix4d ReadMatrixCsv(const fs::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw InputError(file, "", "cannot read the file");
  const std::string expected = "a 4x4 matrix: 4 lines of 4 numbers separated by spaces or commas";
  Eigen::Matrix4d M;
  int row = 0;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (Trim(line).empty()) continue;
    std::vector<std::string> tokens;
    if (line.find(',') != std::string::npos) {
      std::stringstream ss(line);
      for (std::string token; std::getline(ss, token, ',');) tokens.push_back(Trim(token));
    } else {
      std::istringstream ss(line);
      for (std::string token; ss >> token;) tokens.push_back(token);
    }
    if (row == 4 || tokens.size() != 4)
      throw InputError(
          file, "",
          "expected " + expected + "; line " + std::to_string(number) +
              (row == 4 ? " is a fifth row" : " has " + std::to_string(tokens.size()) + " values"));
    for (int col = 0; col < 4; ++col) {
      const auto x = ParseNumber(tokens[col]);
      if (!x || !std::isfinite(*x))
        throw InputError(file, "",
                         "line " + std::to_string(number) + ", value " + std::to_string(col + 1) +
                             ": expected a finite number, got '" + tokens[col] + "'");
      M(row, col) = *x;
    }
    ++row;
  }
  if (row != 4)
    throw InputError(file, "", "expected " + expected + "; found " + std::to_string(row) + " rows");
  return M;
}

Eigen::Isometry3d ReadRigidCsv(const fs::path& path) {
  std::string why;
  const auto T = RigidFromMatrix(ReadMatrixCsv(path), false, &why);
  if (!T) throw InputError(path.string(), "", "expected " + why);
  return *T;
}

Camera ReadIntrinsics(const fs::path& path, const std::string& name) {
  const FlatYaml yaml(path);
  const double fx = yaml.Positive("fx");
  const double fy = yaml.Positive("fy");
  const double cx = yaml.Number("cx");
  const double cy = yaml.Number("cy");
  std::vector<double> distortion;
  if (yaml.Flag("has_dist_coeff")) {
    // The original tool's names for OpenCV's k1 k2 p1 p2 k3 k4 k5 k6.
    for (const char* key :
         {"dist_k0", "dist_k1", "dist_px", "dist_py", "dist_k2", "dist_k3", "dist_k4", "dist_k5"})
      distortion.push_back(yaml.Number(key));
  }
  const int width = yaml.Int("img_width", 1, 1 << 20);
  const int height = yaml.Int("img_height", 1, 1 << 20);
  std::string why;
  const auto camera = Camera::Make(name, width, height, fx, fy, cx, cy, distortion, &why);
  if (!camera) throw InputError(path.string(), "", "expected " + why);
  return *camera;
}

bool IsImageFile(const fs::path& path) {
  const std::string ext = Lower(path.extension().string());
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff";
}

std::vector<fs::path> ListImages(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(folder.string(), "", "image folder does not exist (METRIC layout, SPEC §8)");
  std::vector<fs::path> images;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file() && IsImageFile(entry.path())) images.push_back(entry.path());
  std::sort(images.begin(), images.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  if (images.empty())
    throw InputError(folder.string(), "", "no images (png, jpg, jpeg, tif or tiff) in the folder");
  for (std::size_t i = 1; i < images.size(); ++i)
    if (images[i].stem() == images[i - 1].stem())
      throw InputError(images[i].string(), "",
                       "two images share the name stem '" + images[i].stem().string() + "' (also " +
                           images[i - 1].filename().string() +
                           "); one pose file cannot serve both");
  return images;
}

/// One camera's pose file for one image.
struct PoseRecord {
  std::string camera;
  fs::path file;
  Eigen::Isometry3d T_base_ee;
  std::string image;  ///< absolute path
};

struct PoseDifference {
  double translation_m = 0;
  double rotation_rad = 0;
  bool Within() const {
    return translation_m <= kSamePoseTolerance_m && rotation_rad <= kSamePoseTolerance_rad;
  }
};

PoseDifference Difference(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return {(a.translation() - b.translation()).norm(), RotationDistance(a.rotation(), b.rotation())};
}

/// Chordal mean of the rotations, mean of the translations.
Eigen::Isometry3d MeanPose(const std::vector<const PoseRecord*>& records) {
  Eigen::Matrix3d R_sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d t_sum = Eigen::Vector3d::Zero();
  for (const PoseRecord* r : records) {
    R_sum += r->T_base_ee.rotation();
    t_sum += r->T_base_ee.translation();
  }
  Eigen::Isometry3d mean = Eigen::Isometry3d::Identity();
  mean.linear() = Orthonormalise(R_sum);
  mean.translation() = t_sum / static_cast<double>(records.size());
  return mean;
}

std::string Micrometres(double m) {
  std::ostringstream out;
  out.precision(3);
  out << m * 1e6 << " µm";
  return out.str();
}

std::string Degrees(double rad) {
  std::ostringstream out;
  out.precision(3);
  out << rad * 180.0 / M_PI << "°";
  return out.str();
}

/// The records of one name stem as robot poses: records that agree within the
/// tolerance (with the first of their group) are one pose at their mean; a
/// stem whose records disagree becomes one pose per group, named
/// `<stem>_<first camera of the group>`, with a warning.
void AddPoses(const std::string& stem, const std::vector<PoseRecord>& records, MetricImport* out,
              PoseDifference* largest_merged) {
  std::vector<std::vector<const PoseRecord*>> groups;
  for (const PoseRecord& record : records) {
    auto group = std::find_if(groups.begin(), groups.end(), [&](const auto& g) {
      return Difference(g.front()->T_base_ee, record.T_base_ee).Within();
    });
    if (group == groups.end()) groups.push_back({&record});
    else group->push_back(&record);
  }
  for (const auto& group : groups) {
    RobotPose pose;
    pose.id = groups.size() == 1 ? stem : stem + "_" + group.front()->camera;
    pose.T_base_ee = MeanPose(group);
    for (const PoseRecord* r : group) {
      pose.images[r->camera] = r->image;
      const PoseDifference d = Difference(group.front()->T_base_ee, r->T_base_ee);
      largest_merged->translation_m = std::max(largest_merged->translation_m, d.translation_m);
      largest_merged->rotation_rad = std::max(largest_merged->rotation_rad, d.rotation_rad);
    }
    out->dataset.poses.push_back(std::move(pose));
  }
  if (groups.size() > 1) {
    const PoseDifference d = Difference(groups[0].front()->T_base_ee, groups[1].front()->T_base_ee);
    std::ostringstream warning;
    warning << "pose files named " << stem << " disagree: " << groups[1].front()->file.string()
            << " differs from " << groups[0].front()->file.string() << " by "
            << d.translation_m * 1000.0 << " mm and " << Degrees(d.rotation_rad)
            << " (more than 0.1 mm or 0.01°); each camera keeps its own record as its own pose ("
            << groups.size() << " poses " << stem << "_<camera>), with no camera-to-camera terms "
            << "between them";
    out->warnings.push_back(GeneralWarning(WarningKind::kPoseFilesDisagree, warning.str()));
  }
}

}  // namespace

MetricImport ImportMetricFolder(const std::string& folder) {
  const fs::path root(folder);
  std::error_code ec;
  if (!fs::is_directory(root, ec))
    throw InputError(folder, "",
                     "folder does not exist; expected a METRIC folder with CalibrationInfo.yaml");
  const FlatYaml info(root / "CalibrationInfo.yaml");
  const int num_cameras = info.Int("number_of_cameras", 1, 1000);
  const std::string prefix = info.String("camera_folder_prefix");
  if (prefix.find_first_of("/\\") != std::string::npos)
    throw InputError(
        info.path(), "/camera_folder_prefix",
        "expected a folder name prefix such as 'camera', without '/', got '" + prefix + "'");
  const std::string pattern = info.String("pattern_type");
  if (pattern != "checkerboard")
    throw InputError(info.path(), "/pattern_type",
                     "unsupported pattern_type '" + pattern + "'; expected checkerboard");
  const int number_of_rows = info.Int("number_of_rows", 2, 10000);
  const int number_of_columns = info.Int("number_of_columns", 2, 10000);
  const double square_m = info.Positive("size");
  const int setup_code = info.Int("calibration_setup", 0, 1);

  MetricImport out;
  Dataset& dataset = out.dataset;
  dataset.setup = setup_code == 1 ? Setup::kEyeToHand : Setup::kEyeInHand;
  // The original tool calls cv::findChessboardCorners(image,
  // cv::Size(number_of_rows, number_of_columns), ...). cv::Size is (width,
  // height) and OpenCV returns corners row by row with `width` corners per row,
  // so OpenCV's points-per-row is number_of_rows. Our ids run j·cols + i with i
  // along a row (SPEC §4), so our cols (points per row) = number_of_rows and our
  // rows = number_of_columns: the ids then follow OpenCV's corner order.
  TargetSpec spec;
  spec.type = "checkerboard";
  spec.values["inner_corners"] =
      std::vector<double>{double(number_of_rows), double(number_of_columns)};
  spec.values["square_size_m"] = square_m;
  try {
    dataset.target = MakeTarget(spec);
  } catch (const InputError& e) {
    throw InputError(
        info.path(), "",
        std::string("checkerboard from number_of_rows, number_of_columns, size: ") + e.what());
  }

  std::map<std::string, std::vector<PoseRecord>> records;  // by file name stem, sorted
  for (int k = 1; k <= num_cameras; ++k) {
    const std::string name = prefix + std::to_string(k);
    const fs::path camera_dir = root / name;
    if (!fs::is_directory(camera_dir, ec))
      throw InputError(
          camera_dir.string(), "",
          "camera folder does not exist (CalibrationInfo.yaml has number_of_cameras: " +
              std::to_string(num_cameras) + ")");
    dataset.cameras.push_back(ReadIntrinsics(camera_dir / "intrinsic_pars_file.yaml", name));
    for (const fs::path& image : ListImages(camera_dir / "image")) {
      const std::string stem = image.stem().string();
      const fs::path pose_file = camera_dir / "pose" / (stem + ".csv");
      if (!fs::is_regular_file(pose_file, ec))
        throw InputError(pose_file.string(), "",
                         "pose file does not exist; expected one per image with the same name "
                         "stem (for " +
                             image.string() + ")");
      records[stem].push_back({name, pose_file, ReadRigidCsv(pose_file),
                               fs::absolute(image).lexically_normal().string()});
    }
  }
  PoseDifference largest_merged;
  std::size_t merged = 0;
  for (const auto& [stem, stem_records] : records) {
    AddPoses(stem, stem_records, &out, &largest_merged);
    if (stem_records.size() > 1) ++merged;
  }
  if (merged > 0 && largest_merged.translation_m + largest_merged.rotation_rad > 0)
    out.notes.push_back("pose files with the same name in several camera folders are one robot "
                        "pose (their mean): the copies differ by up to " +
                        Micrometres(largest_merged.translation_m) + " and " +
                        Degrees(largest_merged.rotation_rad));

  const fs::path gt_dir = root / "GT";
  if (fs::is_directory(gt_dir, ec)) {
    // gt_cam<k>.csv is T_base_cam, constant only when the cameras stand in the cell.
    if (dataset.setup != Setup::kEyeToHand)
      throw InputError(gt_dir.string(), "",
                       "GT/gt_cam<k>.csv holds T_base_cam, which is only defined for "
                       "calibration_setup 1 (eye-on-base); this folder has calibration_setup 0");
    GroundTruth truth;
    truth.setup = dataset.setup;
    truth.has_T_target = false;  // METRIC gives the cameras only
    for (int k = 1; k <= num_cameras; ++k) {
      const fs::path file = gt_dir / ("gt_cam" + std::to_string(k) + ".csv");
      if (!fs::is_regular_file(file, ec))
        throw InputError(
            file.string(), "",
            "ground-truth file does not exist; GT/ needs one gt_cam<k>.csv per camera");
      truth.T_cam[dataset.cameras[k - 1].name] = ReadRigidCsv(file);
    }
    out.truth = std::move(truth);
  }
  return out;
}

}  // namespace handeye
