// SPDX-License-Identifier: GPL-2.0-or-later
// A calibration target of your own, plugged into handeye from outside the
// library: a grid of black dots whose first dot is larger (it marks the
// origin), found with OpenCV's circle-grid detector. Once registered, the
// type works everywhere a built-in one does: in dataset files, in DetectAll,
// in the simulator and renderer.
//
// The program renders a simulated two-camera cell showing this target to
// OUTDIR (default: dot_grid_cell), then does what you would do with your own
// images: load the dataset file, detect, calibrate. Exit code 0 when every
// camera lands within 1 mm and 0.05° of the simulation's truth.
#include <handeye/sim/synthetic.h>
#include <handeye/handeye.h>
#include <handeye/sim/simulation.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace {

using namespace handeye;

/// `{"type": "dot_grid", "dots": [cols, rows], "spacing_m": s}`: dot (i, j),
/// id j·cols + i, is centred at (i·s, j·s, 0); dots have radius s/4, dot 0
/// radius 0.36·s. cols ≠ rows, so that only the origin dot tells 0° from 180°.
class DotGridTarget : public Target {
 public:
  explicit DotGridTarget(const TargetSpec& spec) : spec_(spec) {
    spec.RejectUnknownKeys({"dots", "spacing_m"});
    const auto dots = spec.GetIntPair("dots", 3);
    cols_ = dots[0];
    rows_ = dots[1];
    spacing_ = spec.GetPositive("spacing_m");
    if (cols_ == rows_) throw InputError("", "/dots", "expected different numbers of columns and rows");
    for (int j = 0; j < rows_; ++j)
      for (int i = 0; i < cols_; ++i) points_.push_back({j * cols_ + i, Eigen::Vector3d(i * spacing_, j * spacing_, 0)});
  }

  std::string Type() const override { return "dot_grid"; }
  const TargetSpec& Spec() const override { return spec_; }
  const std::vector<TargetPoint>& Points() const override { return points_; }
  Eigen::AlignedBox2d Extent() const override {
    return Eigen::AlignedBox2d(Eigen::Vector2d(-spacing_, -spacing_),
                               Eigen::Vector2d(cols_ * spacing_, rows_ * spacing_));
  }
  double Albedo(double x_m, double y_m) const override {
    const int i = std::clamp(static_cast<int>(std::lround(x_m / spacing_)), 0, cols_ - 1);
    const int j = std::clamp(static_cast<int>(std::lround(y_m / spacing_)), 0, rows_ - 1);
    const double radius = (i == 0 && j == 0 ? kOriginRadius : kRadius) * spacing_;
    return std::hypot(x_m - i * spacing_, y_m - j * spacing_) <= radius ? 0.0 : 1.0;
  }

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  static constexpr double kRadius = 0.25, kOriginRadius = 0.36;  // × spacing

 private:
  TargetSpec spec_;
  int cols_ = 0, rows_ = 0;
  double spacing_ = 0;
  std::vector<TargetPoint> points_;
};

class DotGridDetector : public Detector {
 public:
  explicit DotGridDetector(std::shared_ptr<const DotGridTarget> target) : target_(std::move(target)) {}

