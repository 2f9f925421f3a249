// SPDX-License-Identifier: GPL-2.0-or-later
// Closed-form hand-eye: the adapters to OpenCV and ViSP (the only place their
// frame names appear), a linear shared-target solve over all cameras, and the
// initialisation of the joint solve.
#include "closed_form.h"

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/vision/vpHandEyeCalibration.h>

#include <Eigen/SVD>
#include <cstdio>
#include <iostream>
#include <limits>
#include <mutex>
#include <opencv2/calib3d.hpp>
#include <sstream>
#include <streambuf>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "motion_diversity.h"
#include "pose_consensus.h"
#include "problem.h"
#include "residuals.h"

namespace handeye::internal {
namespace {

cv::Mat RotationToCv(const Eigen::Isometry3d& T) {
  cv::Mat R(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R.at<double>(r, c) = T.rotation()(r, c);
  return R;
}

cv::Mat TranslationToCv(const Eigen::Isometry3d& T) {
  return (cv::Mat_<double>(3, 1) << T.translation().x(), T.translation().y(), T.translation().z());
}

std::optional<Eigen::Isometry3d> FromCv(const cv::Mat& R, const cv::Mat& t) {
  if (R.rows != 3 || R.cols != 3 || t.total() != 3) return std::nullopt;
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) M(r, c) = R.at<double>(r, c);
    M(r, 3) = t.at<double>(r);
  }
  std::string why;
  // Closed-form solvers return rotations that are orthonormal only to their
  // own numerical precision.
  return RigidFromMatrix(M, /*reorthonormalise=*/true, &why);
}

vpHomogeneousMatrix ToVisp(const Eigen::Isometry3d& T) {
  vpHomogeneousMatrix M;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) M[r][c] = T.rotation()(r, c);
    M[r][3] = T.translation()(r);
  }
  return M;
}

std::optional<Eigen::Isometry3d> FromVisp(const vpHomogeneousMatrix& V) {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = V[r][c];
  std::string why;
  return RigidFromMatrix(M, /*reorthonormalise=*/true, &why);
}

// ViSP 3.5 has one public hand-eye entry point, vpHandEyeCalibration::calibrate,
// and it always prints: printf for its headings, std::cout for its residuals
// (calibrationVerifrMo). A library must not write to stdout, and must not
// touch the process's file descriptors either (another thread, a child
// process or an embedding program such as Python may own fd 1). So for the
// call both of the process's C++ and C stdout streams point at a sink that
// drops everything: std::cout gets another buffer, and glibc's `stdout`
// (an ordinary variable there, which printf reads at each call) another
// FILE. The streams stay swapped while any thread is in such a call (the
// setup checks run ViSP on several threads at once): the first in swaps
// them, the last out puts back what the process had; the sinks hold no
// state. Whatever another thread prints to std::cout or stdout meanwhile is
// lost (documented on kVisp); writes straight to fd 1 are not affected.
class NullBuffer : public std::streambuf {
 protected:
  int_type overflow(int_type c) override { return traits_type::not_eof(c); }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

ssize_t DropWrite(void*, const char*, size_t size) { return static_cast<ssize_t>(size); }

class SilencedStdout {
 public:
  SilencedStdout() {
    Swap& swap = TheSwap();
    const std::lock_guard<std::mutex> lock(swap.mutex);
    if (swap.users++ > 0) return;
    swap.saved_buffer = std::cout.rdbuf(&swap.null_buffer);
    cookie_io_functions_t drop{};
    drop.write = DropWrite;
    swap.sink = fopencookie(nullptr, "w", drop);
    if (swap.sink != nullptr) {
      swap.saved_stdout = stdout;
      stdout = swap.sink;
    }
  }
  ~SilencedStdout() {
    Swap& swap = TheSwap();
    const std::lock_guard<std::mutex> lock(swap.mutex);
    if (--swap.users > 0) return;
    std::cout.rdbuf(swap.saved_buffer);
    if (swap.sink != nullptr) {
      stdout = swap.saved_stdout;
      std::fclose(swap.sink);
      swap.sink = nullptr;
    }
  }
  SilencedStdout(const SilencedStdout&) = delete;
  SilencedStdout& operator=(const SilencedStdout&) = delete;

