// SPDX-License-Identifier: GPL-2.0-or-later
// Synthetic workcells with ground truth. Geometry (metres, base frame z up):
// the robot base is at the origin; eye_to_hand cameras stand on a ring (or an
// arc, for fewer than four) around it and look at the robot's workspace; the
// robot carries the target and turns its printed face towards one camera or
// between two neighbours, so that views are shared. eye_in_hand puts a small
// rig of cameras on the flange and a fixed target in the cell.

#include "handeye/sim/synthetic.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "handeye/core/calibration.h"
#include "handeye/core/checkerboard.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "scene_views.h"

namespace handeye {
namespace {

using namespace sim_detail;

// ---- Cell presets -----------------------------------------------------------

struct CellPreset {
  /// Nominal camera–target distance (m): sets the ring radius (eye_to_hand) or
  /// where the fixed target stands (eye_in_hand).
  double distance_m = 0;
  /// fx / image width: wider lenses for small cells so the workspace fits.
  double focal_per_width = 0;
  /// Camera mounting heights (m): poles and walls in a real cell.
  double min_height_m = 0, max_height_m = 0;
  /// METRIC's synthetic medium cell: fixed intrinsics, ring radius and height.
  bool metric = false;
};

std::optional<CellPreset> FindPreset(const std::string& cell) {
  // Focal lengths give ≈ 85°, 70° and 56° horizontal fields of view: what
  // cell-monitoring cameras use at these distances.
  if (cell == "small") return CellPreset{1.5, 0.55, 1.8, 2.4, false};
  if (cell == "medium") return CellPreset{2.5, 0.714, 1.9, 2.5, false};
  if (cell == "large") return CellPreset{4.0, 0.95, 2.0, 2.6, false};
  // Cameras 2.3 m from the base axis at 1.15 m; the target works ≈ 1.65 m
  // from them (used for where an eye_in_hand target stands).
  if (cell == "metric-medium") return CellPreset{1.65, 1371.02 / 1920.0, 1.15, 1.15, true};
  return std::nullopt;
}

constexpr double kMetricFocalPx = 1371.02;  // at 1920 × 1080
constexpr double kMetricRingRadiusM = 2.3;
constexpr double kMetricHeightM = 1.15;

// The robot's workspace for the target's centre (eye_to_hand) and limits we
// invent for "reachable" (no kinematics): the flange stays in a cylinder
// shell around the base and its tool axis never points back at the robot.
constexpr double kTargetMinRadiusM = 0.4, kTargetMaxRadiusM = 0.9;
constexpr double kTargetMinHeightM = 0.7, kTargetMaxHeightM = 1.5;
constexpr double kWorkspaceMidHeightM = 1.1;
constexpr double kWorkspaceMidRadiusM = 0.65;
constexpr double kRingOffsetM = 0.35;
constexpr double kFlangeMinRadiusM = 0.25, kFlangeMaxRadiusM = 1.05;
constexpr double kFlangeMinHeightM = 0.3, kFlangeMaxHeightM = 1.9;
constexpr double kToolAxisMinOutward = -0.3;  // cos of ≈ 107°

constexpr int kMaxAttemptsPerPose = 20000;

// ---- The scene builder -----------------------------------------------------

class SceneBuilder {
 public:
  SceneBuilder(const SceneOptions& options, std::shared_ptr<const Target> target)
      : options_(options), preset_(*FindPreset(options.cell)), target_(std::move(target)),
        engine_(options.seed), rng_(&engine_) {
    width_ = options.width > 0 ? options.width : 1920;
    height_ = options.height > 0 ? options.height : 1080;
  }

  SyntheticScene Build() {
    scene_.dataset.setup = options_.setup;
    scene_.dataset.target = target_;
    scene_.truth.setup = options_.setup;
    scene_.truth.has_T_target = true;
    MakeCameras();
    if (options_.setup == Setup::kEyeToHand) {
      PlaceCamerasAroundRobot();
      MountTargetOnFlange();
    } else {
      MountRigOnFlange();
      PlaceTargetInCell();
    }
    BumpCamera();
    // A later capture of the same cell: the cameras and target of `seed`,
    // the robot poses (and their noise) of `pose_seed`.
    if (options_.pose_seed != 0) engine_.seed(options_.pose_seed);
    for (int j = 0; j < options_.num_poses; ++j) AddPose(j);
    AddPoseNoise();
    SwapPoseRecords();
    return std::move(scene_);
  }

