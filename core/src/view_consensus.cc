// SPDX-License-Identifier: GPL-2.0-or-later
// Views that do not fit the consensus of the others: the robot-motion vote
// before any estimate, the residual check after a solve, and the warnings
// that name robot poses whose record does not belong to their images.
#include "view_consensus.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "cost_jacobians.h"
#include "detection_noise.h"
#include "half_turn.h"
#include "handeye/core/transform.h"
#include "problem.h"
#include "residuals.h"
#include "robot_error.h"

namespace handeye::internal {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// What PnP's own noise contributes, per axis, to a view's target rotation
/// and to the target centre's offset across the viewing ray (variances,
/// rad² and m²): σ² (JᵀJ)⁻¹ of the pinhole projection of the view's points.
struct PnpNoise {
  double rotation_rad2 = 0;
  double across_m2 = 0;
  double position_m2 = 0;  ///< the centre's, all three axes together (along the ray the most)
};

PnpNoise PnpNoiseOf(const View& view, const Camera& camera, const Eigen::Vector3d& centre,
                    double sigma_px) {
  Eigen::Matrix<double, 6, 6> JtJ = Eigen::Matrix<double, 6, 6>::Zero();
  const Eigen::Isometry3d& T = *view.T_cam_target;
  for (const Eigen::Vector3d& p : view.p_target) {
    const Eigen::Vector3d P = T * p;
    if (P.z() <= 0) continue;
    Eigen::Matrix<double, 2, 3> dproj;
    dproj << camera.fx() / P.z(), 0, -camera.fx() * P.x() / (P.z() * P.z()), 0, camera.fy() / P.z(),
        -camera.fy() * P.y() / (P.z() * P.z());
    Eigen::Matrix<double, 3, 6> dP;  // a small turn ω and shift δt of the target, camera frame
    dP << -cost_internal::Skew(P), Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 2, 6> J = dproj * dP;
    JtJ += J.transpose() * J;
  }
  PnpNoise out;
  Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(JtJ);
  if (!lu.isInvertible()) return out;
  const Eigen::Matrix<double, 6, 6> C = sigma_px * sigma_px * lu.inverse();
  out.rotation_rad2 = C.topLeftCorner<3, 3>().trace() / 3.0;
  const Eigen::Vector3d c = T * centre;
  Eigen::Matrix<double, 3, 6> dc;
  dc << -cost_internal::Skew(c), Eigen::Matrix3d::Identity();
  const Eigen::Vector3d ray = c.normalized();
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - ray * ray.transpose();
  out.across_m2 = (across * dc * C * dc.transpose() * across).trace() / 2.0;
  out.position_m2 = (dc * C * dc.transpose()).trace();
  return out;
}

/// Conjugation invariants of a rigid motion: its rotation angle, and its
/// translation along the rotation axis (the screw pitch).
struct Screw {
  double angle_rad = 0;
  double pitch_m = 0;
};

Screw ScrewOf(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d rotvec = RotationVectorFromMatrix(T.rotation());
  Screw screw;
  screw.angle_rad = rotvec.norm();
  if (screw.angle_rad > 1e-9) screw.pitch_m = T.translation().dot(rotvec / screw.angle_rad);
  return screw;
}

/// The axis of a motion that turns by less than this is too poorly defined
/// for its pitch to be compared.
constexpr double kMinAngleForPitch = 3.0 * kDeg;
/// Each view is compared with at most this many others of its camera.
constexpr size_t kMaxPartners = 48;

/// How two views' motions compare: differences of the invariants.
struct MotionMismatch {
  double angle_rad = 0;
  double pitch_m = -1;  ///< < 0: not comparable (small rotation)
  /// σ of the two differences that the two views' PnP noise alone gives.
  double angle_noise_rad = 0, pitch_noise_m = 0;
};

/// View a, seen at T_cam_target_a, against view b.
MotionMismatch Compare(const Problem& problem, const View& a,
                       const Eigen::Isometry3d& T_cam_target_a, const View& b) {
  const Screw seen = ScrewOf(T_cam_target_a * b.T_cam_target->inverse());
  const Screw moved =
      ScrewOf(problem.T_mount_holder[a.pose] * problem.T_mount_holder[b.pose].inverse());
  MotionMismatch m;
  m.angle_rad = std::abs(seen.angle_rad - moved.angle_rad);
  if (seen.angle_rad > kMinAngleForPitch && moved.angle_rad > kMinAngleForPitch)
    m.pitch_m = std::abs(seen.pitch_m - moved.pitch_m);
  return m;
}

/// The target's centre (its points' mean), which locates it better than its origin.
Eigen::Vector3d TargetCentre(const Target& target) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const TargetPoint& p : target.Points()) centre += p.p_target;
  return centre / static_cast<double>(std::max<size_t>(1, target.Points().size()));
}

}  // namespace

