// SPDX-License-Identifier: GPL-2.0-or-later
// Candidate robot poses for a capture plan (handeye/core/plan.h) and the
// views a camera would get at each: the whole target inside the image with a
// margin, seen from its printed side, not too obliquely, its squares large
// enough to detect.
#include <algorithm>
#include <cmath>

#include "handeye/core/setup_frames.h"
#include "plan_internal.h"
#include "problem.h"

namespace handeye::plan_internal {
namespace {

constexpr double kDeg = M_PI / 180.0;
/// Candidates turn the target (eye_to_hand) or the camera (eye_in_hand) up
/// to this far from facing a camera squarely: what varies the view angles.
constexpr double kMaxAimOffsetDeg = 40.0;
/// Tries per candidate to meet the tilt limits.
constexpr int kTiltTries = 8;

/// A rotation whose z axis is `forward` (unit), turned by `roll` about it.
Eigen::Matrix3d LookRotation(const Eigen::Vector3d& forward, double roll) {
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d helper =
      std::abs(z.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x = helper.cross(z).normalized();
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  return R * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

/// `direction` turned by a uniformly drawn angle up to `max_angle` about a random perpendicular
/// axis.
Eigen::Vector3d TurnedAtRandom(const Eigen::Vector3d& direction, double max_angle,
                               std::mt19937_64* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector3d axis(normal(*rng), normal(*rng), normal(*rng));
  axis = (axis - axis.dot(direction.normalized()) * direction.normalized()).normalized();
  return Eigen::AngleAxisd(max_angle * unit(*rng), axis) * direction;
}

Eigen::Vector3d SheetCentreOf(const Target& target) {
  const Eigen::Vector2d c = target.Extent().center();
  return Eigen::Vector3d(c.x(), c.y(), 0.0);
}

/// Where camera k sits in the base frame with the flange at `flange` (eye_in_hand: roughly,
/// unturned).
Eigen::Vector3d CameraPosition(const PlanCell& cell, int k, const Eigen::Vector3d& flange) {
  const Eigen::Vector3d t = cell.cameras[k].T_mount_cam.translation();
  return cell.setup == Setup::kEyeToHand ? t : flange;
}

/// A camera that shares views with camera k: the one whose direction from
/// `point` is closest to k's, when within 100 degrees; else k itself.
int Neighbour(const PlanCell& cell, int k, const Eigen::Vector3d& point) {
  const Eigen::Vector3d to_k = (CameraPosition(cell, k, point) - point).normalized();
  int best = k;
  double best_cos = std::cos(100.0 * kDeg);
  for (int t = 0; t < static_cast<int>(cell.cameras.size()); ++t) {
    if (t == k) continue;
    const double c = to_k.dot((CameraPosition(cell, t, point) - point).normalized());
    if (c > best_cos) {
      best_cos = c;
      best = t;
    }
  }
  return best;
}

/// One candidate with the flange at `flange`, turned towards camera k (and
/// perhaps a neighbour) with a random offset and roll.
Eigen::Isometry3d AimedPose(const PlanCell& cell, const Eigen::Vector3d& flange, int k,
                            std::mt19937_64* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double roll = 2.0 * M_PI * unit(*rng);
  Eigen::Isometry3d T_base_ee = Eigen::Isometry3d::Identity();
  T_base_ee.translation() = flange;
  if (cell.setup == Setup::kEyeToHand) {
    Eigen::Vector3d face = (CameraPosition(cell, k, flange) - flange).normalized();
    if (unit(*rng) < 0.5)
      face += (CameraPosition(cell, Neighbour(cell, k, flange), flange) - flange).normalized();
    face = TurnedAtRandom(face.normalized(), kMaxAimOffsetDeg * kDeg, rng);
    // The print faces the camera: the target's z axis points away from it.
    const Eigen::Matrix3d R_base_target = LookRotation(-face, roll);
    T_base_ee.linear() = R_base_target * cell.T_holder_target.linear().transpose();
  } else {
    const Eigen::Vector3d centre = cell.T_holder_target * SheetCentreOf(*cell.target);
    const Eigen::Vector3d forward =
        TurnedAtRandom((centre - flange).normalized(), 0.5 * kMaxAimOffsetDeg * kDeg, rng);
    const Eigen::Matrix3d R_base_cam = LookRotation(forward, roll);
    T_base_ee.linear() = R_base_cam * cell.cameras[k].T_mount_cam.linear().transpose();
  }
  return T_base_ee;
}

/// Whether camera k sees the whole target at T_base_ee (see the file comment).
bool Sees(const Model& model, int k, const Eigen::Isometry3d& T_base_ee) {
  const PlanCell& cell = *model.cell;
  const Camera& camera = cell.cameras[k].camera;
  const Eigen::Isometry3d T_cam_target = FromPoseParams(model.T_cam_mount[k].data()) *
                                         FramesOf(cell.setup).MountFromHolder(T_base_ee) *
                                         cell.T_holder_target;
  // The print is seen from the target's -z side (target.h).
  if (T_cam_target.inverse().translation().z() >= 0) return false;
  std::vector<Eigen::Vector3d> p_target;
  for (const TargetPoint& p : cell.target->Points()) p_target.push_back(p.p_target);
  const double angle = internal::ViewAngle(T_cam_target, p_target);
  if (angle > cell.constraints.max_view_angle_deg * kDeg) return false;
  const double margin = cell.constraints.margin_px + model.uncertainty_margin_px[k];
  double farthest = 0;
  for (const Eigen::Vector3d& p : p_target) {
    const Eigen::Vector3d p_cam = T_cam_target * p;
    if (p_cam.z() <= 0) return false;
    const auto uv = camera.Project(p_cam);
    if (!uv || !camera.InImage(*uv, margin)) return false;
    farthest = std::max(farthest, p_cam.z());
  }
  // The spacing of neighbouring points at the far end, foreshortened by the tilt.
  const double square_px =
      std::min(camera.fx(), camera.fy()) * model.point_spacing_m * std::cos(angle) / farthest;
  return square_px >= cell.constraints.min_square_px;
}

}  // namespace

std::vector<int> VisibleCameras(const Model& model, const Eigen::Isometry3d& T_base_ee) {
  std::vector<int> out;
  for (int k = 0; k < static_cast<int>(model.cell->cameras.size()); ++k)
    if (Sees(model, k, T_base_ee)) out.push_back(k);
  return out;
}

std::vector<Eigen::Isometry3d> DrawCandidates(const Model& model, int count, std::mt19937_64* rng) {
  const PlanCell& cell = *model.cell;
  std::vector<Eigen::Isometry3d> out;
  for (const Eigen::Isometry3d& T : cell.region.taught)
    if (InRegion(cell.region, T)) out.push_back(T);
  if (!cell.region.box || cell.cameras.empty()) return out;
  const Eigen::AlignedBox3d& box = *cell.region.box;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> camera(0, static_cast<int>(cell.cameras.size()) - 1);
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d flange =
        box.min() + Eigen::Vector3d(unit(*rng), unit(*rng), unit(*rng)).cwiseProduct(box.sizes());
    const int k = camera(*rng);
    for (int attempt = 0; attempt < kTiltTries; ++attempt) {
      const Eigen::Isometry3d T_base_ee = AimedPose(cell, flange, k, rng);
      if (!InRegion(cell.region, T_base_ee)) continue;
      out.push_back(T_base_ee);
      break;
    }
  }
  return out;
}

}  // namespace handeye::plan_internal

namespace handeye {

bool InRegion(const PlanRegion& region, const Eigen::Isometry3d& T_base_ee) {
  const double c =
      std::clamp(T_base_ee.linear().col(2).dot(region.tilt_axis.normalized()), -1.0, 1.0);
  if (region.max_tilt_rad < M_PI && std::acos(c) > region.max_tilt_rad + 1e-9) return false;
  if (!region.box) return true;
  // Taught poses are reachable by definition.
  for (const Eigen::Isometry3d& T : region.taught)
    if (T.isApprox(T_base_ee, 1e-12)) return true;
  return region.box->contains(T_base_ee.translation());
}

}  // namespace handeye
