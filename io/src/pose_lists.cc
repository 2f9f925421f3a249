// SPDX-License-Identifier: GPL-2.0-or-later
// Robot pose lists (io/pose_formats.h): CSV with a quaternion, a rotation
// vector or Euler angles, and YAML lists of ROS geometry_msgs/Pose.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <sstream>

#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/io/pose_formats.h"
#include "handeye/io/yaml_file.h"
#include "text_file.h"

namespace handeye {
namespace {

using Fail = std::function<InputError(const std::string&)>;

// --- CSV -------------------------------------------------------------------------

struct CsvForm {
  CsvRotation rotation;
  std::vector<std::string> header;
  const char* meaning;
};

const std::vector<CsvForm>& CsvForms() {
  static const std::vector<CsvForm> forms = {
      {CsvRotation::kQuaternion,
       {"id", "x", "y", "z", "qx", "qy", "qz", "qw"},
       "quaternion x y z w"},
      {CsvRotation::kRotationVector,
       {"id", "x", "y", "z", "rx", "ry", "rz"},
       "rotation vector in radians"},
      {CsvRotation::kKukaAbc, {"id", "x", "y", "z", "a", "b", "c"}, "KUKA A B C in degrees"},
      {CsvRotation::kRpy,
       {"id", "x", "y", "z", "roll", "pitch", "yaw"},
       "roll pitch yaw in degrees"}};
  return forms;
}

const CsvForm& FormOf(CsvRotation rotation) {
  for (const CsvForm& form : CsvForms())
    if (form.rotation == rotation) return form;
  return CsvForms().front();
}

std::string Join(const std::vector<std::string>& fields) {
  std::string out;
  for (const std::string& f : fields) out += (out.empty() ? "" : ",") + f;
  return out;
}

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    std::string field =
        Trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (field.size() >= 2 && field.front() == '"' && field.back() == '"')
      field = field.substr(1, field.size() - 2);
    fields.push_back(field);
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

std::optional<double> ParseFiniteNumber(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(x))
    return std::nullopt;
  return x;
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

const char* UnitName(LengthUnit unit) {
  return unit == LengthUnit::kMillimetre ? "millimetres" : "metres";
}

std::string KnownHeaders(LengthUnit unit) {
  std::string out;
  for (const CsvForm& form : CsvForms())
    out += (out.empty() ? "" : ", ") + ("'" + Join(form.header) + "' (" + form.meaning + ")");
  return out + "; x, y, z in " + UnitName(unit) + " (--rotation names the form for other headers)";
}

// The form the header names, or the one asked for when its column count fits.
const CsvForm& HeaderForm(const std::vector<std::string>& fields, const PoseListOptions& options,
                          const Fail& fail) {
  if (options.rotation) {
    const CsvForm& form = FormOf(*options.rotation);
    if (fields.size() != form.header.size())
      throw fail("expected a header of " + std::to_string(form.header.size()) +
                 " columns for --rotation " + CsvRotationName(form.rotation) + " (" +
                 Join(form.header) + "), got " + std::to_string(fields.size()));
    return form;
  }
  std::vector<std::string> lower;
  for (const std::string& f : fields) lower.push_back(Lower(f));
  for (const CsvForm& form : CsvForms())
    if (lower == form.header) return form;
  throw fail("expected one of the headers " + KnownHeaders(options.unit) + ", got '" +
             Join(fields) + "'");
}

Eigen::Matrix3d RowRotation(const CsvForm& form, const double* r, bool reorthonormalise,
                            const Fail& fail) {
  const Eigen::Vector3d v(r[0], r[1], r[2]);
  switch (form.rotation) {
    case CsvRotation::kQuaternion: {
      std::string why;
      const auto q = UnitQuaternion(r[3], r[0], r[1], r[2], reorthonormalise, &why);
      if (!q)
        throw fail("columns " + Join({form.header.begin() + 4, form.header.end()}) + ": expected " +
                   why);
      return q->toRotationMatrix();
    }
    case CsvRotation::kRotationVector:
      return MatrixFromRotationVector(v);
    case CsvRotation::kKukaAbc:
      return RotationFromEulerDeg(EulerConvention::kKukaAbc, v);
    case CsvRotation::kRpy:
      return RotationFromEulerDeg(EulerConvention::kRpy, v);
  }
  return Eigen::Matrix3d::Identity();
}

// Ids are unique; `where` of the first is remembered for the message
// ("line 3", "/poses/2").
void RequireNewId(std::map<std::string, std::string>* seen, const std::string& id,
                  const std::string& where, const Fail& fail) {
  const auto [it, inserted] = seen->emplace(id, where);
  if (!inserted) throw fail("duplicate pose id '" + id + "' (also " + it->second + ")");
}

PoseRow CsvRow(const std::vector<std::string>& fields, const CsvForm& form, int line, double scale,
               bool reorthonormalise, const Fail& fail) {
  const std::size_t columns = form.header.size();
  if (fields.size() != columns)
    throw fail("expected " + std::to_string(columns) + " comma-separated fields (" +
               Join(form.header) + "), got " + std::to_string(fields.size()));
  PoseRow row;
  row.line = line;
  row.id = fields[0];
  if (row.id.empty()) throw fail("column id: expected a pose id, got an empty field");
  double v[7];
  for (std::size_t k = 1; k < columns; ++k) {
    const auto x = ParseFiniteNumber(fields[k]);
    if (!x)
      throw fail("column " + form.header[k] + ": expected a finite number, got '" + fields[k] +
                 "'");
    v[k - 1] = *x;
  }
  row.T_base_ee.linear() = RowRotation(form, v + 3, reorthonormalise, fail);
  row.T_base_ee.translation() = scale * Eigen::Vector3d(v[0], v[1], v[2]);
  return row;
}

// --- YAML ------------------------------------------------------------------------

// {x, y, z} or, with `w`, {x, y, z, w}: the numbers in that order.
std::vector<double> YamlNumbers(const JsonReader& r, bool with_w) {
  r.ExpectObject(with_w ? "a quaternion {x, y, z, w}" : "a position {x, y, z}");
  r.RejectUnknownKeys(with_w ? std::vector<std::string>{"x", "y", "z", "w"}
                             : std::vector<std::string>{"x", "y", "z"});
  std::vector<double> v = {r.Key("x").Number(), r.Key("y").Number(), r.Key("z").Number()};
  if (with_w) v.push_back(r.Key("w").Number());
  return v;
}

std::string YamlId(const JsonReader& item, std::size_t index) {
  if (!item.Has("id")) {
    char id[32];
    std::snprintf(id, sizeof id, "%04zu", index + 1);
    return id;
  }
  const JsonReader id = item.Key("id");
  if (id.json().is_number_integer()) return std::to_string(id.json().get<long long>());
  return id.NonEmptyString("a pose id (a string, or an integer)");
}

PoseRow YamlRow(const JsonReader& item, std::size_t index, double scale, bool reorthonormalise) {
  const std::string expected =
      "a geometry_msgs/Pose {position: {x, y, z}, orientation: {x, y, z, w}}";
  item.ExpectObject(expected + ", optionally with id, or a PoseStamped {header, pose}");
  const bool stamped = item.Has("pose");
  const JsonReader pose = stamped ? item.Key("pose") : item;
  item.RejectUnknownKeys(stamped ? std::vector<std::string>{"id", "header", "pose"}
                                 : std::vector<std::string>{"id", "position", "orientation"});
  pose.ExpectObject(expected);
  if (stamped) pose.RejectUnknownKeys({"position", "orientation"});
  PoseRow row;
  row.id = YamlId(item, index);
  const JsonReader orientation = pose.Key("orientation");
  const std::vector<double> o = YamlNumbers(orientation, true);
  std::string why;
  const auto q = UnitQuaternion(o[3], o[0], o[1], o[2], reorthonormalise, &why);
  if (!q) throw orientation.Error("expected " + why);
  const std::vector<double> p = YamlNumbers(pose.Key("position"), false);
  row.T_base_ee = MakeTransform(*q, scale * Eigen::Vector3d(p[0], p[1], p[2]));
  return row;
}

double Scale(LengthUnit unit) { return unit == LengthUnit::kMillimetre ? 1e-3 : 1.0; }

std::string Metres(double d) {
  char text[32];
  if (d >= 1) {
    std::snprintf(text, sizeof text, "%.4g m", d);
  } else {
    std::snprintf(text, sizeof text, "%.4g mm", d * 1e3);
  }
  return text;
}

}  // namespace

const char* CsvRotationName(CsvRotation rotation) {
  switch (rotation) {
    case CsvRotation::kQuaternion:
      return "quaternion";
    case CsvRotation::kRotationVector:
      return "rotvec";
    case CsvRotation::kKukaAbc:
      return "kuka_abc";
    case CsvRotation::kRpy:
      return "rpy";
  }
  return "";
}

std::optional<CsvRotation> ParseCsvRotation(const std::string& name) {
  for (const CsvForm& form : CsvForms())
    if (name == CsvRotationName(form.rotation)) return form.rotation;
  return std::nullopt;
}

std::vector<PoseRow> ReadPoseCsv(const std::string& path, const PoseListOptions& options) {
  std::istringstream in(internal::ReadTextFile(path, "a CSV pose list"));
  const CsvForm* form = nullptr;
  std::vector<PoseRow> rows;
  std::map<std::string, std::string> seen;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    if (number == 1 && text.rfind("\xEF\xBB\xBF", 0) == 0)
      text = text.substr(3);  // spreadsheet BOM
    const std::string line = Trim(text);
    if (line.empty() || line[0] == '#') continue;
    const Fail fail = [&](const std::string& what) {
      return InputError(path, "", "line " + std::to_string(number) + ": " + what);
    };
    const std::vector<std::string> fields = SplitFields(line);
    if (!form) {
      form = &HeaderForm(fields, options, fail);
      continue;
    }
    PoseRow row =
        CsvRow(fields, *form, number, Scale(options.unit), options.reorthonormalise, fail);
    RequireNewId(&seen, row.id, "on line " + std::to_string(number), fail);
    rows.push_back(std::move(row));
  }
  if (!form)
    throw InputError(path, "",
                     "empty file; expected a header row and rows: " + KnownHeaders(options.unit));
  if (rows.empty())
    throw InputError(path, "",
                     "no poses; expected rows after the header '" + Join(form->header) + "'");
  return rows;
}

