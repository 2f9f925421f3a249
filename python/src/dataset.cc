// SPDX-License-Identifier: GPL-2.0-or-later
// handeye.Dataset: load a dataset or observations file, or build one from
// numpy arrays (cameras, robot poses, views), then detect and save.
#include <pybind11/stl.h>

#include <cstring>

#include "../../tools/output_paths.h"
#include "bindings.h"
#include "convert.h"
#include "handeye/core/error.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/image.h"
#include "image.h"
#include "progress.h"

namespace handeye::python {
namespace {

Setup SetupFrom(const std::string& name) {
  const auto setup = ParseSetup(name);
  if (!setup)
    throw InputError("", "setup", "expected eye_to_hand or eye_in_hand, got '" + name + "'");
  return *setup;
}

PyDataset MakeDataset(const std::string& setup, py::handle target) {
  PyDataset out;
  out.dataset.setup = SetupFrom(setup);
  out.dataset.target = TargetFrom(target, &out.warnings);
  WarnAll(out.warnings);
  return out;
}

PyDataset Load(const std::string& path, bool reorthonormalise) {
  PyDataset out;
  out.path = path;
  LoadOptions options;
  options.reorthonormalise = reorthonormalise;
  out.dataset = WithoutGil([&] { return LoadDataset(path, options, &out.warnings); });
  WarnAll(out.warnings);
  return out;
}

void AddCamera(PyDataset& self, const std::string& name, py::handle K, py::handle distortion,
               py::handle image_size) {
  if (self.dataset.CameraIndex(name) >= 0)
    throw InputError("", "cameras", "unique camera names; '" + name + "' twice");
  if (name.empty() || name.find('/') != std::string::npos)
    throw InputError("", "cameras", "a camera name, not empty and without '/', got '" + name + "'");
  if (!K.is_none()) {
    self.dataset.cameras.push_back(CameraFromArrays(name, K, distortion, image_size));
    return;
  }
  // No intrinsics: Calibrate() estimates them from the views (SPEC §4).
  Camera camera =
      CameraFromArrays(name, MatrixArray(Eigen::Matrix3d::Identity()), py::none(), image_size);
  camera.has_intrinsics = false;
  self.dataset.cameras.push_back(camera);
}

std::string AddPose(PyDataset& self, py::handle T_base_ee, py::object id, py::object images,
                    bool reorthonormalise) {
  RobotPose pose;
  const std::size_t index = self.dataset.poses.size();
  pose.id = id.is_none() ? std::to_string(index) : py::str(id).cast<std::string>();
  if (pose.id.empty() || self.dataset.PoseIndex(pose.id) >= 0)
    throw InputError("", "poses", "unique, non-empty pose ids; got '" + pose.id + "' again");
  pose.T_base_ee =
      RigidTransform(T_base_ee, "T_base_ee[" + std::to_string(index) + "]", reorthonormalise);
  if (!images.is_none())
    for (const auto& [camera, path] : images.cast<py::dict>()) {
      const std::string name = py::str(camera).cast<std::string>();
      if (self.dataset.CameraIndex(name) < 0)
        throw InputError("", "images",
                         "cameras added before their images; no camera '" + name + "'");
      pose.images[name] = py::str(path).cast<std::string>();
    }
  self.dataset.poses.push_back(pose);
  return pose.id;
}

std::vector<std::string> AddPoses(PyDataset& self, py::handle T_base_ee, py::object ids,
                                  bool reorthonormalise) {
  py::array all = py::array::ensure(T_base_ee);
  if (!all || all.ndim() != 3 || all.shape(1) != 4 || all.shape(2) != 4)
    throw InputError("", "T_base_ee", "expected an N×4×4 array of robot poses");
  if (!ids.is_none() && py::len(ids) != static_cast<std::size_t>(all.shape(0)))
    throw InputError("", "ids", "expected one id per pose (" + std::to_string(all.shape(0)) + ")");
  std::vector<std::string> added;
  for (py::ssize_t j = 0; j < all.shape(0); ++j) {
    py::object id = ids.is_none() ? py::object(py::none()) : py::object(ids[py::int_(j)]);
    added.push_back(AddPose(self, py::object(all[py::int_(j)]), id, py::none(), reorthonormalise));
  }
  return added;
}

// The pose id a view names: an id string, or an index into the poses.
std::string PoseIdOf(const PyDataset& self, py::handle pose) {
  if (py::isinstance<py::int_>(pose) && !py::isinstance<py::bool_>(pose)) {
    const long index = pose.cast<long>();
    if (index < 0 || index >= static_cast<long>(self.dataset.poses.size()))
      throw InputError("", "pose",
                       "a pose index below " + std::to_string(self.dataset.poses.size()) +
                           ", got " + std::to_string(index));
    return self.dataset.poses[index].id;
  }
  const std::string id = py::str(pose).cast<std::string>();
  if (self.dataset.PoseIndex(id) < 0)
    throw InputError("", "pose", "the id of an added pose, got '" + id + "'");
  return id;
}

void CheckCamera(const PyDataset& self, const std::string& camera) {
  if (self.dataset.CameraIndex(camera) < 0)
    throw InputError("", "camera", "the name of an added camera, got '" + camera + "'");
}

void AddView(PyDataset& self, const std::string& camera, py::handle pose, py::handle ids,
             py::handle pixels) {
  CheckCamera(self, camera);
  Observation view{PoseIdOf(self, pose), camera, {}, {}};
  const std::string where = "view(" + camera + ", " + view.pose_id + ")";
  view.ids = IdVector(ids, where + ".ids");
  const Eigen::MatrixXd px = FiniteMatrix(pixels, -1, 2, where + ".pixels");
  if (static_cast<std::size_t>(px.rows()) != view.ids.size())
    throw InputError("", where,
                     "as many pixels as ids; got " + std::to_string(px.rows()) + " and " +
                         std::to_string(view.ids.size()));
  for (Eigen::Index i = 0; i < px.rows(); ++i) view.points_px.emplace_back(px(i, 0), px(i, 1));
  self.dataset.observations.push_back(std::move(view));
}

bool DetectImage(PyDataset& self, const std::string& camera, py::handle pose, py::handle image) {
  CheckCamera(self, camera);
  const std::string pose_id = PoseIdOf(self, pose);
  const Camera& cam = self.dataset.cameras[self.dataset.CameraIndex(camera)];
  const std::string where = "image(" + camera + ", " + pose_id + ")";
  GrayImage gray(image, where);
  if (gray.mat.cols != cam.width || gray.mat.rows != cam.height)
    throw InputError("", where,
                     "an image of the camera's size " + std::to_string(cam.width) + "×" +
                         std::to_string(cam.height) + ", got " + std::to_string(gray.mat.cols) +
                         "×" + std::to_string(gray.mat.rows));
  const auto found = DetectIn(gray, self.dataset.target);
  if (!found) return false;
  self.dataset.observations.push_back(Observation{pose_id, camera, found->ids, found->points_px});
  return true;
}

py::array_t<std::uint8_t> LoadImage(const PyDataset& self, const std::string& camera,
                                    py::handle pose) {
  CheckCamera(self, camera);
  const RobotPose& at = self.dataset.poses[self.dataset.PoseIndex(PoseIdOf(self, pose))];
  const auto path = at.images.find(camera);
  if (path == at.images.end())
    throw InputError(self.path, "/poses",
                     "an image of camera '" + camera + "' at pose '" + at.id + "'");
  const Camera& cam = self.dataset.cameras[self.dataset.CameraIndex(camera)];
  const cv::Mat gray = WithoutGil([&] { return LoadGrayImage(path->second, cam); });
  py::array_t<std::uint8_t> out({gray.rows, gray.cols});
  for (int r = 0; r < gray.rows; ++r) std::memcpy(out.mutable_data(r, 0), gray.ptr(r), gray.cols);
  return out;
}

void DetectImageFiles(PyDataset& self, int threads, py::object progress) {
  CheckThreads(threads);
  Progress report(std::move(progress));
  DetectOptions options;
  options.threads = threads;
  options.progress = report.Hook();
  // Into a copy: other Python threads may read this Dataset meanwhile.
  Dataset detected = self.dataset;
  WithoutGil([&] { DetectAll(&detected, options); });
  report.Rethrow();
  self.dataset = std::move(detected);
}

// As the CLI checks its outputs: writable, and none of the dataset's own
// files (the file it was loaded from, its images).
void CheckOutput(const PyDataset& self, const std::string& path) {
  std::vector<tools::NamedPath> inputs = tools::ImageInputs(self.dataset);
  inputs.push_back({"DATASET", self.path});
  tools::CheckFileOutputs(inputs, {{"path", path}});
}

py::list Views(const PyDataset& self) {
  py::list views;
  for (const Observation& o : self.dataset.observations) {
    Eigen::MatrixXd px(o.points_px.size(), 2);
    for (std::size_t i = 0; i < o.points_px.size(); ++i) px.row(i) = o.points_px[i].transpose();
    py::array_t<int> ids(o.ids.size(), o.ids.data());
    views.append(py::make_tuple(o.camera, o.pose_id, ids, MatrixArray(px)));
  }
  return views;
}

py::array_t<double> PoseArray(const PyDataset& self) {
  const py::ssize_t n = self.dataset.poses.size();
  py::array_t<double> out({n, py::ssize_t{4}, py::ssize_t{4}});
  auto a = out.mutable_unchecked<3>();
  for (py::ssize_t j = 0; j < n; ++j)
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) a(j, r, c) = self.dataset.poses[j].T_base_ee.matrix()(r, c);
  return out;
}

py::dict CameraDict(const PyDataset& self, const std::string& name) {
  CheckCamera(self, name);
  const Camera& c = self.dataset.cameras[self.dataset.CameraIndex(name)];
  py::dict d;
  d["K"] = c.has_intrinsics ? py::object(CameraMatrix(c)) : py::object(py::none());
  d["distortion"] = py::array_t<double>(py::cast(c.Distortion()));
  d["image_size"] = py::make_tuple(c.width, c.height);
  return d;
}

}  // namespace

