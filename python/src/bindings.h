// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The pieces of the `handeye._handeye` extension, each adding its classes
/// and functions to the module (module.cc calls them in order).

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "handeye/core/dataset.h"
#include "handeye/core/warning.h"

namespace handeye::python {

namespace py = pybind11;

/// A dataset as Python holds it: the library's Dataset, the file it came
/// from (empty when built in memory) and the warnings its loading gave.
struct PyDataset {
  Dataset dataset;
  std::string path;
  std::vector<Warning> warnings;
};

/// Issues each warning's text as a Python UserWarning (stacklevel 2: the caller's line).
void WarnAll(const std::vector<Warning>& warnings);

void AddErrors(py::module_& m);     ///< InputError, SolveError and their translation
void AddDataset(py::module_& m);    ///< Dataset
void AddResult(py::module_& m);     ///< CameraResult, Result, load_result
void AddCalibrate(py::module_& m);  ///< calibrate
void AddTools(py::module_& m);      ///< detect, check, export, simulate

}  // namespace handeye::python