 private:
  struct Swap {
    std::mutex mutex;
    int users = 0;  ///< threads inside a silenced call
    NullBuffer null_buffer;
    std::streambuf* saved_buffer = nullptr;
    FILE* sink = nullptr;
    FILE* saved_stdout = nullptr;
  };
  static Swap& TheSwap() {
    static Swap swap;
    return swap;
  }
};

// ViSP solves rMe[j] · eMc · cMo[j] = const. eye_in_hand is its native case
// (rMe = T_holder_mount, eMc = T_mount_cam); for eye_to_hand the target rides
// on the robot, so rMe = T_mount_holder and eMc = T_holder_target with cMo = T_target_cam.
std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> VispHandEye(const Problem& problem,
                                                                           int camera,
                                                                           std::string* why) {
  const bool eye_to_hand = problem.dataset->setup == Setup::kEyeToHand;
  std::vector<vpHomogeneousMatrix> rMe, cMo;
  for (int v : problem.camera_views[camera]) {
    const View& view = problem.views[v];
    if (eye_to_hand) {
      rMe.push_back(ToVisp(problem.T_mount_holder[view.pose]));
      cMo.push_back(ToVisp(view.T_cam_target->inverse()));
    } else {
      rMe.push_back(ToVisp(problem.T_mount_holder[view.pose].inverse()));
      cMo.push_back(ToVisp(*view.T_cam_target));
    }
  }
  vpHomogeneousMatrix eMc;
  int status = -1;
  try {
    const SilencedStdout silenced;
    status = vpHandEyeCalibration::calibrate(cMo, rMe, eMc);
  } catch (const std::exception& e) {
    *why = std::string("ViSP failed: ") + e.what();
    return std::nullopt;
  }
  const auto solved = FromVisp(eMc);
  if (status != 0 || !solved) {
    *why = "ViSP hand-eye calibration did not find a solution";
    return std::nullopt;
  }
  if (eye_to_hand) {
    const auto T_cam_mount = CameraGivenTarget(problem, camera, *solved);
    return std::make_pair(*T_cam_mount, *solved);
  }
  const Eigen::Isometry3d T_cam_mount = solved->inverse();
  return std::make_pair(T_cam_mount, *TargetGivenCamera(problem, camera, T_cam_mount));
}

/// OpenCV 4.6's Tsai, Horaud and Daniilidis forms go wrong on motion pairs
/// whose rotation is large: Tsai's linear system is near singular towards a
/// half turn, and Horaud's and Daniilidis' (dual) quaternions of the two
/// motions of a pair may come out with opposite signs once the rotation
/// passes 120° (OpenCV issue 24871, fixed in 4.10). A camera's views easily
/// span more, turned about the board's normal: on a rendered small
/// eye_to_hand cell with exact data they were 1.8-3.2 m off. These forms get
/// the largest set of the camera's views within kHalfSpread of one of them
/// (every pair then within 2 · kHalfSpread), or every view when that set has
/// fewer than three.
constexpr double kHalfSpreadRad = 55.0 * M_PI / 180.0;

std::vector<int> ViewsWithinSpread(const Problem& problem, int camera) {
  const std::vector<int>& all = problem.camera_views[camera];
  std::vector<int> best;
  for (int r : all) {
    const Eigen::Matrix3d R_r = problem.T_mount_holder[problem.views[r].pose].rotation();
    std::vector<int> near;
    for (int v : all)
      if (RotationDistance(problem.T_mount_holder[problem.views[v].pose].rotation(), R_r) <=
          kHalfSpreadRad)
        near.push_back(v);
    if (near.size() > best.size()) best = std::move(near);
  }
  return best.size() >= 3 ? best : all;
}

// Both setups map onto OpenCV's eye-in-hand form by passing T_holder_mount as
// "gripper2base": T_holder_mount[j] · T_mount_cam · T_cam_target[j] = T_holder_target for every j.
std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> OpenCvHandEye(
    const Problem& problem, int camera, cv::HandEyeCalibrationMethod method, std::string* why) {
  std::vector<cv::Mat> R_gripper2base, t_gripper2base, R_target2cam, t_target2cam;
  const bool spread_limited = method == cv::CALIB_HAND_EYE_TSAI ||
                              method == cv::CALIB_HAND_EYE_HORAUD ||
                              method == cv::CALIB_HAND_EYE_DANIILIDIS;
  for (int v : spread_limited ? ViewsWithinSpread(problem, camera) : problem.camera_views[camera]) {
    const View& view = problem.views[v];
    const Eigen::Isometry3d T_holder_mount = problem.T_mount_holder[view.pose].inverse();
    R_gripper2base.push_back(RotationToCv(T_holder_mount));
    t_gripper2base.push_back(TranslationToCv(T_holder_mount));
    R_target2cam.push_back(RotationToCv(*view.T_cam_target));
    t_target2cam.push_back(TranslationToCv(*view.T_cam_target));
  }
  cv::Mat R_cam2gripper, t_cam2gripper;
  try {
    cv::calibrateHandEye(R_gripper2base, t_gripper2base, R_target2cam, t_target2cam, R_cam2gripper,
                         t_cam2gripper, method);
  } catch (const cv::Exception& e) {
    *why = std::string("OpenCV calibrateHandEye failed: ") + e.what();
    return std::nullopt;
  }
  const auto T_mount_cam = FromCv(R_cam2gripper, t_cam2gripper);
  if (!T_mount_cam) {
    *why = "OpenCV calibrateHandEye returned no rigid transform (NaN or degenerate)";
    return std::nullopt;
  }
  const Eigen::Isometry3d T_cam_mount = T_mount_cam->inverse();
  return std::make_pair(T_cam_mount, *TargetGivenCamera(problem, camera, T_cam_mount));
}

// OpenCV's robot-world form cTw · wTb = cTg · gTb with c = target, w = camera,
// g·b = T_holder_mount: T_target_cam[j] · T_cam_mount = T_target_holder · T_holder_mount[j].
std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> OpenCvRobotWorld(
    const Problem& problem, int camera, cv::RobotWorldHandEyeCalibrationMethod method,
    std::string* why) {
  std::vector<cv::Mat> R_world2cam, t_world2cam, R_base2gripper, t_base2gripper;
  for (int v : problem.camera_views[camera]) {
    const View& view = problem.views[v];
    const Eigen::Isometry3d T_target_cam = view.T_cam_target->inverse();
    const Eigen::Isometry3d T_holder_mount = problem.T_mount_holder[view.pose].inverse();
    R_world2cam.push_back(RotationToCv(T_target_cam));
    t_world2cam.push_back(TranslationToCv(T_target_cam));
    R_base2gripper.push_back(RotationToCv(T_holder_mount));
    t_base2gripper.push_back(TranslationToCv(T_holder_mount));
  }
  cv::Mat R_base2world, t_base2world, R_gripper2cam, t_gripper2cam;
  try {
    cv::calibrateRobotWorldHandEye(R_world2cam, t_world2cam, R_base2gripper, t_base2gripper,
                                   R_base2world, t_base2world, R_gripper2cam, t_gripper2cam,
                                   method);
  } catch (const cv::Exception& e) {
    *why = std::string("OpenCV calibrateRobotWorldHandEye failed: ") + e.what();
    return std::nullopt;
  }
  const auto T_cam_mount = FromCv(R_base2world, t_base2world);
  const auto T_target_holder = FromCv(R_gripper2cam, t_gripper2cam);
  if (!T_cam_mount || !T_target_holder) {
    *why = "OpenCV calibrateRobotWorldHandEye returned no rigid transform (NaN or degenerate)";
    return std::nullopt;
  }
  return std::make_pair(*T_cam_mount, T_target_holder->inverse());
}

}  // namespace

