// SPDX-License-Identifier: GPL-2.0-or-later
// What a robot pose tells the solve (handeye/core/plan.h): the Fisher
// information of its views through the solver's own cost functions, with the
// pose's robot error marginalised out, and the σ per camera it leads to.
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "cost_functions.h"
#include "handeye/core/setup_frames.h"
#include "intrinsics_internal.h"
#include "plan_internal.h"
#include "pose_manifold.h"
#include "pose_uncertainty.h"

namespace handeye::plan_internal {
namespace {

/// The intrinsics a solve refines: fx fy cx cy (`--refine-intrinsics
/// focal,principal_point`), and k1 k2 p1 p2 too where none are given (the
/// solve estimates them all: PrepareCameras, InitialiseJointStage).
constexpr int kRefinedIntrinsics = 4, kEstimatedIntrinsics = 8;
/// What a pose nobody has seen is known to: its σ in the forecast.
constexpr double kUnknownPositionM = 1.0, kUnknownRotationRad = 1.0;
using Tangent = Eigen::Matrix<double, 7, 6, Eigen::RowMajor>;
using DynamicRowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// d(block)/d(tangent) of a pose block at `params` (PoseManifold).
Tangent PlusJacobian(const PoseParams& params) {
  internal::PoseManifold manifold;
  Tangent J;
  manifold.PlusJacobian(params.data(), J.data());
  return J;
}

double Sq(double x) { return x * x; }

/// The median of |s|² for s ~ N(0, covariance): a weighted sum of χ²₁ whose
/// weights are the covariance's eigenvalues, taken as a scaled χ² of as many
/// degrees of freedom as matches its mean and variance (ν = (Σλ)² / Σλ²;
/// Satterthwaite), whose median is ν (1 − 2 / (9ν))³ (Wilson and Hilferty):
/// 0.47 of the mean for one direction (exactly 0.455), 0.79 for three alike.
double MedianSquaredNorm(const Eigen::Matrix3d& covariance) {
  const Eigen::Vector3d eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly)
          .eigenvalues()
          .cwiseMax(0.0);
  const double sum = eigenvalues.sum(), sum_sq = eigenvalues.squaredNorm();
  if (!(sum > 0)) return 0.0;
  const double nu = sum * sum / sum_sq;
  return sum * std::pow(1.0 - 2.0 / (9.0 * nu), 3);
}

double SmallestSpacing(const Target& target) {
  double best = std::numeric_limits<double>::infinity();
  const auto& points = target.Points();
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t j = i + 1; j < points.size(); ++j)
      best = std::min(best, (points[i].p_target - points[j].p_target).norm());
  return std::isfinite(best) ? best : 0.0;
}

