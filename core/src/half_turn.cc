// SPDX-License-Identifier: GPL-2.0-or-later
// Views of a 180°-ambiguous checkerboard (cols + rows even): no detector can
// tell its corner (0, 0) from the opposite one, so views seen turned may be
// numbered half a turn round. They are numbered alike here, from the robot's
// motions and the poses cameras share, before any view is judged.
#include <algorithm>
#include <map>

#include "handeye/core/checkerboard.h"
#include "handeye/core/transform.h"
#include "problem.h"

namespace handeye::internal {
namespace {

double AngleOf(const Eigen::Matrix3d& R) { return RotationVectorFromMatrix(R).norm(); }

/// How two views of one camera are numbered relative to each other: +1 alike,
/// -1 one of them half a turn round, 0 cannot tell. The rotation angle of the
/// target's motion seen by the camera equals the robot's whatever the
/// unknowns are; turned, it does not.
int Relation(const Problem& problem, const View& a, const View& b, const Eigen::Matrix3d& R_F) {
  const double moved = AngleOf(
      (problem.T_mount_holder[a.pose] * problem.T_mount_holder[b.pose].inverse()).rotation());
  const Eigen::Matrix3d R_a = a.T_cam_target->rotation(), R_b = b.T_cam_target->rotation();
  const double alike = std::abs(AngleOf(R_a * R_b.transpose()) - moved);
  const double turned = std::abs(AngleOf(R_a * R_F * R_b.transpose()) - moved);
  if (alike < 0.5 * turned) return 1;
  if (turned < 0.5 * alike) return -1;
  return 0;
}

/// A numbering of a camera's views (true: half a turn round from the
/// numbering of the view labelled false first) that agrees with the most
/// pair relations, by sweeps of majority votes from all alike.
std::vector<bool> LabelCamera(const Problem& problem, const std::vector<int>& ids,
                              const Eigen::Matrix3d& R_F) {
  const size_t n = ids.size();
  std::vector<std::vector<int>> relation(n, std::vector<int>(n, 0));
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b)
      relation[a][b] = relation[b][a] =
          Relation(problem, problem.views[ids[a]], problem.views[ids[b]], R_F);
  std::vector<bool> turned(n, false);
  for (int sweep = 0; sweep < 20; ++sweep) {
    bool changed = false;
    for (size_t a = 0; a < n; ++a) {
      int keep = 0, change = 0;  // relations each choice agrees with
      for (size_t b = 0; b < n; ++b) {
        if (b == a || relation[a][b] == 0) continue;
        const bool alike_now = turned[a] == turned[b];
        ((relation[a][b] > 0) == alike_now ? keep : change) += 1;
      }
      if (change > keep) {
        turned[a] = !turned[a];
        changed = true;
      }
    }
    if (!changed) break;
  }
  return turned;
}

/// How much the camera-to-camera rotation that the shared poses give varies
/// (sum of angles to the first, rad), with camera t's views turned `flip_t`
/// relative to their labels. `turned` holds each view's turn so far.
double SharedSpread(const Problem& problem, const std::vector<std::pair<int, int>>& shared,
                    const std::vector<bool>& turned, bool flip_t, const Eigen::Matrix3d& R_F) {
  auto R = [&](int v, bool extra) {
    const Eigen::Matrix3d R_v = problem.views[v].T_cam_target->rotation();
    return turned[v] != extra ? Eigen::Matrix3d(R_v * R_F) : R_v;
  };
  const Eigen::Matrix3d first = R(shared[0].first, false) * R(shared[0].second, flip_t).transpose();
  double spread = 0;
  for (const auto& [k, t] : shared)
    spread += RotationDistance(R(k, false) * R(t, flip_t).transpose(), first);
  return spread;
}

}  // namespace

std::optional<Eigen::Isometry3d> HalfTurnSymmetry(const Target& target) {
  const auto* board = dynamic_cast<const CheckerboardTarget*>(&target);
  if (!board || !board->IsAmbiguous()) return std::nullopt;
  // p ↦ 2c − p in the plane, c the middle of the corners: corner (i, j) onto
  // (cols − 1 − i, rows − 1 − j).
  const double s = board->square_size_m();
  Eigen::Isometry3d F = Eigen::Isometry3d::Identity();
  F.linear() = Eigen::Vector3d(-1, -1, 1).asDiagonal();
  F.translation() = Eigen::Vector3d((board->cols() - 1) * s, (board->rows() - 1) * s, 0);
  return F;
}

void FlipView(const Eigen::Isometry3d& F, View* view) {
  for (Eigen::Vector3d& p : view->p_target) p = F * p;
  if (view->T_cam_target) view->T_cam_target = *view->T_cam_target * F;
  view->flipped = !view->flipped;
}

int NumberViewsAlike(Problem* problem, const Eigen::Isometry3d& F) {
  const Eigen::Matrix3d R_F = F.rotation();
  const size_t num_cameras = problem->camera_views.size();
  std::vector<bool> turned(problem->views.size(), false);
  for (const std::vector<int>& ids : problem->camera_views) {
    const std::vector<bool> labels = LabelCamera(*problem, ids, R_F);
    for (size_t a = 0; a < ids.size(); ++a) turned[ids[a]] = labels[a];
  }
  // Cameras joined one at a time to those already numbered, through the
  // poses they share (each camera's numbering holds up to turning all its views).
  std::vector<std::map<int, int>> view_at_pose(num_cameras);
  for (size_t k = 0; k < num_cameras; ++k)
    for (int v : problem->camera_views[k]) view_at_pose[k][problem->views[v].pose] = v;
  std::vector<bool> joined(num_cameras, false);
  for (bool progress = true; progress;) {
    progress = false;
    for (size_t t = 0; t < num_cameras; ++t) {
      if (joined[t] || view_at_pose[t].empty()) continue;
      if (std::none_of(joined.begin(), joined.end(), [](bool j) { return j; })) {
        joined[t] = progress = true;  // the first camera with views sets the numbering
        continue;
      }
      for (size_t k = 0; k < num_cameras && !joined[t]; ++k) {
        if (!joined[k]) continue;
        std::vector<std::pair<int, int>> shared;
        for (const auto& [pose, v] : view_at_pose[t])
          if (const auto it = view_at_pose[k].find(pose); it != view_at_pose[k].end())
            shared.emplace_back(it->second, v);
        if (shared.size() < 2) continue;
        if (SharedSpread(*problem, shared, turned, true, R_F) <
            SharedSpread(*problem, shared, turned, false, R_F))
          for (int v : problem->camera_views[t]) turned[v] = !turned[v];
        joined[t] = progress = true;
      }
    }
  }
  // The board's numbering is a convention: turn the fewer views.
  size_t used = 0, count = 0;
  for (const std::vector<int>& ids : problem->camera_views)
    for (int v : ids) {
      ++used;
      count += turned[v] ? 1 : 0;
    }
  const bool flip_when = 2 * count <= used;  // flip the views whose label is this
  int flipped = 0;
  for (const std::vector<int>& ids : problem->camera_views)
    for (int v : ids) {
      if (turned[v] != flip_when) continue;
      FlipView(F, &problem->views[v]);
      ++flipped;
    }
  return flipped;
}

}  // namespace handeye::internal
