// SPDX-License-Identifier: GPL-2.0-or-later
// handeye check: each camera's pose from new views, the target transform held.
#include "handeye/core/drift.h"

#include <ceres/crs_matrix.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>
#include <ceres/solver.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "chain_problem.h"
#include "cost_functions.h"
#include "covariance.h"
#include "diagnostics_internal.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "pose_uncertainty.h"
#include "problem.h"
#include "residuals.h"
#include "robot_error.h"

namespace handeye {

bool DriftOptions::Check(std::string* why) const {
  auto fail = [why](const char* reason) {
    if (why) *why = reason;
    return false;
  };
  if (!(tolerance_mm > 0) || !std::isfinite(tolerance_mm)) return fail("tolerance_mm must be > 0");
  if (!(tolerance_deg > 0) || !std::isfinite(tolerance_deg))
    return fail("tolerance_deg must be > 0");
  if (min_views < 1) return fail("min_views must be >= 1");
  if (threads < 1) return fail("threads must be >= 1");
  return true;
}

bool DriftResult::AnyMoved() const {
  for (const CameraDrift& camera : cameras)
    if (camera.verdict == "moved") return true;
  return false;
}

bool DriftResult::AnyNotAssessed() const {
  for (const CameraDrift& camera : cameras)
    if (camera.verdict == "not_assessed") return true;
  return false;
}

namespace {

/// The fewest degrees of freedom RobotSigmaDof gives: with fewer poses than
/// unknowns the σ is SettleRobotSigma's at its widest, and known to no better
/// than Student's t with 3 (3σ becomes 9.2σ).
constexpr double kMinRobotSigmaDof = 3;

/// The robot's pose error (σ mm, deg) new poses carry: the one the cameras'
/// sigma assumes (the solved pose blocks'; results written before it, the
/// prior the solve weighed with) or, where the exact poses were chosen over a
/// model (solver.model), the last model compared (the solved poses' σ where
/// it was a candidate). The misfit per pose is in the new views whichever
/// predicted left-out poses better: on rendered ChArUco cells with robot error
/// where the exact robot was chosen, unmoved cameras were called moved in 2 of
/// 8 checks without it. The prior, wide on purpose, made unmoved cameras move
/// 0.72 / 0.69 of the check's σ (mm, deg, RMS over 494 checks of
/// bench/leave-out's rendered captures).
std::pair<double, double> RobotSigmaOf(const SolverSummary& solver) {
  if (solver.robot_sigma_solved_mm > 0)
    return {solver.robot_sigma_solved_mm, solver.robot_sigma_solved_deg};
  if (solver.robot_sigma_mm > 0) return {solver.robot_sigma_mm, solver.robot_sigma_deg};
  if (solver.model)
    for (auto c = solver.model->candidates.rbegin(); c != solver.model->candidates.rend(); ++c)
      if (c->robot_sigma_mm > 0) return {c->robot_sigma_mm, c->robot_sigma_deg};
  return {0.0, 0.0};
}

/// The degrees of freedom the robot's σ that `check` carries (RobotSigmaOf)
/// was estimated from: 3 per axis group of each record SettleRobotSigma's
/// count keeps (RobotRecordsKept over the poses the calibration used);
/// infinite where the σ was given, or is none.
double RobotSigmaDof(const CalibrationResult& calibration) {
  if (RobotSigmaOf(calibration.solver).first <= 0 || calibration.options.robot_sigma_mm >= 0)
    return std::numeric_limits<double>::infinity();
  std::set<std::string> poses;
  for (const ViewResult& view : calibration.views)
    if (view.used) poses.insert(view.pose_id);
  int cameras = 0;
  size_t free_intrinsics = 0;
  for (const CameraResult& cam : calibration.cameras) {
    if (!cam.calibrated) continue;
    ++cameras;
    if (cam.intrinsics) free_intrinsics += cam.intrinsics->refined.size();
  }
  return std::max(
      3.0 * internal::RobotRecordsKept(static_cast<int>(poses.size()), cameras, free_intrinsics),
      kMinRobotSigmaDof);
}

/// How many σ a difference must exceed to be as unlikely from noise alone
/// as beyond `sigmas` of a normal, where σ was estimated from `dof` degrees
/// of freedom (Student's t).
double StudentThreshold(double sigmas, double dof) {
  if (!std::isfinite(dof)) return sigmas;
  return internal::StudentUpperQuantile(0.5 * std::erfc(sigmas / std::sqrt(2.0)), dof);
}

/// How far a move must go, in σ of the check's noise, to be called moved
/// (a normal's 3σ) or to hint at a move (2σ), for a calibration whose robot
/// σ was estimated from `dof` degrees of freedom (RobotSigmaDof): the same
/// for every camera of a check.
struct NoiseThresholds {
  double dof = std::numeric_limits<double>::infinity();
  double moved = 3.0, hint = 2.0;
};

NoiseThresholds NoiseThresholdsOf(const CalibrationResult& calibration) {
  NoiseThresholds t;
  t.dof = RobotSigmaDof(calibration);
  t.moved = StudentThreshold(3.0, t.dof);
  t.hint = StudentThreshold(2.0, t.dof);
  return t;
}

/// How the least-squares estimate of T_cam_mount (tangent) moves with the
/// held T_holder_target (tangent): −(H⁻¹ H_xT) in T_cam_mount's rows, H = JᵀJ
/// of `problem` at its solution over every free block x and the target.
/// nullopt where the Jacobian cannot be read or H_xx is singular.
std::optional<Eigen::Matrix<double, 6, 6>> TargetSensitivity(ceres::Problem* problem,
                                                             double* T_cam_mount,
                                                             double* T_holder_target) {
  std::vector<double*> blocks;
  problem->GetParameterBlocks(&blocks);
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = {T_cam_mount};
  for (double* block : blocks)
    if (block != T_cam_mount && block != T_holder_target &&
        !problem->IsParameterBlockConstant(block))
      evaluate.parameter_blocks.push_back(block);
  evaluate.parameter_blocks.push_back(T_holder_target);
  problem->SetParameterBlockVariable(T_holder_target);
  ceres::CRSMatrix jacobian;
  const bool evaluated = problem->Evaluate(evaluate, nullptr, nullptr, nullptr, &jacobian);
  problem->SetParameterBlockConstant(T_holder_target);
  if (!evaluated) return std::nullopt;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(jacobian.num_rows, jacobian.num_cols);
  for (int row = 0; row < jacobian.num_rows; ++row)
    for (int i = jacobian.rows[row]; i < jacobian.rows[row + 1]; ++i)
      J(row, jacobian.cols[i]) = jacobian.values[i];
  const Eigen::MatrixXd H = J.transpose() * J;
  const int free = jacobian.num_cols - 6;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(H.topLeftCorner(free, free));
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return std::nullopt;
  return Eigen::Matrix<double, 6, 6>(-ldlt.solve(H.topRightCorner(free, 6)).topRows(6));
}

/// The covariance (PoseUncertainty's coordinates) of the new estimate `now`
/// less the calibrated camera: the new views' noise, and the calibration's
/// error as far as the target held at its calibrated value does not carry
/// it into the new estimate too. With δT the target's error and A how the
/// new estimate follows it, the difference holds A δT − δc:
/// A Σ_T Aᵀ + Σ_c − A Σ_Tc − Σ_cT Aᵀ, each without what the given intrinsics
/// add (the new views go through the same intrinsics, and their error moves
/// both alike). Results without the camera's covariance with the target:
/// the two apart, Σ_c as if independent.
Eigen::Matrix<double, 6, 6> DifferenceCovariance(
    const PoseUncertainty& now, const CameraResult& cam, const CalibrationResult& calibration,
    const std::optional<Eigen::Matrix<double, 6, 6>>& A) {
  if (!cam.sigma) return now.covariance;
  const Eigen::Matrix<double, 6, 6> own = cam.sigma->covariance - cam.sigma->from_given_intrinsics;
  if (!A || !cam.sigma->covariance_with_target || !calibration.target_sigma)
    return now.covariance + own;
  const Eigen::Matrix<double, 6, 6> target =
      calibration.target_sigma->covariance - calibration.target_sigma->from_given_intrinsics;
  const Eigen::Matrix<double, 6, 6>& with_target = *cam.sigma->covariance_with_target;
  return now.covariance + *A * target * A->transpose() + own - *A * with_target.transpose() -
         with_target * A->transpose();
}

/// The camera's pose from its new views alone (`views` of `problem`),
/// started at the calibrated one, how far it moved and the noise of that
/// difference (DifferenceCovariance). Where the
/// calibration saw the robot's pose error, each new pose is a block of the
/// solve too, under its σ (RobotSigmaOf): an error a view's points share
/// moves the camera found through it, and taken as independent per corner it
/// was in no σ (on rendered cells with robot error, unmoved cameras had moved
/// 3.4 times the check's σ; bench/leave-out).
void EstimateAgain(const internal::Problem& problem, int k, const std::vector<int>& views,
                   const CameraResult& cam, const CalibrationResult& calibration, int threads,
                   CameraDrift* drift_out) {
  const Dataset& dataset = *problem.dataset;
  CameraDrift& drift = *drift_out;
  const auto [robot_mm, robot_deg] = RobotSigmaOf(calibration.solver);
  const bool robot_error = robot_mm > 0;
  const internal::RobotPrior robot{robot_mm / 1000.0, robot_deg * M_PI / 180.0,
                                   internal::DetectionSigmaPx(problem)};
  internal::ChainProblem chain(2 + (robot_error ? views.size() : 0), 0);
  ceres::Problem& ceres_problem = chain.problem();
  double* T_cam_mount = chain.AddPose(cam.T_cam.inverse());
  double* T_holder_target = chain.AddPose(calibration.T_target, true);
  const double scale = std::max(1.0, 3.0 * robot.pixel_sigma_px);
  std::vector<ceres::ResidualBlockId> blocks;
  for (int v : views) {
    const internal::View& view = problem.views[v];
    auto points =
        std::make_shared<const ViewPoints>(ViewPoints{view.p_target, view.observation->points_px});
    if (robot_error) {
      double* T_mount_holder = chain.AddRobotPose(problem.T_mount_holder[view.pose],
                                                  dataset.poses[view.pose], dataset.setup, robot);
      blocks.push_back(ceres_problem.AddResidualBlock(
          ViewReprojectionWithRobotError::Create(dataset.cameras[k], std::move(points), scale),
          nullptr, T_cam_mount, T_mount_holder, T_holder_target));
    } else {
      blocks.push_back(ceres_problem.AddResidualBlock(
          ViewReprojectionError::Create(dataset.cameras[k], problem.T_mount_holder[view.pose],
                                        std::move(points), scale),
          nullptr, T_cam_mount, T_holder_target));
    }
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = 100;
  solver.num_threads = threads;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &ceres_problem, &summary);
  const Eigen::Isometry3d T_cam_mount_now = internal::ChainProblem::Pose(T_cam_mount);
  drift.T_cam = T_cam_mount_now.inverse();
  drift.estimated = true;
  const internal::PoseDifference moved = internal::DifferenceOf(drift.T_cam, cam.T_cam);
  drift.moved_mm = moved.translation_mm;
  drift.moved_deg = moved.rotation_deg;
  const internal::BlockCovariance covariance(&ceres_problem, {{T_cam_mount, T_cam_mount}},
                                             ceres::DENSE_SVD);
  if (covariance.ok()) {
    const Eigen::Matrix<double, 6, 6> C = covariance.Tangent(T_cam_mount, T_cam_mount);
    const double variance_factor = internal::VarianceFactor(&ceres_problem, blocks);
    const PoseUncertainty u = internal::UncertaintyOf(T_cam_mount_now, C * variance_factor, true);
    // A in PoseUncertainty's coordinates of the camera and of the target.
    std::optional<Eigen::Matrix<double, 6, 6>> A =
        TargetSensitivity(&ceres_problem, T_cam_mount, T_holder_target);
    if (A)
      A = internal::UncertaintyJacobian(T_cam_mount_now, true) * *A *
          internal::UncertaintyJacobian(calibration.T_target, false).inverse();
    const Eigen::Matrix<double, 6, 6> difference = DifferenceCovariance(u, cam, calibration, A);
    drift.sigma_mm = std::sqrt(std::max(0.0, difference.topLeftCorner<3, 3>().trace()));
    drift.sigma_deg = std::sqrt(std::max(0.0, difference.bottomRightCorner<3, 3>().trace()));
  }
}

/// The verdict on a re-estimated camera, and the warning when it cannot tell.
void Judge(const DriftOptions& options, const NoiseThresholds& thresholds, const CameraResult& cam,
           CameraDrift* drift_out, std::vector<Warning>* warnings) {
  CameraDrift& drift = *drift_out;
  // Moved: beyond the tolerance, and by more than the two estimates' noise
  // (3σ, or as unlikely where the robot's σ is estimated from few poses),
  // so that a few noisy views do not call a camera moved.
  const auto beyond_sigmas = [&](double sigmas) {
    return drift.moved_mm > sigmas * drift.sigma_mm || drift.moved_deg > sigmas * drift.sigma_deg;
  };
  const bool beyond =
      drift.moved_mm > options.tolerance_mm || drift.moved_deg > options.tolerance_deg;
  const bool significant = beyond_sigmas(thresholds.moved);
  // Beyond a tolerance but within the noise: the check cannot tell either way.
  drift.verdict = beyond && significant ? "moved" : beyond ? "not_assessed" : "ok";
  // Within 2σ (or its like) the difference is what the noise alone gives: no
  // hint of a move, only a check too coarse for the tolerance (below).
  const bool hint = beyond_sigmas(thresholds.hint);
  std::ostringstream w;
  w.precision(3);
  if (beyond && !significant && hint) {
    w << "seems " << drift.moved_mm << " mm / " << drift.moved_deg
      << " deg from its calibrated pose, within ";
    if (std::isfinite(thresholds.dof))
      w << std::setprecision(2) << std::fixed << thresholds.moved << std::defaultfloat
        << std::setprecision(3)
        << "σ of the noise of the check (as unlikely as 3σ where the robot's σ is estimated from "
        << thresholds.dof << " degrees of freedom; ";
    else
      w << "3σ of the noise of the check (";
    w << "± " << drift.sigma_mm << " mm / ± " << drift.sigma_deg << " deg)";
    drift.reason = w.str();
    warnings->push_back(CameraWarning(
        WarningKind::kDriftWithinNoise, cam.name,
        "camera '" + cam.name + "' " + drift.reason +
            ": not called moved; take more poses with the target in its view to tell"));
  } else if (beyond && !significant) {
    w << "the new views know it to ± " << drift.sigma_mm << " mm / ± " << drift.sigma_deg
      << " deg, too coarse to tell a move of " << options.tolerance_mm << " mm / "
      << options.tolerance_deg << " deg (what they found is within 2σ of that noise)";
    drift.reason = w.str();
    warnings->push_back(
        CameraWarning(WarningKind::kDriftTooCoarse, cam.name,
                      "camera '" + cam.name + "': " + drift.reason +
                          ": not assessed; take more poses with the target in its view"));
  } else if (drift.sigma_mm > 0.5 * options.tolerance_mm ||
             drift.sigma_deg > 0.5 * options.tolerance_deg) {
    w << "camera '" << cam.name << "': its " << drift.views << " new views know it to ± "
      << drift.sigma_mm << " mm / ± " << drift.sigma_deg << " deg, too coarse for the tolerance ("
      << options.tolerance_mm << " mm, " << options.tolerance_deg
      << " deg): take more poses with the target in its view";
    warnings->push_back(CameraWarning(WarningKind::kDriftTooCoarse, cam.name, w.str()));
  }
}

}  // namespace

DriftResult CheckDrift(const Dataset& input, const CalibrationResult& calibration,
                       const DriftOptions& options) {
  std::string why;
  if (!options.Check(&why)) throw InputError("", "", "invalid check options: " + why);
  if (input.setup != calibration.setup)
    throw InputError("", "/setup",
                     std::string("the result's setup, ") + SetupName(calibration.setup) +
                         "; the dataset is " + SetupName(input.setup));
  Dataset dataset = input;
  for (const CameraResult& cam : calibration.cameras) {
    const int k = dataset.CameraIndex(cam.name);
    if (k < 0)
      throw InputError("", "/cameras", "a camera named '" + cam.name + "' (the result has one)");
    if (cam.intrinsics) {
      dataset.cameras[k].params = cam.intrinsics->camera.params;
      dataset.cameras[k].num_distortion = cam.intrinsics->camera.num_distortion;
      dataset.cameras[k].has_intrinsics = true;
    }
  }
  CalibrationOptions calibration_options;
  internal::Problem problem = internal::BuildProblem(dataset, calibration_options);
  DriftResult out;
  const NoiseThresholds thresholds = NoiseThresholdsOf(calibration);
  for (const CameraResult& cam : calibration.cameras) {
    CameraDrift drift;
    drift.name = cam.name;
    const int k = dataset.CameraIndex(cam.name);
    const auto& views = problem.camera_views[k];
    drift.views = static_cast<int>(views.size());
    if (!cam.calibrated || drift.views < options.min_views) {
      drift.verdict = "not_assessed";
      drift.reason = !cam.calibrated ? std::string("not calibrated in the result")
                     : drift.views == 0
                         ? std::string("not seen: no new view of the target")
                         : "only " + std::to_string(drift.views) + " usable new view" +
                               (drift.views == 1 ? "" : "s") + ", at least " +
                               std::to_string(options.min_views) + " needed";
      out.warnings.push_back(
          CameraWarning(WarningKind::kDriftNotChecked, cam.name,
                        "camera '" + cam.name + "': " + drift.reason + ": not checked"));
      out.cameras.push_back(drift);
      continue;
    }
    EstimateAgain(problem, k, views, cam, calibration, options.threads, &drift);
    Judge(options, thresholds, cam, &drift, &out.warnings);
    out.cameras.push_back(drift);
  }
  return out;
}

}  // namespace handeye