void AddDataset(py::module_& m) {
  py::class_<PyDataset>(
      m, "Dataset",
      "A calibration problem: setup, target, cameras, robot poses and views (detected corners).\n"
      "Load one with Dataset.load(path) or build it with the add_* methods.")
      .def(
          py::init(&MakeDataset), py::arg("setup") = "eye_to_hand",
          py::arg("target") = "checkerboard",
          "An empty dataset. target: a dict (the dataset's `target` object, SPEC §4), a type name "
          "for its "
          "default sheet (checkerboard, charuco, aprilgrid) or a path to a .json file holding one.")
      .def_static(
          "load", &Load, py::arg("path"), py::arg("reorthonormalise") = false,
          "Reads a handeye-dataset/1 or handeye-observations/1 file (as `handeye calibrate` does).")
      .def("add_camera", &AddCamera, py::arg("name"), py::arg("K"),
           py::arg("distortion") = py::none(), py::arg("image_size"),
           "Adds a camera: K 3×3 (no skew; None: estimated from the views), distortion in OpenCV "
           "order, "
           "image_size (width, height).")
      .def("add_pose", &AddPose, py::arg("T_base_ee"), py::arg("id") = py::none(),
           py::arg("images") = py::none(), py::arg("reorthonormalise") = false,
           "Adds a robot pose (4×4 T_base_ee, metres) with an optional {camera: image path}; "
           "returns its id.")
      .def("add_poses", &AddPoses, py::arg("T_base_ee"), py::arg("ids") = py::none(),
           py::arg("reorthonormalise") = false,
           "Adds N robot poses from an N×4×4 array; returns their ids.")
      .def("add_view", &AddView, py::arg("camera"), py::arg("pose"), py::arg("ids"),
           py::arg("pixels"),
           "Adds what `camera` detected at `pose` (id or index): target point ids (N,) and pixels "
           "(N, 2).")
      .def("detect_image", &DetectImage, py::arg("camera"), py::arg("pose"), py::arg("image"),
           "Runs the target's detector on an image array (H×W uint8, or H×W×3 BGR) and adds the "
           "view; "
           "False when the target is not found.")
      .def("image", &LoadImage, py::arg("camera"), py::arg("pose"),
           "The image of `camera` at `pose` as 8-bit grey (H×W uint8), read as detection reads it.")
      .def("detect", &DetectImageFiles, py::arg("threads") = 0, py::arg("progress") = py::none(),
           "Detects the target in every image file of the poses (as `handeye detect`), replacing "
           "the views. "
           "progress(done, total) is called after each image.")
      .def(
          "save",
          [](const PyDataset& self, const std::string& path) {
            CheckOutput(self, path);
            SaveDataset(self.dataset, path);
          },
          py::arg("path"),
          "Writes handeye-dataset/1 (never over the file it was loaded from or an image).")
      .def(
          "save_observations",
          [](const PyDataset& self, const std::string& path) {
            CheckOutput(self, path);
            SaveObservations(self.dataset, path);
          },
          py::arg("path"), "Writes handeye-observations/1 (what `handeye detect -o` writes).")
      .def_property_readonly("setup",
                             [](const PyDataset& self) { return SetupName(self.dataset.setup); })
      .def_property_readonly("target",
                             [](const PyDataset& self) { return TargetDict(*self.dataset.target); })
      .def_property_readonly("cameras",
                             [](const PyDataset& self) {
                               std::vector<std::string> names;
                               for (const Camera& c : self.dataset.cameras) names.push_back(c.name);
                               return names;
                             })
      .def("camera", &CameraDict, py::arg("name"), "A camera's K, distortion and image_size.")
      .def_property_readonly("pose_ids",
                             [](const PyDataset& self) {
                               std::vector<std::string> ids;
                               for (const RobotPose& p : self.dataset.poses) ids.push_back(p.id);
                               return ids;
                             })
      .def_property_readonly("T_base_ee", &PoseArray, "The robot poses, N×4×4.")
      .def_property_readonly("views", &Views, "Every view as (camera, pose id, ids, pixels).")
      .def_property_readonly("path", [](const PyDataset& self) { return self.path; })
      .def_property_readonly("warnings", [](const PyDataset& self) { return WarningTexts(self.warnings); })
      .def("__repr__", [](const PyDataset& self) {
        return "<handeye.Dataset " + std::string(SetupName(self.dataset.setup)) + ", " +
               std::to_string(self.dataset.cameras.size()) + " cameras, " +
               std::to_string(self.dataset.poses.size()) + " poses, " +
               std::to_string(self.dataset.observations.size()) + " views>";
      });
}

}  // namespace handeye::python
