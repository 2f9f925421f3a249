// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/core/error.h"

namespace handeye {
namespace {

std::string Compose(const std::string& file, const std::string& json_path,
                    const std::string& expected) {
  std::string msg;
  if (!file.empty()) msg += file;
  if (!json_path.empty()) msg += (msg.empty() ? "at " : ": at ") + json_path;
  if (!msg.empty()) msg += ": ";
  return msg + expected;
}

}  // namespace

InputError::InputError(std::string file, std::string json_path, std::string expected)
    : std::runtime_error(Compose(file, json_path, expected)),
      file_(std::move(file)),
      json_path_(std::move(json_path)),
      expected_(std::move(expected)) {}

InputError InputError::WithFile(const std::string& file, const std::string& path_prefix) const {
  return InputError(file, path_prefix + json_path_, expected_);
}

}  // namespace handeye
