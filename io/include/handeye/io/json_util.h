// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Reading JSON input with errors that name the file, the JSON pointer path
/// (RFC 6901, e.g. `/poses/3/T_base_ee`) and what was expected, and writing
/// JSON output that people can read (numbers at full double precision).
/// Shared by every JSON format of io/ (dataset, observations, ground truth,
/// result).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "handeye/core/error.h"
#include "handeye/core/target_spec.h"

namespace handeye {

struct GivenIntrinsicsSigma;  // handeye/core/calibration.h

/// Parses a JSON file. Throws InputError naming `path` when the file is
/// missing or unreadable, when the JSON is malformed (with line and column),
/// when a number does not fit a double (e.g. `1e999`), or when an object has
/// the same key twice (nlohmann would silently keep the last one).
nlohmann::json ReadJsonFile(const std::string& path);

/// Escapes one JSON pointer component (`~` → `~0`, `/` → `~1`, RFC 6901).
std::string JsonPointerEscape(const std::string& key);

/// A read-only view of one value inside a parsed JSON file that knows where it
/// is (file and JSON pointer path), so that every complaint can say so.
///
/// A view may be *absent* (made by Key() for a key the object lacks). Typed
/// getters on an absent view throw "missing key; expected <what the getter
/// wanted>", so `root.Key("T_base_ee").Rigid(false)` reports a missing key, a
/// wrong type and a non-rigid matrix with the same path. Getters never fall
/// back to a default. The viewed JSON must outlive the reader.
class JsonReader {
 public:
  /// @param value  the value viewed (nullptr: absent)
  /// @param file   the file it came from, used in messages
  /// @param path   its JSON pointer inside that file ("" for the root)
  JsonReader(const nlohmann::json* value, std::string file, std::string path = "");

  bool present() const { return value_ != nullptr; }
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  /// The value itself; throws "missing key" when absent.
  const nlohmann::json& json() const;

  /// An InputError at this value's path.
  InputError Error(const std::string& expected) const;

  // --- Objects -------------------------------------------------------------
  /// Throws unless this is an object; `what` describes it ("a camera object").
  void ExpectObject(const std::string& what) const;
  /// The member `key` (absent when missing); this must be an object.
  JsonReader Key(const std::string& key) const;
  /// True when this object has `key`.
  bool Has(const std::string& key) const;
  /// Members in the object's order (keys sorted, as nlohmann::json stores them).
  std::vector<std::pair<std::string, JsonReader>> Members(const std::string& what) const;
  /// Throws at `<path>/<key>` for a key not in `known`, naming the known keys
  /// and the nearest one when the key looks like a typo of it.
  void RejectUnknownKeys(const std::vector<std::string>& known) const;

  // --- Arrays --------------------------------------------------------------
  /// Throws unless this is an array; returns its size. `what` describes it.
  std::size_t ArraySize(const std::string& what) const;
  /// Element `index` (must be < ArraySize()).
  JsonReader At(std::size_t index) const;

  // --- Scalars -------------------------------------------------------------
  /// A finite number (JSON has no NaN; strings such as "nan" are rejected).
  double Number() const;
  /// A finite number > 0.
  double Positive() const;
  /// An integer in [min_value, max_value] (4 and 4.0 both count).
  int Int(int min_value = std::numeric_limits<int>::min(),
          int max_value = std::numeric_limits<int>::max()) const;
  /// A string.
  std::string String() const;
  /// A non-empty string; `what` describes it ("a pose id").
  std::string NonEmptyString(const std::string& what) const;

  // --- Composites ----------------------------------------------------------
  /// An array of finite numbers; `count` >= 0 requires exactly that many.
  std::vector<double> Numbers(int count = -1) const;
  /// An array of integers >= min_value.
  std::vector<int> Ints(int min_value) const;
  /// An array of [u, v] pairs of finite numbers (pixels).
  std::vector<Eigen::Vector2d> Points2() const;
  /// A 4×4 row-major nested array of finite numbers.
  Eigen::Matrix4d Matrix4() const;
  /// A 4×4 rigid transform (core RigidFromMatrix): finite, last row
  /// [0 0 0 1], rotation orthonormal within kOrthonormalityTolerance unless
  /// `reorthonormalise`, in which case it is replaced by the nearest rotation.
  Eigen::Isometry3d Rigid(bool reorthonormalise) const;

 private:
  void RequirePresent(const std::string& expected) const;
  std::string TypeDescription() const;

  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
};

/// The `target` object (SPEC §4) as a TargetSpec: `type` (a string) plus
/// other keys whose values are numbers, strings or arrays of numbers. Throws
/// InputError at the offending key otherwise.
TargetSpec TargetSpecFromJson(const JsonReader& target);

/// A TargetSpec as the `target` object: `type` first, then the other keys in
/// name order; integral numbers are written as integers (e.g. `[4, 3]`).
nlohmann::ordered_json JsonFromTargetSpec(const TargetSpec& spec);

/// `intrinsics_sigma` as results, cell and plan files write it:
/// {"focal_percent", "principal_point_px"}.
nlohmann::ordered_json JsonFromIntrinsicsSigma(const GivenIntrinsicsSigma& sigma);

/// A 4×4 matrix as a row-major nested array (full double precision).
nlohmann::ordered_json JsonFromMatrix(const Eigen::Matrix4d& M);
/// A rigid transform as a 4×4 nested array with last row exactly [0 0 0 1].
nlohmann::ordered_json JsonFromTransform(const Eigen::Isometry3d& T);

/// Serialises for people: objects one key per line (2-space indent), arrays
/// of scalars on one line, arrays of such arrays (matrices, pixel lists) one
/// row per line; numbers round-trip exactly (shortest representation that
/// reads back to the same double). Ends with a newline.
std::string DumpJson(const nlohmann::ordered_json& value);

}  // namespace handeye
