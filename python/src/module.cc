// SPDX-License-Identifier: GPL-2.0-or-later
// handeye._handeye: the compiled part of the `handeye` Python package
// (python/handeye/__init__.py re-exports it and adds the OpenCV adapter).
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "handeye/core/error.h"

namespace handeye::python {

void WarnAll(const std::vector<Warning>& warnings) {
  for (const Warning& w : warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.text.c_str(), 2) != 0) throw py::error_already_set();
}

void AddErrors(py::module_& m) {
  // Python classes of their own (not py::register_exception) so that they can
  // carry the file, the path and what was expected as attributes, and derive
  // from the built-ins a caller would catch.
  static py::handle input_error, solve_error;
  py::object builtins = py::module_::import("builtins");
  py::dict input_ns, solve_ns;
  input_ns["__doc__"] =
      "Bad input (exit code 2 in the CLI): the message names the file or argument, the path "
      "inside it and what was expected; also as the attributes file, json_path and expected.";
  input_ns["__module__"] = "handeye";
  solve_ns["__doc__"] =
      "The calibration could not be solved (exit code 3 in the CLI): too few views, "
      "degenerate motion, a failed solve.";
  solve_ns["__module__"] = "handeye";
  py::object type = builtins.attr("type");
  py::object input_cls = type("InputError", py::make_tuple(builtins.attr("ValueError")), input_ns);
  py::object solve_cls =
      type("SolveError", py::make_tuple(builtins.attr("RuntimeError")), solve_ns);
  m.attr("InputError") = input_cls;
  m.attr("SolveError") = solve_cls;
  input_error = input_cls.release();
  solve_error = solve_cls.release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      py::object error = py::reinterpret_borrow<py::object>(input_error)(e.what());
      error.attr("file") = e.file();
      error.attr("json_path") = e.json_path();
      error.attr("expected") = e.expected();
      PyErr_SetObject(input_error.ptr(), error.ptr());
    } catch (const SolveError& e) {
      PyErr_SetString(solve_error.ptr(), e.what());
    }
  });
}

}  // namespace handeye::python

PYBIND11_MODULE(_handeye, m) {
  m.doc() = "handeye: multi-camera hand-eye calibration (the compiled core; use `import handeye`).";
  namespace hp = handeye::python;
  hp::AddErrors(m);
  hp::AddDataset(m);
  hp::AddResult(m);
  hp::AddCalibrate(m);
  hp::AddTools(m);
}
