// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The setup-mistake detective (issue 24): the mistakes users of hand-eye
// tools make most, tried against the views before the solve, and the robot
// error after it that no real robot has. Each names the mistake and the fix
// instead of letting the robot model absorb it.

#include <limits>
#include <string>
#include <vector>

#include "problem.h"
#include "robot_error.h"

namespace handeye::internal {

/// A setup mistake explains the views this many times better than the data
/// as given (median view RMS through a closed-form chain) before it is named.
constexpr double kMistakeRatio = 5.0;
/// A repair the closed forms favour by this much, but not by kMistakeRatio,
/// is scored again through chains refined from them (JudgeSetup), and named
/// where it explains the views kRefinedMistakeRatio times better there. A
/// refined chain leaves only the misfit: on rendered cameras whose
/// distortion was left out, 1.1-1.4 px for correct records and 5.7-6.5 px
/// for a target declared 10 % off in size (closed forms: 4-7 px and 12-21 px).
constexpr double kRefineRatio = 1.25;
constexpr double kRefinedMistakeRatio = 4.0;

/// Views of a camera whose detected points are identical, point for point, to
/// another view of the same camera: the same image under several robot poses
/// (one file listed twice, or a camera that did not take a new picture).
/// Detection noise alone makes two real images differ, so they are left out
/// (the image belongs to one of the poses at most), each naming the others.
/// Throws SolveError when they are a third of the views or more: the solve
/// would then calibrate against one picture.
void LeaveOutRepeatedViews(Problem* problem);

/// What the setup checks found: the data as given and the best repair,
/// scored (median view RMS through a closed-form chain, pixels).
struct SetupVerdict {
  double given_px = 0;
  double best_px = std::numeric_limits<double>::infinity();  ///< the best repair's score
  std::string best;                                          ///< the best repair, in words
  std::string mistake;  ///< the message when it is called a mistake; empty otherwise
};
/// The judgement CheckSetupMistakes acts on (see there), the hypotheses
/// scored on `threads` threads (0 = all cores).
SetupVerdict JudgeSetup(const Problem& problem, int threads);

/// Tries each usual mistake against the views' PnP poses: robot poses
/// inverted (or the setup swapped, which fits the same chain), rotation
/// transposed, quaternion order swapped, translations 1000× off, the target's
/// size off (the scale the camera and robot motions disagree by), images one
/// pose early or late. Each repairs the robot records, a closed form solves
/// every camera again, and the median view RMS through its chain scores it.
/// Throws SolveError naming the mistake and its fix when one scores
/// kMistakeRatio times better than the data as given; else returns a note
/// of what it found (for the result's notes).
std::string CheckSetupMistakes(const Problem& problem, int threads);

/// Whether a robot pose error of σ per axis (m, rad) is one an industrial
/// robot can have: ≤ 5 mm and ≤ 0.5°.
bool RobotSigmaPlausible(double sigma_m, double sigma_rad);

/// RobotSigmaPlausible of the σ the robot's solved pose blocks show where it
/// was settled, else of the prior's: the σ CheckRobotSigma judges.
bool RobotPlausible(const RobotPrior& robot);

/// Throws SolveError when the robot's pose error, estimated from the views,
/// is larger than any industrial robot's (σ > 5 mm or > 0.5° per axis): a
/// misfit of that size is a setup mistake the checks above did not name, not
/// the robot's.
void CheckRobotSigma(const RobotPrior& robot);

}  // namespace handeye::internal
