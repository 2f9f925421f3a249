// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// OpenCV FileStorage text, checked before OpenCV reads it. How deeply it
// nests: OpenCV 4.6's YAML, JSON and XML parsers recurse once per level with
// no limit, and a 100 KB file nested 50 000 deep overflows the stack.
// Internal to the io library (and its fuzz targets).

#include <opencv2/core/persistence.hpp>
#include <string>

namespace handeye::internal {

/// The text forms OpenCV's FileStorage reads.
enum class FileStorageSyntax { kYaml, kJson, kXml };

/// A first, quick measure of the nesting, made before OpenCV reads the text:
/// the deepest nesting of collections (YAML block and flow mappings and
/// sequences, JSON objects and arrays, XML elements) in `text`, following
/// where OpenCV's parsers see a collection open and close (quoted strings,
/// flow-map keys, YAML `a: b: c` on one line). Never less than OpenCV's
/// own depth for the texts fuzz/run and the tests have tried; where a text
/// outwits it, ParseFileStorageText still cannot overflow the stack and
/// FileStorageTreeDepth still refuses the tree.
/// Stops as soon as the depth passes `stop_above` and returns that depth.
int FileStorageNestingDepth(const std::string& text, FileStorageSyntax syntax, int stop_above);

/// The deepest nesting OpenCV FileStorage text may have. An intrinsics file
/// nests 3 levels (root, matrix, data); 64 is also the limit of the YAML
/// loader of the ROS and Kalibr files.
constexpr int kMaxFileStorageDepth = 64;

/// OpenCV FileStorage text (XML when it starts with '<', JSON with '{',
/// else YAML, with or without the %YAML header) opened in memory, after the
/// checks that keep OpenCV 4.6's parsers from crashing or looping: no NUL
/// byte, no base64 value, one YAML mapping, an XML text that ends with a
/// tag, and nesting of at most kMaxFileStorageDepth (FileStorageNestingDepth).
/// Throws InputError(path, "", ...) for each, and when OpenCV refuses it.
/// The tree OpenCV builds is measured again (FileStorageTreeDepth) and
/// refused when deeper than kMaxFileStorageDepth.
cv::FileStorage OpenFileStorageText(std::string text, const std::string& path);

/// The longest FileStorage text read (ParseFileStorageText).
constexpr std::size_t kMaxFileStorageTextBytes = std::size_t{1} << 20;

/// cv::FileStorage::open(text, flags) on a thread of its own whose stack
/// holds OpenCV's recursion however deep the text nests (a level per byte at
/// most). Rethrows what OpenCV throws; throws std::length_error for a text
/// over kMaxFileStorageTextBytes and std::runtime_error when no such thread
/// can be made.
cv::FileStorage ParseFileStorageText(const std::string& text, int flags);

/// The depth of the collections under `root` (a scalar 0, a mapping of
/// scalars 1), counted without recursion.
int FileStorageTreeDepth(const cv::FileNode& root);

}  // namespace handeye::internal
