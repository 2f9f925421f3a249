// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Robot poses as controllers and middleware print them, read into the rigid
/// transforms of SPEC §2 (metres, radians inside).
///
/// In a dataset, `T_base_ee` may be the 4×4 array of SPEC §4 or an object with
/// one translation and exactly one rotation:
///
/// | key | meaning |
/// |---|---|
/// | `translation_m` / `translation_mm` | [x, y, z] of the ee origin in the base frame, metres / millimetres |
/// | `quaternion_xyzw` | [qx, qy, qz, qw] (ROS, Eigen's coeffs()) |
/// | `quaternion_wxyz` | [qw, qx, qy, qz] (ABB RAPID `orient` q1..q4) |
/// | `rotvec_rad` | [rx, ry, rz] axis · angle in radians (Universal Robots) |
/// | `euler_deg` + `euler_convention` | three angles in degrees, convention `kuka_abc` or `rpy` |
///
/// `kuka_abc` is [A, B, C]: A about z, then B about the new y, then C about
/// the newest x (intrinsic z-y'-x''), R = Rz(A)·Ry(B)·Rx(C). `rpy` is
/// [roll, pitch, yaw] about the fixed x, y, z axes in that order (ROS, URDF),
/// R = Rz(yaw)·Ry(pitch)·Rx(roll). The two name the same rotation with the
/// angles listed in opposite order.
///
/// A quaternion must have unit norm within kQuaternionNormTolerance (controllers
/// print six decimals, which is well inside); with `reorthonormalise` any
/// finite non-zero quaternion is normalised instead.

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "handeye/io/json_util.h"