void IndexUsedViews(Problem* problem) {
  for (auto& views : problem->camera_views) views.clear();
  for (size_t i = 0; i < problem->views.size(); ++i)
    if (problem->views[i].used)
      problem->camera_views[problem->views[i].camera].push_back(static_cast<int>(i));
}

namespace {

/// Per view of `ids`: the σ of its PnP rotation (per axis, rad) and position
/// (m) from its own corners' noise.
void PnpSigmas(const Problem& problem, const std::vector<int>& ids, const Eigen::Vector3d& centre,
               double pixel_sigma_px, std::vector<double>* rotation_rad,
               std::vector<double>* position_m) {
  rotation_rad->resize(ids.size());
  position_m->resize(ids.size());
  for (size_t a = 0; a < ids.size(); ++a) {
    const View& view = problem.views[ids[a]];
    const PnpNoise noise =
        PnpNoiseOf(view, problem.dataset->cameras[view.camera], centre, pixel_sigma_px);
    (*rotation_rad)[a] = std::sqrt(noise.rotation_rad2);
    (*position_m)[a] = std::sqrt(noise.position_m2);
  }
}

/// A view the robot-motion vote left out: its support against its camera's median.
struct Disagreement {
  int view = 0;
  double support = 0, median_support = 0;
};

/// What the votes of every camera said (RejectInconsistentMotions).
struct VoteOutcome {
  std::vector<Disagreement> left_out;
  std::vector<bool> agreed;  ///< per view: its camera voted and it agreed with most of the others
};

/// Why the vote left a view out. Its robot record is the pose's, which other
/// cameras' views of the same pose test too: where one of them agreed with
/// its own camera's views, the record holds, and the view is what is off.
std::string DisagreementReason(const Problem& problem, const Disagreement& d,
                               const VoteOutcome& votes) {
  const View& view = problem.views[d.view];
  std::string confirmed_by;
  for (size_t i = 0; i < problem.views.size() && confirmed_by.empty(); ++i)
    if (votes.agreed[i] && problem.views[i].pose == view.pose &&
        problem.views[i].camera != view.camera)
      confirmed_by = problem.dataset->cameras[problem.views[i].camera].name;
  std::ostringstream why;
  why << "its robot motion agrees with " << std::lround(100.0 * d.support)
      << " % of the camera's other views (most agree with " << std::lround(100.0 * d.median_support)
      << " %)";
  // Beyond 60° the corners are squeezed to half and less across the tilt.
  const double angle_deg = ViewAngle(*view.T_cam_target, view.p_target) / kDeg;
  if (!confirmed_by.empty()) {
    why << ", where camera '" << confirmed_by
        << "' finds the same robot record agree with its own views: the record holds, and this "
           "view's corners or the pose they give are off (blur, glare, a target partly hidden";
    if (angle_deg > 60.0) why << ", or seen " << std::lround(angle_deg) << " deg from face-on";
    why << ")";
    return why.str();
  }
  why << ": the robot record likely belongs to another pose or time";
  if (angle_deg > 60.0)
    why << ", or the target, seen " << std::lround(angle_deg)
        << " deg from face-on, gave a poor pose";
  return why.str();
}

/// The robot-motion vote among one camera's used views `ids`
/// (RejectInconsistentMotions): the views it left out, and those that agreed,
/// into `votes`.
void VoteCamera(Problem* problem, const std::vector<int>& ids, const Eigen::Vector3d& centre,
                double pixel_sigma_px, const std::optional<Eigen::Isometry3d>& half_turn,
                VoteOutcome* votes) {
  const size_t n = ids.size();
  if (n < 4) return;  // three views: one pair against each; no majority to speak of
  // What each view's rotation (σ per axis, rad) and position (σ, m) from
  // PnP may be off by its own corners' noise alone: much more for a board
  // seen obliquely or small.
  std::vector<double> pnp_rotation_rad, pnp_position_m;
  PnpSigmas(*problem, ids, centre, pixel_sigma_px, &pnp_rotation_rad, &pnp_position_m);
  // Each view against up to kMaxPartners others, spread over the camera's
  // views; view a seen at T_a.
  const size_t partners = std::min(n - 1, kMaxPartners);
  auto mismatches = [&](size_t a, const Eigen::Isometry3d& T_a) {
    std::vector<MotionMismatch> out;
    for (size_t i = 1; i <= partners; ++i) {
      const size_t b = (a + i * (n - 1) / partners) % n;
      MotionMismatch m = Compare(*problem, problem->views[ids[a]], T_a, problem->views[ids[b]]);
      m.angle_noise_rad = std::hypot(pnp_rotation_rad[a], pnp_rotation_rad[b]);
      m.pitch_noise_m = std::hypot(pnp_position_m[a], pnp_position_m[b]);
      out.push_back(m);
    }
    return out;
  };
  std::vector<std::vector<MotionMismatch>> mismatch(n);
  std::vector<double> angles, pitches;
  for (size_t a = 0; a < n; ++a) {
    mismatch[a] = mismatches(a, *problem->views[ids[a]].T_cam_target);
    for (const MotionMismatch& m : mismatch[a]) {
      angles.push_back(m.angle_rad);
      if (m.pitch_m >= 0) pitches.push_back(m.pitch_m);
    }
  }
  // Tolerances from the camera's own pairs (≈ 4σ of the typical mismatch,
  // which PnP and the robot's own errors set), with floors for noise-free
  // data; for each pair at least 4σ of what PnP's noise gives it (on a
  // rendered cell good views at 65-70° from face-on failed the typical
  // pairs' pitch tolerance against most of the views).
  const double angle_tolerance = std::max(0.1 * kDeg, 6.0 * Median(angles));
  const double pitch_tolerance = std::max(1e-3, 6.0 * Median(pitches));
  auto support_of = [&](const std::vector<MotionMismatch>& pairs) {
    int agree = 0;
    for (const MotionMismatch& m : pairs) {
      const double angle_limit = std::max(angle_tolerance, 4.0 * m.angle_noise_rad);
      const double pitch_limit = std::max(pitch_tolerance, 4.0 * m.pitch_noise_m);
      agree += m.angle_rad <= angle_limit && m.pitch_m <= pitch_limit ? 1 : 0;
    }
    return static_cast<double>(agree) / pairs.size();
  };
  std::vector<double> support(n);
  for (size_t a = 0; a < n; ++a) support[a] = support_of(mismatch[a]);
  // Only a clear majority votes a view out.
  if (Median(support) < 0.5) return;
  for (size_t a = 0; a < n; ++a) {
    if (support[a] >= 0.5) {
      votes->agreed[ids[a]] = true;
      continue;
    }
    View& view = problem->views[ids[a]];
    // A 180°-ambiguous board numbered the other way round in this image
    // (its detector cannot tell): its pose is off by the half turn, which
    // no robot record explains. Numbered back, it agrees.
    if (half_turn && support_of(mismatches(a, *view.T_cam_target * *half_turn)) >= 0.5) {
      FlipView(*half_turn, &view);
      continue;
    }
    view.used = false;
    view.inconsistent = true;
    votes->left_out.push_back({ids[a], support[a], Median(support)});
  }
}

}  // namespace

