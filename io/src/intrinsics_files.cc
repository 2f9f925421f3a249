// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/intrinsics_files.h"

#include <cctype>
#include <cmath>
#include <stdexcept>
#include <opencv2/core.hpp>

#include "handeye/core/error.h"
#include "handeye/io/json_util.h"
#include "handeye/io/yaml_file.h"
#include "filestorage_depth.h"
#include "text_file.h"

namespace handeye {
namespace {

constexpr int kMaxImageSide = 1 << 20;

// A camera matrix must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0.
// Skew is tolerated only at the level of rounding: the model has none, and
// dropping a real skew would bias every projection.
void CheckCameraMatrix(const std::vector<double>& K, const std::string& file, const std::string& path,
                       FileIntrinsics* out) {
  auto fail = [&](const std::string& what) {
    return InputError(file, path, "expected a camera matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]; " + what);
  };
  for (double k : K)
    if (!std::isfinite(k)) throw fail("an entry is not finite");
  if (!(K[0] > 0) || !(K[4] > 0)) throw fail("fx and fy must be positive");
  if (std::abs(K[1]) > 1e-9 * K[0]) throw fail("skew " + std::to_string(K[1]) + " is not supported");
  if (K[3] != 0 || K[6] != 0 || K[7] != 0 || std::abs(K[8] - 1) > 1e-12)
    throw fail("the last row must be [0, 0, 1] and K[1][0] zero");
  out->fx = K[0];
  out->fy = K[4];
  out->cx = K[2];
  out->cy = K[5];
}

void CheckCoefficientCount(std::size_t n, const std::string& file, const std::string& path) {
  if (n != 0 && n != 4 && n != 5 && n != 8 && n != 12 && n != 14)
    throw InputError(file, path,
                     "expected 0, 4, 5, 8, 12 or 14 distortion coefficients in OpenCV's order, got " +
                         std::to_string(n));
}

// --- OpenCV FileStorage ------------------------------------------------------------

// The largest opencv-matrix an intrinsics file needs: 3x3, or 14 coefficients.
constexpr int kMaxMatrixSide = 64;

cv::Mat ReadMatrixNode(const cv::FileStorage& fs, const std::string& key, const std::string& path) {
  const cv::FileNode node = fs[key];
  if (node.empty() || node.isNone())
    throw InputError(path, "/" + key, "missing key; expected an opencv-matrix");
  // cv::read allocates rows x cols from the header before it reads `data`
  // (a fuzzed 'cols: 2147483647' asked for 16 GB), so the header is checked
  // against the data first.
  const std::string expected = "expected an opencv-matrix (rows, cols, dt, data) of at most " +
                               std::to_string(kMaxMatrixSide) + " x " + std::to_string(kMaxMatrixSide) +
                               " single-channel values, with rows x cols of them in data";
  if (!node.isMap() || !node["rows"].isInt() || !node["cols"].isInt() || !node["data"].isSeq())
    throw InputError(path, "/" + key, expected);
  const int rows = static_cast<int>(node["rows"]), cols = static_cast<int>(node["cols"]);
  const std::string dt = node["dt"].isString() ? static_cast<std::string>(node["dt"]) : "";
  if (rows < 1 || cols < 1 || rows > kMaxMatrixSide || cols > kMaxMatrixSide || dt.size() != 1 ||
      node["data"].size() != static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols))
    throw InputError(path, "/" + key, expected);
  cv::Mat m;
  try {
    node >> m;
  } catch (const cv::Exception&) {
    m.release();
  }
  if (m.empty()) throw InputError(path, "/" + key, "expected an opencv-matrix (rows, cols, dt, data)");
  m.convertTo(m, CV_64F);
  return m;
}

std::optional<int> ReadOptionalSide(const cv::FileStorage& fs, const std::string& key, const std::string& path) {
  const cv::FileNode node = fs[key];
  if (node.empty() || node.isNone()) return std::nullopt;
  if (!node.isInt() || static_cast<int>(node) < 1 || static_cast<int>(node) > kMaxImageSide)
    throw InputError(path, "/" + key, "expected a positive integer (pixels)");
  return static_cast<int>(node);
}

// OpenCV 4.6 loops for ever on some base64 payloads (YAML `!!binary`, XML
// type_id="binary", JSON "$base64$"; found by fuzz/run: 32 'A's are enough).
// Intrinsics are a few numbers that every tool writes as text, so a file
// that asks for base64 is refused before OpenCV sees it.
bool AsksForBase64(const std::string& text, int format) {
  if (format == cv::FileStorage::FORMAT_JSON) return text.find("$base64$") != std::string::npos;
  const auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t at = text.find("binary"); at != std::string::npos; at = text.find("binary", at + 1)) {
    const char before = at == 0 ? '\0' : text[at - 1];
    const char after = at + 6 < text.size() ? text[at + 6] : '\0';
    const bool yaml_tag = (before == '!' || before == ':') && !word_char(after);     // !!binary, !<...:binary>
    const bool xml_value = (before == '"' || before == '\'') && after == before;      // type_id="binary"
    if (format == cv::FileStorage::FORMAT_XML ? xml_value : yaml_tag) return true;
  }
  return false;
}

