// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The setup-mistake detective's hypotheses and their scores
// (setup_scoring.cc): each usual mistake as a repair of the robot records,
// scored by how well a chain through the repaired records explains the views.

#include <Eigen/Geometry>
#include <limits>
#include <vector>

#include "problem.h"

namespace handeye::internal {

/// A camera is scored only with this many views: fewer leave a closed form
/// free to fit a wrong record set too.
constexpr size_t kMinScoredViews = 6;

enum class Mistake {
  kAsGiven,
  kInverted,          ///< T_ee_base given as T_base_ee (or the other setup)
  kTransposed,        ///< R_base_ee transposed, translation kept
  kXyzwReadAsWxyz,    ///< a quaternion x, y, z, w read as w, x, y, z
  kWxyzReadAsXyzw,    ///< and the reverse
  kTranslationScale,  ///< the robot's translations in another unit (× 1000, ÷ 1000)
  kTargetScale,       ///< the target's size off: camera motions scaled against the robot's
  kShifted,           ///< each image belongs to the next (or previous) pose record
};

struct Hypothesis {
  Mistake mistake = Mistake::kAsGiven;
  double scale = 1.0;  ///< kTranslationScale, kTargetScale: the records' translations × this
  int shift = 0;       ///< kShifted: the view of pose j takes the record of pose j + shift
};

/// How well a hypothesis explains the views.
struct Score {
  double median_rms_px = std::numeric_limits<double>::infinity();
  /// The median of what the chain adds to each view's own PnP fit,
  /// √(RMS² − PnP RMS²): the misfit of the records alone.
  double median_excess_px = std::numeric_limits<double>::infinity();
  int cameras = 0;  ///< cameras the closed form solved
  int views = 0;    ///< views in the median
  /// Per solved camera: |t| of T_mount_cam and of T_holder_target, metres.
  std::vector<double> camera_lever_m, target_lever_m;
};

/// The views the hypotheses are scored on (per camera with enough views, a
/// sample of them away from the first and last pose).
Problem ScoringProblem(const Problem& problem);

/// The records under `h` scored on `scoring`: through a closed-form chain
/// per camera, or with `refine` through chains refined from them.
Score ScoreOf(Problem scoring, const Hypothesis& h, bool refine = false);

/// The hypotheses worth scoring: every discrete mistake, and the target scale
/// the motions show when it is clearly not 1.
std::vector<Hypothesis> Hypotheses(const Problem& scoring);

/// A kTargetScale hypothesis' scale moved to where closed-form chains
/// (FitTargetScale) or refined ones (RefineTargetScale) explain the views
/// best, with its score; scored on `threads` threads.
void FitTargetScale(const Problem& scoring, int threads, Hypothesis* h, Score* score);
void RefineTargetScale(const Problem& scoring, int threads, Hypothesis* h, Score* score);

}  // namespace handeye::internal