namespace handeye {

/// Largest accepted | ‖q‖ − 1 | of a quaternion read from a file.
constexpr double kQuaternionNormTolerance = 1e-6;

/// Conventions for three Euler angles (see the file comment).
enum class EulerConvention {
  kKukaAbc,  ///< [A, B, C], R = Rz(A)·Ry(B)·Rx(C)
  kRpy,      ///< [roll, pitch, yaw], R = Rz(yaw)·Ry(pitch)·Rx(roll)
};
/// "kuka_abc" / "rpy".
const char* EulerConventionName(EulerConvention convention);
/// Parses a convention name; nullopt if unknown.
std::optional<EulerConvention> ParseEulerConvention(const std::string& name);

/// Rotation matrix of three angles in degrees under `convention`.
Eigen::Matrix3d RotationFromEulerDeg(EulerConvention convention, const Eigen::Vector3d& angles_deg);

/// A rotation from a quaternion given as (w, x, y, z). Returns nullopt and
/// says why when an entry is not finite or the norm is off by more than
/// kQuaternionNormTolerance (unless `normalise`, which accepts any non-zero norm).
std::optional<Eigen::Quaterniond> UnitQuaternion(double w, double x, double y, double z,
                                                 bool normalise, std::string* why);

/// Reads a `T_base_ee` value: a 4×4 array (JsonReader::Rigid) or a pose object
/// as in the file comment. Throws InputError at the offending key; a pose
/// object with no rotation, two rotations, two translations, an
/// `euler_convention` without `euler_deg` (or the reverse), or a key whose
/// meaning is ambiguous (`quaternion`, `translation`, `rpy`, …) is rejected
/// with a message saying which keys to use.
Eigen::Isometry3d ReadPose(const JsonReader& value, bool reorthonormalise);

/// Unit of the translation columns of a pose list.
enum class LengthUnit { kMetre, kMillimetre };

/// One row of a robot pose list.
struct PoseRow {
  std::string id;
  Eigen::Isometry3d T_base_ee = Eigen::Isometry3d::Identity();
  int line = 0;  ///< 1-based line in a CSV file, for messages (0: YAML)
};

/// How the three rotation columns of a CSV pose list are written.
enum class CsvRotation {
  kQuaternion,      ///< qx, qy, qz, qw (four columns)
  kRotationVector,  ///< rx, ry, rz: axis · angle in radians (Universal Robots)
  kKukaAbc,         ///< a, b, c in degrees, EulerConvention::kKukaAbc
  kRpy,             ///< roll, pitch, yaw in degrees, EulerConvention::kRpy
};
/// "quaternion", "rotvec", "kuka_abc", "rpy".
const char* CsvRotationName(CsvRotation rotation);
/// Parses a CsvRotationName; nullopt if unknown.
std::optional<CsvRotation> ParseCsvRotation(const std::string& name);

/// How to read a pose list.
struct PoseListOptions {
  LengthUnit unit = LengthUnit::kMetre;  ///< of the translations
  bool reorthonormalise = false;         ///< normalise quaternions that are not unit
  /// CSV: the rotation columns; nullopt reads them from the header row.
  std::optional<CsvRotation> rotation;
};

/// Reads a CSV pose list: a header row, then one row per pose with the id,
/// the translation x, y, z (in `options.unit`) and the rotation. The header
/// names the columns (case and blanks do not matter):
///
/// | header | rotation |
/// |---|---|
/// | `id,x,y,z,qx,qy,qz,qw` | quaternion |
/// | `id,x,y,z,rx,ry,rz` | rotation vector, radians (Universal Robots) |
/// | `id,x,y,z,a,b,c` | KUKA A, B, C in degrees (kuka_abc) |
/// | `id,x,y,z,roll,pitch,yaw` | roll, pitch, yaw in degrees (rpy) |
///
/// With `options.rotation` set, the header must have the id, x, y, z and
/// that rotation's number of columns, under any names. Blank lines and lines
/// starting with '#' are skipped; fields may be surrounded by blanks or
/// double quotes ("0001" keeps its zeros: ids are strings). Throws
/// InputError naming the file, the line and the column for a header that
/// names no known form, a wrong field count, a field that is not a finite
/// number, a quaternion that is not unit, an empty or duplicate id, or a
/// file without rows.
std::vector<PoseRow> ReadPoseCsv(const std::string& path, const PoseListOptions& options);

/// ReadPoseCsv with the rotation read from the header.
std::vector<PoseRow> ReadPoseCsv(const std::string& path, LengthUnit unit, bool reorthonormalise);

/// Reads a YAML list of ROS `geometry_msgs/Pose`: either a sequence or a
/// mapping with `poses:` (a `geometry_msgs/PoseArray` as `rostopic echo`
/// prints it), each item `{position: {x, y, z}, orientation: {x, y, z, w}}`,
/// or a `geometry_msgs/PoseStamped` `{header: ..., pose: {position,
/// orientation}}`. An item may carry `id` (a string or an integer); items
/// without one are numbered from 1 as "0001", "0002", ... Positions are in
/// `options.unit` (ROS uses metres). Throws InputError naming the file and
/// the YAML path (`/poses/3/orientation/w`).
std::vector<PoseRow> ReadPoseYaml(const std::string& path, const PoseListOptions& options);

/// ReadPoseYaml for a file ending in .yaml or .yml, else ReadPoseCsv.
std::vector<PoseRow> ReadPoseList(const std::string& path, const PoseListOptions& options);

/// The farthest a robot flange plausibly is from its base, metres.
constexpr double kMaxRobotReachM = 10.0;
/// The least that the farthest of several poses is from the base, metres.
constexpr double kMinRobotReachM = 0.01;

/// The pose (index into `translations`) whose translation is farthest from
/// the base, when it is over kMaxRobotReachM or, for two poses or more,
/// under kMinRobotReachM: the sign of a unit mistake (millimetres read as
/// metres make 400 mm 400 m; the reverse, 0.4 mm). nullopt when plausible.
std::optional<std::size_t> ImplausibleReach(const std::vector<Eigen::Vector3d>& translations);

/// Throws InputError(path) when ImplausibleReach finds a pose, naming the
/// pose, its line, its distance and the unit to try with `unit_option`
/// (e.g. "use --translation-unit mm").
void RequirePlausibleReach(const std::vector<PoseRow>& rows, const std::string& path, LengthUnit unit,
                           const std::string& unit_option);

}  // namespace handeye
