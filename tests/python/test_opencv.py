# SPDX-License-Identifier: GPL-2.0-or-later
"""handeye.calibrateHandEye takes cv2.calibrateHandEye's lists and answers as
`handeye calibrate --method` of the same name (joint without one)."""

import json

import numpy as np
import pytest

import handeye
from conftest import run_cli


def one_camera_cell(tmp_root, setup):
    out = tmp_root / f"opencv_{setup}"
    sim = handeye.simulate(str(out / "sim"), setup=setup, cell="small", cameras=1, poses=12, seed=3,
                           image_size=(960, 540), visible_only=True, threads=2)
    observations = str(out / "observations.json")
    run_cli("detect", sim["dataset"], "-o", observations, "--threads", 2)
    dataset = handeye.Dataset.load(observations)
    views = {pose: (ids, pixels) for _, pose, ids, pixels in dataset.views}
    corners = [views.get(pose) for pose in dataset.pose_ids]
    truth = json.load(open(sim["ground_truth"]))
    return {"dir": out, "observations": observations, "dataset": dataset, "corners": corners, "truth": truth}


@pytest.fixture(scope="module")
def eye_in_hand(tmp_root):
    return one_camera_cell(tmp_root, "eye_in_hand")


def cli_T_cam(cell, method, key):
    path = cell["dir"] / f"{method}.json"
    run_cli("calibrate", cell["observations"], "-o", path, "--threads", 2, "--method", method)
    return np.array(json.load(open(path))["cameras"]["cam0"][key])


def opencv_lists(cell):
    """The four lists cv2.calibrateHandEye takes for an eye-in-hand camera,
    target2cam from the simulator's truth (what a PnP would estimate)."""
    T_base_ee = cell["dataset"].T_base_ee
    T_ee_cam = np.array(cell["truth"]["T_ee_cam"]["cam0"])
    T_base_target = np.array(cell["truth"]["T_base_target"])
    T_cam_target = [np.linalg.inv(T_ee_cam) @ np.linalg.inv(T) @ T_base_target for T in T_base_ee]
    return ([T[:3, :3] for T in T_base_ee], [T[:3, 3:] for T in T_base_ee],
            [T[:3, :3] for T in T_cam_target], [T[:3, 3:] for T in T_cam_target])


def camera_of(cell):
    camera = cell["dataset"].camera("cam0")
    return dict(corners=cell["corners"], target=cell["dataset"].target, cameraMatrix=camera["K"],
                distCoeffs=camera["distortion"], image_size=camera["image_size"], threads=2)


# cv2.CALIB_HAND_EYE_TSAI, _PARK, _HORAUD, _ANDREFF, _DANIILIDIS are 0 to 4.
OPENCV_METHODS = [(0, "tsai"), (1, "park"), (2, "horaud"), (3, "andreff"), (4, "daniilidis"), (None, "joint")]


@pytest.mark.parametrize("method, name", OPENCV_METHODS)
def test_the_answer_is_the_cli_method_of_the_same_name(eye_in_hand, method, name):
    R, t = handeye.calibrateHandEye(*opencv_lists(eye_in_hand), method, **camera_of(eye_in_hand))
    expected = cli_T_cam(eye_in_hand, name, "T_ee_cam")
    assert R.shape == (3, 3) and t.shape == (3, 1)
    # To a nanometre and 1e-9 rad: far below the 0.01 mm the CLI prints.
    assert np.allclose(R, expected[:3, :3], rtol=0, atol=1e-9)
    assert np.allclose(t[:, 0], expected[:3, 3], rtol=0, atol=1e-9)


def test_rotation_vectors_give_the_same_answer_and_the_full_result(eye_in_hand):
    R_g, t_g, R_t, t_t = opencv_lists(eye_in_hand)
    as_matrices = handeye.calibrateHandEye(R_g, t_g, R_t, t_t, **camera_of(eye_in_hand))

    def rotvec(R):
        angle = np.arccos((np.trace(R) - 1) / 2)
        axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (2 * np.sin(angle))
        return (axis * angle).reshape(3, 1)

    as_vectors = handeye.calibrateHandEye([rotvec(R) for R in R_g], t_g, [rotvec(R) for R in R_t], t_t,
                                          **camera_of(eye_in_hand))
    assert np.allclose(as_vectors.R, as_matrices.R, atol=1e-9)
    assert as_matrices.result.method == "joint" and as_matrices.result.camera("camera").sigma is not None
    assert not [w for w in as_matrices.warnings if "R_target2cam" in w]


def test_target2cam_given_inverted_is_warned_about(eye_in_hand):
    R_g, t_g, R_t, t_t = opencv_lists(eye_in_hand)
    inverted = [np.linalg.inv(np.vstack([np.hstack([R, t]), [0, 0, 0, 1]])) for R, t in zip(R_t, t_t)]
    solution = handeye.calibrateHandEye(R_g, t_g, [T[:3, :3] for T in inverted], [T[:3, 3] for T in inverted],
                                        **camera_of(eye_in_hand))
    assert [w for w in solution.warnings if "cam2target" in w]


def test_eye_to_hand_takes_base2gripper_and_answers_cam2base(tmp_root):
    cell = one_camera_cell(tmp_root, "eye_to_hand")
    T_ee_base = [np.linalg.inv(T) for T in cell["dataset"].T_base_ee]
    R, t = handeye.calibrateHandEye([T[:3, :3] for T in T_ee_base], [T[:3, 3] for T in T_ee_base], None, None,
                                    "park", setup="eye_to_hand", **camera_of(cell))
    expected = cli_T_cam(cell, "park", "T_base_cam")
    assert np.allclose(R, expected[:3, :3], rtol=0, atol=1e-9)
    assert np.allclose(t[:, 0], expected[:3, 3], rtol=0, atol=1e-9)


def test_lists_of_different_lengths_are_refused(eye_in_hand):
    R_g, t_g, R_t, t_t = opencv_lists(eye_in_hand)
    with pytest.raises(handeye.InputError, match="one rotation and one translation per robot pose"):
        handeye.calibrateHandEye(R_g, t_g[:-1], R_t, t_t, **camera_of(eye_in_hand))
    with pytest.raises(handeye.InputError, match="3x3 rotation matrix or a rotation vector"):
        handeye.calibrateHandEye([np.eye(2)] * len(R_g), t_g, R_t, t_t, **camera_of(eye_in_hand))