  std::optional<Detection> Detect(const cv::Mat& gray) const override {
    const int cols = target_->cols(), rows = target_->rows();
    std::vector<cv::Point2f> found;  // row by row, `cols` per row, in some orientation
    // The graph search fails on some oblique views that the clustering search
    // finds, and the other way round: try both.
    const cv::Size size(cols, rows);
    if (!cv::findCirclesGrid(gray, size, found, cv::CALIB_CB_SYMMETRIC_GRID) &&
        !cv::findCirclesGrid(gray, size, found, cv::CALIB_CB_SYMMETRIC_GRID | cv::CALIB_CB_CLUSTERING))
      return std::nullopt;
    auto at = [&](int r, int c) { return Eigen::Vector2d(found[r * cols + c].x, found[r * cols + c].y); };

    // The grid may come back turned by 180° or mirrored: the large dot is the
    // corner with the darkest ring at 0.3 spacings from its centre (outside a
    // small dot, inside the large one). The neighbours' offsets map that
    // circle of the target plane into the image, foreshortening included.
    const int corner_r[] = {0, 0, rows - 1, rows - 1}, corner_c[] = {0, cols - 1, 0, cols - 1};
    const double ring = 0.5 * (DotGridTarget::kRadius + DotGridTarget::kOriginRadius);
    int origin = 0;
    double darkest = 1e9;
    for (int k = 0; k < 4; ++k) {
      const int r = corner_r[k], c = corner_c[k];
      const Eigen::Vector2d u = at(r, c == 0 ? 1 : c - 1) - at(r, c);
      const Eigen::Vector2d v = at(r == 0 ? 1 : r - 1, c) - at(r, c);
      double sum = 0;
      for (int s = 0; s < 16; ++s) {
        const Eigen::Vector2d p = at(r, c) + ring * (std::cos(s * M_PI / 8) * u + std::sin(s * M_PI / 8) * v);
        sum += gray.at<uchar>(std::clamp(static_cast<int>(std::lround(p.y())), 0, gray.rows - 1),
                              std::clamp(static_cast<int>(std::lround(p.x())), 0, gray.cols - 1));
      }
      if (sum < darkest) {
        darkest = sum;
        origin = k;
      }
    }
    const bool flip_r = corner_r[origin] != 0, flip_c = corner_c[origin] != 0;
    Detection detection;
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < cols; ++i) {
        detection.ids.push_back(j * cols + i);
        detection.points_px.push_back(at(flip_r ? rows - 1 - j : j, flip_c ? cols - 1 - i : i));
      }
    // The printed face is seen from the front (target.h): target x then y
    // turn clockwise in the image. Anything else is a misdetection.
    const Eigen::Vector2d x_axis = detection.points_px[1] - detection.points_px[0];
    const Eigen::Vector2d y_axis = detection.points_px[cols] - detection.points_px[0];
    if (x_axis.x() * y_axis.y() - x_axis.y() * y_axis.x() <= 0) return std::nullopt;
    return detection;
  }

 private:
  std::shared_ptr<const DotGridTarget> target_;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string outdir = argc > 1 ? argv[1] : "dot_grid_cell";

  // 1. Register the plugin before anything reads a dataset with this type.
  RegisterTargetPlugin(MakeTargetPlugin<DotGridTarget, DotGridDetector>("dot_grid"));

  // 2. Images of a simulated cell (with yours: skip this step).
  TargetSpec spec;
  spec.type = "dot_grid";
  spec.values = {{"dots", std::vector<double>{6, 5}}, {"spacing_m", 0.05}};
  SceneOptions cell;
  cell.cell = "small";
  cell.num_cameras = 2;
  cell.num_poses = 12;
  cell.width = 1280;
  cell.height = 960;
  SyntheticScene scene = MakeScene(cell, MakeTarget(spec));
  WriteSimulation(&scene, RenderOptions{}, outdir);

  // 3. Load, detect with the plugin's detector, calibrate.
  Dataset dataset = LoadDataset(outdir + "/dataset.json");
  DetectAll(&dataset);
  const CalibrationResult result = Calibrate(dataset, CalibrationOptions{});

  const GroundTruth truth = LoadGroundTruth(outdir + "/ground_truth.json");
  const Evaluation errors = EvaluateAgainstTruth(result, truth);
  std::printf("%zu views detected; rms %.3f px\n", dataset.observations.size(), result.metrics.rms_px);
  bool close = errors.cameras.size() == dataset.cameras.size();
  for (const CameraError& camera : errors.cameras) {
    std::printf("%-6s T_base_cam off by %.3f mm, %.4f deg\n", camera.name.c_str(), camera.translation_mm,
                camera.rotation_deg);
    close = close && camera.translation_mm < 1.0 && camera.rotation_deg < 0.05;
  }
  return close ? 0 : 1;
}
