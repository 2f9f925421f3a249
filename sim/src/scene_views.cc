// SPDX-License-Identifier: GPL-2.0-or-later
// What a camera of a simulated cell sees of the target: visibility of each
// point, the lens checks, the true chain, and observations from the truth.
#include "scene_views.h"

#include <algorithm>
#include <array>

#include "handeye/core/setup_frames.h"
#include "handeye/sim/synthetic.h"

namespace handeye {
namespace sim_detail {

// A print seen more obliquely than this is a sliver no detector finds; an
// operator would not count such a view.
constexpr double kMaxViewAngle = Deg(70.0);

// ---- Small geometry helpers ---------------------------------------------------

const Eigen::Vector3d kUp(0.0, 0.0, 1.0);

/// A rotation whose z axis is `forward` and whose x axis is horizontal (for a
/// camera: image rows level, y pointing down).
Eigen::Matrix3d LookRotation(const Eigen::Vector3d& forward) {
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d x = z.cross(kUp);
  if (x.norm() < 1e-9) x = z.unitOrthogonal();
  x.normalize();
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  return R;
}

Eigen::Vector3d Horizontal(double azimuth) {
  return {std::cos(azimuth), std::sin(azimuth), 0.0};
}

/// Centre of the printed sheet in the target frame.
Eigen::Vector3d SheetCentre(const Target& target) {
  const Eigen::Vector2d c = target.Extent().center();
  return {c.x(), c.y(), 0.0};
}

// ---- Visibility ----------------------------------------------------------------

/// Whether one target point is seen: in front of the camera, on the printed
/// face's side (face normal is the target's −z), not too oblique, and
/// projected at least `margin_px` inside the image. The last test also asks
/// that the pixel's ray is the point's ray, because a distortion polynomial
/// can fold points far outside the field of view back into the image.
bool PointVisible(const Camera& camera, const Eigen::Isometry3d& T_cam_target,
                  const Eigen::Vector3d& p_target, double margin_px, Eigen::Vector2d* uv) {
  const Eigen::Vector3d p_cam = T_cam_target * p_target;
  if (!(p_cam.z() > 0.0)) return false;
  const Eigen::Vector3d face_normal_cam = -T_cam_target.linear().col(2);
  if (face_normal_cam.dot(-p_cam.normalized()) < std::cos(kMaxViewAngle)) return false;
  const auto px = camera.Project(p_cam);
  if (!px || !camera.InImage(*px, margin_px)) return false;
  const auto ray = camera.Undistort(*px);
  const Eigen::Vector2d expected(p_cam.x() / p_cam.z(), p_cam.y() / p_cam.z());
  if (!ray || (*ray - expected).norm() > 1e-6) return false;
  *uv = *px;
  return true;
}

/// The one rule for when a view counts: a checkerboard detector needs every
/// corner; targets with coded points (charuco, aprilgrid) work from partial
/// views, and four points fix a pose.
bool ViewCounts(const Target& target, std::size_t visible_points) {
  if (target.Type() == "checkerboard") return visible_points == target.Points().size();
  return visible_points >= 4;
}

/// The true pixels of the target's visible points, or nullopt when the view
/// does not count.
std::optional<Observation> SeeTarget(const Camera& camera, const Target& target,
                                     const Eigen::Isometry3d& T_cam_target, double margin_px) {
  Observation obs;
  obs.camera = camera.name;
  Eigen::Vector2d uv;
  for (const TargetPoint& point : target.Points()) {
    if (!PointVisible(camera, T_cam_target, point.p_target, margin_px, &uv)) continue;
    obs.ids.push_back(point.id);
    obs.points_px.push_back(uv);
  }
  if (!ViewCounts(target, obs.ids.size())) return std::nullopt;
  return obs;
}

Eigen::Isometry3d TargetInCamera(Setup setup, const Eigen::Isometry3d& T_cam, const Eigen::Isometry3d& T_target,
                                 const Eigen::Isometry3d& T_base_ee) {
  // T_cam is T_mount_cam, T_target T_holder_target.
  return T_cam.inverse() * FramesOf(setup).MountFromHolder(T_base_ee) * T_target;
}

// ---- Lens distortion --------------------------------------------------------

/// True when the lens model is one-to-one over the whole image: the image
/// corners undistort and project back, and the radial factor keeps growing
/// a little beyond the corners' field angle (so nothing folds over).
bool DistortionUsable(const Camera& camera) {
  double max_radius = 0.0;
  const double w = camera.width - 0.5, h = camera.height - 0.5;
  const std::array<Eigen::Vector2d, 4> corners = {Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(w, -0.5),
                                                  Eigen::Vector2d(-0.5, h), Eigen::Vector2d(w, h)};
  for (const Eigen::Vector2d& corner : corners) {
    const auto ray = camera.Undistort(corner);
    if (!ray) return false;
    const auto back = camera.Project(Eigen::Vector3d(ray->x(), ray->y(), 1.0));
    if (!back || (*back - corner).norm() > 1e-6) return false;
    max_radius = std::max(max_radius, ray->norm());
  }
  const double k1 = camera.params[4], k2 = camera.params[5], k3 = camera.params[8];
  for (double r = 0.0; r <= 1.25 * max_radius; r += 0.01) {
    const double r2 = r * r;
    // d/dr of r (1 + k1 r² + k2 r⁴ + k3 r⁶).
    if (1.0 + 3.0 * k1 * r2 + 5.0 * k2 * r2 * r2 + 7.0 * k3 * r2 * r2 * r2 < 0.2) return false;
  }
  return true;
}

}  // namespace sim_detail

using namespace sim_detail;

Eigen::Isometry3d TrueCameraFromTarget(const SyntheticScene& scene, int camera, int pose_index) {
  const std::string& name = scene.dataset.cameras.at(camera).name;
  return TargetInCamera(scene.truth.setup, scene.truth.T_cam.at(name), scene.truth.T_target,
                        scene.truth.poses.at(pose_index).T_base_ee_true);
}

void AddProjectedObservations(SyntheticScene* scene, double noise_px, std::mt19937_64* rng) {
  Rng noise(rng);
  scene->dataset.observations.clear();
  for (const GroundTruth::PoseTruth& pose : scene->truth.poses) {
    // Dataset camera order, so a seed gives the same noise whatever the names.
    for (const Camera& camera : scene->dataset.cameras) {
      const auto it = pose.points_px.find(camera.name);
      if (it == pose.points_px.end()) continue;
      Observation obs = it->second;
      obs.pose_id = pose.id;
      obs.camera = camera.name;
      if (noise_px > 0)
        for (Eigen::Vector2d& uv : obs.points_px) uv += Eigen::Vector2d(noise.Normal(noise_px),
                                                                        noise.Normal(noise_px));
      scene->dataset.observations.push_back(std::move(obs));
    }
  }
}

}  // namespace handeye