/// Information known before any view: the intrinsics' prior the solve uses,
/// and the rough poses' ± (`use` kChoice), or for the forecast only what keeps
/// cameras without views finite: the solve has no prior on the poses, and
/// `advise` takes them and their ± from a solve of the recorded views, which
/// the forecast counts (with the ± it counted them twice: bench/plan_advise's
/// forecast for a camera of 4 views was 0.8 of the σ the solve then reported,
/// median of 6 seeds). The choice keeps the ±: without them the large cells'
/// planned captures were worse (bench/plan: 1.595 against 1.542 mm, mean of 6
/// seeds) and their solves' own σ further below the true error.
void AddPrior(const PlanCell& cell, ModelUse use, Model* model) {
  model->prior = Eigen::MatrixXd::Zero(model->size, model->size);
  // The quaternion tangent turns by twice its length.
  auto add_pose = [&](int offset, const Eigen::Isometry3d& T_mount_cam, double sigma_m,
                      double sigma_rad) {
    if (use == ModelUse::kForecast) {
      sigma_m = kUnknownPositionM;
      sigma_rad = kUnknownRotationRad;
    }
    const double lever = T_mount_cam.translation().norm() * sigma_rad;
    const double sigma_t = std::sqrt(sigma_m * sigma_m + lever * lever);
    for (int i = 0; i < 3; ++i) {
      model->prior(offset + i, offset + i) = 4.0 / (sigma_rad * sigma_rad);
      model->prior(offset + 3 + i, offset + 3 + i) = 1.0 / (sigma_t * sigma_t);
    }
  };
  add_pose(model->target_offset, cell.T_holder_target, cell.target_position_sigma_m,
           cell.target_rotation_sigma_rad);
  for (const auto& [pair, offset] : model->pair_offset)
    add_pose(offset, cell.cameras[pair.first].T_mount_cam, kUnknownPositionM, kUnknownRotationRad);
  for (size_t k = 0; k < cell.cameras.size(); ++k) {
    const PlanCamera& camera = cell.cameras[k];
    add_pose(model->camera_offset[k], camera.T_mount_cam, camera.position_sigma_m,
             camera.rotation_sigma_rad);
    if (model->given_offset[k] >= 0) {
      // The solve's prior on the given values (UncertainGivenIntrinsics).
      int at = model->given_offset[k];
      const GivenIntrinsicsSigma& given = cell.intrinsics_sigma;
      if (model->given_focal) {
        const double focal = 0.01 * given.focal_percent;
        model->prior(at, at) = 1.0 / (focal * focal);
        ++at;
      }
      if (model->given_principal_point)
        for (int i = 0; i < 2; ++i, ++at)
          model->prior(at, at) = 1.0 / (given.principal_point_px * given.principal_point_px);
    }
    if (model->intrinsics_offset[k] < 0) continue;
    const auto sigma = internal::IntrinsicsPriorSigma(camera.camera);
    for (int i = 0; i < model->intrinsics_count[k]; ++i)
      model->prior(model->intrinsics_offset[k] + i, model->intrinsics_offset[k] + i) =
          1.0 / (sigma[i] * sigma[i]);
  }
}

/// The given intrinsics' error coordinates of every camera, in order.
std::vector<int> GivenCoordinatesOf(const Model& model) {
  std::vector<int> c;
  for (int offset : model.given_offset)
    for (int i = 0; offset >= 0 && i < model.GivenCoordinates(); ++i) c.push_back(offset + i);
  return c;
}

/// What the information says of the given intrinsics' error coordinates
/// `c`: Σ_post = H⁻¹_cc, its inverse, and the views' information on them,
/// S = (H⁻¹_cc)⁻¹ − P (P their prior).
struct OnGiven {
  Eigen::MatrixXd posterior, posterior_inverse, S;
};

/// OnGiven from `columns`, H⁻¹ e_c for each coordinate of `c` in order (rows: the unknowns).
OnGiven OnGivenOf(const Model& model, const std::vector<int>& c, const Eigen::MatrixXd& columns) {
  const int nc = static_cast<int>(c.size());
  OnGiven out;
  out.posterior.resize(nc, nc);
  Eigen::MatrixXd P(nc, nc);
  for (int i = 0; i < nc; ++i)
    for (int j = 0; j < nc; ++j) {
      out.posterior(i, j) = columns(c[i], j);
      P(i, j) = model.prior(c[i], c[j]);
    }
  out.posterior_inverse = out.posterior.ldlt().solve(Eigen::MatrixXd::Identity(nc, nc));
  out.S = out.posterior_inverse - P;
  return out;
}

/// The positive part of a symmetric matrix.
Eigen::MatrixXd PositivePart(const Eigen::MatrixXd& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (m + m.transpose()));
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eigen.eigenvectors().transpose();
}

