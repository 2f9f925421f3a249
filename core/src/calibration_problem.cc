// SPDX-License-Identifier: GPL-2.0-or-later
// Preparing the solver's views: PnP per view, its consistency check, and the
// geometric helpers every method shares.
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <set>
#include <sstream>

#include "diagnostics_internal.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "handeye/core/transform.h"
#include "motion_diversity.h"
#include "pose_consensus.h"
#include "problem.h"

namespace handeye::internal {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d FromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  return MakeTransformFromRotationVector(
      Eigen::Vector3d(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2)),
      Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
}

double PnpRms(const Camera& camera, const View& view, const Eigen::Isometry3d& T_cam_target,
              std::vector<double>* errors = nullptr) {
  double sum = 0;
  for (size_t i = 0; i < view.p_target.size(); ++i) {
    const auto uv = camera.Project(T_cam_target * view.p_target[i]);
    const double e = uv ? (*uv - view.observation->points_px[i]).norm() : 1e6;
    if (errors) errors->push_back(e);
    sum += e * e;
  }
  return std::sqrt(sum / view.p_target.size());
}

// Target pose in the camera from a planar point set: IPPE on all points, then
// Levenberg–Marquardt; when that does not fit, RANSAC finds the points that do.
void SolvePnpAnySide(const Camera& camera, double max_rms_px, View* view) {
  const size_t n = view->p_target.size();
  if (n < 4) {
    view->used = false;
    view->rejected_because = "fewer than 4 points";
    return;
  }
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (size_t i = 0; i < n; ++i) {
    object.emplace_back(view->p_target[i].x(), view->p_target[i].y(), view->p_target[i].z());
    image.emplace_back(view->observation->points_px[i].x(), view->observation->points_px[i].y());
  }
  const cv::Matx33d K(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
  const std::vector<double> dist = camera.Distortion();
  cv::Mat rvec, tvec;
  bool ok = false;
  try {
    ok = cv::solvePnP(object, image, K, dist, rvec, tvec, false, cv::SOLVEPNP_IPPE);
    if (ok) cv::solvePnPRefineLM(object, image, K, dist, rvec, tvec);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (ok) {
    const Eigen::Isometry3d T = FromRvecTvec(rvec, tvec);
    const double rms = PnpRms(camera, *view, T);
    if (rms <= max_rms_px) {
      view->T_cam_target = T;
      view->pnp_rms_px = rms;
      return;
    }
  }
  // Some corners do not fit: keep the view when a clear majority does.
  std::vector<int> inliers;
  try {
    ok = cv::solvePnPRansac(object, image, K, dist, rvec, tvec, false, 200, float(max_rms_px),
                            0.999, inliers, cv::SOLVEPNP_EPNP);
  } catch (const cv::Exception&) {
    ok = false;
  }
  const size_t needed = std::max<size_t>(4, static_cast<size_t>(std::ceil(0.8 * n)));
  if (ok && inliers.size() >= needed) {
    std::vector<cv::Point3d> object_in;
    std::vector<cv::Point2d> image_in;
    for (int i : inliers) {
      object_in.push_back(object[i]);
      image_in.push_back(image[i]);
    }
    cv::solvePnPRefineLM(object_in, image_in, K, dist, rvec, tvec);
    view->T_cam_target = FromRvecTvec(rvec, tvec);
    view->pnp_rms_px = PnpRms(camera, *view, *view->T_cam_target);
    return;
  }
  view->used = false;
  std::ostringstream why;
  why << "the detected points fit no plane pose (PnP: " << (ok ? inliers.size() : 0) << " of " << n
      << " points within " << max_rms_px << " px)";
  view->rejected_because = why.str();
}

// The printed face is seen from the target's -z side. A pose that puts the
// camera on the +z side explains points whose ids are mirrored: a see-through
// (glass) target seen from behind, whose pattern the detector read reversed.
bool SeenFromBehind(const Eigen::Isometry3d& T_cam_target) {
  return T_cam_target.inverse().translation().z() > 0;
}

constexpr double kMaxViewAngle = kMaxViewAngleDeg * kDeg;

void SolvePnp(const Camera& camera, double max_rms_px, View* view) {
  SolvePnpAnySide(camera, max_rms_px, view);
  if (view->T_cam_target && SeenFromBehind(*view->T_cam_target)) {
    // No pose of the target fits the view as it was read.
    view->T_cam_target.reset();
    view->used = false;
    view->rejected_because =
        "the target is seen from behind: its points are mirrored (a see-through target seen "
        "from its back?)";
  }
  if (view->T_cam_target) {
    const double angle = ViewAngle(*view->T_cam_target, view->p_target);
    if (angle > kMaxViewAngle) {
      view->T_cam_target.reset();
      view->used = false;
      view->oblique_deg = angle / kDeg;
      std::ostringstream why;
      why.precision(0);
      why << std::fixed << "the target is seen " << view->oblique_deg
          << " deg from face-on (more than " << kMaxViewAngleDeg
          << "): its corners are too squeezed to give a good pose";
      view->rejected_because = why.str();
    }
  }
}

// The robot motions between the views of each camera, together.
RobotMotions CollectMotions(const Problem& problem, const std::vector<int>& cameras) {
  RobotMotions motions;
  for (int k : cameras) {
    RobotMotions camera = CollectRobotMotions(problem, problem.camera_views[k]);
    motions.axes.insert(motions.axes.end(), camera.axes.begin(), camera.axes.end());
    motions.largest_deg = std::max(motions.largest_deg, camera.largest_deg);
  }
  return motions;
}

}  // namespace

double ViewAngle(const Eigen::Isometry3d& T_cam_target,
                 const std::vector<Eigen::Vector3d>& p_target) {
  Eigen::Vector3d middle = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : p_target) middle += p;
  const Eigen::Vector3d ray =
      (T_cam_target * (middle / static_cast<double>(p_target.size()))).normalized();
  return std::acos(std::min(1.0, std::abs(ray.dot(T_cam_target.linear().col(2)))));
}

