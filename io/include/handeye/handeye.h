// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// handeye as a library: one include for the whole workflow. Link
/// `handeye::io` (it brings `handeye::detectors` and `handeye::core`):
///
///     find_package(handeye 1.0 REQUIRED)
///     target_link_libraries(my_program PRIVATE handeye::io)
///
/// The workflow, in the order a program calls it:
///
/// 1. **Input.** `LoadDataset(path)` reads a `handeye-dataset/1` or
///    `handeye-observations/1` file (handeye/io/dataset_json.h), or build a
///    `Dataset` in memory (handeye/core/dataset.h): `setup`, a `target` from
///    `MakeTarget(TargetSpec)`, `cameras` from `Camera::Make`, `poses`
///    (`RobotPose{id, T_base_ee, images}`) and, if you detect yourself,
///    `observations` (`Observation{pose_id, camera, ids, points_px}`).
/// 2. **Detect.** `DetectAll(&dataset)` runs the target's detector on every
///    image (handeye/io/detection.h). Your own target types plug in with
///    `RegisterTargetPlugin` (handeye/detectors/registry.h) before loading.
/// 3. **Calibrate.** `CalibrationOptions` (method, robust loss, threads; check
///    them with `Check(&why)`), then `Calibrate(dataset, options)`
///    (handeye/core/calibration.h).
/// 4. **Use the result.** `CalibrationResult::cameras[k].T_cam` is T_base_cam
///    (eye_to_hand) or T_ee_cam (eye_in_hand), `T_target` is T_ee_target or
///    T_base_target, plus per-camera RMS, camera pairs and per-view
///    residuals. `SaveResult` writes `handeye-result/1`
///    (handeye/io/result_json.h); `ExportResult` writes ROS and OpenCV files
///    (handeye/io/export.h). `ComputePositionCovariance` gives the spread
///    that pixel noise alone leaves (handeye/core/uncertainty.h).
///
/// Conventions (SPEC §2): `T_a_b` maps points of frame b into frame a
/// (`p_a = T_a_b * p_b`, Eigen::Isometry3d); metres and radians; camera
/// frames are OpenCV optical frames (x right, y down, z forward); pixel (0, 0)
/// is the centre of the top-left pixel.
///
/// Errors: bad input throws `InputError` (its message names the file, the
/// JSON path and what was expected); a problem that cannot be solved (too few
/// views, degenerate motion) throws `SolveError` (handeye/core/error.h).
/// A target not found in an image is not an error: that view has no
/// observation.
///
/// Threads: the functions keep no hidden state except the target plugin
/// registry, which is guarded by a lock; `Calibrate` and `DetectAll` may run
/// concurrently on different datasets.

#include "handeye/core/calibration.h"
#include "handeye/core/camera.h"
#include "handeye/core/dataset.h"
#include "handeye/core/error.h"
#include "handeye/core/evaluation.h"
#include "handeye/core/target.h"
#include "handeye/core/target_spec.h"
#include "handeye/core/transform.h"
#include "handeye/core/uncertainty.h"
#include "handeye/detectors/detector.h"
#include "handeye/detectors/registry.h"
#include "handeye/io/dataset_json.h"
#include "handeye/io/detection.h"
#include "handeye/io/export.h"
#include "handeye/io/intrinsics_files.h"
#include "handeye/io/pose_formats.h"
#include "handeye/io/result_json.h"
