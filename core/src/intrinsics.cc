// SPDX-License-Identifier: GPL-2.0-or-later
// Intrinsics the hand-eye views determine: which to refine, which the views
// cannot determine, an estimate for a camera given none, and the check of
// given intrinsics after a solve.
#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>
#include <ceres/solver.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <sstream>

#include "chain_problem.h"
#include "cost_functions.h"
#include "cost_jacobians.h"
#include "covariance.h"
#include "detection_noise.h"
#include "handeye/core/error.h"
#include "handeye/core/setup_frames.h"
#include "intrinsics_internal.h"
#include "pose_manifold.h"
#include "problem.h"
#include "robot_error.h"

namespace handeye::internal {
namespace {

constexpr int kN = OpenCVCameraModel::kNumParams;
using Intrinsics = std::array<double, kN>;

/// The prior of refined intrinsics: 1σ of each parameter moves an image
/// corner by this many pixels (focal length ≈ 2 %, principal point 20 px, k1
/// ≈ 0.03 on a 1920×1080 image with a 70° lens): loose enough for the errors
/// of factory intrinsics, firm enough to keep what the views cannot tell.
constexpr double kPriorCornerPx = 20.0;

/// Normalised coordinates of the image's four corners (through the inverse
/// distortion where it converges, else the pinhole).
std::vector<Eigen::Vector2d> CornerRays(const Camera& camera) {
  std::vector<Eigen::Vector2d> rays;
  for (double u : {0.0, camera.width - 1.0})
    for (double v : {0.0, camera.height - 1.0}) {
      const auto xy = camera.Undistort({u, v});
      rays.push_back(
          xy ? *xy
             : Eigen::Vector2d((u - camera.cx()) / camera.fx(), (v - camera.cy()) / camera.fy()));
    }
  return rays;
}

}  // namespace

std::vector<int> FreeIntrinsics(const Camera& camera, unsigned groups) {
  std::vector<int> free;
  if (groups & kFocal) free.insert(free.end(), {0, 1});
  if (groups & kPrincipalPoint) free.insert(free.end(), {2, 3});
  if (groups & kDistortion) {
    free.insert(free.end(), {4, 5, 6, 7});
    // Higher-order terms only where the given model uses them; never the tilt
    // (its derivative at zero tilt is not modelled).
    for (int p = 8; p < 16; ++p)
      if (camera.params[p] != 0.0) free.push_back(p);
  }
  return free;
}

namespace {

/// Largest pixel shift at an image corner per unit of each parameter.
Intrinsics CornerEffect(const Camera& camera) {
  Intrinsics effect{};
  for (const Eigen::Vector2d& xy : CornerRays(camera)) {
    const double p_cam[3] = {xy.x(), xy.y(), 1.0};
    double residual[2];
    Eigen::Matrix<double, 2, 3> d_p;
    cost_internal::IntrinsicsJacobian d_k;
    if (!cost_internal::ProjectPointWithIntrinsicsJacobian(
            camera.params.data(), p_cam, Eigen::Vector2d::Zero(), 0.0, residual, &d_p, &d_k))
      continue;
    for (int p = 0; p < kN; ++p) effect[p] = std::max(effect[p], d_k.col(p).norm());
  }
  return effect;
}

/// (K[free] − given[free]) / σ_prior · σ_pixel per free parameter: a Gaussian
/// prior in the units of the pixel residuals.
class IntrinsicsPriorCost : public ceres::CostFunction {
 public:
  IntrinsicsPriorCost(const Intrinsics& given, std::vector<int> free, std::vector<double> weight)
      : given_(given), free_(std::move(free)), weight_(std::move(weight)) {
    set_num_residuals(static_cast<int>(free_.size()));
    mutable_parameter_block_sizes()->push_back(kN);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    for (size_t i = 0; i < free_.size(); ++i)
      residuals[i] = weight_[i] * (parameters[0][free_[i]] - given_[free_[i]]);
    if (jacobians && jacobians[0]) {
      std::fill(jacobians[0], jacobians[0] + free_.size() * kN, 0.0);
      for (size_t i = 0; i < free_.size(); ++i) jacobians[0][i * kN + free_[i]] = weight_[i];
    }
    return true;
  }

