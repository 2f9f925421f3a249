# SPDX-License-Identifier: GPL-2.0-or-later
"""calibrate from a file, from arrays and from images gives what the CLI gives."""

import json
import threading
import time

import numpy as np
import pytest

import handeye
from conftest import assert_same_result, run_cli


def test_calibrate_from_the_observations_file_writes_the_clis_result(cell, cli_result):
    result = handeye.calibrate(cell["observations"], threads=1)
    assert_same_result(result.to_json(), cli_result, input_path=cell["observations"])


def test_calibrate_from_arrays_gives_the_same_numbers_as_from_the_file(cell, cli_result):
    loaded = handeye.Dataset.load(cell["observations"])
    cameras = {name: loaded.camera(name) for name in loaded.cameras}
    views = [(camera, loaded.pose_ids.index(pose), ids, pixels) for camera, pose, ids, pixels in loaded.views]
    built = handeye.dataset_from_arrays(loaded.target, cameras, loaded.T_base_ee, views, pose_ids=loaded.pose_ids)
    result = handeye.calibrate(built, threads=1)
    assert_same_result(result.to_json(), cli_result, input_path="")  # built in memory: no input file


def test_calibrate_from_images_detects_first_and_reports_progress(cell, cli_result):
    calls = []
    result = handeye.calibrate(cell["dataset"], threads=1, progress=lambda done, total: calls.append((done, total)))
    total = calls[-1][1]
    assert total == 30 and calls[-1] == (total, total) and len(calls) == total
    assert_same_result(result.to_json(), cli_result, input_path=cell["dataset"])


def test_a_closed_form_method_matches_the_cli_method_of_that_name(cell):
    path = cell["dir"] / "cli_park.json"
    run_cli("calibrate", cell["observations"], "-o", path, "--threads", 1, "--method", "park")
    result = handeye.calibrate(cell["observations"], threads=1, method="park")
    assert result.method == "park"
    assert_same_result(result.to_json(), path.read_text(), input_path=cell["observations"])


def test_the_result_gives_numpy_transforms_sigma_and_the_json_it_saves(cell, tmp_path):
    result = handeye.calibrate(cell["observations"], threads=2)
    truth = json.load(open(cell["truth"]))
    for camera in result.cameras:
        assert camera.calibrated and camera.T_cam.shape == (4, 4)
        R = camera.T_cam[:3, :3]
        assert np.allclose(R @ R.T, np.eye(3), atol=1e-12)
        T_true = np.array(truth["T_base_cam"][camera.name])
        error_mm = 1000 * np.linalg.norm(camera.T_cam[:3, 3] - T_true[:3, 3])
        assert error_mm < 4 * camera.sigma["position_mm"] + 1.0
        assert camera.sigma["covariance"].shape == (6, 6)
        # the views' own part: the whole less what the given intrinsics' uncertainty adds
        own = camera.sigma["covariance"] - camera.sigma["covariance_from_given_intrinsics"]
        assert camera.sigma["own_position_mm"] == pytest.approx(np.sqrt(np.trace(own[:3, :3])))
        assert camera.sigma["own_rotation_deg"] == pytest.approx(np.sqrt(np.trace(own[3:, 3:])))
        assert 0 < camera.sigma["own_position_mm"] < camera.sigma["position_mm"]
        offset = camera.given_intrinsics_offset_px  # the cell's given intrinsics are right
        assert set(offset) == {"fx", "fy", "cx", "cy"} and max(abs(v) for v in offset.values()) < 5
        assert np.array_equal(result.T_cam[camera.name], camera.T_cam)
    assert result.T_target.shape == (4, 4)
    assert all(isinstance(w, str) for w in result.warnings)
    assert [d["text"] for d in result.warning_details] == result.warnings
    assert all(isinstance(d["kind"], str) and set(d) == {"kind", "camera", "pose", "view", "text"}
               for d in result.warning_details)
    assert result.metrics["rms_px"] < 0.5 and result.solver["converged"]
    path = tmp_path / "result.json"
    result.save(str(path))
    assert path.read_text() == result.to_json()
    again = handeye.load_result(str(path))
    assert np.array_equal(again.camera("cam1").T_cam, result.camera("cam1").T_cam)
    with pytest.raises(KeyError):
        result.camera("nope")


def test_calibrate_releases_the_gil_while_it_detects_and_solves(cell):
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    start = time.perf_counter()
    handeye.calibrate(cell["dataset"], threads=1)  # detects 30 images first: long enough to see
    end = time.perf_counter()
    done.set()
    counter.join()
    # Holding the GIL, the call would stop the counter for its whole length.
    inside = [start] + [t for t in ticks if start < t < end] + [end]
    longest_gap = max(b - a for a, b in zip(inside, inside[1:]))
    assert end - start > 0.1 and longest_gap < 0.25 * (end - start)


