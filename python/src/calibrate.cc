// SPDX-License-Identifier: GPL-2.0-or-later
// handeye.calibrate: the same calls as `handeye calibrate` (tools/calibrate.cc),
// from a file, a Dataset in memory or images on disk.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "bindings.h"
#include "convert.h"
#include "handeye/core/calibration.h"
#include "handeye/core/error.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/result_json.h"
#include "progress.h"
#include "result.h"

namespace handeye::python {
namespace {

Method MethodFrom(const std::string& name) {
  const auto method = ParseMethod(name);
  if (method) return *method;
  std::string names;
  for (const auto& n : MethodNames()) names += (names.empty() ? "" : ", ") + n;
  throw InputError("", "method", "expected one of " + names + "; got '" + name + "'");
}

unsigned IntrinsicsFrom(py::handle refine) {
  if (refine.is_none()) return kNoIntrinsics;
  std::string list;
  if (py::isinstance<py::str>(refine)) {
    list = refine.cast<std::string>();
  } else {
    for (py::handle item : refine)
      list += (list.empty() ? "" : ",") + py::str(item).cast<std::string>();
  }
  std::string why;
  const auto groups = ParseIntrinsicsGroups(list, &why);
  if (!groups) throw InputError("", "refine_intrinsics", why);
  return *groups;
}

// The given intrinsics' σ: None (the defaults), or the --intrinsics-sigma text.
GivenIntrinsicsSigma IntrinsicsSigmaFrom(py::handle value) {
  if (value.is_none()) return GivenIntrinsicsSigma{};
  if (!py::isinstance<py::str>(value))
    throw InputError("", "intrinsics_sigma", "expected a string such as 'focal=1%,principal_point=3px', '0' or None");
  std::string why;
  const auto sigma = ParseIntrinsicsSigma(value.cast<std::string>(), &why);
  if (!sigma) throw InputError("", "intrinsics_sigma", why);
  return *sigma;
}

// A robot sigma as given (None: -1, estimated), which must be finite and >= 0.
double RobotSigma(py::handle value, const std::string& name) {
  if (value.is_none()) return -1;
  const bool number = (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value)) &&
                      !py::isinstance<py::bool_>(value);
  const double sigma = number ? value.cast<double>() : -1;
  if (!number || !std::isfinite(sigma) || sigma < 0)
    throw InputError("", name, "expected a non-negative number or None (estimated from the views)");
  return sigma;
}

// `keep_cameras` with `from_result` (a Result or a result file): the cameras
// held at their earlier poses, as --keep-cameras with --from.
void HoldCameras(py::handle from_result, py::handle keep_cameras, CalibrationOptions* options,
                 Setup* setup) {
  if (from_result.is_none() && keep_cameras.is_none()) return;
  if (from_result.is_none() || keep_cameras.is_none())
    throw InputError("", "keep_cameras",
                     "keep_cameras and from_result go together: the cameras to hold, and the "
                     "result whose poses they keep");
  const bool is_path = py::isinstance<py::str>(from_result);
  const CalibrationResult previous = is_path ? LoadResult(from_result.cast<std::string>())
                                             : from_result.cast<const PyResult&>().result;
  const std::string file = is_path ? from_result.cast<std::string>() : "";
  *setup = previous.setup;
  for (py::handle item : keep_cameras) {
    const std::string name = py::str(item).cast<std::string>();
    const auto it = std::find_if(previous.cameras.begin(), previous.cameras.end(),
                                 [&](const CameraResult& c) { return c.name == name; });
    if (it == previous.cameras.end() || !it->calibrated)
      throw InputError(file, "/cameras",
                       "keep_cameras: a calibrated camera named '" + name + "' in from_result");
    options->fixed_cameras[name] = it->T_cam;
  }
}

struct CalibrateCall {
  py::object source;
  std::string method;
  double cauchy_scale_px;
  bool cross_terms, keep_all_views, cross_validate, closed_form, reorthonormalise;
  py::object robot_sigma_mm, robot_sigma_deg, refine_intrinsics, intrinsics_sigma, from_result, keep_cameras;
  int threads;
  py::object progress;
};

CalibrationOptions OptionsOf(const CalibrateCall& call, std::optional<Setup>* from_setup) {
  CalibrationOptions options;
  options.method = MethodFrom(call.method);
  options.cauchy_scale_px = call.cauchy_scale_px;
  options.cross_terms = call.cross_terms;
  options.compare_closed_form = call.closed_form;
  options.reject_views = !call.keep_all_views;
  options.robot_sigma_mm = RobotSigma(call.robot_sigma_mm, "robot_sigma_mm");
  options.robot_sigma_deg = RobotSigma(call.robot_sigma_deg, "robot_sigma_deg");
  options.refine_intrinsics = IntrinsicsFrom(call.refine_intrinsics);
  options.intrinsics_sigma = IntrinsicsSigmaFrom(call.intrinsics_sigma);
  Setup setup{};
  HoldCameras(call.from_result, call.keep_cameras, &options, &setup);
  if (!options.fixed_cameras.empty()) *from_setup = setup;
  options.cross_validate = call.cross_validate;
  CheckThreads(call.threads);
  // As the CLI: 0 is every core.
  options.threads = call.threads > 0
                        ? call.threads
                        : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::string why;
  if (!options.Check(&why)) throw InputError("", "", "invalid option: " + why);
  return options;
}

PyResult Calibrate(const CalibrateCall& call) {
  std::optional<Setup> from_setup;
  const CalibrationOptions options = OptionsOf(call, &from_setup);
  // A path is read as the CLI reads it; a Dataset is copied (cheap next to a
  // solve), so that other Python threads may change it while the solve runs
  // without the GIL.
  PyDataset loaded;
  const PyDataset* input = nullptr;
  if (py::isinstance<py::str>(call.source)) {
    loaded.path = call.source.cast<std::string>();
    LoadOptions load;
    load.reorthonormalise = call.reorthonormalise;
    loaded.dataset = WithoutGil([&] { return LoadDataset(loaded.path, load, &loaded.warnings); });
    WarnAll(loaded.warnings);
    input = &loaded;
  } else if (py::isinstance<PyDataset>(call.source)) {
    input = &call.source.cast<const PyDataset&>();
  } else {
    throw InputError("", "source",
                     "expected a dataset or observations file path, or a handeye.Dataset");
  }
  if (from_setup && *from_setup != input->dataset.setup)
    throw InputError("", "from_result/setup",
                     std::string("the dataset's setup, ") + SetupName(input->dataset.setup) +
                         ", for from_result");
  Dataset dataset = input == &loaded ? std::move(loaded.dataset) : input->dataset;
  if (dataset.observations.empty()) {
    bool has_images = false;
    for (const auto& pose : dataset.poses) has_images = has_images || !pose.images.empty();
    if (!has_images)
      throw InputError(input->path, "/observations",
                       "observations, or poses with images to detect in");
    Progress report(call.progress);
    DetectOptions detect;
    detect.threads = call.threads;
    detect.progress = report.Hook();
    WithoutGil([&] { DetectAll(&dataset, detect); });
    report.Rethrow();
  }
  PyResult out;
  try {
    out.result = WithoutGil([&] { return handeye::Calibrate(dataset, options); });
  } catch (const InputError& e) {
    throw e.file().empty() && !input->path.empty() ? e.WithFile(input->path) : e;
  }
  out.result.input = input->path;
  return out;
}

}  // namespace