 private:
  Intrinsics given_;
  std::vector<int> free_;
  std::vector<double> weight_;
};

/// How far (mm) the camera centre of the T_cam_mount block `T` moves for the
/// tangent step `step` of its pose manifold.
double MovedMm(const double* T, const Eigen::Matrix<double, 6, 1>& step) {
  PoseParams moved;
  PoseManifold().Plus(T, step.data(), moved.data());
  return 1000.0 * (FromPoseParams(T).inverse().translation() -
                   FromPoseParams(moved.data()).inverse().translation())
                      .norm();
}

}  // namespace

Intrinsics IntrinsicsPriorSigma(const Camera& camera) {
  const Intrinsics effect = CornerEffect(camera);
  Intrinsics sigma{};
  for (int p = 0; p < kN; ++p) sigma[p] = effect[p] > 0 ? kPriorCornerPx / effect[p] : 0.0;
  return sigma;
}

ceres::CostFunction* IntrinsicsPrior(const Camera& given, const std::vector<int>& free,
                                     double pixel_sigma_px) {
  const Intrinsics sigma = IntrinsicsPriorSigma(given);
  std::vector<double> weight;
  for (int p : free) weight.push_back(sigma[p] > 0 ? pixel_sigma_px / sigma[p] : 0.0);
  return new IntrinsicsPriorCost(given.params, free, std::move(weight));
}

UncertainIntrinsics UncertainGivenIntrinsics(const Camera& camera, const std::vector<int>& free,
                                             const GivenIntrinsicsSigma& sigma) {
  auto is_free = [&](int p) { return std::find(free.begin(), free.end(), p) != free.end(); };
  UncertainIntrinsics out;
  const double focal = 0.01 * sigma.focal_percent;
  // push_back, not insert of a list: GCC 12 at -O3 warned of an overflow
  // (-Wstringop-overflow, a false positive) on the inlined insert.
  auto add = [&](int p, int q) {
    out.params.push_back(p);
    out.params.push_back(q);
  };
  if (focal > 0 && !is_free(0) && !is_free(1)) add(0, 1);
  if (sigma.principal_point_px > 0 && !is_free(2) && !is_free(3)) add(2, 3);
  const int n = static_cast<int>(out.params.size());
  out.covariance = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int p = out.params[i], q = out.params[j];
      if (p < 2 && q < 2)
        out.covariance(i, j) = focal * focal * camera.params[p] * camera.params[q];
      else if (p == q)
        out.covariance(i, j) = sigma.principal_point_px * sigma.principal_point_px;
    }
  return out;
}

ceres::CostFunction* UncertainIntrinsicsPrior(const Camera& camera,
                                              const UncertainIntrinsics& uncertain,
                                              double pixel_sigma_px) {
  std::vector<double> weight;
  for (size_t i = 0; i < uncertain.params.size(); ++i)
    weight.push_back(pixel_sigma_px / std::sqrt(uncertain.covariance(i, i)));
  return new IntrinsicsPriorCost(camera.params, uncertain.params, std::move(weight));
}

Eigen::MatrixXd UncertainIntrinsicsPriorInformation(const UncertainIntrinsics& uncertain,
                                                    double pixel_sigma_px) {
  // The weights of UncertainIntrinsicsPrior, squared.
  return (pixel_sigma_px * pixel_sigma_px * uncertain.covariance.diagonal().cwiseInverse())
      .asDiagonal();
}

std::vector<int> IntrinsicsUnknowns(const std::vector<int>& free,
                                    const UncertainIntrinsics& uncertain,
                                    std::vector<int>* uncertain_tangent) {
  std::vector<int> unknowns = free;
  unknowns.insert(unknowns.end(), uncertain.params.begin(), uncertain.params.end());
  std::sort(unknowns.begin(), unknowns.end());
  unknowns.erase(std::unique(unknowns.begin(), unknowns.end()), unknowns.end());
  uncertain_tangent->clear();
  for (int p : uncertain.params)
    uncertain_tangent->push_back(
        static_cast<int>(std::lower_bound(unknowns.begin(), unknowns.end(), p) - unknowns.begin()));
  return unknowns;
}

