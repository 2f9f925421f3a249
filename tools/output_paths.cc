// SPDX-License-Identifier: GPL-2.0-or-later
#include "output_paths.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>

#include "handeye/core/error.h"
#include "handeye/io/atomic_file.h"

namespace handeye::tools {
namespace {

namespace fs = std::filesystem;

struct FileId {
  dev_t device;
  ino_t inode;
  bool operator==(const FileId& other) const {
    return device == other.device && inode == other.inode;
  }
};

// The identity of what `path` names, following symbolic links; none when it does not exist.
std::optional<FileId> IdOf(const fs::path& path) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileId{st.st_dev, st.st_ino};
}

// The path with every existing part resolved (links, "." and ".."), made
// absolute first: weakly_canonical leaves a relative path whose first part
// does not exist as it is, so "x.json" and "./x.json" would differ.
fs::path Canonical(const std::string& path, std::error_code* ec) {
  const fs::path absolute = fs::absolute(path, *ec);
  return *ec ? fs::path() : fs::weakly_canonical(absolute, *ec);
}

std::string Quoted(const NamedPath& named) { return named.option + " '" + named.path + "'"; }

// The same file: one identity, or (one of them not there yet) one canonical path.
bool SameFile(const std::string& a, const std::string& b) {
  const auto id_a = IdOf(a), id_b = IdOf(b);
  if (id_a && id_b) return *id_a == *id_b;
  std::error_code ec_a, ec_b;
  const fs::path canonical_a = Canonical(a, &ec_a), canonical_b = Canonical(b, &ec_b);
  return !ec_a && !ec_b && canonical_a == canonical_b;
}

fs::path FolderOf(const std::string& path) {
  const fs::path p(path);
  return p.has_parent_path() ? p.parent_path() : fs::path(".");
}

// A new file can be made in `folder`: tried, since permission bits do not
// tell (root, read-only mounts, ACLs).
void CheckFolderTakesFiles(const fs::path& folder, const NamedPath& output) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(
        output.path, "",
        output.option + ": cannot write: folder '" + folder.string() + "' does not exist");
  const std::string probe = TemporarySibling((folder / "probe").string());
  const TemporaryInFlight in_flight(probe);
  const int fd = open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0)
    throw InputError(output.path, "",
                     output.option + ": cannot write into folder '" + folder.string() +
                         "': " + std::strerror(errno));
  close(fd);
  unlink(probe.c_str());
}

void CheckNotAnInput(const std::vector<NamedPath>& inputs, const NamedPath& output) {
  for (const NamedPath& input : inputs)
    if (!input.path.empty() && SameFile(input.path, output.path))
      throw InputError(
          output.path, "",
          output.option + " names the input " + Quoted(input) +
              " (the same file): writing it would destroy the input; write to another file");
}

// The first of `paths` that is `folder` or lies inside it (at any depth),
// by canonical path or, for paths that exist, by the folders' identity.
const NamedPath* Inside(const std::vector<NamedPath>& paths, const std::string& folder) {
  std::error_code ec;
  fs::path canonical_folder = Canonical(folder, &ec);
  if (!canonical_folder.has_filename())
    canonical_folder = canonical_folder.parent_path();  // "out/"
  const auto folder_id = IdOf(folder);
  for (const NamedPath& named : paths) {
    if (named.path.empty()) continue;
    const fs::path canonical = Canonical(named.path, &ec);
    if (ec) continue;
    for (fs::path up = canonical;; up = up.parent_path()) {
      if (up == canonical_folder || (folder_id && IdOf(up) == folder_id)) return &named;
      if (up == up.parent_path()) break;
    }
  }
  return nullptr;
}

}  // namespace

void CheckFileOutputs(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& output = outputs[i];
    if (output.path.empty()) continue;
    CheckNotAnInput(inputs, output);
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].path.empty() && SameFile(outputs[j].path, output.path))
        throw InputError(
            output.path, "",
            output.option + " and " + Quoted(outputs[j]) + " name the same file; give two files");
    std::error_code ec;
    const fs::file_status status = fs::status(output.path, ec);
    if (fs::is_directory(status))
      throw InputError(output.path, "",
                       output.option + ": is a folder; expected the name of a file to write");
    if (fs::exists(status) && !fs::is_regular_file(status))
      throw InputError(output.path, "", output.option + ": exists and is not a regular file");
    CheckFolderTakesFiles(FolderOf(output.path), output);
  }
}

void CheckFolderOutput(const std::vector<NamedPath>& inputs,
                       const std::vector<NamedPath>& other_outputs, const NamedPath& output,
                       bool (*is_earlier)(const std::string& folder)) {
  if (output.path.empty()) return;
  std::error_code ec;
  const fs::file_status status = fs::status(output.path, ec);
  if (fs::exists(status) && !fs::is_directory(status))
    throw InputError(output.path, "", output.option + ": is a file; expected a folder to write");
  if (const NamedPath* input = Inside(inputs, output.path))
    throw InputError(
        output.path, "",
        output.option + " holds the input " + Quoted(*input) +
            "; the folder is replaced whole, which would destroy it: name another folder");
  if (const NamedPath* other = Inside(other_outputs, output.path))
    throw InputError(
        output.path, "",
        output.option + " holds the output " + Quoted(*other) +
            "; the folder is replaced whole, which would remove it: name another folder");
  if (fs::exists(status)) {
    if (!is_earlier(output.path))
      throw InputError(
          output.path, "",
          output.option +
              ": the folder exists and is not an earlier report; it is replaced whole, "
              "so name a new folder (or remove this one)");
  }
  fs::path folder = fs::absolute(output.path, ec).lexically_normal();
  if (!folder.has_filename()) folder = folder.parent_path();  // "out/"
  const fs::path parent = folder.parent_path();
  fs::create_directories(parent, ec);
  CheckFolderTakesFiles(parent, output);
}

std::vector<NamedPath> ImageInputs(const Dataset& dataset) {
  std::vector<NamedPath> images;
  for (const RobotPose& pose : dataset.poses)
    for (const auto& [camera, path] : pose.images) images.push_back({"image", path});
  return images;
}

}  // namespace handeye::tools