Problem BuildProblem(const Dataset& dataset, const CalibrationOptions& options) {
  if (!dataset.target) throw InputError("", "/target", "a target");
  Problem problem;
  problem.dataset = &dataset;
  const SetupFrames frames = FramesOf(dataset.setup);
  for (const auto& pose : dataset.poses)
    problem.T_mount_holder.push_back(frames.MountFromHolder(pose.T_base_ee));
  problem.camera_views.resize(dataset.cameras.size());
  std::set<std::pair<int, int>> seen;
  for (const auto& obs : dataset.observations) {
    View view;
    view.camera = dataset.CameraIndex(obs.camera);
    view.pose = dataset.PoseIndex(obs.pose_id);
    if (view.camera < 0)
      throw InputError("", "/observations",
                       "an observation names unknown camera '" + obs.camera + "'");
    if (view.pose < 0)
      throw InputError("", "/observations",
                       "an observation names unknown pose '" + obs.pose_id + "'");
    if (!seen.insert({view.pose, view.camera}).second)
      throw InputError("", "/observations",
                       "one observation per pose and camera; pose '" + obs.pose_id + "', camera '" +
                           obs.camera + "' has two");
    if (obs.ids.size() != obs.points_px.size())
      throw InputError("", "/observations", "as many points_px as ids");
    view.observation = &obs;
    for (int id : obs.ids) {
      const TargetPoint* p = dataset.target->FindPoint(id);
      if (!p) throw InputError("", "/observations", "ids of the target; got " + std::to_string(id));
      view.p_target.push_back(p->p_target);
    }
    SolvePnp(dataset.cameras[view.camera], options.pnp_max_rms_px, &view);
    problem.views.push_back(std::move(view));
  }
  IndexUsedViews(&problem);
  return problem;
}

void RecomputePnp(Problem* problem, double max_rms_px) {
  for (View& view : problem->views) {
    if (!view.used) continue;
    View fresh = view;
    SolvePnp(problem->dataset->cameras[view.camera], max_rms_px, &fresh);
    // A view the refined intrinsics no longer fit on its own keeps its old pose.
    if (fresh.used && fresh.T_cam_target) {
      view.T_cam_target = fresh.T_cam_target;
      view.pnp_rms_px = fresh.pnp_rms_px;
    }
  }
}

