// SPDX-License-Identifier: GPL-2.0-or-later
// Repeated image files: the same picture under several robot poses.
#include "handeye/io/repeated_images.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>

namespace handeye {
namespace {

/// Bytes read to tell two files of one size apart before reading them whole.
constexpr std::streamsize kPrefixBytes = 64 * 1024;

/// FNV-1a over the file's first `limit` bytes (all of it for a negative
/// limit); nullopt when it cannot be read.
std::optional<std::uint64_t> HashOf(const std::string& path, std::streamsize limit) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::uint64_t hash = 14695981039346656037ull;
  std::vector<char> buffer(kPrefixBytes);
  std::streamsize left = limit < 0 ? std::numeric_limits<std::streamsize>::max() : limit;
  while (left > 0 && in) {
    in.read(buffer.data(), std::min<std::streamsize>(left, kPrefixBytes));
    const std::streamsize got = in.gcount();
    if (got <= 0) break;
    for (std::streamsize i = 0; i < got; ++i) {
      hash ^= static_cast<unsigned char>(buffer[i]);
      hash *= 1099511628211ull;
    }
    left -= got;
  }
  if (in.bad()) return std::nullopt;
  return hash;
}

/// Splits each group of poses (indices into `paths`) by `key`; groups of one
/// are dropped. A key of nullopt drops the pose.
template <typename Key>
std::vector<std::vector<size_t>> SplitBy(const std::vector<std::vector<size_t>>& groups,
                                         const std::function<std::optional<Key>(size_t)>& key) {
  std::vector<std::vector<size_t>> out;
  for (const auto& group : groups) {
    std::map<Key, std::vector<size_t>> by_key;
    for (size_t i : group)
      if (const auto k = key(i)) by_key[*k].push_back(i);
    for (auto& [k, members] : by_key)
      if (members.size() > 1) out.push_back(std::move(members));
  }
  return out;
}

/// "'a', 'b' and 3 more" of at most six names.
std::string Named(const std::vector<std::string>& names) {
  std::string list;
  for (size_t i = 0; i < names.size() && i < 6; ++i) list += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > 6) list += " and " + std::to_string(names.size() - 6) + " more";
  return list;
}

}  // namespace

std::vector<Warning> RepeatedImageWarnings(const Dataset& dataset) {
  std::vector<Warning> warnings;
  for (const Camera& camera : dataset.cameras) {
    std::vector<std::string> poses, paths;
    for (const RobotPose& pose : dataset.poses) {
      const auto it = pose.images.find(camera.name);
      if (it == pose.images.end()) continue;
      poses.push_back(pose.id);
      paths.push_back(std::filesystem::path(it->second).lexically_normal().string());
    }
    if (paths.size() < 2) continue;
    std::vector<size_t> all(paths.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    // Alike by size, then by their first bytes, then by all of them: most
    // files are told apart without being read, few are read whole.
    const std::function<std::optional<std::uintmax_t>(size_t)> size = [&](size_t i) {
      std::error_code ec;
      const std::uintmax_t bytes = std::filesystem::file_size(paths[i], ec);
      return ec ? std::nullopt : std::optional<std::uintmax_t>(bytes);
    };
    const std::function<std::optional<std::uint64_t>(size_t)> prefix = [&](size_t i) {
      return HashOf(paths[i], kPrefixBytes);
    };
    const std::function<std::optional<std::uint64_t>(size_t)> whole = [&](size_t i) {
      return HashOf(paths[i], -1);
    };
    const auto groups = SplitBy(SplitBy(SplitBy<std::uintmax_t>({all}, size), prefix), whole);
    for (const auto& group : groups) {
      std::vector<std::string> group_poses, group_files;
      for (size_t i : group) {
        group_poses.push_back(poses[i]);
        if (std::find(group_files.begin(), group_files.end(), paths[i]) == group_files.end())
          group_files.push_back(paths[i]);
      }
      warnings.push_back(CameraWarning(WarningKind::kRepeatedImages, camera.name,
                         "camera '" + camera.name + "': the images of poses " + Named(group_poses) +
                         (group_files.size() == 1
                              ? " are one file, " + Named(group_files)
                              : " are byte for byte the same (" + Named(group_files) + ")") +
                         ": one picture under " + std::to_string(group.size()) +
                         " robot poses; every pose needs its own image"));
    }
  }
  return warnings;
}

}  // namespace handeye