 private:
  // A camera knocked after calibration: moved by bump_mm along its own x axis
  // and turned by bump_deg about its own y axis. The truth is the bumped pose.
  void BumpCamera() {
    if (options_.bumped_camera.empty()) return;
    const auto it = scene_.truth.T_cam.find(options_.bumped_camera);
    if (it == scene_.truth.T_cam.end())
      throw std::invalid_argument("MakeScene: no camera '" + options_.bumped_camera + "' to bump");
    Eigen::Isometry3d bump = Eigen::Isometry3d::Identity();
    bump.translation() = Eigen::Vector3d(options_.bump_mm / 1000.0, 0.0, 0.0);
    bump.linear() = Eigen::AngleAxisd(options_.bump_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
    it->second = it->second * bump;
  }

  // Intrinsics: fx a few % around the preset's, square-ish pixels, principal
  // point near the centre, mild barrel distortion that stays invertible.
  void MakeCameras() {
    for (int k = 0; k < options_.num_cameras; ++k) {
      const std::string name = "cam" + std::to_string(k);
      std::string why;
      std::optional<Camera> camera;
      if (preset_.metric) {
        // METRIC's values at 1920 × 1080, scaled with the width otherwise so
        // the field of view stays the same.
        const double scale = width_ / 1920.0;
        camera = Camera::Make(name, width_, height_, kMetricFocalPx * scale, kMetricFocalPx * scale,
                              width_ / 2.0 + 0.5, height_ / 2.0 + 0.5, {}, &why);
      } else {
        const double fx = preset_.focal_per_width * width_ * rng_.Uniform(0.97, 1.03);
        const double fy = fx * rng_.Uniform(0.998, 1.002);
        const double cx = (width_ - 1) / 2.0 + rng_.Uniform(-0.01, 0.01) * width_;
        const double cy = (height_ - 1) / 2.0 + rng_.Uniform(-0.01, 0.01) * height_;
        camera = options_.distortion ? WithDistortion(name, fx, fy, cx, cy)
                                     : Camera::Make(name, width_, height_, fx, fy, cx, cy, {}, &why);
      }
      if (!camera) throw std::logic_error("synthetic camera rejected: " + why);
      scene_.dataset.cameras.push_back(*camera);
    }
  }

  std::optional<Camera> WithDistortion(const std::string& name, double fx, double fy, double cx,
                                       double cy) {
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const std::vector<double> coeffs = {rng_.Uniform(-0.15, 0.02), rng_.Uniform(-0.01, 0.05),
                                          rng_.Uniform(-2e-3, 2e-3), rng_.Uniform(-2e-3, 2e-3),
                                          rng_.Uniform(-0.01, 0.01)};
      std::string why;
      auto camera = Camera::Make(name, width_, height_, fx, fy, cx, cy, coeffs, &why);
      if (camera && DistortionUsable(*camera)) return camera;
    }
    throw std::logic_error("no invertible lens distortion found for " + name);
  }

  // Azimuth of camera k: a full ring from four cameras on; fewer stand on an
  // arc a quarter turn apart so that neighbours can share views of a flat
  // target (two cameras facing each other never see the same face).
  double CameraSpacing() const {
    return std::min(2.0 * kPi / options_.num_cameras, kPi / 2.0);
  }