std::vector<int> UndeterminedIntrinsics(const Camera& given, const Intrinsics& sigma,
                                        const std::vector<int>& free) {
  const Intrinsics prior = IntrinsicsPriorSigma(given);
  std::vector<int> undetermined;
  for (int p : free)
    if (!(sigma[p] <= 0.5 * prior[p])) undetermined.push_back(p);
  return undetermined;
}

EstimatedIntrinsics EstimateIntrinsics(const Dataset& dataset, int k) {
  const Camera& camera = dataset.cameras[k];
  std::vector<const Observation*> views;
  for (const Observation& obs : dataset.observations)
    if (obs.camera == camera.name && obs.ids.size() >= 6) views.push_back(&obs);
  const std::string advice =
      "; take at least 10 views with the target tilted by 20° or more in different directions and "
      "covering the image, or give the camera's intrinsics in the dataset";
  if (views.size() < 3)
    throw SolveError("camera '" + camera.name + "' has no intrinsics and " +
                     std::to_string(views.size()) +
                     " views of the target: too few to estimate them" + advice);
  // OpenCV's calibration grows with the views; 40 spread over the capture are plenty for a start.
  constexpr size_t kMaxViews = 40;
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  const size_t step = (views.size() + kMaxViews - 1) / kMaxViews;
  for (size_t i = 0; i < views.size(); i += step) {
    std::vector<cv::Point3f> o;
    std::vector<cv::Point2f> im;
    for (size_t p = 0; p < views[i]->ids.size(); ++p) {
      const TargetPoint* point = dataset.target->FindPoint(views[i]->ids[p]);
      if (!point) continue;
      o.emplace_back(point->p_target.x(), point->p_target.y(), point->p_target.z());
      im.emplace_back(views[i]->points_px[p].x(), views[i]->points_px[p].y());
    }
    object.push_back(o);
    image.push_back(im);
  }
  cv::Mat K, dist, std_intrinsics, std_extrinsics, per_view;
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    // Zhang's closed form from the views' homographies, then Levenberg–Marquardt
    // over fx, fy, cx, cy, k1, k2, p1, p2 (k3 held at 0: few views cannot tell it).
    cv::calibrateCamera(object, image, cv::Size(camera.width, camera.height), K, dist, rvecs, tvecs,
                        std_intrinsics, std_extrinsics, per_view, cv::CALIB_FIX_K3);
  } catch (const cv::Exception& e) {
    throw SolveError("camera '" + camera.name +
                     "' has no intrinsics and its views do not determine them (" + e.err + ")" +
                     advice);
  }
  const double fx = K.at<double>(0, 0), fy = K.at<double>(1, 1), cx = K.at<double>(0, 2),
               cy = K.at<double>(1, 2);
  const double s_fx = std_intrinsics.at<double>(0), s_fy = std_intrinsics.at<double>(1);
  const double s_cx = std_intrinsics.at<double>(2), s_cy = std_intrinsics.at<double>(3);
  // Their σ as a share of the focal length or the image side: within
  // kViewsAloneShare the views alone determine them; within kStartShare they
  // are still a start the joint solve (the robot's motions: views at known
  // distances apart fix the focal length that similar tilts trade against
  // depth) can refine, which RefinedIntrinsicsStage then checks; beyond, a
  // local solve from them is not to be trusted.
  constexpr double kViewsAloneShare = 0.05, kStartShare = 0.15;
  double share = 0;  // NaN where a σ is (std::max would drop it)
  for (double part : {s_fx / fx, s_fy / fy, s_cx / camera.width, s_cy / camera.height})
    share = std::isnan(part) ? part : std::max(share, part);
  std::ostringstream seen;
  seen.precision(3);
  seen << "fx " << fx << " ± " << s_fx << ", cx " << cx << " ± " << s_cx << ", cy " << cy << " ± "
       << s_cy << " px";
  if (!(fx > 0 && fy > 0 && std::isfinite(share) && share < kStartShare))
    throw SolveError("camera '" + camera.name + "' has no intrinsics and its " +
                     std::to_string(views.size()) + " views are too alike to estimate them (" +
                     seen.str() + ")" + advice);
  std::vector<double> coeffs(5, 0.0);
  for (int i = 0; i < 5 && i < static_cast<int>(dist.total()); ++i) coeffs[i] = dist.at<double>(i);
  std::string why;
  auto estimated =
      Camera::Make(camera.name, camera.width, camera.height, fx, fy, cx, cy, coeffs, &why);
  if (!estimated)
    throw SolveError("camera '" + camera.name +
                     "': the intrinsics estimated from its views: " + why);
  EstimatedIntrinsics out{*estimated, {}};
  if (share >= kViewsAloneShare) out.weakly = seen.str();
  return out;
}