void AddCalibrate(py::module_& m) {
  m.def(
      "calibrate",
      [](py::object source, const std::string& method, double cauchy_scale_px, bool cross_terms,
         bool keep_all_views, py::object robot_sigma_mm, py::object robot_sigma_deg,
         py::object refine_intrinsics, py::object intrinsics_sigma, py::object from_result,
         py::object keep_cameras, bool cross_validate, bool closed_form, int threads, bool reorthonormalise,
         py::object progress) {
        return Calibrate(CalibrateCall{source, method, cauchy_scale_px, cross_terms, keep_all_views,
                                       cross_validate, closed_form, reorthonormalise,
                                       robot_sigma_mm, robot_sigma_deg, refine_intrinsics,
                                       intrinsics_sigma, from_result, keep_cameras, threads, progress});
      },
      py::arg("source"), py::kw_only(), py::arg("method") = "joint",
      py::arg("cauchy_scale_px") = 0.0, py::arg("cross_terms") = true,
      py::arg("keep_all_views") = false, py::arg("robot_sigma_mm") = py::none(),
      py::arg("robot_sigma_deg") = py::none(), py::arg("refine_intrinsics") = py::none(),
      py::arg("intrinsics_sigma") = py::none(),
      py::arg("from_result") = py::none(), py::arg("keep_cameras") = py::none(),
      py::arg("cross_validate") = false, py::arg("closed_form") = true, py::arg("threads") = 0,
      py::arg("reorthonormalise") = false, py::arg("progress") = py::none(),
      "Calibrates every camera against the robot, as `handeye calibrate`: source is a dataset or "
      "observations "
      "file, or a handeye.Dataset (detected first when it has only images; progress(done, total) "
      "hears the "
      "detection). The keywords are the CLI's flags.");
}

}  // namespace handeye::python