  void PlaceCamerasAroundRobot() {
    const double first_azimuth = rng_.Uniform(0.0, 2.0 * kPi);
    const double spacing = CameraSpacing();
    for (int k = 0; k < options_.num_cameras; ++k) {
      const double azimuth = first_azimuth + k * spacing +
                             (preset_.metric ? 0.0 : rng_.Uniform(-0.15, 0.15) * spacing);
      double height, radius;
      if (preset_.metric) {
        height = kMetricHeightM + rng_.Uniform(-0.02, 0.02);
        radius = kMetricRingRadiusM + rng_.Uniform(-0.03, 0.03);
      } else {
        // Ring radius chosen so the camera is ≈ distance_m from the target on
        // average over its views: from a point 0.35 m out on its side (views
        // of targets turned between two cameras lie further off).
        height = rng_.Uniform(preset_.min_height_m, preset_.max_height_m);
        const double distance = preset_.distance_m * rng_.Uniform(0.92, 1.08);
        const double dz = height - kWorkspaceMidHeightM;
        radius = kRingOffsetM + std::sqrt(std::max(0.25, distance * distance - dz * dz));
      }
      const Eigen::Vector3d position = radius * Horizontal(azimuth) + height * kUp;
      // Look at the workspace between the base axis and the target ring, with
      // a little aim error and roll so no two cameras are alike.
      const Eigen::Vector3d aim =
          0.35 * Horizontal(azimuth) + kWorkspaceMidHeightM * kUp;
      const Eigen::Vector3d forward = rng_.Turn(aim - position, Deg(rng_.Uniform(0.0, 2.0)));
      const Eigen::Matrix3d R_base_cam =
          LookRotation(forward) *
          Eigen::AngleAxisd(Deg(rng_.Uniform(-2.0, 2.0)), Eigen::Vector3d::UnitZ()).toRotationMatrix();
      Eigen::Isometry3d T_base_cam = Eigen::Isometry3d::Identity();
      T_base_cam.linear() = R_base_cam;
      T_base_cam.translation() = position;
      scene_.truth.T_cam[scene_.dataset.cameras[k].name] = T_base_cam;
      camera_azimuths_.push_back(azimuth);
    }
  }

  // The print faces away from the flange (along +z_ee, so target z = −z_ee),
  // its centre 5–15 cm in front of the flange and a little off its axis, with
  // a random turn about the axis and a small mounting tilt.
  void MountTargetOnFlange() {
    const Eigen::Matrix3d R_ee_target =
        Eigen::AngleAxisd(Deg(rng_.Uniform(0.0, 8.0)), rng_.Perpendicular(Eigen::Vector3d::UnitZ()))
            .toRotationMatrix() *
        Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()).toRotationMatrix() *
        Eigen::AngleAxisd(rng_.Uniform(-kPi, kPi), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d centre_ee(rng_.Uniform(-0.02, 0.02), rng_.Uniform(-0.02, 0.02),
                                    rng_.Uniform(0.05, 0.15));
    Eigen::Isometry3d T_ee_target = Eigen::Isometry3d::Identity();
    T_ee_target.linear() = R_ee_target;
    T_ee_target.translation() = centre_ee - R_ee_target * SheetCentre(*target_);
    scene_.truth.T_target = T_ee_target;
  }

  // A compact rig: cameras on a 6 cm circle 8 cm in front of the flange, each
  // looking 3–8° outwards from the tool axis, slightly rolled.
  void MountRigOnFlange() {
    const double first = rng_.Uniform(0.0, 2.0 * kPi);
    for (int k = 0; k < options_.num_cameras; ++k) {
      const double around = first + 2.0 * kPi * k / options_.num_cameras;
      const Eigen::Vector3d outward = Horizontal(around);  // in the ee xy plane
      const Eigen::Vector3d position = 0.06 * outward + Eigen::Vector3d(0, 0, 0.08);
      const Eigen::Vector3d tilt_axis = Eigen::Vector3d::UnitZ().cross(outward);
      const Eigen::Matrix3d R_ee_cam =
          Eigen::AngleAxisd(Deg(rng_.Uniform(3.0, 8.0)), tilt_axis).toRotationMatrix() *
          Eigen::AngleAxisd(Deg(rng_.Uniform(-15.0, 15.0)), Eigen::Vector3d::UnitZ())
              .toRotationMatrix();
      Eigen::Isometry3d T_ee_cam = Eigen::Isometry3d::Identity();
      T_ee_cam.linear() = R_ee_cam;
      T_ee_cam.translation() = position;
      scene_.truth.T_cam[scene_.dataset.cameras[k].name] = T_ee_cam;
    }
  }

