# SPDX-License-Identifier: GPL-2.0-or-later
"""detect, check, export and simulate give what their subcommands give."""

import json

import numpy as np
import pytest

import handeye
from conftest import run_cli


def cli_views(observations):
    return {(o["camera"], o["pose"]): o for o in json.load(open(observations))["observations"]}


def test_detect_on_an_image_array_finds_what_handeye_detect_found(cell):
    dataset = handeye.Dataset.load(cell["dataset"])
    expected = cli_views(cell["observations"])
    (camera, pose), view = next(iter(expected.items()))
    image = dataset.image(camera, pose)
    assert image.dtype == np.uint8 and image.shape == (540, 960)
    for variant in (image, np.dstack([image] * 3), image.astype(np.uint16) * 257):
        ids, pixels = handeye.detect(variant, dataset.target)
        assert ids.tolist() == view["ids"]
        assert np.array_equal(pixels, np.array(view["points_px"]))
    assert handeye.detect(np.full((540, 960), 128, np.uint8), dataset.target) is None


def test_detect_image_adds_the_view_to_a_dataset(cell):
    loaded = handeye.Dataset.load(cell["dataset"])
    dataset = handeye.Dataset(target=loaded.target)
    for name in loaded.cameras:
        dataset.add_camera(name, **loaded.camera(name))
    dataset.add_poses(loaded.T_base_ee, ids=loaded.pose_ids)
    found = [dataset.detect_image(c, p, loaded.image(c, p)) for p in loaded.pose_ids for c in loaded.cameras]
    expected = cli_views(cell["observations"])
    assert sum(found) == len(expected)
    for camera, pose, ids, pixels in dataset.views:
        assert ids.tolist() == expected[(camera, pose)]["ids"]


def test_detect_on_a_dataset_matches_the_cli_observations(cell, tmp_path):
    dataset = handeye.Dataset.load(cell["dataset"])
    dataset.detect(threads=2)
    path = tmp_path / "obs.json"
    dataset.save_observations(str(path))
    assert path.read_text() == open(cell["observations"]).read()


def test_export_writes_what_handeye_export_writes(cell, cli_result, tmp_path):
    result_path = cell["dir"] / "cli_result.json"
    for fmt in ("urdf", "ros2-launch", "tf-static-yaml", "opencv-yaml"):
        out = tmp_path / f"cli.{fmt}"
        run_cli("export", result_path, "--to", fmt, "-o", out, "--camera-frame", "cam0=front_optical")
        written = tmp_path / f"py.{fmt}"
        text = handeye.export(str(result_path), fmt, str(written), camera_frames={"cam0": "front_optical"})
        assert text == out.read_text() == written.read_text()
    with pytest.raises(handeye.InputError, match="at to: expected one of ros2-launch"):
        handeye.export(str(result_path), "sdf")


def test_simulate_writes_what_handeye_simulate_writes(tmp_path):
    args = dict(cell="small", cameras=2, poses=3, seed=7, image_size=(320, 240), threads=2)
    handeye.simulate(str(tmp_path / "py"), **args)
    run_cli("simulate", tmp_path / "cli", "--cell", "small", "--cameras", 2, "--poses", 3, "--seed", 7,
            "--image-size", "320x240", "--threads", 2)
    for name in ("dataset.json", "ground_truth.json", "images/cam1/0002.png"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name


def test_check_finds_the_bumped_camera_as_handeye_check_does(cell, cli_result, tmp_path):
    result_path = cell["dir"] / "cli_result.json"
    later = handeye.simulate(str(tmp_path / "later"), cell="small", cameras=3, poses=8, seed=4, pose_seed=9,
                             bump_camera=("cam1", 5.0, 0.2), image_size=(960, 540), visible_only=True, threads=2)
    check_path = tmp_path / "check.json"
    code, _, _ = run_cli("check", result_path, later["dataset"], "-o", check_path, "--threads", 2, check=False)
    progress = []
    verdict = handeye.check(handeye.load_result(str(result_path)), later["dataset"], threads=2,
                            progress=lambda done, total: progress.append(done))
    cli = json.load(open(check_path))
    assert code == 4 and verdict["moved"] == ["cam1"] and progress
    assert verdict["cameras"].keys() == cli["cameras"].keys()
    for name, camera in cli["cameras"].items():
        ours = verdict["cameras"][name]
        for key in ("verdict", "reason", "views", "moved_mm", "moved_deg", "sigma_mm", "sigma_deg"):
            assert ours.get(key) == camera.get(key), (name, key)
        assert ("T_cam" in ours) == ("moved_mm" in camera)
    assert verdict["warnings"] == cli["warnings"]
    assert verdict["warning_details"] == cli["warning_details"]
