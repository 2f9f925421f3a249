// SPDX-License-Identifier: GPL-2.0-or-later
#include "convert.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <thread>

#include "../../tools/cli_numbers.h"
#include "../../tools/target_options.h"
#include "handeye/core/error.h"
#include "handeye/core/transform.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/json_util.h"

namespace handeye::python {
namespace {

std::string TypeName(py::handle value) {
  return py::str(py::type::handle_of(value).attr("__name__"));
}

std::string ShapeText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// The value as a numpy array whose dtype kind is one of `kinds` ('f' float,
// 'i' / 'u' integer). Lists and tuples are converted as numpy would; strings,
// objects and ragged lists are refused.
py::array NumericArray(py::handle value, const std::string& where, const char* kinds,
                       const std::string& what) {
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) || value.is_none())
    throw InputError("", where, "expected " + what + ", got " + TypeName(value));
  py::array a = py::array::ensure(value);
  if (!a)
    throw InputError(
        "", where,
        "expected " + what + ", got " + TypeName(value) + " that is no array of numbers");
  const char kind = a.dtype().kind();
  if (!std::strchr(kinds, kind))
    throw InputError(
        "", where,
        "expected " + what + ", got an array of dtype " + std::string(py::str(a.dtype())));
  return a;
}

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

DoubleArray AsDoubles(py::handle value, const std::string& where, const std::string& what) {
  return DoubleArray::ensure(NumericArray(value, where, "fiu", what));
}

void RequireFinite(const double* data, py::ssize_t n, const std::string& where) {
  for (py::ssize_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i]))
      throw InputError("", where, "expected finite numbers, got NaN or infinity");
}

TargetValue TargetValueOf(py::handle value, const std::string& where) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::bool_>(value))
    throw InputError("", where, "expected a number, a string or a list of numbers, got bool");
  if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value))
    return value.cast<double>();
  return FiniteVector(value, where);
}

}  // namespace

Eigen::MatrixXd FiniteMatrix(py::handle value, int rows, int cols, const std::string& where) {
  const std::string what = (rows < 0 ? std::string("an N") : std::to_string(rows)) + "×" +
                           std::to_string(cols) + " array of numbers";
  DoubleArray a = AsDoubles(value, where, what);
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || a.shape(1) != cols)
    throw InputError("", where, "expected " + what + ", got shape " + ShapeText(a));
  RequireFinite(a.data(), a.size(), where);
  Eigen::MatrixXd M(a.shape(0), cols);
  for (py::ssize_t r = 0; r < a.shape(0); ++r)
    for (int c = 0; c < cols; ++c) M(r, c) = a.at(r, c);
  return M;
}

std::vector<double> FiniteVector(py::handle value, const std::string& where) {
  DoubleArray a = AsDoubles(value, where, "a list of numbers");
  const bool column_or_row = a.ndim() == 2 && (a.shape(0) == 1 || a.shape(1) == 1);
  if (a.ndim() != 1 && !column_or_row)
    throw InputError("", where, "expected a list of numbers (1-D), got shape " + ShapeText(a));
  RequireFinite(a.data(), a.size(), where);
  return std::vector<double>(a.data(), a.data() + a.size());
}

std::vector<int> IdVector(py::handle value, const std::string& where) {
  const std::string what = "a 1-D array of integer ids";
  py::array a = NumericArray(value, where, "iu", what);
  if (a.ndim() != 1)
    throw InputError("", where, "expected " + what + ", got shape " + ShapeText(a));
  auto ids = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<int> out;
  out.reserve(ids.size());
  for (py::ssize_t i = 0; i < ids.size(); ++i) {
    const long long id = ids.at(i);
    if (id < 0 || id > 1000000000)
      throw InputError("", where, "expected ids between 0 and 10^9, got " + std::to_string(id));
    out.push_back(static_cast<int>(id));
  }
  return out;
}

void CheckThreads(int threads) {
  const long long cores = std::max(1u, std::thread::hardware_concurrency());
  const long long most = std::min<long long>(tools::kMaxThreads, tools::kMaxThreadsPerCore * cores);
  if (threads < 0 || threads > most)
    throw InputError("", "threads",
                     "expected 0 (all cores) or a positive count up to " + std::to_string(most) +
                         ", got " + std::to_string(threads));
}

