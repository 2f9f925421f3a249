// SPDX-License-Identifier: GPL-2.0-or-later
#include "handeye/io/pose_formats.h"

#include <cmath>
#include <cstdio>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"

namespace handeye {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

const char* const kRotationKeys[] = {"quaternion_xyzw", "quaternion_wxyz", "rotvec_rad", "euler_deg"};
const char* const kTranslationKeys[] = {"translation_m", "translation_mm"};

const char kRotationChoices[] =
    "quaternion_xyzw [qx, qy, qz, qw] (ROS), quaternion_wxyz [qw, qx, qy, qz] (ABB RAPID), "
    "rotvec_rad [rx, ry, rz] (Universal Robots) or euler_deg [a, b, c] with euler_convention "
    "\"kuka_abc\" or \"rpy\"";

// Keys people reach for that do not say which order or unit they mean.
std::optional<std::string> AmbiguousKeyAdvice(const std::string& key) {
  if (key == "quaternion" || key == "q" || key == "orientation" || key == "orient")
    return "a quaternion's element order differs between robots; use quaternion_xyzw [qx, qy, qz, qw] "
           "or quaternion_wxyz [qw, qx, qy, qz]";
  if (key == "translation" || key == "position" || key == "t" || key == "xyz")
    return "the unit of a translation must be stated; use translation_m or translation_mm";
  if (key == "rotation" || key == "rotvec" || key == "rpy" || key == "rpy_deg" || key == "euler" ||
      key == "abc" || key == "euler_rad")
    return std::string("ambiguous rotation key; use one of ") + kRotationChoices;
  return std::nullopt;
}

Eigen::Vector3d Vector3(const JsonReader& r) {
  const std::vector<double> v = r.Numbers(3);
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Eigen::Matrix3d ReadRotation(const JsonReader& r, const std::string& key, bool reorthonormalise) {
  const JsonReader value = r.Key(key);
  if (key == "quaternion_xyzw" || key == "quaternion_wxyz") {
    const std::vector<double> q = value.Numbers(4);
    const bool xyzw = key == "quaternion_xyzw";
    std::string why;
    const auto unit = xyzw ? UnitQuaternion(q[3], q[0], q[1], q[2], reorthonormalise, &why)
                           : UnitQuaternion(q[0], q[1], q[2], q[3], reorthonormalise, &why);
    if (!unit) throw value.Error("expected " + why);
    return unit->toRotationMatrix();
  }
  if (key == "rotvec_rad") return MatrixFromRotationVector(Vector3(value));
  // euler_deg
  const JsonReader convention_json = r.Key("euler_convention");
  if (!convention_json.present())
    throw convention_json.Error(
        "missing key; euler_deg needs euler_convention, \"kuka_abc\" ([A, B, C]: Rz(A)·Ry(B)·Rx(C)) "
        "or \"rpy\" ([roll, pitch, yaw] about fixed x, y, z)");
  const std::string name = convention_json.NonEmptyString("an Euler convention, \"kuka_abc\" or \"rpy\"");
  const auto convention = ParseEulerConvention(name);
  if (!convention)
    throw convention_json.Error("unknown Euler convention '" + name + "'; expected \"kuka_abc\" or \"rpy\"");
  return RotationFromEulerDeg(*convention, Vector3(value));
}

}  // namespace

const char* EulerConventionName(EulerConvention convention) {
  return convention == EulerConvention::kKukaAbc ? "kuka_abc" : "rpy";
}

std::optional<EulerConvention> ParseEulerConvention(const std::string& name) {
  if (name == "kuka_abc") return EulerConvention::kKukaAbc;
  if (name == "rpy") return EulerConvention::kRpy;
  return std::nullopt;
}

Eigen::Matrix3d RotationFromEulerDeg(EulerConvention convention, const Eigen::Vector3d& angles_deg) {
  const Eigen::Vector3d a = angles_deg * kDegToRad;
  // Both are Rz·Ry·Rx; KUKA lists the z angle first, ROS lists it last.
  const double z = convention == EulerConvention::kKukaAbc ? a[0] : a[2];
  const double y = a[1];
  const double x = convention == EulerConvention::kKukaAbc ? a[2] : a[0];
  return (Eigen::AngleAxisd(z, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(y, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(x, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

std::optional<Eigen::Quaterniond> UnitQuaternion(double w, double x, double y, double z, bool normalise,
                                                 std::string* why) {
  if (!std::isfinite(w) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
    *why = "a quaternion of finite numbers";
    return std::nullopt;
  }
  Eigen::Quaterniond q(w, x, y, z);
  const double norm = q.norm();
  if (normalise ? !(norm > 0) : !(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "a unit quaternion (norm within %g of 1), got norm %.9g", kQuaternionNormTolerance,
                  norm);
    *why = buf;
    if (!normalise) *why += " (--reorthonormalise normalises it)";
    return std::nullopt;
  }
  q.normalize();
  return q;
}

Eigen::Isometry3d ReadPose(const JsonReader& value, bool reorthonormalise) {
  if (value.present() && value.json().is_array()) return value.Rigid(reorthonormalise);
  value.ExpectObject(std::string("a 4x4 array of numbers (row-major) or a pose object {\"translation_m\" or ") +
                     "\"translation_mm\": [x, y, z], and one of " + kRotationChoices + "}");
  for (const auto& [key, member] : value.Members("a pose object"))
    if (const auto advice = AmbiguousKeyAdvice(key)) throw member.Error(*advice);
  value.RejectUnknownKeys({"translation_m", "translation_mm", "quaternion_xyzw", "quaternion_wxyz", "rotvec_rad",
                           "euler_deg", "euler_convention"});

  std::vector<std::string> rotations, translations;
  for (const char* key : kRotationKeys)
    if (value.Has(key)) rotations.push_back(key);
  for (const char* key : kTranslationKeys)
    if (value.Has(key)) translations.push_back(key);
  if (rotations.size() > 1)
    throw value.Error("give exactly one rotation; found both " + rotations[0] + " and " + rotations[1]);
  if (rotations.empty()) throw value.Error(std::string("missing rotation; expected one of ") + kRotationChoices);
  if (translations.size() > 1)
    throw value.Error("give exactly one translation; found both translation_m and translation_mm");
  if (translations.empty())
    throw value.Error("missing translation; expected translation_m [x, y, z] (metres) or translation_mm (millimetres)");
  if (value.Has("euler_convention") && rotations[0] != "euler_deg")
    throw value.Key("euler_convention")
        .Error("euler_convention belongs to euler_deg; the rotation here is " + rotations[0]);

  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = ReadRotation(value, rotations[0], reorthonormalise);
  const double scale = translations[0] == "translation_mm" ? 1e-3 : 1.0;
  T.translation() = scale * Vector3(value.Key(translations[0]));
  return T;
}

}  // namespace handeye