// OpenCV 4.6's YAML parser loops for ever when, after its first collection,
// the text goes on with a '-' that does not start "---": after a line
// indented less than the first key (" s: 3\nabc-\nr"), after a "..."
// document end ("a: 1\n...\n-x"), or after "---" lines that start more
// streams (all found by fuzz/run). An intrinsics file is one mapping in one
// document, so before OpenCV reads the text this requires: directives and at
// most one "---" (alone on its line) before the first key, a first key that
// starts a block mapping, no line indented less than it, and nothing after "...".
void RequireOneOpenCvYamlMapping(const std::string& text, const std::string& path) {
  std::size_t root_indent = std::string::npos, line_number = 0, root_line = 0, end_line = 0;
  bool document_start = false;
  for (std::size_t start = 0; start < text.size(); ++line_number) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    const std::size_t indent = line.find_first_not_of(' ');
    if (indent == std::string::npos || line[indent] == '#' || line[indent] == '\r') continue;  // blank, comment
    const std::string where = "line " + std::to_string(line_number + 1) + ": ";
    auto refuse = [&](const std::string& why) { throw InputError(path, "", where + why); };
    if (end_line)
      refuse("more after the document end ('...') on line " + std::to_string(end_line) + "; expected one document");
    const bool marker = line.compare(indent, 3, "---") == 0;
    if (line.compare(indent, 3, "...") == 0) {
      end_line = line_number + 1;
    } else if (root_indent == std::string::npos && line[indent] == '%') {
      continue;  // a directive
    } else if (marker && (root_indent != std::string::npos || document_start)) {
      refuse("a second YAML document ('---'); expected one document");
    } else if (marker) {
      const std::size_t rest = line.find_first_not_of(" \r", indent + 3);
      if (rest != std::string::npos && line[rest] != '#') refuse("expected '---' alone on its line");
      document_start = true;
    } else if (root_indent == std::string::npos) {
      if (line[indent] == '-' || line[indent] == '[')
        refuse("expected a mapping (camera_matrix: ...), got a sequence");
      root_indent = indent;
      root_line = line_number + 1;
    } else if (indent < root_indent) {
      refuse("indented less than the first key (line " + std::to_string(root_line) +
             "); OpenCV's YAML parser reads one mapping, indented alike");
    }
  }
}

InputError DeepNesting(const std::string& path) {
  return InputError(path, "", "nested more than " + std::to_string(internal::kMaxFileStorageDepth) +
                                  " levels deep; an intrinsics file needs 3 (camera_matrix: rows, cols, dt, data)");
}

// OpenCV 4.6's parsers recurse once per nesting level without a limit: a
// camera_matrix nested 50 000 deep (100 KB) overflowed the stack.
void RequireShallowNesting(const std::string& text, int format, const std::string& path) {
  using internal::kMaxFileStorageDepth;
  const auto syntax = format == cv::FileStorage::FORMAT_XML    ? internal::FileStorageSyntax::kXml
                      : format == cv::FileStorage::FORMAT_JSON ? internal::FileStorageSyntax::kJson
                                                               : internal::FileStorageSyntax::kYaml;
  if (internal::FileStorageNestingDepth(text, syntax, kMaxFileStorageDepth) > kMaxFileStorageDepth)
    throw DeepNesting(path);
}

}  // namespace