/// One camera's view at a robot pose, differentiated: its residuals'
/// Jacobian with respect to the unknowns' tangent (J_u) and to the robot
/// pose's (J_r), in units of the cell's detection σ. False when the camera
/// sees none of the target's points there.
bool ViewJacobians(const Model& model, int k, const PoseParams& T_mount_holder,
                   Eigen::MatrixXd* J_u, Eigen::MatrixXd* J_r) {
  const PlanCell& cell = *model.cell;
  const Camera& camera = cell.cameras[k].camera;
  auto points = std::make_shared<ViewPoints>();
  const Eigen::Isometry3d T_cam_target = FromPoseParams(model.T_cam_mount[k].data()) *
                                         FromPoseParams(T_mount_holder.data()) *
                                         cell.T_holder_target;
  for (const TargetPoint& p : cell.target->Points()) {
    const auto uv = camera.Project(T_cam_target * p.p_target);
    if (!uv) continue;
    points->p_target.push_back(p.p_target);
    points->observed_px.push_back(*uv);
  }
  if (points->p_target.empty()) return false;
  const bool refined = model.intrinsics_offset[k] >= 0, given = model.given_offset[k] >= 0;
  const bool free = refined || given;  // the intrinsics' Jacobian is wanted
  std::unique_ptr<ceres::CostFunction> cost(
      ViewReprojectionWithRobotError::Create(camera, points, 0.0, free));
  const int rows = cost->num_residuals();
  std::vector<DynamicRowMajor> J(free ? 4 : 3);
  for (size_t b = 0; b < J.size(); ++b) J[b].resize(rows, cost->parameter_block_sizes()[b]);
  const double* parameters[4] = {model.T_cam_mount[k].data(), T_mount_holder.data(),
                                 model.T_holder_target.data(), camera.params.data()};
  double* jacobians[4] = {J[0].data(), J[1].data(), J[2].data(), free ? J[3].data() : nullptr};
  Eigen::VectorXd residuals(rows);
  if (!cost->Evaluate(parameters, residuals.data(), jacobians)) return false;
  *J_u = Eigen::MatrixXd::Zero(rows, model.size);
  J_u->middleCols(model.camera_offset[k], 6) = J[0] * PlusJacobian(model.T_cam_mount[k]);
  J_u->middleCols(model.target_offset, 6) = J[2] * PlusJacobian(model.T_holder_target);
  if (refined)
    J_u->middleCols(model.intrinsics_offset[k], model.intrinsics_count[k]) =
        J[3].leftCols(model.intrinsics_count[k]);
  if (given) {
    int at = model.given_offset[k];
    if (model.given_focal)  // fx, fy → fx (1 + e), fy (1 + e)
      J_u->col(at++) = J[3].col(0) * camera.params[0] + J[3].col(1) * camera.params[1];
    if (model.given_principal_point) J_u->middleCols(at, 2) = J[3].middleCols(2, 2);
  }
  // A camera with its own detection noise weighs as the solve weighs it
  // (CameraWeights): its rows in units of the cell's σ.
  const double own_sigma = cell.cameras[k].pixel_sigma_px;
  const double weight = own_sigma > 0 ? cell.pixel_sigma_px / own_sigma : 1.0;
  *J_u *= weight;
  *J_r = J[1] * PlusJacobian(T_mount_holder) * weight;
  return true;
}

}  // namespace

