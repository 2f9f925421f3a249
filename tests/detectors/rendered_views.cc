// SPDX-License-Identifier: GPL-2.0-or-later
#include "detectors/rendered_views.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace handeye::test {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

Eigen::Isometry3d RandomView(const Camera& camera, const Target& target,
                             const ViewSampling& sampling, std::mt19937_64* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Feature size in the image log-uniform in the range; face-on distance for it.
  const double px = sampling.min_feature_px *
                    std::pow(sampling.max_feature_px / sampling.min_feature_px, unit(*rng));
  const double distance = camera.fx() * sampling.feature_m / px;
  // Face-on: target z along camera z (the printed face is seen from -z),
  // turned about its normal, then tilted about a random in-plane axis.
  const double spin = 2 * kPi * unit(*rng);
  const double tilt = sampling.max_tilt_deg * kPi / 180.0 * std::sqrt(unit(*rng));
  const double axis_angle = 2 * kPi * unit(*rng);
  const Eigen::Vector3d axis(std::cos(axis_angle), std::sin(axis_angle), 0.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(tilt, axis) * Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  // The sheet's centre on the ray through a random pixel.
  const double beyond = sampling.centre_beyond_border;
  const double u = (-beyond + (1 + 2 * beyond) * unit(*rng)) * camera.width;
  const double v = (-beyond + (1 + 2 * beyond) * unit(*rng)) * camera.height;
  const Eigen::Vector3d ray((u - camera.cx()) / camera.fx(), (v - camera.cy()) / camera.fy(), 1.0);
  const Eigen::Vector2d centre2 = target.Extent().center();
  const Eigen::Vector3d centre(centre2.x(), centre2.y(), 0.0);
  T.translation() = distance * ray - T.linear() * centre;
  return T;
}

Eigen::Isometry3d ViewAt(const Camera& camera, const Target& target, double u, double v,
                         double distance_m, double spin_rad, double tilt_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(tilt_rad, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(spin_rad, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  const Eigen::Vector3d ray((u - camera.cx()) / camera.fx(), (v - camera.cy()) / camera.fy(), 1.0);
  const Eigen::Vector2d centre = target.Extent().center();
  T.translation() = distance_m * ray - T.linear() * Eigen::Vector3d(centre.x(), centre.y(), 0.0);
  return T;
}

IdentifyingCorners CharucoMarkers(const CharucoTarget& board) {
  return [&board](int id) {
    std::vector<Eigen::Vector3d> corners;
    for (int marker : board.MarkersAtCorner(id))
      for (const auto& p : board.MarkerCorners(marker)) corners.push_back(p);
    return corners;
  };
}

double Score::MeanError() const {
  if (errors_px.empty()) return 0.0;
  double sum = 0;
  for (double e : errors_px) sum += e;
  return sum / errors_px.size();
}

std::string Score::Summary() const {
  std::ostringstream out;
  out << "views " << views << " (detected " << views_detected << "), expected corners " << expected
      << ", found " << found << " (" << 100.0 * Rate() << " %), wrong ids " << wrong
      << ", mean error " << MeanError() << " px";
  return out.str();
}

void ScoreView(const Camera& camera, const Target& target, const Eigen::Isometry3d& T_cam_target,
               const IdentifyingCorners& identifying, const std::optional<Detection>& detection,
               double min_feature_px, double border_px, double wrong_px, int min_points,
               Score* score) {
  ++score->views;
  std::map<int, Eigen::Vector2d> reported;
  if (detection) {
    ++score->views_detected;
    for (std::size_t i = 0; i < detection->ids.size(); ++i)
      reported[detection->ids[i]] = detection->points_px[i];
  }
  auto project = [&](const Eigen::Vector3d& p, Eigen::Vector2d* uv) {
    const auto px = camera.Project(T_cam_target * p);
    if (!px) return false;
    *uv = *px;
    return true;
  };
  int expected = 0, found = 0;
  for (const TargetPoint& point : target.Points()) {
    Eigen::Vector2d truth;
    const bool projects = project(point.p_target, &truth);
    const auto it = reported.find(point.id);
    if (it != reported.end()) {
      if (!projects || (it->second - truth).norm() > wrong_px) {
        ++score->wrong;
        continue;
      }
    }
    // Expected when the point and its fiducials (groups of four corners) are
    // well inside the image and each fiducial is large enough.
    bool visible = projects && camera.InImage(truth, border_px);
    const std::vector<Eigen::Vector3d> corners = identifying(point.id);
    for (std::size_t q = 0; visible && q + 4 <= corners.size(); q += 4) {
      Eigen::Vector2d uv[4];
      for (int k = 0; k < 4 && visible; ++k)
        visible = project(corners[q + k], &uv[k]) && camera.InImage(uv[k], border_px);
      // Size: the smallest side or width across (area ÷ side), so that a
      // strongly sheared fiducial counts by its narrow dimension.
      double area = 0;
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d& a = uv[k];
        const Eigen::Vector2d& b = uv[(k + 1) % 4];
        area += 0.5 * (a.x() * b.y() - b.x() * a.y());
      }
      for (int k = 0; k < 4 && visible; ++k) {
        const double side = (uv[(k + 1) % 4] - uv[k]).norm();
        visible = side >= min_feature_px && std::abs(area) / side >= min_feature_px;
      }
    }
    if (it != reported.end()) score->errors_px.push_back((it->second - truth).norm());
    if (!visible) continue;
    ++expected;
    if (it != reported.end()) ++found;
  }
  if (expected >= min_points) {
    score->expected += expected;
    score->found += found;
  }
}

Score RenderAndScore(const Camera& camera, const Target& target, const Detector& detector,
                     const IdentifyingCorners& identifying, const ViewSampling& sampling,
                     const RenderOptions& render, int count, std::uint64_t seed, double border_px,
                     double wrong_px, int min_points) {
  std::mt19937_64 rng(seed);
  Score score;
  for (int k = 0; k < count; ++k) {
    const Eigen::Isometry3d T_cam_target = RandomView(camera, target, sampling, &rng);
    RenderOptions options = render;
    options.seed = seed * 1000 + k;
    const cv::Mat image = RenderView(camera, target, T_cam_target, options);
    ScoreView(camera, target, T_cam_target, identifying, detector.Detect(image),
              sampling.expected_feature_px, border_px, wrong_px, min_points, &score);
  }
  return score;
}

Camera PinholeCamera(int width, int height, double fx) {
  std::string why;
  return *Camera::Make("cam", width, height, fx, fx, (width - 1) / 2.0, (height - 1) / 2.0, {},
                       &why);
}

}  // namespace handeye::test
