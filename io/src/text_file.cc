// SPDX-License-Identifier: GPL-2.0-or-later
#include "text_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "handeye/core/error.h"

namespace handeye::internal {

std::string ReadTextFile(const std::string& path, const std::string& expected) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "", "file does not exist");
  if (fs::is_directory(path, ec)) throw InputError(path, "", "is a folder; expected " + expected);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", std::string("cannot read: ") + std::strerror(errno));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path, "", std::string("cannot read: ") + std::strerror(errno));
  return text;
}

}  // namespace handeye::internal
