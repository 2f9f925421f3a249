// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>

#include "handeye/core/error.h"

namespace handeye {

void WriteFileAtomically(const std::string& path, const std::string& content) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(path, "", "cannot write: folder '" + folder.string() + "' does not exist");
  // Unique name in the same folder so rename() is atomic on the same file system.
  std::random_device rd;
  const fs::path tmp = folder / ("." + target.filename().string() + ".tmp" +
                                 std::to_string(getpid()) + "-" + std::to_string(rd()));
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw InputError(path, "", std::string("cannot write: ") + std::strerror(errno));
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const bool flushed = std::fflush(f) == 0 && fsync(fileno(f)) == 0;
  const bool closed = std::fclose(f) == 0;
  if (!written || !flushed || !closed) {
    const std::string reason = std::strerror(errno);
    fs::remove(tmp, ec);
    throw InputError(path, "", "cannot write: " + reason);
  }
  if (std::rename(tmp.c_str(), target.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    fs::remove(tmp, ec);
    throw InputError(path, "", "cannot write: " + reason);
  }
}

}  // namespace handeye