Eigen::Isometry3d RigidTransform(py::handle value, const std::string& where,
                                 bool reorthonormalise) {
  const Eigen::Matrix4d M = FiniteMatrix(value, 4, 4, where);
  std::string why;
  const auto T = RigidFromMatrix(M, reorthonormalise, &why);
  if (!T) throw InputError("", where, "expected a rigid 4×4 transform: " + why);
  return *T;
}

py::array_t<double> TransformArray(const Eigen::Isometry3d& T) { return MatrixArray(T.matrix()); }

py::array_t<double> MatrixArray(const Eigen::MatrixXd& M) {
  py::array_t<double> a({static_cast<py::ssize_t>(M.rows()), static_cast<py::ssize_t>(M.cols())});
  auto out = a.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < M.rows(); ++r)
    for (Eigen::Index c = 0; c < M.cols(); ++c) out(r, c) = M(r, c);
  return a;
}

Camera CameraFromArrays(const std::string& name, py::handle K, py::handle distortion,
                        py::handle image_size) {
  const std::string where = "cameras['" + name + "']";
  const Eigen::Matrix3d k = FiniteMatrix(K, 3, 3, where + ".K");
  if (k(0, 1) != 0 || k(1, 0) != 0 || k(2, 0) != 0 || k(2, 1) != 0 || k(2, 2) != 1)
    throw InputError("", where + ".K", "expected [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)");
  const std::vector<double> dist = distortion.is_none()
                                       ? std::vector<double>{}
                                       : FiniteVector(distortion, where + ".distortion");
  const std::vector<double> size = FiniteVector(image_size, where + ".image_size");
  if (size.size() != 2 || size[0] != std::floor(size[0]) || size[1] != std::floor(size[1]) ||
      size[0] < 1 || size[1] < 1 || size[0] > 1e6 || size[1] > 1e6)
    throw InputError("", where + ".image_size", "expected (width, height) in whole pixels");
  std::string why;
  auto camera = Camera::Make(name, static_cast<int>(size[0]), static_cast<int>(size[1]), k(0, 0),
                             k(1, 1), k(0, 2), k(1, 2), dist, &why);
  if (!camera) throw InputError("", where, "expected a valid camera: " + why);
  return *camera;
}

py::array_t<double> CameraMatrix(const Camera& camera) {
  Eigen::Matrix3d K;
  K << camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1;
  return MatrixArray(K);
}

std::shared_ptr<const Target> TargetFrom(py::handle target, std::vector<Warning>* warnings) {
  std::shared_ptr<const Target> made;
  if (py::isinstance<py::str>(target)) {
    // A type name gives that type's default sheet, a .json path the target in
    // it: exactly what `handeye simulate --target` / `--target-json` make.
    const std::string text = target.cast<std::string>();
    tools::TargetOptions options;
    const bool file = text.size() > 5 && text.compare(text.size() - 5, 5, ".json") == 0;
    (file ? options.target_json : options.type) = text;
    made = tools::MakeTargetFromOptions(options, false);
  } else if (py::isinstance<py::dict>(target)) {
    TargetSpec spec;
    for (const auto& [key, value] : target.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key)) throw InputError("", "target", "expected string keys");
      const std::string name = key.cast<std::string>();
      if (name == "type") {
        if (!py::isinstance<py::str>(value))
          throw InputError("", "target/type", "expected a string");
        spec.type = value.cast<std::string>();
      } else {
        spec.values[name] = TargetValueOf(value, "target/" + name);
      }
    }
    if (spec.type.empty())
      throw InputError("", "target/type",
                       "missing key; expected the target type, e.g. 'checkerboard'");
    try {
      made = MakeTarget(spec);
    } catch (const InputError& e) {
      throw e.WithFile("", "target");
    }
  } else {
    throw InputError(
        "", "target",
        "expected a dict (the dataset's target object), a type name or a .json path, got " +
            TypeName(target));
  }
  if (warnings)
    for (const auto& w : made->Warnings()) warnings->push_back(GeneralWarning(WarningKind::kTargetAmbiguous, w));
  return made;
}

py::dict TargetDict(const Target& target) {
  const std::string text = JsonFromTargetSpec(target.Spec()).dump();
  return py::dict(py::module_::import("json").attr("loads")(text));
}

}  // namespace handeye::python
