// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/atomic_file.h"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <random>
#include <set>

#include "handeye/core/error.h"

namespace handeye {
namespace {

namespace fs = std::filesystem;

// The temporaries in flight, and whether RemoveTemporariesInFlight ran: a
// folder exchange holds the mutex, so it never swaps in a staging folder that
// is being removed.
struct InFlightRegistry {
  std::mutex mutex;
  std::multiset<std::string> paths;
  bool removed = false;
};

InFlightRegistry& Registry() {
  // Never destroyed: the thread that handles an interrupt may still use it
  // while the program exits.
  static InFlightRegistry* const registry = new InFlightRegistry;
  return *registry;
}

// Removes a file or a whole folder. A folder that other threads still write
// into may gain a file between listing and rmdir: try a few times.
void RemoveAll(const std::string& path) {
  std::error_code ec;
  for (int attempt = 0; attempt < 20; ++attempt) {
    fs::remove_all(path, ec);
    if (!fs::exists(fs::symlink_status(path, ec))) return;
  }
}

// Writes the whole string to the open file, flushes it to disk and closes it;
// false (errno set) on any failure.
bool WriteAndClose(FILE* f, const std::string& content) {
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const bool flushed = written && std::fflush(f) == 0 && fsync(fileno(f)) == 0;
  const int saved = errno;
  const bool closed = std::fclose(f) == 0;
  if (!flushed) errno = saved;
  return written && flushed && closed;
}

// Puts `staging` in the place of `dir` (which exists); the old folder is then
// at `staging` (or already removed).
bool Exchange(const std::string& staging, const std::string& dir) {
  if (renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, dir.c_str(), RENAME_EXCHANGE) == 0)
    return true;
  if (errno != EINVAL && errno != ENOSYS) return false;
  // No RENAME_EXCHANGE on this file system: the old folder goes aside first,
  // so that there is never a mix of the two, only an instant without `dir`.
  const std::string aside = TemporarySibling(dir);
  if (std::rename(dir.c_str(), aside.c_str()) != 0) return false;
  if (std::rename(staging.c_str(), dir.c_str()) != 0) {
    const int saved = errno;
    std::rename(aside.c_str(), dir.c_str());
    errno = saved;
    return false;
  }
  RemoveAll(aside);
  return true;
}

}  // namespace

std::string TemporarySibling(const std::string& path) {
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::random_device rd;
  return (folder / ("." + target.filename().string() + ".tmp" + std::to_string(getpid()) + "-" +
                    std::to_string(rd())))
      .string();
}

TemporaryInFlight::TemporaryInFlight(std::string path) : path_(std::move(path)) {
  InFlightRegistry& registry = Registry();
  const std::lock_guard<std::mutex> lock(registry.mutex);
  registry.paths.insert(path_);
}

TemporaryInFlight::~TemporaryInFlight() {
  InFlightRegistry& registry = Registry();
  const std::lock_guard<std::mutex> lock(registry.mutex);
  const auto it = registry.paths.find(path_);
  if (it != registry.paths.end()) registry.paths.erase(it);
}

void RemoveTemporariesInFlight() {
  InFlightRegistry& registry = Registry();
  const std::lock_guard<std::mutex> lock(registry.mutex);
  registry.removed = true;
  for (const std::string& path : registry.paths) RemoveAll(path);
  registry.paths.clear();
}

void WriteFileAtomically(const std::string& path, const std::string& content) {
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(path, "", "cannot write: folder '" + folder.string() + "' does not exist");
  const std::string tmp = TemporarySibling(path);
  const TemporaryInFlight in_flight(tmp);
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw InputError(path, "", std::string("cannot write: ") + std::strerror(errno));
  // Whatever fails from here (the write, the rename), no temporary file stays.
  if (!WriteAndClose(f, content) || std::rename(tmp.c_str(), target.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    fs::remove(tmp, ec);
    throw InputError(path, "", "cannot write: " + reason);
  }
}

void ReplaceFolderAtomically(const std::string& dir,
                             const std::function<void(const std::string&)>& write) {
  const std::string staging = TemporarySibling(dir);
  const TemporaryInFlight in_flight(staging);
  try {
    write(staging);
    std::error_code ec;
    const bool replace = fs::exists(fs::symlink_status(dir, ec));
    InFlightRegistry& registry = Registry();
    const std::lock_guard<std::mutex> lock(registry.mutex);
    if (registry.removed) throw InputError(dir, "", "interrupted: the old folder is kept");
    if (replace ? !Exchange(staging, dir) : std::rename(staging.c_str(), dir.c_str()) != 0)
      throw InputError(dir, "",
                       std::string("cannot put the new folder in place: ") + std::strerror(errno));
  } catch (...) {
    RemoveAll(staging);
    throw;
  }
  // After the exchange the staging name holds the old folder.
  RemoveAll(staging);
}

}  // namespace handeye