void HoldRecorded(const Eigen::MatrixXd& information, Model* model) {
  model->recorded_information_on_given.resize(0, 0);
  model->recorded_given_offset.resize(0);
  const PlanCell& cell = *model->cell;
  bool measured = false;
  for (size_t k = 0; k < cell.cameras.size(); ++k)
    measured =
        measured || (model->given_offset[k] >= 0 && cell.cameras[k].given_intrinsics_offset_px);
  const std::vector<int> c = GivenCoordinatesOf(*model);
  if (!measured || c.empty()) return;
  const Eigen::LLT<Eigen::MatrixXd> llt(information);
  if (llt.info() != Eigen::Success) return;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(model->size, static_cast<Eigen::Index>(c.size()));
  for (size_t j = 0; j < c.size(); ++j) rhs(c[j], static_cast<Eigen::Index>(j)) = 1.0;
  const OnGiven given = OnGivenOf(*model, c, llt.solve(rhs));
  const Eigen::MatrixXd& S = given.S;
  // What the views' noise alone makes of δc where the given values are
  // right: Σ_post S Σ_post (SigmaOf).
  const Eigen::MatrixXd noise = given.posterior * PositivePart(S) * given.posterior;
  // Per camera, the offset in the model's coordinates (the focal length's
  // relative error: fx, fy → fx (1 + e), fy (1 + e); cx and cy in pixels),
  // kept by how far it stands out of that noise: the positive-part
  // James-Stein factor max(0, 1 − d / z²), z² its squared Mahalanobis length
  // under the noise, d its coordinates: a camera whose given values are off
  // keeps it, as more views keep finding it; a δc that is a draw of the
  // noise mostly not. Rows of S are held out as much, so the views recorded
  // count once. This noise is too narrow by about 2 (bench/plan_advise, the
  // given intrinsics right: z² of 12 values for 3 coordinates, mean 6.2, not
  // 3), so a camera of 4 views keeps much of a δc of noise in some draws
  // (there 4 of 6, z² 7-18; in 2 its forecast 2.5-3.6 times the σ then
  // reported).
  Eigen::VectorXd offset = Eigen::VectorXd::Zero(S.rows()),
                  weight = Eigen::VectorXd::Zero(S.rows());
  int at = 0;
  for (size_t k = 0; k < cell.cameras.size(); ++k) {
    if (model->given_offset[k] < 0) continue;
    const Camera& camera = cell.cameras[k].camera;
    const auto& found = cell.cameras[k].given_intrinsics_offset_px;
    const Eigen::Vector4d d = found.value_or(Eigen::Vector4d::Zero());
    const int first = at;
    if (model->given_focal) offset[at++] = 0.5 * (d[0] / camera.fx() + d[1] / camera.fy());
    if (model->given_principal_point) {
      offset[at++] = d[2];
      offset[at++] = d[3];
    }
    const int n = at - first;
    if (!found) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(noise.block(first, first, n, n));
    const Eigen::VectorXd along = eigen.eigenvectors().transpose() * offset.segment(first, n);
    const double largest = eigen.eigenvalues().maxCoeff();
    double z2 = 0;
    for (int i = 0; i < n; ++i)
      if (eigen.eigenvalues()[i] > 1e-12 * largest)
        z2 += along[i] * along[i] / eigen.eigenvalues()[i];
    const double kept = z2 > n ? 1.0 - n / z2 : 0.0;
    offset.segment(first, n) *= kept;
    weight.segment(first, n).setConstant(std::sqrt(kept));
  }
  model->recorded_information_on_given = weight.asDiagonal() * S * weight.asDiagonal();
  model->recorded_given_offset = offset;
}

Model MakeModel(const PlanCell& cell, ModelUse use) {
  Model model;
  model.cell = &cell;
  model.target_offset = 0;
  model.size = 6;
  model.given_focal = cell.intrinsics_sigma.focal_percent > 0;
  model.given_principal_point = cell.intrinsics_sigma.principal_point_px > 0;
  for (const PlanCamera& camera : cell.cameras) {
    model.camera_offset.push_back(model.size);
    model.size += 6;
    const int refined = !camera.refine_intrinsics   ? 0
                        : camera.intrinsics_unknown ? kEstimatedIntrinsics
                                                    : kRefinedIntrinsics;
    model.intrinsics_offset.push_back(refined ? model.size : -1);
    model.intrinsics_count.push_back(refined);
    model.size += refined;
    const bool given = !camera.refine_intrinsics && model.GivenCoordinates() > 0;
    model.given_offset.push_back(given ? model.size : -1);
    if (given) model.size += model.GivenCoordinates();
    model.T_cam_mount.push_back(ToPoseParams(camera.T_mount_cam.inverse()));
    model.position_jacobian.push_back(
        internal::UncertaintyJacobian(camera.T_mount_cam.inverse(), true).topRows<3>());
    // Where the rough pose's ± may move the image: its position over the
    // working distance and its turn, each in pixels at the focal length.
    const double f = std::max(camera.camera.fx(), camera.camera.fy());
    const double distance = std::max(0.3, camera.T_mount_cam.translation().norm());
    const double position = camera.position_sigma_m + cell.target_position_sigma_m;
    model.uncertainty_margin_px.push_back(
        f * (position / distance + std::tan(camera.rotation_sigma_rad)));
  }
  const int cameras = static_cast<int>(cell.cameras.size());
  for (int k = 0; use == ModelUse::kForecast && cell.cross_terms && k < cameras; ++k)
    for (int t = 0; t < cameras; ++t)
      if (t != k) {
        model.pair_offset[{k, t}] = model.size;
        model.size += 6;
      }
  model.T_holder_target = ToPoseParams(cell.T_holder_target);
  model.point_spacing_m = SmallestSpacing(*cell.target);
  AddPrior(cell, use, &model);
  return model;
}