  // The fixed target stands ≈ distance_m beyond the workspace, its print
  // turned towards the robot with a small fixed tilt.
  void PlaceTargetInCell() {
    target_azimuth_ = rng_.Uniform(0.0, 2.0 * kPi);
    const double radius = kWorkspaceMidRadiusM + preset_.distance_m * rng_.Uniform(0.95, 1.05);
    const double height = rng_.Uniform(0.9, 1.3);
    const Eigen::Vector3d centre = radius * Horizontal(target_azimuth_) + height * kUp;
    const Eigen::Vector3d face = rng_.Turn(-Horizontal(target_azimuth_), Deg(rng_.Uniform(5.0, 20.0)));
    scene_.truth.T_target = PlaceSheet(centre, face, rng_.Uniform(-kPi, kPi));
  }

  /// T_base_target with the sheet's centre at `centre_base`, its printed face
  /// towards `face_base` (so target z = −face) and turned by `in_plane` about it.
  Eigen::Isometry3d PlaceSheet(const Eigen::Vector3d& centre_base, const Eigen::Vector3d& face_base,
                               double in_plane) const {
    Eigen::Isometry3d T_base_target = Eigen::Isometry3d::Identity();
    T_base_target.linear() =
        LookRotation(-face_base) *
        Eigen::AngleAxisd(in_plane, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T_base_target.translation() = centre_base - T_base_target.linear() * SheetCentre(*target_);
    return T_base_target;
  }

  // Which cameras pose j turns the target towards: alternately one camera and
  // a pair of neighbours, round the ring, so every camera gets views and
  // neighbours share some.
  std::vector<int> FacingCameras(int j) const {
    const int n = options_.num_cameras;
    const int num_pairs = n >= 4 ? n : n - 1;  // an arc has no wrap-around pair
    if (num_pairs <= 0 || j % 2 == 0) return {(j / 2) % n};
    const int first = (j / 2) % num_pairs;
    return {first, (first + 1) % n};
  }

  Eigen::Isometry3d SampleEyeToHandPose(int j) {
    const std::vector<int> facing = FacingCameras(j);
    double azimuth = camera_azimuths_[facing[0]];
    if (facing.size() == 2) {
      const double a = camera_azimuths_[facing[0]], b = camera_azimuths_[facing[1]];
      azimuth = a + 0.5 * std::remainder(b - a, 2.0 * kPi);
    }
    // Between two cameras the print is seen obliquely by both; keeping the
    // target nearer the base axis and the bisector keeps both angles usable.
    const bool pair = facing.size() == 2;
    azimuth += Deg(pair ? rng_.Uniform(-10.0, 10.0) : rng_.Uniform(-25.0, 25.0));
    const double radius = pair ? rng_.Uniform(kTargetMinRadiusM, kWorkspaceMidRadiusM)
                               : rng_.Uniform(kTargetMinRadiusM, kTargetMaxRadiusM);
    const Eigen::Vector3d centre =
        radius * Horizontal(azimuth) + rng_.Uniform(kTargetMinHeightM, kTargetMaxHeightM) * kUp;
    Eigen::Vector3d face = Eigen::Vector3d::Zero();
    for (int k : facing)
      face += (scene_.truth.T_cam.at(CameraName(k)).translation() - centre).normalized();
    face.normalize();
    const double tilt = Deg(rng_.Uniform(10.0, 35.0));
    if (pair) {
      // Tilt mostly up or down: a sideways tilt would turn the print away
      // from one of the two cameras it is meant for.
      Eigen::Vector3d axis = face.cross(kUp).normalized();
      axis = Eigen::AngleAxisd(Deg(rng_.Uniform(-30.0, 30.0)), face) * axis;
      if (rng_.Unit() < 0.5) axis = -axis;
      face = Eigen::AngleAxisd(tilt, axis) * face;
    } else {
      face = rng_.Turn(face, tilt);
    }
    const Eigen::Isometry3d T_base_target = PlaceSheet(centre, face, rng_.Uniform(-kPi, kPi));
    return T_base_target * scene_.truth.T_target.inverse();
  }

  Eigen::Isometry3d SampleEyeInHandPose() {
    // The robot turns towards the target; the rig points at it with an aim
    // error of up to most of the half field of view, so the target wanders
    // over the images and the tool axis tilts (from afar, moving the flange
    // alone hardly changes the viewing direction), and it rolls freely.
    const double azimuth = target_azimuth_ + Deg(rng_.Uniform(-35.0, 35.0));
    const Eigen::Vector3d flange = rng_.Uniform(0.3, 1.0) * Horizontal(azimuth) +
                                   rng_.Uniform(0.6, 1.7) * kUp;
    const Eigen::Vector3d target_centre = scene_.truth.T_target * SheetCentre(*target_);
    const double half_fov = std::atan(0.5 * height_ / (preset_.focal_per_width * width_));
    const Eigen::Vector3d forward =
        rng_.Turn(target_centre - flange, rng_.Uniform(0.0, 0.8 * half_fov));
    Eigen::Isometry3d T_base_ee = Eigen::Isometry3d::Identity();
    T_base_ee.linear() =
        LookRotation(forward) *
        Eigen::AngleAxisd(rng_.Uniform(-kPi, kPi), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T_base_ee.translation() = flange;
    return T_base_ee;
  }

  static bool Reachable(const Eigen::Isometry3d& T_base_ee) {
    const Eigen::Vector3d p = T_base_ee.translation();
    const double radius = std::hypot(p.x(), p.y());
    if (radius < kFlangeMinRadiusM || radius > kFlangeMaxRadiusM) return false;
    if (p.z() < kFlangeMinHeightM || p.z() > kFlangeMaxHeightM) return false;
    const Eigen::Vector3d outward(p.x() / radius, p.y() / radius, 0.0);
    return T_base_ee.linear().col(2).dot(outward) >= kToolAxisMinOutward;
  }

  std::string CameraName(int k) const { return scene_.dataset.cameras[k].name; }

  void AddPose(int j) {
    char id[16];
    std::snprintf(id, sizeof id, "%04d", j + 1);
    const bool given = !options_.given_poses.empty();
    for (int attempt = 0; attempt < kMaxAttemptsPerPose; ++attempt) {
      const Eigen::Isometry3d T_base_ee = given ? options_.given_poses[j]
                                          : options_.setup == Setup::kEyeToHand ? SampleEyeToHandPose(j)
                                                                                : SampleEyeInHandPose();
      if (!given && !Reachable(T_base_ee)) continue;
      GroundTruth::PoseTruth truth;
      truth.id = id;
      truth.T_base_ee_true = T_base_ee;
      for (const Camera& camera : scene_.dataset.cameras) {
        const Eigen::Isometry3d T_cam_target =
            TargetInCamera(options_.setup, scene_.truth.T_cam.at(camera.name), scene_.truth.T_target, T_base_ee);
        auto obs = SeeTarget(camera, *target_, T_cam_target, options_.border_margin_px);
        if (!obs) continue;
        obs->pose_id = id;
        truth.points_px[camera.name] = std::move(*obs);
      }
      if (truth.points_px.empty() && !given) continue;
      RobotPose pose;
      pose.id = id;
      pose.T_base_ee = T_base_ee;
      scene_.dataset.poses.push_back(pose);
      scene_.truth.poses.push_back(std::move(truth));
      return;
    }
    throw InputError("", "",
                     "no robot pose found in which a camera sees the whole target after " +
                         std::to_string(kMaxAttemptsPerPose) +
                         " tries; the target may be too large for the images or the cell");
  }

  // A separate random stream, so that switching pose noise on or off leaves
  // the rest of the scene exactly as it was.
  void AddPoseNoise() {
    if (options_.pose_noise_mm == 0.0 && options_.pose_noise_deg == 0.0) return;
    std::mt19937_64 noise_engine(options_.seed ^ 0x9e3779b97f4a7c15ULL);
    Rng noise(&noise_engine);
    for (RobotPose& pose : scene_.dataset.poses) {
      const Eigen::Vector3d dt(noise.Normal(options_.pose_noise_mm),
                               noise.Normal(options_.pose_noise_mm),
                               noise.Normal(options_.pose_noise_mm));
      const Eigen::Vector3d axis = noise.Direction();
      const double angle = Deg(noise.Normal(options_.pose_noise_deg));
      // Error about an axis through the flange, expressed in the base frame.
      pose.T_base_ee.linear() =
          Eigen::AngleAxisd(angle, axis).toRotationMatrix() * pose.T_base_ee.linear();
      pose.T_base_ee.translation() += dt / 1000.0;
    }
  }

  // Exchanges the reported T_base_ee of disjoint random pairs of poses, from
  // a random stream of its own (the scene is otherwise unchanged).
  void SwapPoseRecords() {
    if (options_.swap_poses == 0) return;
    std::vector<std::size_t> order(scene_.dataset.poses.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::mt19937_64 swap_engine(options_.seed ^ 0x5157a9b0c3d2e1f4ULL);
    std::shuffle(order.begin(), order.end(), swap_engine);
    for (int p = 0; p < options_.swap_poses; ++p) {
      RobotPose& a = scene_.dataset.poses[order[2 * p]];
      RobotPose& b = scene_.dataset.poses[order[2 * p + 1]];
      std::swap(a.T_base_ee, b.T_base_ee);
      scene_.swapped_poses.emplace_back(a.id, b.id);
    }
  }

  const SceneOptions& options_;
  const CellPreset preset_;
  std::shared_ptr<const Target> target_;
  std::mt19937_64 engine_;
  Rng rng_;
  int width_ = 0, height_ = 0;
  std::vector<double> camera_azimuths_;  // eye_to_hand
  double target_azimuth_ = 0.0;          // eye_in_hand
  SyntheticScene scene_;
};

}  // namespace

bool SceneOptions::Check(std::string* why) const {
  auto fail = [why](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (!FindPreset(cell))
    return fail("cell '" + cell + "' is unknown; expected small, medium, large or metric-medium");
  if (num_cameras < 1 || num_cameras > 64) return fail("between 1 and 64 cameras");
  if (num_poses < 1 || num_poses > 100000) return fail("between 1 and 100000 poses");
  if ((width == 0) != (height == 0))
    return fail("both image width and height, or neither (the preset's 1920×1080)");
  if (width != 0 && (width < 32 || height < 32 || width > 20000 || height > 20000))
    return fail("an image size between 32 and 20000 pixels per side");
  if (!std::isfinite(pose_noise_mm) || pose_noise_mm < 0)
    return fail("a finite, non-negative robot translation noise (mm)");
  if (!std::isfinite(pose_noise_deg) || pose_noise_deg < 0)
    return fail("a finite, non-negative robot rotation noise (deg)");
  if (!given_poses.empty() && static_cast<int>(given_poses.size()) != num_poses)
    return fail("as many poses as the given list holds");
  if (swap_poses < 0 || 2 * swap_poses > num_poses)
    return fail("between 0 and half as many swapped pose pairs as poses");
  const int smaller_side = width != 0 ? std::min(width, height) : 1080;
  if (!std::isfinite(border_margin_px) || border_margin_px < 0 ||
      border_margin_px >= smaller_side / 4.0)
    return fail("a border margin of at least 0 and under a quarter of the image's smaller side");
  return true;
}

SyntheticScene MakeScene(const SceneOptions& options, std::shared_ptr<const Target> target) {
  if (!target) throw std::invalid_argument("MakeScene: null target");
  std::string why;
  if (!options.Check(&why)) throw std::invalid_argument("MakeScene: bad options: " + why);
  return SceneBuilder(options, std::move(target)).Build();
}

}  // namespace handeye