std::string MotionDiversityProblem(const Problem& problem, const std::vector<int>& cameras) {
  const RobotMotions motions = CollectMotions(problem, cameras);
  std::ostringstream why;
  if (motions.axes.empty()) {
    why << "degenerate robot motion: the views differ in rotation by at most "
        << motions.largest_deg
        << " deg; add poses that tilt the target by 15-30 deg about at least two different axes in "
           "view of the cameras";
    return why.str();
  }
  // Two axes count as non-parallel above 5 degrees apart.
  const double min_sin = std::sin(5.0 * kDeg);
  for (const auto& a : motions.axes)
    for (const auto& b : motions.axes)
      if (a.cross(b).norm() > min_sin) return "";
  why << "degenerate robot motion: every motion between the views rotates about the same axis; add "
         "poses that rotate the target about a second, different axis (e.g. tilt it forward and "
         "sideways) in view of the cameras";
  return why.str();
}

void CheckMotionDiversity(const Problem& problem, const std::vector<int>& cameras) {
  std::vector<int> all = cameras;
  if (all.empty())
    for (size_t k = 0; k < problem.camera_views.size(); ++k) all.push_back(static_cast<int>(k));
  const std::string why = MotionDiversityProblem(problem, all);
  if (!why.empty()) throw SolveError(why);
}

Eigen::Isometry3d MeanTransform(const std::vector<Eigen::Isometry3d>& transforms) {
  Eigen::Matrix3d R_sum = Eigen::Matrix3d::Zero();
  Eigen::Vector3d t_sum = Eigen::Vector3d::Zero();
  for (const auto& T : transforms) {
    R_sum += T.rotation();
    t_sum += T.translation();
  }
  Eigen::Isometry3d mean = Eigen::Isometry3d::Identity();
  mean.linear() = Orthonormalise(R_sum);
  mean.translation() = t_sum / static_cast<double>(transforms.size());
  return mean;
}

namespace {

/// The mean of the estimates that lie near their medoid (the estimate with the
/// least summed distance to the others; 1 rad counts as 1 m): one view whose
/// robot record belongs to another pose cannot drag the start off.
Eigen::Isometry3d ConsensusTransform(const std::vector<Eigen::Isometry3d>& estimates) {
  const size_t n = estimates.size();
  if (n <= 2) return MeanTransform(estimates);
  auto distance = [](const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return (a.translation() - b.translation()).norm() +
           RotationDistance(a.rotation(), b.rotation());
  };
  // With many views, the medoid among a spread-out subset is as good.
  const size_t step = std::max<size_t>(1, n / 64);
  size_t medoid = 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; i += step) {
    double sum = 0;
    for (size_t j = 0; j < n; j += step) sum += distance(estimates[i], estimates[j]);
    if (sum < best) {
      best = sum;
      medoid = i;
    }
  }
  std::vector<double> distances;
  for (const auto& T : estimates) distances.push_back(distance(T, estimates[medoid]));
  std::vector<double> sorted = distances;
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  const double limit = std::max(3.0 * sorted[n / 2], 1e-6);
  std::vector<Eigen::Isometry3d> near;
  for (size_t i = 0; i < n; ++i)
    if (distances[i] <= limit) near.push_back(estimates[i]);
  return MeanTransform(near);
}

}  // namespace

std::optional<Eigen::Isometry3d> CameraGivenTarget(const Problem& problem, int camera,
                                                   const Eigen::Isometry3d& T_holder_target) {
  std::vector<Eigen::Isometry3d> estimates;
  for (int v : problem.camera_views[camera]) {
    const View& view = problem.views[v];
    estimates.push_back(*view.T_cam_target * T_holder_target.inverse() *
                        problem.T_mount_holder[view.pose].inverse());
  }
  if (estimates.empty()) return std::nullopt;
  return ConsensusTransform(estimates);
}

std::optional<Eigen::Isometry3d> TargetGivenCamera(const Problem& problem, int camera,
                                                   const Eigen::Isometry3d& T_cam_mount) {
  std::vector<Eigen::Isometry3d> estimates;
  for (int v : problem.camera_views[camera]) {
    const View& view = problem.views[v];
    estimates.push_back(problem.T_mount_holder[view.pose].inverse() * T_cam_mount.inverse() *
                        *view.T_cam_target);
  }
  if (estimates.empty()) return std::nullopt;
  return ConsensusTransform(estimates);
}

}  // namespace handeye::internal
