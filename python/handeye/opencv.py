# SPDX-License-Identifier: GPL-2.0-or-later
"""A drop-in for OpenCV's ``cv2.calibrateHandEye``.

OpenCV names a transform by the direction it maps points: ``R_gripper2base``
maps gripper points into the base frame, which this project calls
``T_base_ee``; ``R_target2cam`` is ``T_cam_target``; the answer
``R_cam2gripper`` is ``T_ee_cam``. Those names are translated here and
nowhere else. For a camera fixed in the cell (eye-to-hand) OpenCV's recipe
passes ``base2gripper`` (``T_ee_base``) in the ``gripper2base`` slot and gets
``cam2base``; ``setup="eye_to_hand"`` takes the lists that way.
"""

import math

import numpy as np

from ._handeye import Dataset, InputError, calibrate

# cv2.CALIB_HAND_EYE_TSAI ... DANIILIDIS, as OpenCV numbers them.
_OPENCV_METHODS = {0: "tsai", 1: "park", 2: "horaud", 3: "andreff", 4: "daniilidis"}
_CAMERA = "camera"


class HandEyeSolution(tuple):
    """``(R, t)`` as cv2.calibrateHandEye returns them (3x3, 3x1), plus ``result``
    (the full :class:`handeye.Result`) and ``warnings``."""

    def __new__(cls, R, t, result, warnings):
        solution = super().__new__(cls, (R, t))
        solution.R, solution.t, solution.result, solution.warnings = R, t, result, warnings
        return solution


def _rotation(value, where):
    R = np.asarray(value, dtype=float)
    if R.shape == (3, 3):
        return R
    if R.size == 3 and R.ndim <= 2:  # a rotation vector, as cv2.Rodrigues gives
        r = R.reshape(3)
        angle = float(np.linalg.norm(r))
        if not math.isfinite(angle):
            raise InputError(f"at {where}: expected finite numbers, got NaN or infinity")
        if angle < 1e-300:
            return np.eye(3)
        k = r / angle
        K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K
    raise InputError(f"at {where}: expected a 3x3 rotation matrix or a rotation vector (3,), got shape {R.shape}")


def _transform(R, t, where):
    T = np.eye(4)
    T[:3, :3] = _rotation(R, f"R_{where}")
    t = np.asarray(t, dtype=float)
    if t.size != 3 or t.ndim > 2:
        raise InputError(f"at t_{where}: expected a translation (3,) or (3, 1), got shape {t.shape}")
    T[:3, 3] = t.reshape(3)
    return T


def _transforms(Rs, ts, name, count=None):
    if len(Rs) != len(ts) or (count is not None and len(Rs) != count):
        raise InputError(f"at R_{name}, t_{name}: expected one rotation and one translation per robot pose "
                         f"({count if count is not None else len(Rs)}), got {len(Rs)} and {len(ts)}")
    return [_transform(R, t, f"{name}[{j}]") for j, (R, t) in enumerate(zip(Rs, ts))]


def _view(corners, j):
    """(ids, pixels) of pose j: given as such, or pixels alone in the target's id order."""
    if isinstance(corners, tuple) and len(corners) == 2:
        return corners
    pixels = np.asarray(corners, dtype=float)
    pixels = pixels.reshape(-1, 2) if pixels.ndim == 3 and pixels.shape[1:] == (1, 2) else pixels
    return np.arange(len(pixels)), pixels


def _method_name(method):
    if method is None:
        return "joint"
    if isinstance(method, str):
        return method
    if isinstance(method, int) and method in _OPENCV_METHODS:
        return _OPENCV_METHODS[method]
    raise InputError(f"at method: expected None (joint), a cv2.CALIB_HAND_EYE_* constant (0-4) or a method "
                     f"name, got {method!r}")


def _rotation_angle_deg(R):
    return math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(R) - 1) / 2))))