std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> ClosedFormHandEye(
    const Problem& problem, int camera, Method method, std::string* why) {
  if (problem.camera_views[camera].size() < 3) {
    *why = "fewer than 3 usable views";
    return std::nullopt;
  }
  const std::string degenerate = MotionDiversityProblem(problem, {camera});
  if (!degenerate.empty()) {
    *why = degenerate;
    return std::nullopt;
  }
  switch (method) {
    case Method::kTsai:
      return OpenCvHandEye(problem, camera, cv::CALIB_HAND_EYE_TSAI, why);
    case Method::kPark:
      return OpenCvHandEye(problem, camera, cv::CALIB_HAND_EYE_PARK, why);
    case Method::kHoraud:
      return OpenCvHandEye(problem, camera, cv::CALIB_HAND_EYE_HORAUD, why);
    case Method::kAndreff:
      return OpenCvHandEye(problem, camera, cv::CALIB_HAND_EYE_ANDREFF, why);
    case Method::kDaniilidis:
      return OpenCvHandEye(problem, camera, cv::CALIB_HAND_EYE_DANIILIDIS, why);
    case Method::kShah:
      return OpenCvRobotWorld(problem, camera, cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH, why);
    case Method::kLi:
      return OpenCvRobotWorld(problem, camera, cv::CALIB_ROBOT_WORLD_HAND_EYE_LI, why);
    case Method::kVisp:
      return VispHandEye(problem, camera, why);
    default:
      *why = "not a closed-form method";
      return std::nullopt;
  }
}

