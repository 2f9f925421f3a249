# SPDX-License-Identifier: GPL-2.0-or-later
"""handeye: calibrates a network of cameras against an industrial robot.

The same engine as the ``handeye`` program, with numpy in and out::

    import handeye
    result = handeye.calibrate("observations.json")          # or a dataset, or a Dataset
    result.T_cam["cam0"]       # 4x4 T_base_cam (eye_to_hand) or T_ee_cam (eye_in_hand)
    result.save("result.json")  # the handeye-result/1 file `handeye calibrate -o` writes

Conventions (SPEC section 2): ``T_a_b`` maps points of frame b into frame a;
metres and radians; camera frames are OpenCV optical frames; pixel (0, 0) is
the centre of the top-left pixel. Bad input raises :class:`InputError` (a
ValueError) with the CLI's message; an unsolvable problem :class:`SolveError`
(a RuntimeError). Long calls release the GIL; ``progress(done, total)``
callbacks are called while they run.
"""

from ._handeye import (
    CameraResult,
    Dataset,
    InputError,
    Result,
    SolveError,
    calibrate,
    check,
    detect,
    export,
    load_result,
    simulate,
)
from .compare import result_differences
from .opencv import HandEyeSolution, calibrateHandEye

__all__ = [
    "CameraResult", "Dataset", "HandEyeSolution", "InputError", "Result", "SolveError",
    "calibrate", "calibrateHandEye", "check", "dataset_from_arrays", "detect", "export",
    "load_result", "result_differences", "simulate",
]


def dataset_from_arrays(target, cameras, T_base_ee, views, *, setup="eye_to_hand", pose_ids=None):
    """A :class:`Dataset` from arrays.

    target: the ``target`` object as a dict (SPEC section 4), or a type name for
    its default sheet. cameras: ``{name: {"K": 3x3, "distortion": (k1, k2, p1,
    p2[, k3...]), "image_size": (width, height)}}``. T_base_ee: N x 4 x 4 robot
    poses (metres). views: iterable of ``(camera, pose, ids, pixels)`` with pose
    an index into T_base_ee (or an id of pose_ids), ids (M,) integers and pixels
    (M, 2).
    """
    dataset = Dataset(setup=setup, target=target)
    for name, camera in cameras.items():
        dataset.add_camera(name, camera.get("K"), camera.get("distortion"), image_size=camera["image_size"])
    dataset.add_poses(T_base_ee, ids=pose_ids)
    for camera, pose, ids, pixels in views:
        dataset.add_view(camera, pose, ids, pixels)
    return dataset
