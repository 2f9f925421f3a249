// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// The Python Result holds the library's CalibrationResult by value.

#include <pybind11/pybind11.h>

#include "handeye/core/calibration.h"

namespace handeye::python {

/// A calibration result as handeye.Result.
struct PyResult {
  CalibrationResult result;
  /// The result file's content (json.loads of ResultJson), made on first use.
  mutable pybind11::object file_content;
};

}  // namespace handeye::python