def _frame_check(T_cam_target_given, T_mount_holder, result, views):
    """Median angle (deg) between the camera motions between consecutive seen
    poses as the given target2cam poses and as the solved chain put them: a
    target frame defined otherwise cancels; target2cam given inverted or in
    another order does not."""
    T_cam_mount = np.linalg.inv(result.camera(_CAMERA).T_cam)
    chain = [T_cam_mount @ M @ result.T_target for M in T_mount_holder]
    seen = [j for j in range(len(chain)) if views[j]]
    angles = []
    for a, b in zip(seen, seen[1:]):
        given = T_cam_target_given[a][:3, :3] @ T_cam_target_given[b][:3, :3].T
        solved = chain[a][:3, :3] @ chain[b][:3, :3].T
        angles.append(_rotation_angle_deg(given.T @ solved))
    return float(np.median(angles)) if angles else 0.0


def calibrateHandEye(R_gripper2base, t_gripper2base, R_target2cam=None, t_target2cam=None, method=None, *,
                     corners, target, cameraMatrix, distCoeffs=None, image_size, setup="eye_in_hand", **options):
    """cv2.calibrateHandEye with the corners behind R_target2cam, solved by handeye.

    The first five arguments are OpenCV's (rotations as 3x3 matrices or
    rotation vectors; method a cv2.CALIB_HAND_EYE_* constant or a handeye
    method name; None: the joint solve). corners: per robot pose, None (target
    not seen), (ids, pixels) or pixels (M, 2) / (M, 1, 2) in the target's id
    order; target: the target as a dict or type name; cameraMatrix, distCoeffs,
    image_size (width, height) the camera's. Other keywords go to
    :func:`handeye.calibrate`.

    Returns (R_cam2gripper, t_cam2gripper) (eye_to_hand: R_cam2base,
    t_cam2base) as a :class:`HandEyeSolution`, which also carries the full
    result. A closed-form method gives `handeye calibrate --method` of that
    name on the same corners; R_target2cam and t_target2cam, when given, are
    only checked against the solution (a warning when they disagree, e.g.
    given as cam2target).
    """
    given = _transforms(R_gripper2base, t_gripper2base, "gripper2base")
    if setup == "eye_in_hand":
        T_base_ee = given
    elif setup == "eye_to_hand":
        T_base_ee = [np.linalg.inv(T) for T in given]  # the slot holds base2gripper, T_ee_base
    else:
        raise InputError(f"at setup: expected eye_in_hand or eye_to_hand, got {setup!r}")
    if len(corners) != len(given):
        raise InputError(f"at corners: expected one entry per robot pose ({len(given)}), got {len(corners)}")
    dataset = Dataset(setup=setup, target=target)
    dataset.add_camera(_CAMERA, cameraMatrix, distCoeffs, image_size=image_size)
    dataset.add_poses(np.array(T_base_ee))
    for j, seen in enumerate(corners):
        if seen is not None:
            dataset.add_view(_CAMERA, j, *_view(seen, j))
    result = calibrate(dataset, method=_method_name(method), **options)
    camera = result.camera(_CAMERA)
    if not camera.calibrated:
        raise InputError("at corners: the target is seen in too few poses to calibrate the camera")
    warnings = list(result.warnings)
    if R_target2cam is not None or t_target2cam is not None:
        T_cam_target = _transforms(R_target2cam, t_target2cam, "target2cam", len(given))
        mount_holder = T_base_ee if setup == "eye_to_hand" else [np.linalg.inv(T) for T in T_base_ee]
        off = _frame_check(T_cam_target, mount_holder, result, corners)
        if off > 1.0:
            warnings.append(f"R_target2cam disagrees with the solution by {off:.2f} deg (median over the camera's "
                            "motions between poses): check that it maps target points into the camera "
                            "(target2cam, not cam2target) and follows the order of R_gripper2base")
    T = camera.T_cam
    return HandEyeSolution(T[:3, :3].copy(), T[:3, 3].reshape(3, 1).copy(), result, warnings)