int RejectInconsistentMotions(Problem* problem) {
  const Eigen::Vector3d centre = TargetCentre(*problem->dataset->target);
  const std::vector<double> pixel_sigma_px = CameraSigmasPx(*problem);
  const std::optional<Eigen::Isometry3d> half_turn = HalfTurnSymmetry(*problem->dataset->target);
  if (half_turn) NumberViewsAlike(problem, *half_turn);
  VoteOutcome votes;
  votes.agreed.assign(problem->views.size(), false);
  for (size_t k = 0; k < problem->camera_views.size(); ++k)
    VoteCamera(problem, problem->camera_views[k], centre, pixel_sigma_px[k], half_turn, &votes);
  for (const Disagreement& d : votes.left_out)
    problem->views[d.view].rejected_because = DisagreementReason(*problem, d, votes);
  if (!votes.left_out.empty()) IndexUsedViews(problem);
  return static_cast<int>(votes.left_out.size());
}

std::vector<int> ViewsOffTheSolution(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target) {
  const size_t n = problem.camera_views.size();
  std::vector<double> rms(problem.views.size(), 0.0);
  std::vector<std::vector<double>> per_camera(n);
  std::vector<double> all;
  for (size_t k = 0; k < n; ++k) {
    if (!T_cam_mount[k]) continue;
    for (int v : problem.camera_views[k]) {
      rms[v] = ViewRms(ViewErrors(problem, problem.views[v], *T_cam_mount[k], T_holder_target[k]));
      per_camera[k].push_back(rms[v]);
      all.push_back(rms[v]);
    }
  }
  auto threshold = [](const std::vector<double>& values) {
    const double median = Median(values);
    std::vector<double> deviations;
    for (double x : values) deviations.push_back(std::abs(x - median));
    return std::max({median + 8.0 * 1.4826 * Median(deviations), 4.0 * median, 0.5});
  };
  const double global_threshold = threshold(all);
  std::vector<int> off;
  for (size_t k = 0; k < n; ++k) {
    if (!T_cam_mount[k]) continue;
    const double limit = per_camera[k].size() >= 5 ? threshold(per_camera[k]) : global_threshold;
    for (int v : problem.camera_views[k])
      if (rms[v] > limit) off.push_back(v);
  }
  return off;
}

