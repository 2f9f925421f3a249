// SPDX-License-Identifier: GPL-2.0-or-later
// OpenCV's FileStorage parsers, run where their recursion cannot overflow
// the stack, and the depth of the tree they built.
#include <pthread.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "filestorage_depth.h"

namespace handeye::internal {
namespace {

// OpenCV 4.6's parsers recurse once per level and a level takes at least one
// byte of text. Measured (Release and ASan builds): 50 000 levels of YAML
// '[' (one byte each) need between 8 and 16 MB of stack, i.e. at most
// 336 bytes a byte; XML needs less a byte. A kilobyte a byte is three times
// that.
constexpr std::size_t kStackPerTextByte = 1024;
constexpr std::size_t kBaseStack = std::size_t{8} << 20;

struct ParseJob {
  const std::string* text;
  int flags;
  cv::FileStorage storage;
  std::exception_ptr error;
};

void* RunParse(void* arg) {
  auto* job = static_cast<ParseJob*>(arg);
  try {
    job->storage.open(*job->text, job->flags);
  } catch (...) {
    job->error = std::current_exception();
  }
  return nullptr;
}

}  // namespace

cv::FileStorage ParseFileStorageText(const std::string& text, int flags) {
  if (text.size() > kMaxFileStorageTextBytes)
    throw std::length_error("longer than " + std::to_string(kMaxFileStorageTextBytes >> 20) +
                            " MB; an intrinsics file is a few kilobytes");
  ParseJob job{&text, flags, {}, nullptr};
  pthread_attr_t attributes;
  pthread_attr_init(&attributes);
  pthread_attr_setstacksize(&attributes, kBaseStack + kStackPerTextByte * text.size());
  pthread_t thread;
  const int failed = pthread_create(&thread, &attributes, RunParse, &job);
  pthread_attr_destroy(&attributes);
  if (failed != 0)
    throw std::runtime_error(std::string("no thread to read it on: ") + std::strerror(failed));
  pthread_join(thread, nullptr);
  if (job.error) std::rethrow_exception(job.error);
  return std::move(job.storage);
}

int FileStorageTreeDepth(const cv::FileNode& root) {
  // Walked with a list, not recursion: the tree may be as deep as the text
  // is long.
  int deepest = 0;
  std::vector<std::pair<cv::FileNode, int>> pending{{root, 1}};
  while (!pending.empty()) {
    const auto [node, depth] = pending.back();
    pending.pop_back();
    if (!node.isMap() && !node.isSeq()) continue;
    deepest = std::max(deepest, depth);
    for (auto it = node.begin(); it != node.end(); ++it) pending.emplace_back(*it, depth + 1);
  }
  return deepest;
}

}  // namespace handeye::internal
