// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// What the simulated cells (synthetic.cc) are made of: platform-independent
// random numbers, and what a camera sees of a target (visibility, lens
// checks, the chain of true poses). Internal to handeye::sim.

#include <Eigen/Geometry>
#include <cmath>
#include <cstddef>
#include <optional>
#include <random>

#include "handeye/core/camera.h"
#include "handeye/core/dataset.h"
#include "handeye/core/target.h"

namespace handeye::sim_detail {

constexpr double kPi = 3.14159265358979323846;
constexpr double Deg(double degrees) { return degrees * kPi / 180.0; }

// libstdc++ and libc++ implement the <random> distributions differently;
// deriving values from the engine's raw bits keeps a seed's scene the same on
// every platform.
class Rng {
 public:
  explicit Rng(std::mt19937_64* engine) : engine_(engine) {}
  /// Uniform in [0, 1), 53 random bits.
  double Unit() { return static_cast<double>((*engine_)() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Unit(); }
  /// Zero-mean Gaussian (Box–Muller; one of the pair is dropped for simplicity).
  double Normal(double sigma) {
    const double u1 = 1.0 - Unit();  // (0, 1], so the log is finite
    const double u2 = Unit();
    return sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
  }
  /// Uniform on the unit sphere.
  Eigen::Vector3d Direction() {
    const double z = Uniform(-1.0, 1.0), a = Uniform(0.0, 2.0 * kPi);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(a), r * std::sin(a), z};
  }
  /// A unit vector perpendicular to the unit vector v, uniform in angle.
  Eigen::Vector3d Perpendicular(const Eigen::Vector3d& v) {
    Eigen::Vector3d a = v.unitOrthogonal();
    const Eigen::Vector3d b = v.cross(a).normalized();
    const double angle = Uniform(0.0, 2.0 * kPi);
    return std::cos(angle) * a + std::sin(angle) * b;
  }
  /// v turned by `angle` radians in a random direction.
  Eigen::Vector3d Turn(const Eigen::Vector3d& v, double angle) {
    return Eigen::AngleAxisd(angle, Perpendicular(v.normalized())) * v;
  }

 private:
  std::mt19937_64* engine_;
};

/// Straight up in the base frame (z).
extern const Eigen::Vector3d kUp;

/// A rotation whose z axis is `forward` and whose x axis is horizontal (for a
/// camera: image rows level, y pointing down).
Eigen::Matrix3d LookRotation(const Eigen::Vector3d& forward);
/// The horizontal unit vector at `azimuth` radians from x.
Eigen::Vector3d Horizontal(double azimuth);
/// Centre of the printed sheet in the target frame.
Eigen::Vector3d SheetCentre(const Target& target);

/// Whether one target point is seen, and where (see scene_views.cc).
bool PointVisible(const Camera& camera, const Eigen::Isometry3d& T_cam_target,
                  const Eigen::Vector3d& p_target, double margin_px, Eigen::Vector2d* uv);
/// The one rule for when a view counts: a checkerboard detector needs every
/// corner; targets with coded points (charuco, aprilgrid) work from partial
/// views, and four points fix a pose.
bool ViewCounts(const Target& target, std::size_t visible_points);
/// The true pixels of the target's visible points, or nullopt when the view
/// does not count.
std::optional<Observation> SeeTarget(const Camera& camera, const Target& target,
                                     const Eigen::Isometry3d& T_cam_target, double margin_px);
/// T_cam_target from the setup's unknowns: T_cam (T_base_cam or T_ee_cam),
/// T_target (T_ee_target or T_base_target) and the robot pose.
Eigen::Isometry3d TargetInCamera(Setup setup, const Eigen::Isometry3d& T_cam, const Eigen::Isometry3d& T_target,
                                 const Eigen::Isometry3d& T_base_ee);
/// True when the lens model is one-to-one over the whole image.
bool DistortionUsable(const Camera& camera);

}  // namespace handeye::sim_detail
