// SPDX-License-Identifier: GPL-2.0-or-later
#include "support/test_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace handeye::test {

std::string TempDir(const std::string& name) {
  // ctest runs test cases in parallel processes, and several cases of one
  // file may ask for the same name: the process id keeps their folders apart.
  const std::filesystem::path dir =
      std::filesystem::path(HANDEYE_TEST_TMPDIR) / (name + "-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

void WriteText(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

namespace {

int RunCommand(const std::string& cmd, std::string* output) {
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + cmd);
  std::array<char, 4096> buf;
  std::string out;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

std::uint32_t Crc32(const std::uint8_t* data, std::size_t n) {
  std::uint32_t crc = 0xffffffffu;
  for (std::size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xffffffffu;
}

std::string HandeyeBinary() {
  const char* other = std::getenv("HANDEYE_TEST_BINARY");
  return other != nullptr && *other != '\0' ? other : HANDEYE_BINARY;
}

int RunHandeye(const std::string& args, std::string* output) {
  return RunCommand(HandeyeBinary() + " " + args + " 2>&1", output);
}

int RunHandeyeOnTerminal(const std::string& args, std::string* output) {
  if (args.find('"') != std::string::npos)
    throw std::invalid_argument("RunHandeyeOnTerminal: '\"' in the arguments");
  // -e: script exits with the program's exit code; the typescript file is
  // not wanted, the terminal's output comes through script's stdout.
  return RunCommand("script -qec \"" + HandeyeBinary() + " " + args + "\" /dev/null",
                    output);
}

}  // namespace handeye::test
