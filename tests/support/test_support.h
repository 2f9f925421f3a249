// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Helpers shared by the test programs.

#include <cstddef>
#include <cstdint>
#include <string>

namespace handeye::test {

/// A fresh, empty folder under the build tree for one test, unique to this
/// process (test cases run in parallel).
std::string TempDir(const std::string& name);
/// Writes text to a file (creating folders).
void WriteText(const std::string& path, const std::string& text);
/// The whole content of a file, byte for byte ("" when it cannot be read).
std::string ReadText(const std::string& path);
/// The handeye program the CLI tests run: the build's, or the one
/// HANDEYE_TEST_BINARY names.
std::string HandeyeBinary();
/// Runs the handeye program with arguments; returns its exit code and
/// fills *output with stdout+stderr. The program is the build's, or the one
/// HANDEYE_TEST_BINARY names: the CLI tests run against an older build show
/// which of them that build fails.
int RunHandeye(const std::string& args, std::string* output);
/// The same with stdout and stderr on a pseudo-terminal (util-linux
/// `script`), as when a person runs it; `args` must not contain '"'.
int RunHandeyeOnTerminal(const std::string& args, std::string* output);
/// The CRC-32 of PNG chunks (and zlib), for tests that write PNG bytes.
std::uint32_t Crc32(const std::uint8_t* data, std::size_t n);

}  // namespace handeye::test