namespace internal {

cv::FileStorage OpenFileStorageText(std::string text, const std::string& path) {
  // OpenCV's parsers read the text as a C string (a NUL ends it early), and
  // its XML parser dereferences a null pointer when the text ends just after
  // an attribute's '=' (OpenCV 4.6; both found by fuzz/run). Neither reaches it.
  if (text.size() > kMaxFileStorageTextBytes)
    throw InputError(path, "", std::to_string(text.size()) + " bytes; an OpenCV intrinsics file is a few kilobytes, and at most " +
                                   std::to_string(kMaxFileStorageTextBytes >> 20) + " MB is read");
  const std::size_t nul = text.find('\0');
  if (nul != std::string::npos)
    throw InputError(path, "", "not a text file: a NUL byte at offset " + std::to_string(nul));
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  const char lead = first == std::string::npos ? '\0' : text[first];
  // OpenCV tells its formats apart by the first characters and insists on
  // the %YAML header for YAML; files written by hand or other tools often
  // lack it.
  int format = cv::FileStorage::FORMAT_YAML;
  if (lead == '<') {
    format = cv::FileStorage::FORMAT_XML;
    if (text[text.find_last_not_of(" \t\r\n")] != '>')
      throw InputError(path, "", "not an OpenCV FileStorage XML file: it does not end with a closing tag");
  } else if (lead == '{') {
    format = cv::FileStorage::FORMAT_JSON;
  } else {
    RequireOneOpenCvYamlMapping(text, path);
    if (text.compare(first == std::string::npos ? 0 : first, 5, "%YAML") != 0) text = "%YAML:1.0\n" + text;
  }
  if (AsksForBase64(text, format))
    throw InputError(path, "", "base64 (binary) values are not read: write the matrices as text");
  RequireShallowNesting(text, format, path);
  cv::FileStorage fs;
  try {
    fs = ParseFileStorageText(text, cv::FileStorage::READ | cv::FileStorage::MEMORY | format);
  } catch (const cv::Exception& e) {
    throw InputError(path, "", "not an OpenCV FileStorage file (YAML, XML or JSON): " + e.msg);
  } catch (const std::logic_error& e) {
    // OpenCV 4.6's YAML parser lets std::string throw length_error on a key
    // with no name ("  : 3" under a mapping; found by fuzz/run).
    throw InputError(path, "", std::string("not an OpenCV FileStorage file (YAML, XML or JSON): ") + e.what());
  } catch (const std::runtime_error& e) {
    throw InputError(path, "", std::string("could not be read: ") + e.what());
  }
  if (!fs.isOpened()) throw InputError(path, "", "not an OpenCV FileStorage file (YAML, XML or JSON)");
  if (FileStorageTreeDepth(fs.root()) > kMaxFileStorageDepth) throw DeepNesting(path);
  return fs;
}

}  // namespace internal

