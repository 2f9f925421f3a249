// SPDX-License-Identifier: GPL-2.0-or-later
// handeye.Result and handeye.CameraResult: a CalibrationResult with its
// transforms as numpy arrays and the same JSON the CLI writes.
#include "result.h"

#include <pybind11/stl.h>

#include <cstdio>

#include "../../tools/output_paths.h"
#include "bindings.h"
#include "convert.h"
#include "handeye/core/calibration.h"
#include "handeye/core/setup_frames.h"
#include "handeye/io/result_json.h"

namespace handeye::python {
namespace {

py::object SigmaDict(const std::optional<PoseUncertainty>& sigma) {
  if (!sigma) return py::none();
  py::dict d;
  d["position_mm"] = sigma->position_mm;
  d["rotation_deg"] = sigma->rotation_deg;
  d["own_position_mm"] = sigma->OwnPositionMm();
  d["own_rotation_deg"] = sigma->OwnRotationDeg();
  d["covariance"] = MatrixArray(sigma->covariance);
  d["covariance_from_given_intrinsics"] = MatrixArray(sigma->from_given_intrinsics);
  return std::move(d);
}

py::object IntrinsicsDict(const std::optional<IntrinsicsResult>& intrinsics) {
  if (!intrinsics) return py::none();
  py::dict d;
  d["K"] = CameraMatrix(intrinsics->camera);
  d["distortion"] = py::array_t<double>(py::cast(intrinsics->camera.Distortion()));
  d["image_size"] = py::make_tuple(intrinsics->camera.width, intrinsics->camera.height);
  d["sigma"] = py::array_t<double>(
      py::cast(std::vector<double>(intrinsics->sigma.begin(), intrinsics->sigma.end())));
  d["refined"] = intrinsics->refined;
  d["undetermined"] = intrinsics->undetermined;
  return std::move(d);
}

const CameraResult& CameraNamed(const CalibrationResult& r, const std::string& name) {
  for (const CameraResult& c : r.cameras)
    if (c.name == name) return c;
  throw py::key_error("no camera '" + name + "' in the result");
}

py::dict TransformsOfCameras(const CalibrationResult& r) {
  py::dict out;
  for (const CameraResult& c : r.cameras)
    if (c.calibrated) out[py::str(c.name)] = TransformArray(c.T_cam);
  return out;
}

py::list Pairs(const CalibrationResult& r) {
  py::list out;
  for (const CameraPairResult& p : r.camera_pairs) {
    py::dict d;
    d["camera_k"] = p.camera_k;
    d["camera_t"] = p.camera_t;
    d["T_camk_camt"] = TransformArray(p.T_camk_camt);
    d["shared_views"] = p.shared_views;
    out.append(d);
  }
  return out;
}

// One part of the result file's content as Python values (the file is
// formatted and parsed once per Result): the figures the file names are
// handed out under its own names.
py::object FilePart(const PyResult& r, const char* key) {
  if (!r.file_content)
    r.file_content = py::module_::import("json").attr("loads")(ResultJson(r.result));
  return r.file_content[key];
}

std::string CameraRepr(const CameraResult& c) {
  if (!c.calibrated) return "<handeye.CameraResult " + c.name + ": not calibrated>";
  const Eigen::Vector3d t = 1000.0 * c.T_cam.translation();
  char text[160];
  std::snprintf(text, sizeof text,
                "<handeye.CameraResult %s: at (%.2f, %.2f, %.2f) mm, rms %.3f px, %d views>",
                c.name.c_str(), t.x(), t.y(), t.z(), c.rms_px, c.views);
  return text;
}

}  // namespace

void AddResult(py::module_& m) {
  // CameraResult objects share their Result's storage (keep_alive via reference_internal).
  py::class_<CameraResult>(m, "CameraResult", "One camera's calibration.")
      .def_readonly("name", &CameraResult::name)
      .def_readonly("calibrated", &CameraResult::calibrated)
      .def_property_readonly(
          "T_cam",
          [](const CameraResult& c) {
            return c.calibrated ? py::object(TransformArray(c.T_cam)) : py::none();
          },
          "4×4: T_base_cam (eye_to_hand) or T_ee_cam (eye_in_hand); None when not calibrated.")
      .def_readonly("rms_px", &CameraResult::rms_px)
      .def_readonly("max_px", &CameraResult::max_px)
      .def_readonly("views", &CameraResult::views)
      .def_readonly("views_rejected", &CameraResult::views_rejected)
      .def_readonly("outliers", &CameraResult::outliers)
      .def_property_readonly(
          "sigma", [](const CameraResult& c) { return SigmaDict(c.sigma); },
          "1σ: position_mm, rotation_deg and the 6×6 covariance (mm, deg); own_position_mm, "
          "own_rotation_deg without covariance_from_given_intrinsics, the part the given "
          "intrinsics' uncertainty adds (what a capture again with the same intrinsics scatters "
          "by); None when unknown.")
      .def_property_readonly(
          "given_intrinsics_offset_px",
          [](const CameraResult& c) -> py::object {
            if (!c.given_intrinsics_offset_px) return py::none();
            const Eigen::Vector4d& d = *c.given_intrinsics_offset_px;
            py::dict out;
            out["fx"] = d[0];
            out["fy"] = d[1];
            out["cx"] = d[2];
            out["cy"] = d[3];
            return std::move(out);
          },
          "What the views say the given fx, fy, cx, cy are off by (px), the shift sigma holds; "
          "None where the given intrinsics are exact or refined.")
      .def_property_readonly("intrinsics",
                             [](const CameraResult& c) { return IntrinsicsDict(c.intrinsics); })
      .def("__repr__", &CameraRepr);

  py::class_<PyResult>(m, "Result", "A calibration result (handeye-result/1).")
      .def_property_readonly("setup", [](const PyResult& r) { return SetupName(r.result.setup); })
      .def_property_readonly("method",
                             [](const PyResult& r) { return MethodName(r.result.method); })
      .def_property_readonly(
          "cameras",
          [](py::object self) {
            // Each element refers into this Result, which it keeps alive.
            py::list out;
            for (const CameraResult& c : self.cast<const PyResult&>().result.cameras)
              out.append(py::cast(&c, py::return_value_policy::reference_internal, self));
            return out;
          },
          "The cameras' results (CameraResult), in the dataset's order.")
      .def(
          "camera",
          [](const PyResult& r, const std::string& name) { return &CameraNamed(r.result, name); },
          py::arg("name"), py::return_value_policy::reference_internal)
      .def_property_readonly(
          "T_cam", [](const PyResult& r) { return TransformsOfCameras(r.result); },
          "{camera name: 4×4 T_base_cam or T_ee_cam} of the calibrated cameras.")
      .def_property_readonly(
          "T_target", [](const PyResult& r) { return TransformArray(r.result.T_target); },
          "4×4: T_ee_target (eye_to_hand) or T_base_target (eye_in_hand).")
      // The frame-explicit readings (CalibrationResult): the other setup's
      // frame raises RuntimeError naming the one to read, an unknown or
      // uncalibrated camera IndexError.
      .def(
          "T_base_cam",
          [](const PyResult& r, const std::string& camera) {
            return TransformArray(r.result.T_base_cam(camera));
          },
          py::arg("camera"), "4×4 T_base_cam of an eye_to_hand result.")
      .def(
          "T_ee_cam",
          [](const PyResult& r, const std::string& camera) {
            return TransformArray(r.result.T_ee_cam(camera));
          },
          py::arg("camera"), "4×4 T_ee_cam of an eye_in_hand result.")
      .def(
          "T_ee_target", [](const PyResult& r) { return TransformArray(r.result.T_ee_target()); },
          "4×4 T_ee_target of an eye_to_hand result.")
      .def(
          "T_base_target",
          [](const PyResult& r) { return TransformArray(r.result.T_base_target()); },
          "4×4 T_base_target of an eye_in_hand result.")
      .def(
          "T_base_cam_at",
          [](const PyResult& r, const std::string& camera, py::handle T_base_ee) {
            return TransformArray(
                r.result.T_base_cam_at(camera, RigidTransform(T_base_ee, "T_base_ee", true)));
          },
          py::arg("camera"), py::arg("T_base_ee"),
          "4×4: the camera in the base frame with the robot at T_base_ee (either setup).")
      .def_property_readonly("target_sigma",
                             [](const PyResult& r) { return SigmaDict(r.result.target_sigma); })
      .def_property_readonly("camera_pairs", [](const PyResult& r) { return Pairs(r.result); })
      .def_property_readonly(
          "metrics", [](const PyResult& r) { return FilePart(r, "metrics"); },
          "The result file's `metrics` (rms_px, axzb_…).")
      .def_property_readonly(
          "solver", [](const PyResult& r) { return FilePart(r, "solver"); },
          "The result file's `solver` (seconds, iterations, converged, cauchy_scale_px, …).")
      .def_property_readonly(
          "views", [](const PyResult& r) { return FilePart(r, "views"); },
          "The result file's `views`: pose, camera, points, used, rms_px, … per view.")
      .def_property_readonly(
          "warnings", [](const PyResult& r) { return WarningTexts(r.result.warnings); },
          "What a user must see, as the CLI prints them.")
      .def_property_readonly(
          "warning_details", [](const PyResult& r) { return FilePart(r, "warning_details"); },
          "The result file's `warning_details`: kind, camera, pose, view and text per warning, "
          "in the order of `warnings`.")
      .def_property_readonly("notes", [](const PyResult& r) { return r.result.notes; })
      .def(
          "to_json", [](const PyResult& r) { return ResultJson(r.result); },
          "The handeye-result/1 text `handeye calibrate -o` writes.")
      .def(
          "save",
          [](const PyResult& r, const std::string& path) {
            tools::CheckFileOutputs({{"INPUT", r.result.input}}, {{"path", path}});
            SaveResult(r.result, path);
          },
          py::arg("path"), "Writes handeye-result/1 (atomically).")
      .def("__repr__", [](const PyResult& r) {
        int calibrated = 0;
        for (const CameraResult& c : r.result.cameras) calibrated += c.calibrated ? 1 : 0;
        char text[160];
        std::snprintf(text, sizeof text,
                      "<handeye.Result %s, %s: %d of %zu cameras, rms %.3f px, %zu warnings>",
                      MethodName(r.result.method), SetupName(r.result.setup), calibrated,
                      r.result.cameras.size(), r.result.metrics.rms_px, r.result.warnings.size());
        return std::string(text);
      });

  m.def(
      "load_result",
      [](const std::string& path) {
        PyResult out;
        out.result = LoadResult(path);
        return out;
      },
      py::arg("path"), "Reads a handeye-result/1 file.");
}

}  // namespace handeye::python