std::vector<NamedClosedForm> SilentClosedForms(const Problem& problem, int camera, std::string* why,
                                               ClosedForms which) {
  // Park (rotation on the Lie group), Tsai (rotation axes) and ViSP (Tsai's
  // rotation refined by virtual visual servoing, the paper's initialisation)
  // fail in different ways on poor motion sets. None of them prints (ViSP's
  // output is dropped by SilencedStdout).
  std::vector<NamedClosedForm> solved;
  for (const Method method : {Method::kPark, Method::kTsai, Method::kVisp}) {
    if (method == Method::kVisp && which == ClosedForms::kOpenCvOnly) continue;
    std::string failed;
    if (auto one = ClosedFormHandEye(problem, camera, method, &failed))
      solved.push_back({MethodName(method), one->first, one->second});
    else if (solved.empty())
      *why = failed;
  }
  return solved;
}

std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> SilentClosedFormHandEye(
    const Problem& problem, int camera, std::string* chosen, std::string* why, ClosedForms which) {
  // Keep the closed form whose chain explains this camera's views best.
  std::optional<std::pair<Eigen::Isometry3d, Eigen::Isometry3d>> best;
  double best_score = std::numeric_limits<double>::infinity();
  std::vector<std::optional<Eigen::Isometry3d>> T_cam_mount(problem.camera_views.size());
  for (const NamedClosedForm& candidate : SilentClosedForms(problem, camera, why, which)) {
    T_cam_mount[camera] = candidate.T_cam_mount;
    const double score = MedianViewRms(problem, T_cam_mount, candidate.T_holder_target);
    if (!best || score < best_score) {
      best = std::make_pair(candidate.T_cam_mount, candidate.T_holder_target);
      best_score = score;
      *chosen = candidate.method;
    }
  }
  return best;
}

std::optional<Eigen::Isometry3d> SharedTargetClosedForm(const Problem& problem) {
  // For two views a, b of one camera, W = T_target_holder satisfies A·W = W·B with
  // A = T_cam_target[b]⁻¹ · T_cam_target[a] and B = T_holder_mount[b] · T_mount_holder[a].
  std::vector<Eigen::Isometry3d> A, B;
  for (const auto& ids : problem.camera_views)
    for (size_t a = 0; a < ids.size(); ++a)
      for (size_t b = a + 1; b < ids.size() && b <= a + 8; ++b) {
        const View& va = problem.views[ids[a]];
        const View& vb = problem.views[ids[b]];
        A.push_back(vb.T_cam_target->inverse() * *va.T_cam_target);
        B.push_back(problem.T_mount_holder[vb.pose].inverse() * problem.T_mount_holder[va.pose]);
      }
  if (A.size() < 2) return std::nullopt;
  // Rotation: the axes (rotation vectors) satisfy a_i = R_W · b_i (Kabsch).
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < A.size(); ++i)
    H += RotationVectorFromMatrix(B[i].rotation()) *
         RotationVectorFromMatrix(A[i].rotation()).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Matrix3d R_W = svd.matrixV() * D * svd.matrixU().transpose();
  // Translation: (R_A − I) t_W = R_W t_B − t_A, stacked.
  Eigen::MatrixXd C(3 * A.size(), 3);
  Eigen::VectorXd d(3 * A.size());
  for (size_t i = 0; i < A.size(); ++i) {
    C.block<3, 3>(3 * i, 0) = A[i].rotation() - Eigen::Matrix3d::Identity();
    d.segment<3>(3 * i) = R_W * B[i].translation() - A[i].translation();
  }
  const Eigen::Vector3d t_W = C.colPivHouseholderQr().solve(d);
  if (!R_W.allFinite() || !t_W.allFinite()) return std::nullopt;
  Eigen::Isometry3d W = Eigen::Isometry3d::Identity();
  W.linear() = R_W;
  W.translation() = t_W;
  return W.inverse();
}