namespace {

/// What one camera's views say of its fx, fy, cx, cy: the chain solved
/// with them free (and, with the robot's error modelled, a block per pose
/// under its prior, as in the joint solve: a pose's error moves all points of
/// its view together, which the per-point residuals alone would count as
/// independent evidence: σ too small, false alarms).
struct SeenIntrinsics {
  std::array<double, 4> K{}, sigma{};                 // fx, fy, cx, cy and their 1σ
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> C_KK;  // their tangent covariance
  Eigen::Matrix<double, 6, 4, Eigen::RowMajor> C_xK;  // with the camera pose tangent
  PoseParams T_cam_mount{};                           // the camera as they place it
};

/// A view whose residuals in its camera's own fit (SeeIntrinsics) are more
/// than this many times the median view's has a noise of its own. Views of
/// one camera differ by up to about 3x among themselves (distance, tilt, the
/// robot's error at that pose; rendered AprilGrid cells: 0.022-0.091 px about
/// a median of 0.037); weighed from 2x, a quarter of one such cell's poses
/// had a true principal point called off at 3.5σ.
constexpr double kViewNoiseApart = 4.0;

/// Each view block's residual RMS per image axis at the problem's values.
std::vector<double> ViewRmsPx(const ceres::Problem& problem,
                              const std::vector<ceres::ResidualBlockId>& blocks) {
  std::vector<double> rms;
  for (const ceres::ResidualBlockId block : blocks) {
    double cost = 0;
    std::vector<double> residuals(problem.GetCostFunctionForResidualBlock(block)->num_residuals());
    problem.EvaluateResidualBlock(block, false, &cost, residuals.data(), nullptr);
    rms.push_back(std::sqrt(2.0 * cost / static_cast<double>(residuals.size())));
  }
  return rms;
}

std::optional<SeenIntrinsics> SeeIntrinsics(const Problem& problem, size_t k,
                                            const Eigen::Isometry3d& T_cam_mount,
                                            const Eigen::Isometry3d& T_holder_target,
                                            double cauchy_scale_px,
                                            const std::optional<RobotPrior>& robot) {
  const Dataset& dataset = *problem.dataset;
  const Camera& camera = dataset.cameras[k];
  const std::vector<int>& views = problem.camera_views[k];
  ChainProblem chain(2 + views.size(), 1);
  ceres::Problem& ceres_problem = chain.problem();
  double* T_cam_mount_k = chain.AddPose(T_cam_mount);
  double* T_holder_target_k = chain.AddPose(T_holder_target);
  static const std::vector<int> kFocalAndCentre = {0, 1, 2, 3};  // fx, fy, cx, cy
  double* K = chain.AddIntrinsics(camera.params, kFocalAndCentre);
  std::vector<double*> T_mount_holder(views.size(), nullptr);  // the robot pose blocks
  if (robot)
    for (size_t i = 0; i < views.size(); ++i) {
      const int pose = problem.views[views[i]].pose;
      T_mount_holder[i] = chain.AddRobotPose(problem.T_mount_holder[pose], dataset.poses[pose],
                                             dataset.setup, *robot);
    }
  // View i's block, its squared residuals weighed by `weight`.
  auto add_view = [&](size_t i, double weight) {
    const View& view = problem.views[views[i]];
    auto points =
        std::make_shared<const ViewPoints>(ViewPoints{view.p_target, view.observation->points_px});
    ceres::LossFunction* loss =
        weight == 1.0 ? nullptr : new ceres::ScaledLoss(nullptr, weight, ceres::TAKE_OWNERSHIP);
    if (robot)
      return ceres_problem.AddResidualBlock(
          ViewReprojectionWithRobotError::Create(camera, std::move(points), cauchy_scale_px, true),
          loss, {T_cam_mount_k, T_mount_holder[i], T_holder_target_k, K});
    return ceres_problem.AddResidualBlock(
        ViewReprojectionError::Create(camera, problem.T_mount_holder[view.pose], std::move(points),
                                      cauchy_scale_px, true),
        loss, T_cam_mount_k, T_holder_target_k, K);
  };
  std::vector<ceres::ResidualBlockId> view_blocks;
  for (size_t i = 0; i < views.size(); ++i) view_blocks.push_back(add_view(i, 1.0));
  ceres::Solver::Options solver;
  solver.linear_solver_type = robot ? ceres::SPARSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  solver.max_num_iterations = 50;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &ceres_problem, &summary);
  if (summary.termination_type == ceres::FAILURE) return std::nullopt;
  // A view of a noise of its own is weighed by it (one step of Förstner's
  // variance components, that view a group of its own, the others pooled),
  // then the fit solved again. With its own fx, fy, cx, cy and target
  // transform a camera's views fit to their detection noise; one that fits
  // several times worse (a target partly hidden or blurred: its corners off
  // together, which its PnP pose takes up and the chain does not) would
  // pull the intrinsics as hard as the good ones. bench/leave-out's rendered
  // ChArUco cell (robot 0.5 mm, seed 4): two partial views of one camera at
  // 0.14-0.15 px among its others' 0.013-0.025 px, which the motion vote
  // left out of the whole capture but kept in 10 of 32 quarters left out,
  // each then warned that cx was 8-13 px off at 3-4σ (the given values are
  // the true ones).
  const std::vector<double> rms = ViewRmsPx(ceres_problem, view_blocks);
  const double typical = MedianSigmaPx(rms);
  bool reweighed = false;
  for (size_t i = 0; i < views.size(); ++i)
    if (rms[i] > kViewNoiseApart * typical) {
      ceres_problem.RemoveResidualBlock(view_blocks[i]);
      view_blocks[i] = add_view(i, (typical * typical) / (rms[i] * rms[i]));
      reweighed = true;
    }
  if (reweighed) {
    ceres::Solve(solver, &ceres_problem, &summary);
    if (summary.termination_type == ceres::FAILURE) return std::nullopt;
  }
  const BlockCovariance covariance(&ceres_problem, {{K, K}, {T_cam_mount_k, K}},
                                   robot ? ceres::SPARSE_QR : ceres::DENSE_SVD);
  if (!covariance.ok()) return std::nullopt;
  const Eigen::MatrixXd C = covariance.Ambient(K, K);
  const double variance_factor = VarianceFactor(&ceres_problem, view_blocks);
  SeenIntrinsics seen;
  for (int p = 0; p < 4; ++p) {
    seen.K[p] = K[p];
    seen.sigma[p] = std::sqrt(std::max(0.0, C(p, p)) * variance_factor);
  }
  seen.C_KK = covariance.Tangent(K, K);
  seen.C_xK = covariance.Tangent(T_cam_mount_k, K);
  std::copy(T_cam_mount_k, T_cam_mount_k + seen.T_cam_mount.size(), seen.T_cam_mount.begin());
  return seen;
}