void ExplainInconsistentViews(Problem* problem,
                              const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
                              const TargetPoses& T_holder_target) {
  for (View& view : problem->views) {
    if (!view.inconsistent || !view.T_cam_target || !T_cam_mount[view.camera]) continue;
    // The target pose the view's PnP found, in the target frame the chain predicts.
    const Eigen::Isometry3d T_predicted_seen =
        (*T_cam_mount[view.camera] * problem->T_mount_holder[view.pose] *
         T_holder_target[view.camera])
            .inverse() *
        *view.T_cam_target;
    const Eigen::Vector3d rotvec = RotationVectorFromMatrix(T_predicted_seen.rotation());
    const double angle = rotvec.norm();
    // A half turn about an axis in the target's plane: the sheet turned over.
    if (angle < 170.0 * kDeg || std::abs(rotvec.z()) > std::sin(10.0 * kDeg) * angle) continue;
    view.inconsistent = false;  // the image's problem, not the robot record's
    view.rejected_because =
        "the target is seen from behind, its pattern mirrored (a see-through target?): the view "
        "fits the calibration only with the target turned over";
  }
}

namespace {

/// Whether the chain puts the target further across the viewing rays from
/// where PnP sees it than PnP's own noise explains: `seen_sigma_m` (the
/// median offset over the median of a 2D Gaussian's norm) beyond PnP's σ
/// there (`pnp_variance_m2`) by more than three standard errors of a median
/// of `views` Rayleigh draws (0.72 / √n). Where the residuals leave it open
/// (chain_to_pnp between 1 and 1.2) this tells a robot off by 0.3 mm / 0.03°
/// (1.46–3.6 over PnP's σ in the 12 planned poses of bench/plan) from an
/// exact one (rendered cells of bench/robot-model 0.67–1.17, projected cells
/// of bench_scale 0.84–0.99); an exact robot's cell then skips the held-out
/// model choice, whose solves cost a 32-camera cell 4x its calibration.
bool AcrossRaysShowRobot(double seen_sigma_m, double pnp_variance_m2, size_t views) {
  const double seen_over_pnp = seen_sigma_m / std::sqrt(std::max(pnp_variance_m2, 1e-30));
  return seen_over_pnp > 1.0 + 3.0 * 0.72 / std::sqrt(static_cast<double>(views));
}

}  // namespace