namespace {

FileIntrinsics ReadOpenCv(const std::string& path) {
  const cv::FileStorage fs = internal::OpenFileStorageText(internal::ReadTextFile(path, "an intrinsics file"), path);
  // FileStorage's operator[] asserts (cv::Exception) on a root that is not a
  // mapping (found by fuzz/run).
  if (!fs.root().isMap())
    throw InputError(path, "",
                     "expected an OpenCV FileStorage mapping with camera_matrix and distortion_coefficients");

  FileIntrinsics out;
  const cv::Mat K = ReadMatrixNode(fs, "camera_matrix", path);
  if (K.rows != 3 || K.cols != 3)
    throw InputError(path, "/camera_matrix",
                     "expected a 3x3 matrix, got " + std::to_string(K.rows) + "x" + std::to_string(K.cols));
  CheckCameraMatrix(std::vector<double>(K.begin<double>(), K.end<double>()), path, "/camera_matrix", &out);
  const cv::Mat D = ReadMatrixNode(fs, "distortion_coefficients", path);
  if (D.rows != 1 && D.cols != 1)
    throw InputError(path, "/distortion_coefficients",
                     "expected a 1xN or Nx1 matrix, got " + std::to_string(D.rows) + "x" + std::to_string(D.cols));
  out.distortion.assign(D.begin<double>(), D.end<double>());
  CheckCoefficientCount(out.distortion.size(), path, "/distortion_coefficients");
  for (double d : out.distortion)
    if (!std::isfinite(d)) throw InputError(path, "/distortion_coefficients", "expected finite coefficients");
  const auto width = ReadOptionalSide(fs, "image_width", path);
  const auto height = ReadOptionalSide(fs, "image_height", path);
  if (width.has_value() != height.has_value())
    throw InputError(path, width ? "/image_height" : "/image_width",
                     "missing key; expected both image_width and image_height, or neither");
  if (width) out.image_size = std::array<int, 2>{*width, *height};
  return out;
}

// --- ROS camera_info -----------------------------------------------------------------

// `{rows: R, cols: C, data: [...]}` of a ROS calibration file.
std::vector<double> RosMatrix(const JsonReader& r, int rows, int cols) {
  r.ExpectObject("a matrix {rows, cols, data: [...]}");
  const int R = r.Key("rows").Int(0, 1 << 16);
  const int C = r.Key("cols").Int(0, 1 << 16);
  if ((rows >= 0 && R != rows) || (cols >= 0 && C != cols))
    throw r.Error("expected a " + (rows >= 0 ? std::to_string(rows) : std::string("N")) + "x" +
                  (cols >= 0 ? std::to_string(cols) : std::string("N")) + " matrix, got " + std::to_string(R) + "x" +
                  std::to_string(C));
  return r.Key("data").Numbers(R * C);
}

JsonReader OneOf(const JsonReader& root, const char* upper, const char* lower) {
  if (root.Has(upper) && root.Has(lower))
    throw root.Key(lower).Error(std::string("both '") + upper + "' and '" + lower + "'; expected one of them");
  return root.Key(root.Has(upper) ? upper : lower);
}

std::optional<std::array<int, 2>> RosImageSize(const JsonReader& width, const JsonReader& height) {
  if (!width.present() && !height.present()) return std::nullopt;
  // An unset camera_info message carries 0 × 0; that states no size.
  const int w = width.Int(0, kMaxImageSide);
  const int h = height.Int(0, kMaxImageSide);
  if (w == 0 && h == 0) return std::nullopt;
  if (w == 0) throw width.Error("expected a positive image width");
  if (h == 0) throw height.Error("expected a positive image height");
  return std::array<int, 2>{w, h};
}

FileIntrinsics ReadRos(const std::string& path) {
  const nlohmann::json doc = ReadYamlFile(path);
  const JsonReader root(&doc, path);
  root.ExpectObject("a ROS camera_info (calibration file or message) mapping");
  FileIntrinsics out;
  std::vector<double> K, D;
  JsonReader K_json = root.Key("camera_matrix"), D_json = root.Key("distortion_coefficients");
  if (K_json.present()) {
    // The calibration file written by camera_calibration / camera_info_manager.
    K = RosMatrix(K_json, 3, 3);
    D = RosMatrix(D_json, 1, -1);
    out.image_size = RosImageSize(root.Key("image_width"), root.Key("image_height"));
  } else if (root.Has("K") || root.Has("k")) {
    // The sensor_msgs/CameraInfo message (ROS 1 spells K and D, ROS 2 k and d).
    K_json = OneOf(root, "K", "k");
    D_json = OneOf(root, "D", "d");
    K = K_json.Numbers(9);
    D = D_json.Numbers();
    out.image_size = RosImageSize(root.Key("width"), root.Key("height"));
    for (const char* key : {"binning_x", "binning_y"})
      if (root.Has(key) && root.Key(key).Int(0) > 1)
        throw root.Key(key).Error("binning is not supported; expected 0 or 1 (the intrinsics of the images used)");
  } else {
    throw root.Error(
        "expected a ROS camera_info: camera_matrix and distortion_coefficients (calibration file) or K and D "
        "(message)");
  }
  CheckCameraMatrix(K, path, K_json.path(), &out);
  const JsonReader model_json = root.Key("distortion_model");
  const std::string model = model_json.NonEmptyString("a distortion model, \"plumb_bob\" or \"rational_polynomial\"");
  std::size_t expected_count = 0;
  if (model == "plumb_bob") {
    expected_count = 5;
  } else if (model == "rational_polynomial") {
    expected_count = 8;
  } else {
    throw model_json.Error("unsupported distortion model '" + model +
                           "'; expected \"plumb_bob\" (k1 k2 t1 t2 k3) or \"rational_polynomial\" (k1 k2 t1 t2 k3 "
                           "k4 k5 k6), the models that are OpenCV's");
  }
  if (D.size() != expected_count)
    throw D_json.Error("expected " + std::to_string(expected_count) + " coefficients for " + model + ", got " +
                       std::to_string(D.size()));
  out.distortion = D;
  return out;
}

// --- Kalibr camchain -------------------------------------------------------------------

FileIntrinsics ReadKalibr(const std::string& path, const std::string& camera) {
  const nlohmann::json doc = ReadYamlFile(path);
  const JsonReader root(&doc, path);
  root.ExpectObject("a Kalibr camchain {cam0: {...}, cam1: {...}}");
  if (!root.Has(camera)) {
    std::string names;
    for (const auto& [name, value] : root.Members("a Kalibr camchain")) names += (names.empty() ? "" : ", ") + name;
    throw root.Error("no camera '" + camera + "' in the camchain; it has: " + names);
  }
  const JsonReader cam = root.Key(camera);
  cam.ExpectObject("a Kalibr camera {camera_model, intrinsics, distortion_model, distortion_coeffs, resolution}");
  if (cam.Has("camera_model")) {
    const JsonReader model = cam.Key("camera_model");
    if (model.String() != "pinhole")
      throw model.Error("unsupported camera model '" + model.String() + "'; expected \"pinhole\"");
  }
  FileIntrinsics out;
  const std::vector<double> k = cam.Key("intrinsics").Numbers(4);
  CheckCameraMatrix({k[0], 0, k[2], 0, k[1], k[3], 0, 0, 1}, path, cam.Key("intrinsics").path(), &out);
  const JsonReader model_json = cam.Key("distortion_model");
  const std::string model = model_json.NonEmptyString("a distortion model, \"radtan\" or \"none\"");
  const JsonReader coeffs = cam.Key("distortion_coeffs");
  if (model == "radtan") {
    out.distortion = coeffs.Numbers(4);  // k1 k2 r1 r2 = OpenCV's k1 k2 p1 p2
  } else if (model == "none") {
    if (coeffs.present() && !coeffs.Numbers().empty()) throw coeffs.Error("expected no coefficients for model none");
  } else {
    throw model_json.Error("unsupported distortion model '" + model +
                           "'; expected \"radtan\" (k1 k2 r1 r2, OpenCV's k1 k2 p1 p2) or \"none\"");
  }
  const JsonReader resolution = cam.Key("resolution");
  if (resolution.present()) {
    if (resolution.ArraySize("[width, height] in pixels") != 2)
      throw resolution.Error("expected [width, height] in pixels");
    out.image_size = std::array<int, 2>{resolution.At(0).Int(1, kMaxImageSide), resolution.At(1).Int(1, kMaxImageSide)};
  }
  return out;
}

}  // namespace

