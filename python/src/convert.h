// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// numpy arrays and Python values in and out of the library's types. Every
/// conversion checks shape, dtype and finiteness itself and throws
/// handeye::InputError naming the argument (e.g. `T_base_ee[3]`) and what was
/// expected, so that no Python value reaches the library unchecked.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "handeye/core/camera.h"
#include "handeye/core/target.h"
#include "handeye/core/warning.h"

namespace handeye::python {

namespace py = pybind11;

/// A real (float or integer) array of exactly `rows` × `cols` (`rows` < 0:
/// any number of rows) with finite entries, as a row-major matrix. A (rows·cols,)
/// or (rows, cols, 1)-like array of the same size is not accepted: the shape
/// is part of what the argument means.
Eigen::MatrixXd FiniteMatrix(py::handle value, int rows, int cols, const std::string& where);
/// A finite real vector of any length (1-D, or a column / row of a 2-D array).
std::vector<double> FiniteVector(py::handle value, const std::string& where);
/// Integer ids (1-D array or list of integers; floats are refused).
std::vector<int> IdVector(py::handle value, const std::string& where);
/// Throws InputError unless `threads` is 0 (all cores) or a count the CLI's
/// --threads accepts (at most kMaxThreadsPerCore per core and kMaxThreads).
void CheckThreads(int threads);
/// A 4×4 rigid transform: last row [0 0 0 1], rotation orthonormal (or made so).
Eigen::Isometry3d RigidTransform(py::handle value, const std::string& where,
                                 bool reorthonormalise = false);

/// A new (4, 4) float64 array holding the transform's matrix.
py::array_t<double> TransformArray(const Eigen::Isometry3d& T);
/// A new float64 array of the matrix's shape.
py::array_t<double> MatrixArray(const Eigen::MatrixXd& M);

/// A camera from a 3×3 camera matrix (no skew), distortion in OpenCV order
/// (0, 4, 5, 8, 12 or 14 coefficients) and the image size (width, height).
Camera CameraFromArrays(const std::string& name, py::handle K, py::handle distortion,
                        py::handle image_size);
/// The camera matrix K of a camera.
py::array_t<double> CameraMatrix(const Camera& camera);

/// A target from a `target` object as a dict (SPEC §4, e.g. {"type":
/// "checkerboard", "inner_corners": [7, 4], "square_size_m": 0.04}), a type
/// name for its default sheet (as `handeye simulate --target`), or a path to
/// a JSON file holding one (as `--target-json`). Its warnings (an ambiguous
/// board) are appended to `warnings` when given.
std::shared_ptr<const Target> TargetFrom(py::handle target,
                                         std::vector<Warning>* warnings = nullptr);
/// The target's `target` object as a dict.
py::dict TargetDict(const Target& target);

}  // namespace handeye::python