Problem WithDiverseViews(const Problem& problem, size_t max_views) {
  Problem out = problem;
  for (auto& ids : out.camera_views) {
    if (ids.size() <= max_views) continue;
    std::vector<int> chosen = {ids.front()};
    std::vector<double> nearest(ids.size(), std::numeric_limits<double>::infinity());
    while (chosen.size() < max_views) {
      const Eigen::Matrix3d last =
          problem.T_mount_holder[problem.views[chosen.back()].pose].linear();
      size_t best = 0;
      for (size_t i = 0; i < ids.size(); ++i) {
        const Eigen::Matrix3d R = problem.T_mount_holder[problem.views[ids[i]].pose].linear();
        nearest[i] = std::min(nearest[i], RotationDistance(last, R));
        if (nearest[i] > nearest[best]) best = i;
      }
      chosen.push_back(ids[best]);
      nearest[best] = 0.0;
    }
    ids = chosen;
  }
  return out;
}

Initialisation InitialiseJoint(const Problem& full_problem) {
  // Closed forms initialise from a dozen diverse views per camera; the
  // refinement then uses every view.
  const Problem problem = WithDiverseViews(full_problem, 12);
  const size_t num_cameras = problem.camera_views.size();
  // Candidates for the shared T_holder_target: a closed form per camera where a camera has
  // the motions for it, and the linear solve over all cameras. None of them
  // may print (Calibrate() is reentrant and writes nothing to stdout).
  // Every closed form of every camera is a candidate of its own: the one that
  // fits its camera best need not be the one whose target explains all views best.
  std::vector<std::pair<std::string, Eigen::Isometry3d>> candidates;
  for (size_t k = 0; k < num_cameras; ++k) {
    std::string why;
    for (const NamedClosedForm& solved : SilentClosedForms(problem, static_cast<int>(k), &why))
      candidates.emplace_back(
          solved.method + " on camera '" + problem.dataset->cameras[k].name + "'",
          solved.T_holder_target);
  }
  if (const auto shared = SharedTargetClosedForm(problem))
    candidates.emplace_back("linear solve over all cameras", *shared);
  if (candidates.empty())
    throw SolveError("no closed-form initialisation: no camera has 3 views with diverse rotations");

  // Keep the candidate whose chain explains the views best (median view RMS):
  // robust to one camera with poor views.
  Initialisation best;
  double best_score = std::numeric_limits<double>::infinity();
  std::string best_name;
  for (const auto& [name, T_holder_target] : candidates) {
    Initialisation init;
    init.T_holder_target = T_holder_target;
    for (size_t k = 0; k < num_cameras; ++k)
      init.T_cam_mount.push_back(
          CameraGivenTarget(full_problem, static_cast<int>(k), T_holder_target));
    const double score = MedianViewRms(full_problem, init.T_cam_mount, T_holder_target);
    if (score < best_score) {
      best_score = score;
      best = init;
      best_name = name;
    }
  }
  std::ostringstream note;
  note.precision(3);  // a note is read by a person: 0.0398 px, not 0.0397717
  note << "initialised from " << best_name << " (median view RMS " << best_score << " px, "
       << candidates.size() << " candidates)";
  best.notes.push_back(note.str());
  return best;
}

}  // namespace handeye::internal