/// The warning for a camera whose views find its given focal length
/// (`focal_off`) or principal point (`centre_off`) off by `delta` (seen −
/// given); `moved`: where the given values put the camera against the views'.
std::string IntrinsicsOffText(const Camera& camera, const SeenIntrinsics& seen,
                              const std::array<double, 4>& delta, bool focal_off, bool centre_off,
                              const Eigen::Matrix<double, 6, 1>& moved) {
  const std::array<double, 4>& K = seen.K;
  const std::array<double, 4>& sigma = seen.sigma;
  std::ostringstream w;
  w << std::fixed;
  w.precision(1);
  w << "camera '" << camera.name << "': the images suggest ";
  std::vector<std::string> groups;
  if (focal_off) {
    const double percent =
        100.0 * std::max(std::abs(delta[0]) / camera.fx(), std::abs(delta[1]) / camera.fy());
    w << "fx, fy ≈ " << K[0] << ", " << K[1] << " (± " << std::max(sigma[0], sigma[1]) << " px), "
      << percent << " % from the given values";
    groups.push_back("focal");
  }
  if (centre_off) {
    if (focal_off) w << ", and ";
    w.precision(2);
    w << "cx, cy ≈ " << K[2] << ", " << K[3] << " (± " << std::max(sigma[2], sigma[3]) << " px), "
      << std::hypot(delta[2], delta[3]) << " px from the given values";
    if (std::abs(delta[2] + 1.0) < 0.35 && std::abs(delta[3] + 1.0) < 0.35)
      w << "; a 1-based principal point?";
    groups.push_back("principal_point");
  }
  const std::string text = w.str();
  if (text.back() != '?') w << ";";
  w << " rerun with --refine-intrinsics " << groups[0] << (groups.size() > 1 ? "," + groups[1] : "")
    << " (the given values move the camera by ≈ " << std::setprecision(2)
    << MovedMm(seen.T_cam_mount.data(), moved) << " mm, which its sigma includes)";
  return w.str();
}

}  // namespace