std::vector<PoseRow> ReadPoseCsv(const std::string& path, LengthUnit unit, bool reorthonormalise) {
  PoseListOptions options;
  options.unit = unit;
  options.reorthonormalise = reorthonormalise;
  return ReadPoseCsv(path, options);
}

std::vector<PoseRow> ReadPoseYaml(const std::string& path, const PoseListOptions& options) {
  const nlohmann::json doc = ReadYamlFile(path);
  const JsonReader root(&doc, path);
  const bool array = root.present() && root.json().is_object() && root.Has("poses");
  const JsonReader list = array ? root.Key("poses") : root;
  if (array) root.RejectUnknownKeys({"header", "poses"});
  const std::size_t n = list.ArraySize(
      "a list of geometry_msgs/Pose (position, orientation), or a PoseArray {header, poses: "
      "[...]}");
  if (n == 0) throw list.Error("no poses; expected at least one");
  std::vector<PoseRow> rows;
  std::map<std::string, std::string> seen;
  for (std::size_t i = 0; i < n; ++i) {
    const JsonReader item = list.At(i);
    PoseRow row = YamlRow(item, i, Scale(options.unit), options.reorthonormalise);
    RequireNewId(&seen, row.id, "at " + item.path(),
                 [&](const std::string& what) { return item.Error(what); });
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<PoseRow> ReadPoseList(const std::string& path, const PoseListOptions& options) {
  const std::size_t dot = path.find_last_of('.');
  const std::string extension = dot == std::string::npos ? "" : Lower(path.substr(dot));
  if (extension == ".yaml" || extension == ".yml") return ReadPoseYaml(path, options);
  return ReadPoseCsv(path, options);
}

std::optional<std::size_t> ImplausibleReach(const std::vector<Eigen::Vector3d>& translations) {
  if (translations.empty()) return std::nullopt;
  std::size_t farthest = 0;
  for (std::size_t i = 1; i < translations.size(); ++i)
    if (translations[i].norm() > translations[farthest].norm()) farthest = i;
  const double reach = translations[farthest].norm();
  if (reach > kMaxRobotReachM || (translations.size() > 1 && reach < kMinRobotReachM))
    return farthest;
  return std::nullopt;
}

void RequirePlausibleReach(const std::vector<PoseRow>& rows, const std::string& path,
                           LengthUnit unit, const std::string& unit_option) {
  std::vector<Eigen::Vector3d> translations;
  for (const PoseRow& row : rows) translations.push_back(row.T_base_ee.translation());
  const auto farthest = ImplausibleReach(translations);
  if (!farthest) return;
  const PoseRow& row = rows[*farthest];
  const double reach = translations[*farthest].norm();
  const std::string pose =
      "pose '" + row.id + "'" +
      (row.line > 0 ? " (line " + std::to_string(row.line) + ")" : std::string());
  const std::string read_as = std::string(" with x, y, z read as ") + UnitName(unit);
  if (reach > kMaxRobotReachM)
    throw InputError(path, "",
                     pose + " is " + Metres(reach) + " from the robot base" + read_as +
                         ", farther than a robot reaches (" + Metres(kMaxRobotReachM) +
                         "); if they are millimetres, use " + unit_option + " mm");
  throw InputError(path, "",
                   "every pose is within " + Metres(kMinRobotReachM) + " of the robot base" +
                       read_as + " (the farthest, " + pose + ", " + Metres(reach) +
                       "); if they are metres, use " + unit_option + " m");
}

}  // namespace handeye