Eigen::MatrixXd PoseInformation(const Model& model, const Eigen::Isometry3d& T_base_ee,
                                const std::vector<int>& cameras) {
  const PlanCell& cell = *model.cell;
  const SetupFrames frames = FramesOf(cell.setup);
  const PoseParams T_mount_holder = ToPoseParams(frames.MountFromHolder(T_base_ee));
  const bool robot_error = cell.robot_sigma_mm > 0 && cell.robot_sigma_deg > 0;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(model.size, model.size);       // unknowns
  Eigen::MatrixXd H_ur = Eigen::MatrixXd::Zero(model.size, 6);             // unknowns × robot
  Eigen::Matrix<double, 6, 6> H_rr = Eigen::Matrix<double, 6, 6>::Zero();  // robot
  for (int k : cameras) {
    Eigen::MatrixXd J_u, J_r;
    if (!ViewJacobians(model, k, T_mount_holder, &J_u, &J_r)) continue;
    // The same rows through camera k's pose as seen by each other camera.
    std::vector<Eigen::MatrixXd> rows_of = {J_u};
    for (int t : cameras) {
      const auto pair = model.pair_offset.find({k, t});
      if (pair == model.pair_offset.end()) continue;
      Eigen::MatrixXd J_pair = J_u;
      J_pair.middleCols(model.camera_offset[k], 6).setZero();
      J_pair.middleCols(pair->second, 6) = J_u.middleCols(model.camera_offset[k], 6);
      rows_of.push_back(std::move(J_pair));
    }
    for (const Eigen::MatrixXd& J_x : rows_of) {
      H += J_x.transpose() * J_x;
      if (!robot_error) continue;
      H_ur += J_x.transpose() * J_r;
      H_rr += J_r.transpose() * J_r;
    }
  }
  if (robot_error) {
    // The prior on the pose block as the solve weighs it, in pixel units.
    std::unique_ptr<ceres::CostFunction> prior(RobotPosePrior::Create(
        T_base_ee, frames.RobotPoseInverted(), cell.robot_sigma_deg * M_PI / 180.0,
        cell.robot_sigma_mm / 1000.0, cell.pixel_sigma_px));
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> J_prior;
    Eigen::Matrix<double, 6, 1> r;
    const double* parameters[1] = {T_mount_holder.data()};
    double* jacobians[1] = {J_prior.data()};
    prior->Evaluate(parameters, r.data(), jacobians);
    const Eigen::Matrix<double, 6, 6> J_p = J_prior * PlusJacobian(T_mount_holder);
    H_rr += J_p.transpose() * J_p;
    H -= H_ur * H_rr.ldlt().solve(H_ur.transpose());
  }
  return H / (cell.pixel_sigma_px * cell.pixel_sigma_px);
}

