// handeye — multi-camera hand-eye calibration.
// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once

#include <stdexcept>
#include <string>

namespace handeye {

/// Bad user input: a file, a JSON field or an image that is not what the format
/// requires. The message names the file, the JSON path (RFC 6901 pointer, e.g.
/// `/poses/3/T_base_ee`) and what was expected. Tools map it to exit code 2.
class InputError : public std::runtime_error {
 public:
  /// @param file        the offending file ("" while not yet known; see WithFile)
  /// @param json_path   JSON pointer inside that file ("" for the whole file)
  /// @param expected    what was expected or what is wrong, in plain words
  InputError(std::string file, std::string json_path, std::string expected);

  const std::string& file() const { return file_; }
  const std::string& json_path() const { return json_path_; }
  const std::string& expected() const { return expected_; }

  /// The same error attributed to `file`, with `path_prefix` put in front of
  /// the JSON path. Used where a nested parser does not know its file.
  InputError WithFile(const std::string& file, const std::string& path_prefix = "") const;

 private:
  std::string file_, json_path_, expected_;
};

/// The calibration could not be solved (too few views, degenerate motion, no
/// convergence). Tools map it to exit code 3.
class SolveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace handeye
