// SPDX-License-Identifier: GPL-2.0-or-later
// Repeated views: the same image under several robot poses of one camera,
// found by their detected points (issue 28: every pose listing one image
// calibrated with exit 0, cameras 41 m off).
#include <map>
#include <set>

#include "handeye/core/error.h"
#include "problem.h"
#include "setup_mistakes.h"

namespace handeye::internal {
namespace {

/// ", all listing the file F" when the views' poses list one image file for the camera, else "".
std::string SameFile(const Problem& problem, const std::vector<int>& views) {
  const Dataset& dataset = *problem.dataset;
  std::set<std::string> files;
  for (int v : views) {
    const View& view = problem.views[v];
    const auto& images = dataset.poses[view.pose].images;
    const auto it = images.find(view.observation->camera);
    files.insert(it == images.end() ? "" : it->second);
  }
  if (files.size() != 1 || files.begin()->empty()) return "";
  return ", all listing the image file '" + *files.begin() + "'";
}

/// The poses of `views` but `except` (a view index, or -1), quoted, at most six named.
std::string PoseList(const Problem& problem, const std::vector<int>& views, int except) {
  std::string list;
  int named = 0, others = 0;
  for (int v : views) {
    if (v == except) continue;
    ++others;
    if (named < 6) list += (named++ ? ", '" : "'") + problem.views[v].observation->pose_id + "'";
  }
  if (others > named) list += " and " + std::to_string(others - named) + " more";
  return list;
}

}  // namespace

void LeaveOutRepeatedViews(Problem* problem) {
  const Dataset& dataset = *problem->dataset;
  int total = 0, repeated = 0;
  std::string example;
  for (size_t k = 0; k < dataset.cameras.size(); ++k) {
    // Views keyed by their points, ids and pixels exactly: real images of
    // two poses never agree to the last bit.
    std::map<std::vector<double>, std::vector<int>> by_points;
    for (size_t i = 0; i < problem->views.size(); ++i) {
      const View& view = problem->views[i];
      if (view.camera != static_cast<int>(k) || view.observation->ids.size() < 4) continue;
      ++total;
      std::vector<double> key;
      for (size_t p = 0; p < view.observation->ids.size(); ++p)
        key.insert(key.end(), {double(view.observation->ids[p]), view.observation->points_px[p].x(),
                               view.observation->points_px[p].y()});
      by_points[key].push_back(static_cast<int>(i));
    }
    for (const auto& [points, group] : by_points) {
      if (group.size() < 2) continue;
      repeated += static_cast<int>(group.size());
      const std::string file = SameFile(*problem, group);
      if (example.empty())
        example = "camera '" + dataset.cameras[k].name + "' at poses " +
                  PoseList(*problem, group, -1) + file;
      // Each left out view says which others repeat it (the result's warnings list them).
      for (int v : group) {
        problem->views[v].used = false;
        problem->views[v].rejected_because =
            "its detected points are identical to those of the same camera at pose(s) " +
            PoseList(*problem, group, v) + file +
            ": the same image under several robot poses (one file listed for several poses, or a "
            "camera that "
            "took no new picture), so it belongs to one of them at most";
      }
    }
  }
  if (repeated == 0) return;
  IndexUsedViews(problem);
  if (3 * repeated >= total)
    throw SolveError(
        std::to_string(repeated) + " of " + std::to_string(total) +
        " views repeat another view's detected points exactly (e.g. " + example +
        "): the same image under different robot poses, which no calibration can use; every pose "
        "needs its own picture: check the image paths of the poses (several may list one file). To "
        "calibrate the data as they are, pass --accept-setup");
}

}  // namespace handeye::internal