const char* IntrinsicsFileFormatName(IntrinsicsFileFormat format) {
  switch (format) {
    case IntrinsicsFileFormat::kOpenCv: return "opencv";
    case IntrinsicsFileFormat::kRos: return "ros";
    case IntrinsicsFileFormat::kKalibr: return "kalibr";
  }
  return "";
}

std::optional<IntrinsicsFileFormat> ParseIntrinsicsFileFormat(const std::string& name) {
  if (name == "opencv") return IntrinsicsFileFormat::kOpenCv;
  if (name == "ros") return IntrinsicsFileFormat::kRos;
  if (name == "kalibr") return IntrinsicsFileFormat::kKalibr;
  return std::nullopt;
}

FileIntrinsics ReadIntrinsicsFile(const std::string& path, IntrinsicsFileFormat format, const std::string& camera) {
  if (format == IntrinsicsFileFormat::kKalibr && camera.empty())
    throw InputError(path, "", "a Kalibr camchain holds several cameras; the camera name (e.g. cam0) is needed");
  if (format != IntrinsicsFileFormat::kKalibr && !camera.empty())
    throw InputError(path, "", std::string("a camera name is only meaningful for a Kalibr camchain, not for format ") +
                                   IntrinsicsFileFormatName(format));
  switch (format) {
    case IntrinsicsFileFormat::kOpenCv: return ReadOpenCv(path);
    case IntrinsicsFileFormat::kRos: return ReadRos(path);
    case IntrinsicsFileFormat::kKalibr: return ReadKalibr(path, camera);
  }
  throw std::invalid_argument("ReadIntrinsicsFile: unknown format");
}

}  // namespace handeye
