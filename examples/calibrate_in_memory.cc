// SPDX-License-Identifier: GPL-2.0-or-later
// Calibrates two fixed cameras against a robot from observations built in
// memory: no dataset file, no images. In a real cell the robot poses come
// from the controller and the pixels from your own detector; here both are
// made up from a known cell so that the program can show what it recovers.
// Exit code 0 when every camera lands within four standard deviations of the
// truth, the deviations that the pixel noise implies (Cramér–Rao bound).
#include <handeye/handeye.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

// A rotation whose z axis is `forward`, x to the right of it and y down, the
// way a camera hangs (and the way the target faces a camera).
Matrix3d LookAlong(const Vector3d& forward) {
  const Vector3d z = forward.normalized();
  const Vector3d x = z.cross(Vector3d::UnitZ()).normalized();
  Matrix3d R;
  R << x, z.cross(x), z;
  return R;
}

Isometry3d Pose(const Matrix3d& R, const Vector3d& t) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

}  // namespace

int main() {
  using namespace handeye;
  std::mt19937_64 rng(42);
  std::normal_distribution<double> pixel_noise(0.0, 0.2);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);

  Dataset dataset;
  dataset.setup = Setup::kEyeToHand;
  // A built-in target type, made from the parameters a dataset file would list.
  TargetSpec board;
  board.type = "checkerboard";
  board.values = {{"inner_corners", std::vector<double>{7, 4}}, {"square_size_m", 0.04}};
  dataset.target = MakeTarget(board);
  std::string why;
  dataset.cameras.push_back(
      *Camera::Make("left", 1280, 960, 1000, 1000, 639.5, 479.5, {-0.12, 0.08, 5e-4, -3e-4, 0}, &why));
  dataset.cameras.push_back(*Camera::Make("right", 1280, 960, 1010, 1012, 642, 478, {}, &why));

  // The truth of this made-up cell: the cameras look at the robot's workspace
  // from 1.3 m; the target sits 5 cm in front of the flange.
  const Vector3d workspace(0.6, 0.0, 0.6);
  const Vector3d camera_positions[] = {{1.2, 0.8, 1.4}, {1.2, -0.8, 1.4}};
  std::vector<Isometry3d> T_base_cam;
  for (const Vector3d& c : camera_positions) T_base_cam.push_back(Pose(LookAlong(workspace - c), c));
  const Isometry3d T_ee_target = Pose(Matrix3d::Identity(), Vector3d(0, 0, 0.05));

  // Twenty-four robot poses: the target turned towards one camera or the other,
  // tilted and rotated in its plane so that the motion is not degenerate.
  for (int j = 0; j < 24; ++j) {
    const Vector3d centre = workspace + 0.1 * Vector3d(uniform(rng), uniform(rng), uniform(rng));
    const Vector3d towards = camera_positions[j % 2] + 0.5 * Vector3d(uniform(rng), uniform(rng), uniform(rng));
    const Matrix3d R_base_target =
        LookAlong(centre - towards) * Eigen::AngleAxisd(M_PI * uniform(rng), Vector3d::UnitZ()).toRotationMatrix();
    RobotPose pose;
    pose.id = std::to_string(j);
    pose.T_base_ee = Pose(R_base_target, centre) * T_ee_target.inverse();  // what the controller reports
    dataset.poses.push_back(pose);

    // What a detector would report: every corner a camera sees, with noise.
    for (std::size_t k = 0; k < dataset.cameras.size(); ++k) {
      const Camera& camera = dataset.cameras[k];
      const Isometry3d T_cam_target = T_base_cam[k].inverse() * pose.T_base_ee * T_ee_target;
      if (T_cam_target.linear()(2, 2) < 0.5) continue;  // printed face turned away (target.h)
      Observation view{pose.id, camera.name, {}, {}};
      for (const TargetPoint& point : dataset.target->Points()) {
        const auto uv = camera.Project(T_cam_target * point.p_target);
        if (!uv || !camera.InImage(*uv, 5.0)) continue;
        view.ids.push_back(point.id);
        view.points_px.push_back(*uv + Eigen::Vector2d(pixel_noise(rng), pixel_noise(rng)));
      }
      if (view.ids.size() == dataset.target->Points().size()) dataset.observations.push_back(view);
    }
  }

  CalibrationOptions options;  // the paper's joint method
  options.threads = 2;
  if (!options.Check(&why)) {
    std::fprintf(stderr, "invalid options: %s\n", why.c_str());
    return 2;
  }
  const CalibrationResult result = Calibrate(dataset, options);

  // How far off the pixel noise alone should leave each camera: the
  // Cramér–Rao bound at the estimate (handeye/core/uncertainty.h).
  const PositionCovariance bound = ComputePositionCovariance(dataset, result, 0.2);
  bool close = true;
  std::printf("%zu views; rms %.3f px\n", dataset.observations.size(), result.metrics.rms_px);
  for (std::size_t k = 0; k < result.cameras.size(); ++k) {
    const CameraResult& camera = result.cameras[k];  // T_cam is T_base_cam here
    const double mm = 1000 * (camera.T_cam.translation() - T_base_cam[k].translation()).norm();
    const double deg = RotationDistance(camera.T_cam.rotation(), T_base_cam[k].rotation()) * 180 / M_PI;
    const double sigma_mm = 1000 * std::sqrt(bound.camera_position.at(camera.name).trace());
    const double sigma_deg = std::sqrt(bound.camera_rotation.at(camera.name).trace()) * 180 / M_PI;
    std::printf("%-6s views %2d  T_base_cam off by %.3f mm, %.4f deg (noise alone: %.3f mm, %.4f deg)\n",
                camera.name.c_str(), camera.views, mm, deg, sigma_mm, sigma_deg);
    close = close && camera.calibrated && mm < 4 * sigma_mm && deg < 4 * sigma_deg;
  }
  return close ? 0 : 1;
}