std::vector<PredictedSigma> SigmaOf(const Model& model, const Eigen::MatrixXd& information) {
  const size_t cameras = model.camera_offset.size();
  std::vector<PredictedSigma> out(
      cameras, {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                std::numeric_limits<double>::infinity()});
  const Eigen::LLT<Eigen::MatrixXd> llt(information);
  if (llt.info() != Eigen::Success) return out;
  const std::vector<int> c = GivenCoordinatesOf(model);
  const int nc = static_cast<int>(c.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(model.size, 6 * cameras + nc);
  for (size_t k = 0; k < cameras; ++k) rhs.block(model.camera_offset[k], 6 * k, 6, 6).setIdentity();
  for (int j = 0; j < nc; ++j) rhs(c[j], 6 * cameras + j) = 1.0;
  const Eigen::MatrixXd columns = llt.solve(rhs);
  // The views' information on c, S = (H⁻¹_cc)⁻¹ − P, and (H⁻¹_cc)⁻¹ = Σ_post⁻¹.
  Eigen::MatrixXd S, posterior_inverse;
  if (nc > 0) {
    OnGiven given = OnGivenOf(model, c, columns.rightCols(nc));
    S = std::move(given.S);
    posterior_inverse = std::move(given.posterior_inverse);
  }
  // After a recorded capture (HoldRecorded) the shift its solve found stays,
  // as far as it is kept (the views' estimate of a real error is where more
  // views expect it), moved by the new G; the rest of the noise is a draw:
  // the information the new views add on c, and the recorded views' where
  // not kept. (METRIC's published cell, 20 cameras in 5 splits: the σ
  // expected after advise's proposals 0.73 of the σ then reported without
  // it, median, 0.96 with it; bench/plan_advise with the given focal lengths
  // 0.5 % off 0.27 and 0.65.)
  Eigen::MatrixXd S_draw = S;
  Eigen::VectorXd kept;  // Σ_post⁻¹ δc: G δc = X Σ_post⁻¹ δc
  if (nc > 0 && model.recorded_given_offset.size() == nc) {
    S_draw = PositivePart(S - model.recorded_information_on_given);
    kept = posterior_inverse * model.recorded_given_offset;
  }
  for (size_t k = 0; k < cameras; ++k) {
    const Eigen::Isometry3d T_cam_mount = FromPoseParams(model.T_cam_mount[k].data());
    auto uncertainty = [&](const Eigen::Matrix<double, 6, 6>& covariance) {
      return internal::UncertaintyOf(T_cam_mount, 0.5 * (covariance + covariance.transpose()),
                                     true);
    };
    const Eigen::Matrix<double, 6, 6> C = columns.block(model.camera_offset[k], 6 * k, 6, 6);
    Eigen::Matrix<double, 6, 6> own = C;  // A⁻¹ = H⁻¹_xx − H⁻¹_xc Σ_post⁻¹ H⁻¹_cx
    PoseUncertainty shift;                // of G δc, over the noise
    PoseUncertainty held;                 // of G δc, as the recorded views found it
    if (S.size()) {
      const Eigen::MatrixXd X = columns.block(model.camera_offset[k], 6 * cameras, 6, nc);
      shift = uncertainty(X * S_draw * X.transpose());
      own -= X * posterior_inverse * X.transpose();
      if (kept.size()) {
        const Eigen::Matrix<double, 6, 1> moved = X * kept;
        held = uncertainty(moved * moved.transpose());
      }
    }
    const PoseUncertainty u = uncertainty(C);
    const double position_mm = std::sqrt(Sq(u.position_mm) + Sq(held.position_mm) +
                                         MedianSquaredNorm(shift.covariance.topLeftCorner<3, 3>()));
    const double rotation_deg =
        std::sqrt(Sq(u.rotation_deg) + Sq(held.rotation_deg) +
                  MedianSquaredNorm(shift.covariance.bottomRightCorner<3, 3>()));
    out[k] = {position_mm, rotation_deg, uncertainty(own).position_mm};
  }
  return out;
}

std::vector<double> OwnPositionMm(const Model& model, const Eigen::MatrixXd& information) {
  // A⁻¹ = H⁻¹_xx − H⁻¹_xc (H⁻¹_cc)⁻¹ H⁻¹_cx (SigmaOf) is the inverse of the
  // information R with c's rows and columns left out, and the trace of the
  // position's covariance J A⁻¹_k Jᵀ is |L⁻¹ E_k Jᵀ|² for R = L Lᵀ.
  const size_t cameras = model.camera_offset.size();
  std::vector<double> out(cameras, std::numeric_limits<double>::infinity());
  std::vector<bool> given(model.size, false);
  for (int i : GivenCoordinatesOf(model)) given[i] = true;
  std::vector<int> kept, at(model.size, -1);
  for (int i = 0; i < model.size; ++i)
    if (!given[i]) {
      at[i] = static_cast<int>(kept.size());
      kept.push_back(i);
    }
  const int n = static_cast<int>(kept.size());
  Eigen::MatrixXd reduced(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) reduced(i, j) = information(kept[i], kept[j]);
  const Eigen::LLT<Eigen::MatrixXd> llt(reduced);
  if (llt.info() != Eigen::Success) return out;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3 * static_cast<Eigen::Index>(cameras));
  for (size_t k = 0; k < cameras; ++k)
    rhs.block(at[model.camera_offset[k]], 3 * k, 6, 3) = model.position_jacobian[k].transpose();
  llt.matrixL().solveInPlace(rhs);
  for (size_t k = 0; k < cameras; ++k) out[k] = rhs.middleCols(3 * k, 3).norm();
  return out;
}

}  // namespace handeye::plan_internal