std::optional<RobotPrior> EstimateRobotPrior(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target) {
  const Dataset& dataset = *problem.dataset;
  const Eigen::Vector3d centre = TargetCentre(*dataset.target);
  const std::vector<double> pixel_sigma_px = CameraSigmasPx(problem);
  std::vector<double> chain_rms, pnp_rms, across_m, angle_rad, pnp_across_m2, pnp_rotation_rad2;
  for (const View& view : problem.views) {
    if (!view.used || !T_cam_mount[view.camera]) continue;
    chain_rms.push_back(ViewRms(
        ViewErrors(problem, view, *T_cam_mount[view.camera], T_holder_target[view.camera])));
    pnp_rms.push_back(view.pnp_rms_px);
    const Eigen::Isometry3d chain = *T_cam_mount[view.camera] * problem.T_mount_holder[view.pose] *
                                    T_holder_target[view.camera];
    // Across the viewing ray PnP locates the target well; along it, poorly.
    const Eigen::Vector3d offset = chain * centre - *view.T_cam_target * centre;
    const Eigen::Vector3d ray = (*view.T_cam_target * centre).normalized();
    across_m.push_back((offset - offset.dot(ray) * ray).norm());
    angle_rad.push_back(RotationDistance(chain.rotation(), view.T_cam_target->rotation()));
    const PnpNoise noise =
        PnpNoiseOf(view, dataset.cameras[view.camera], centre, pixel_sigma_px[view.camera]);
    pnp_across_m2.push_back(noise.across_m2);
    pnp_rotation_rad2.push_back(noise.rotation_rad2);
  }
  if (chain_rms.size() < 3) return std::nullopt;
  // The chain has 6 fewer unknowns per view than PnP; with an exact robot and
  // the right intrinsics its residuals are within ≈ 15 % of PnP's (rendered
  // cells: 1.00–1.14). Clearly above that (kClearChainToPnp), the robot's
  // poses set them; between, the caller decides (a robot of 0.3 mm / 0.03°
  // seen in 12 poses is often there), where the target's place across the
  // viewing rays says the robot may be off (AcrossRaysShowRobot).
  // Medians of the norm of a 2D and of a 3D isotropic Gaussian: 1.1774 σ and 1.5382 σ.
  const double across_sigma_m = Median(across_m) / 1.1774;
  const double pnp_across_variance_m2 = Median(pnp_across_m2);
  const double chain_to_pnp = Median(chain_rms) / std::max(Median(pnp_rms), 1e-9);
  if (chain_to_pnp < 1.0) return std::nullopt;
  if (chain_to_pnp < kClearChainToPnp &&
      !AcrossRaysShowRobot(across_sigma_m, pnp_across_variance_m2, across_m.size()))
    return std::nullopt;
  RobotPrior prior;
  prior.chain_to_pnp = chain_to_pnp;
  // Where the chain and PnP disagree, PnP's own noise is part of it (at a few
  // metres most of the rotation's): the robot's is what is left.
  const auto beyond_pnp = [](double seen_sigma, double pnp_variance) {
    return std::sqrt(std::max(0.0, seen_sigma * seen_sigma - pnp_variance));
  };
  prior.sigma_rad =
      std::max(beyond_pnp(Median(angle_rad) / 1.5382, Median(pnp_rotation_rad2)), 1e-5 * kDeg);
  // With few views per camera, T_cam_mount absorbs the flange's displacements across
  // the rays, which then look smaller than they are. A robot's pose error
  // comes from its joints, whose angle errors move the flange by about the
  // rotation error times the reach: the larger of the two.
  std::vector<double> reach_m;
  for (const RobotPose& pose : dataset.poses)
    reach_m.push_back(pose.T_base_ee.translation().norm());
  prior.sigma_m = std::max({beyond_pnp(across_sigma_m, pnp_across_variance_m2),
                            prior.sigma_rad * Median(reach_m), 1e-5});
  prior.pixel_sigma_px = DetectionSigmaPx(problem);
  return prior;
}

std::vector<Warning> PoseRecordWarnings(
    const Problem& problem, const std::vector<std::optional<Eigen::Isometry3d>>& T_cam_mount,
    const TargetPoses& T_holder_target) {
  const Dataset& dataset = *problem.dataset;
  const Eigen::Vector3d centre = TargetCentre(*dataset.target);
  std::vector<Warning> warnings;
  for (size_t j = 0; j < dataset.poses.size(); ++j) {
    std::vector<const View*> seen;  // views of the pose that had a target pose of their own
    bool all_inconsistent = true;
    for (const View& view : problem.views) {
      if (view.pose != static_cast<int>(j) || !view.T_cam_target) continue;
      seen.push_back(&view);
      all_inconsistent = all_inconsistent && view.inconsistent;
    }
    if (seen.empty() || !all_inconsistent) continue;
    double sum_mm = 0;
    int measured = 0;
    std::string cameras;
    for (const View* view : seen) {
      cameras += (cameras.empty() ? "" : ", ") + dataset.cameras[view->camera].name;
      if (!T_cam_mount[view->camera]) continue;
      // Where the robot record puts the target, against where the camera saw
      // it, both in the camera's mount frame.
      const Eigen::Vector3d by_robot =
          problem.T_mount_holder[j] * T_holder_target[view->camera] * centre;
      const Eigen::Vector3d by_camera =
          T_cam_mount[view->camera]->inverse() * *view->T_cam_target * centre;
      sum_mm += 1000.0 * (by_robot - by_camera).norm();
      ++measured;
    }
    std::ostringstream warning;
    warning << "pose " << dataset.poses[j].id << ": its robot record disagrees with "
            << (seen.size() == 1   ? "its only view"
                : seen.size() == 2 ? "both views"
                                   : "every view")
            << " (" << cameras << ")";
    if (measured) warning << " by ≈ " << std::lround(sum_mm / measured) << " mm";
    warning << ": the image and the pose likely do not belong together; its views were left out";
    warnings.push_back(
        PoseWarning(WarningKind::kPoseRecordMismatch, dataset.poses[j].id, warning.str()));
  }
  return warnings;
}

}  // namespace handeye::internal