std::vector<Warning> IntrinsicsWarnings(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target, double cauchy_scale_px, const std::vector<unsigned>& check,
    const std::optional<RobotPrior>& robot, std::map<size_t, IntrinsicsOff>* found) {
  const Dataset& dataset = *problem.dataset;
  std::vector<Warning> warnings;
  for (size_t k = 0; k < dataset.cameras.size(); ++k) {
    if (k >= check.size() || !check[k] || !T_cam_mount[k] || problem.camera_views[k].size() < 3)
      continue;
    const Camera& camera = dataset.cameras[k];
    const std::optional<SeenIntrinsics> seen =
        SeeIntrinsics(problem, k, *T_cam_mount[k], T_holder_target[k], cauchy_scale_px, robot);
    if (!seen) continue;
    std::array<double, 4> delta;
    for (int p = 0; p < 4; ++p) delta[p] = seen->K[p] - camera.params[p];
    auto off = [&](int p, double visible) {
      return std::abs(delta[p]) > std::max(3.0 * seen->sigma[p], visible);
    };
    const bool focal_off =
        (check[k] & kFocal) && (off(0, 0.003 * camera.fx()) || off(1, 0.003 * camera.fy()));
    const bool centre_off = (check[k] & kPrincipalPoint) && (off(2, 0.5) || off(3, 0.5));
    if (!focal_off && !centre_off) continue;
    // Where the given values of the groups found off put the camera, against
    // the views' own: the conditional mean C_xK C_KK⁻¹ ΔK over fx, fy, cx, cy
    // (the subset manifold's tangent), the other group's ΔK 0.
    Eigen::Vector4d given_minus_seen = Eigen::Vector4d::Zero();
    for (int p = 0; p < 4; ++p)
      if ((p < 2 && focal_off) || (p >= 2 && centre_off)) given_minus_seen[p] = -delta[p];
    const Eigen::Matrix<double, 6, 1> moved =
        seen->C_xK * seen->C_KK.ldlt().solve(given_minus_seen);
    if (found) (*found)[k] = {moved, -given_minus_seen};
    warnings.push_back(
        CameraWarning(WarningKind::kIntrinsicsOff, camera.name,
                      IntrinsicsOffText(camera, *seen, delta, focal_off, centre_off, moved)));
  }
  return warnings;
}

}  // namespace handeye::internal