def test_keep_cameras_holds_them_at_the_earlier_result(cell, cli_result, tmp_path):
    earlier = json.loads(cli_result)
    earlier["cameras"]["cam0"]["T_base_cam"][0][3] += 0.005  # cam0 held 5 mm off its solved place
    path = tmp_path / "earlier.json"
    path.write_text(json.dumps(earlier))
    again = handeye.calibrate(cell["observations"], threads=2, from_result=str(path), keep_cameras=["cam0"])
    held = np.array(earlier["cameras"]["cam0"]["T_base_cam"])
    assert np.allclose(again.camera("cam0").T_cam, held, rtol=0, atol=1e-12)
    free = json.loads(cli_result)["cameras"]["cam1"]["T_base_cam"]
    assert np.linalg.norm(again.camera("cam1").T_cam[:3, 3] - np.array(free)[:3, 3]) > 1e-3
    with pytest.raises(handeye.InputError, match="keep_cameras and from_result go together"):
        handeye.calibrate(cell["observations"], keep_cameras=["cam0"])


def test_result_differences_sees_what_differs_beyond_the_tolerance(cli_result):
    document = json.loads(cli_result)
    assert handeye.result_differences(cli_result, json.dumps(document)) == ([], ("", 0.0))
    document["cameras"]["cam1"]["rms_px"] *= 1 + 1e-12  # the last bits: agreed
    document["metrics"]["rms_px"] += 1e-3
    document["cameras"]["cam2"]["views"] += 1
    document["warnings"].append("one more")
    del document["cameras"]["cam0"]["sigma"]["position_mm"]
    covariance = document["cameras"]["cam1"]["sigma"]["covariance"]
    covariance[0][0] *= 1 + 1e-7  # a covariance's rounding (see result_differences): agreed
    covariance[1][1] += 1e-5 * max(1.0, abs(covariance[1][1]))  # beyond it (absolute below 1)
    differences, largest = handeye.result_differences(cli_result, json.dumps(document))
    assert [path for path, _, _ in differences] == [
        "/cameras/cam0/sigma/position_mm", "/cameras/cam1/sigma/covariance/1/1", "/cameras/cam2/views", "/metrics/rms_px",
        f"/warnings/{len(document['warnings']) - 1}"]
    assert largest[0] == "/metrics/rms_px"


def test_the_result_reads_in_its_own_setups_frames(cell):
    result = handeye.calibrate(cell["observations"], threads=1)
    assert result.setup == "eye_to_hand"
    assert np.array_equal(result.T_base_cam("cam0"), result.T_cam["cam0"])
    assert np.array_equal(result.T_ee_target(), result.T_target)
    T_base_ee = np.eye(4)
    T_base_ee[:3, 3] = [0.1, 0.2, 0.3]
    assert np.array_equal(result.T_base_cam_at("cam0", T_base_ee), result.T_cam["cam0"])
    with pytest.raises(RuntimeError, match="this result is eye_to_hand.*read T_base_cam"):
        result.T_ee_cam("cam0")
    with pytest.raises(RuntimeError, match="read T_ee_target"):
        result.T_base_target()
    with pytest.raises(IndexError, match="no camera 'cam9'"):
        result.T_base_cam("cam9")


def test_the_robot_model_is_chosen_by_the_poses_it_did_not_see(tmp_path):
    # A cell whose robot poses are off by 0.5 mm / 0.05 deg: modelling the
    # robot's error predicts left-out poses better than taking the poses as
    # exact, so a model is kept; with the poses declared exact no choice is made.
    sim = handeye.simulate(str(tmp_path / "sim"), cell="medium", cameras=4, poses=20, seed=1, pose_noise_mm=0.5,
                           pose_noise_deg=0.05, threads=2)
    observations = str(tmp_path / "observations.json")
    run_cli("detect", sim["dataset"], "-o", observations, "--threads", 2)
    result = json.loads(handeye.calibrate(observations, threads=2).to_json())
    model = result["solver"]["model"]
    assert model["folds"] == 4
    exact, modelled = model["candidates"][:2]
    assert (exact["name"], modelled["name"]) == ("exact robot", "robot error modelled")
    assert exact["points"] == modelled["points"] > 0
    assert modelled["held_out_rms_px"] < exact["held_out_rms_px"]
    # The model, at the σ the views suggest or (a third candidate) at the one its solved poses show.
    chosen = next(c for c in model["candidates"] if c["name"] == model["chosen"])
    assert chosen["name"].startswith("robot error modelled")
    assert chosen["robot_sigma_mm"] == result["solver"]["robot_sigma_mm"]
    assert result["solver"]["robot_sigma_mm"] > 0
    assert any(note.startswith("robot model chosen by how well it predicts poses it did not see")
               for note in result["notes"])
    exact_robot = json.loads(handeye.calibrate(observations, threads=2, robot_sigma_mm=0, robot_sigma_deg=0).to_json())
    assert "model" not in exact_robot["solver"]
    assert exact_robot["solver"]["robot_sigma_mm"] == 0
