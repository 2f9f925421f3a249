// SPDX-License-Identifier: GPL-2.0-or-later
// handeye check: each camera's pose from new views, the target transform held.
#include "handeye/core/drift.h"

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/product_manifold.h>
#include <ceres/solver.h>

#include <algorithm>
#include <cmath>
#include <sstream>

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

/// The robot's pose error (σ mm, deg) new poses carry: what the solve
/// modelled or, where the exact poses were chosen over the model the views
/// suggested (solver.model), that model's σ. The misfit per pose is in the
/// new views whichever of the two predicted left-out poses better: on
/// rendered ChArUco cells with robot error where the exact robot was chosen,
/// unmoved cameras were called moved in 2 of 8 checks without it.
std::pair<double, double> RobotSigmaOf(const SolverSummary& solver) {
  if (solver.robot_sigma_mm > 0) return {solver.robot_sigma_mm, solver.robot_sigma_deg};
  if (solver.model)
    for (const ModelCandidate& candidate : solver.model->candidates)
      if (candidate.robot_sigma_mm > 0) return {candidate.robot_sigma_mm, candidate.robot_sigma_deg};
  return {0.0, 0.0};
}

/// The camera's pose from its new views alone (`views` of `problem`),
/// started at the calibrated one, how far it moved and the noise of that
/// difference: the new estimate's σ and the calibration's own. Where the
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
    // The difference of two estimates: the new one and the calibration's
    // own, less what the given intrinsics' uncertainty adds to it: the new
    // views go through the same intrinsics, and their error moves both alike.
    const double calibrated_mm = cam.sigma ? cam.sigma->OwnPositionMm() : 0.0;
    const double calibrated_deg = cam.sigma ? cam.sigma->OwnRotationDeg() : 0.0;
    drift.sigma_mm = std::hypot(u.position_mm, calibrated_mm);
    drift.sigma_deg = std::hypot(u.rotation_deg, calibrated_deg);
  }
}

/// The verdict on a re-estimated camera, and the warning when it cannot tell.
void Judge(const DriftOptions& options, const CameraResult& cam, CameraDrift* drift_out,
           std::vector<Warning>* warnings) {
  CameraDrift& drift = *drift_out;
  // Moved: beyond the tolerance, and by more than the two estimates' noise
  // (3σ), so that a few noisy views do not call a camera moved.
  const bool beyond =
      drift.moved_mm > options.tolerance_mm || drift.moved_deg > options.tolerance_deg;
  const bool significant =
      drift.moved_mm > 3.0 * drift.sigma_mm || drift.moved_deg > 3.0 * drift.sigma_deg;
  // Beyond a tolerance but within the noise: the check cannot tell either way.
  drift.verdict = beyond && significant ? "moved" : beyond ? "not_assessed" : "ok";
  // Within 2σ the difference is what the noise alone gives: no hint of a
  // move, only a check too coarse for the tolerance (below).
  const bool hint =
      drift.moved_mm > 2.0 * drift.sigma_mm || drift.moved_deg > 2.0 * drift.sigma_deg;
  std::ostringstream w;
  w.precision(3);
  if (beyond && !significant && hint) {
    w << "seems " << drift.moved_mm << " mm / " << drift.moved_deg
      << " deg from its calibrated pose, within 3σ of the noise of the check (± " << drift.sigma_mm
      << " mm / ± " << drift.sigma_deg << " deg)";
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
    Judge(options, cam, &drift, &out.warnings);
    out.cameras.push_back(drift);
  }
  return out;
}

}  // namespace handeye
