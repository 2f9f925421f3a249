# SPDX-License-Identifier: GPL-2.0-or-later
"""Bad input raises InputError (a ValueError) with the CLI's message, an
unsolvable problem SolveError (a RuntimeError); nothing crashes."""

import json

import numpy as np
import pytest

import handeye
from conftest import run_cli

K = np.array([[1000.0, 0, 639.5], [0, 1000.0, 479.5], [0, 0, 1]])


def small_dataset():
    dataset = handeye.Dataset(target={"type": "checkerboard", "inner_corners": [7, 4], "square_size_m": 0.04})
    dataset.add_camera("cam0", K, [0.01, 0, 0, 0, 0], image_size=(1280, 960))
    dataset.add_pose(np.eye(4))
    return dataset


def test_the_exception_classes_derive_from_the_builtins_callers_catch():
    assert issubclass(handeye.InputError, ValueError)
    assert issubclass(handeye.SolveError, RuntimeError)


def test_a_missing_file_gives_the_clis_message(tmp_path):
    missing = str(tmp_path / "nope.json")
    code, _, stderr = run_cli("calibrate", missing, "-o", tmp_path / "r.json", check=False)
    assert code == 2
    with pytest.raises(handeye.InputError) as error:
        handeye.calibrate(missing)
    assert stderr.strip() == "error: " + str(error.value)
    assert error.value.file == missing


def test_a_bad_field_gives_the_clis_message_with_file_and_path(cell, tmp_path):
    document = json.load(open(cell["observations"]))
    document["poses"][2]["T_base_ee"][0][0] = 3.0  # no rotation any more
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(document))
    code, _, stderr = run_cli("calibrate", path, "-o", tmp_path / "r.json", check=False)
    with pytest.raises(handeye.InputError) as error:
        handeye.calibrate(str(path))
    assert code == 2 and stderr.strip() == "error: " + str(error.value)
    assert error.value.json_path == "/poses/2/T_base_ee"


@pytest.mark.parametrize("T, expected", [
    (np.eye(3), "expected 4×4 array of numbers, got shape (3, 3)"),
    (np.full((4, 4), np.nan), "expected finite numbers"),
    (np.diag([2.0, 1, 1, 1]), "expected a rigid 4×4 transform"),
    (np.array([["a"] * 4] * 4), "got an array of dtype <U1"),
    (np.eye(4) * (1 + 1j), "got an array of dtype complex128"),
    ("eye", "got str"),
    (None, "got NoneType"),
    ([[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0], [0, 0, 0, 1]], "no array of numbers"),
])
def test_bad_robot_poses_are_refused_with_the_argument_named(T, expected):
    dataset = small_dataset()
    with pytest.raises(handeye.InputError, match="at T_base_ee\\[1\\]: ") as error:
        dataset.add_pose(T)
    assert expected in str(error.value)


@pytest.mark.parametrize("ids, pixels, expected", [
    ([0, 1], np.zeros((3, 2)), "as many pixels as ids"),
    ([0, 1], np.zeros((2, 3)), "got shape (2, 3)"),
    ([0, 1], np.zeros(4), "got shape (4,)"),
    ([0.0, 1.0], np.zeros((2, 2)), "got an array of dtype float64"),
    ([0, 1], [[np.nan, 0], [0, 0]], "expected finite numbers"),
    ([-1, 1], np.zeros((2, 2)), "ids between 0 and 10^9"),
    ([[0, 1]], np.zeros((2, 2)), "1-D array of integer ids"),
])
def test_bad_views_are_refused(ids, pixels, expected):
    dataset = small_dataset()
    with pytest.raises(handeye.InputError) as error:
        dataset.add_view("cam0", 0, ids, pixels)
    assert expected in str(error.value)


def test_unknown_names_and_bad_cameras_are_refused():
    dataset = small_dataset()
    with pytest.raises(handeye.InputError, match="an added camera, got 'cam9'"):
        dataset.add_view("cam9", 0, [0], [[1.0, 2.0]])
    with pytest.raises(handeye.InputError, match="a pose index below 1, got 5"):
        dataset.add_view("cam0", 5, [0], [[1.0, 2.0]])
    with pytest.raises(handeye.InputError, match="no skew"):
        dataset.add_camera("cam1", [[1000, 5, 640], [0, 1000, 480], [0, 0, 1]], image_size=(1280, 960))
    with pytest.raises(handeye.InputError, match="distortion"):
        dataset.add_camera("cam1", K, [0.1, 0.2, 0.3], image_size=(1280, 960))
    with pytest.raises(handeye.InputError, match="image_size"):
        dataset.add_camera("cam1", K, image_size=(1280.5, 960))
    with pytest.raises(handeye.InputError, match="unique camera names"):
        dataset.add_camera("cam0", K, image_size=(1280, 960))
    with pytest.raises(handeye.InputError, match="at target/inner_corners/0: expected two integers >= 2"):
        handeye.Dataset(target={"type": "checkerboard", "inner_corners": [1, 4], "square_size_m": 0.04})
    with pytest.raises(handeye.InputError, match="unknown target type"):
        handeye.Dataset(target="hexagons")
    with pytest.raises(handeye.InputError, match="at method: expected one of joint"):
        handeye.calibrate(dataset, method="magic")
    with pytest.raises(handeye.InputError, match="at threads: expected 0 \\(all cores\\) or a positive count up to"):
        handeye.calibrate(dataset, threads=100000)


def test_ids_the_target_does_not_have_are_an_input_error():
    dataset = small_dataset()
    dataset.add_view("cam0", 0, [0, 99], [[1.0, 2.0], [3.0, 4.0]])
    with pytest.raises(handeye.InputError, match="ids of the target; got 99"):
        handeye.calibrate(dataset)


def test_too_few_views_is_a_solve_error_with_the_clis_message(cell, tmp_path):
    document = json.load(open(cell["observations"]))
    document["observations"] = document["observations"][:2]
    path = tmp_path / "two_views.json"
    path.write_text(json.dumps(document))
    code, _, stderr = run_cli("calibrate", path, "-o", tmp_path / "r.json", check=False)
    with pytest.raises(handeye.SolveError) as error:
        handeye.calibrate(str(path))
    assert code == 3 and stderr.strip() == "error: calibration failed: " + str(error.value)


def test_an_exception_in_the_progress_callback_reaches_the_caller(cell):
    def fail(done, total):
        raise KeyboardInterrupt("stop")

    with pytest.raises(KeyboardInterrupt, match="stop"):
        handeye.calibrate(cell["dataset"], progress=fail)
    with pytest.raises(TypeError, match="callable"):
        handeye.calibrate(cell["dataset"], progress=3)


def test_bad_images_are_refused():
    for image, expected in [(np.zeros((10, 10), np.float32), "dtype float32"),
                            (np.zeros((10, 10, 2), np.uint8), "3 dimensions"),
                            (np.zeros((0, 10), np.uint8), "2 dimensions"),
                            ([[0, 1], [2, 3]], "expected an image array")]:
        with pytest.raises(handeye.InputError, match="at image: ") as error:
            handeye.detect(image, "checkerboard")
        assert expected in str(error.value)


GARBAGE = [None, "x", b"x", 3, 3.5, True, [], [[]], {}, (), object(), np.zeros(0), np.zeros((0, 4, 4)),
           np.full((4, 4), np.inf), np.array([1, 2], dtype=object), np.array(["a"]), np.eye(4)[::2],
           np.zeros((2, 2, 2, 2)), np.zeros((5, 1 << 16), np.uint8), np.zeros((1, 1), np.uint8),
           np.zeros((3, 3, 3), np.uint16), np.zeros((4, 4, 1), np.uint8)]


@pytest.mark.parametrize("value", GARBAGE, ids=lambda v: type(v).__name__)
def test_any_value_in_any_argument_raises_and_never_crashes(value, tmp_path):
    dataset = small_dataset()
    calls = [
        lambda: dataset.add_camera("c", value, image_size=(640, 480)),
        lambda: dataset.add_camera("c", K, value, image_size=(640, 480)),
        lambda: dataset.add_camera("c", K, image_size=value),
        lambda: dataset.add_pose(value),
        lambda: dataset.add_poses(value),
        lambda: dataset.add_view("cam0", 0, value, [[1.0, 2.0]]),
        lambda: dataset.add_view("cam0", 0, [0], value),
        lambda: dataset.add_view("cam0", value, [0], [[1.0, 2.0]]),
        lambda: dataset.detect_image("cam0", 0, value),
        lambda: handeye.detect(value, "checkerboard"),
        lambda: handeye.detect(np.zeros((8, 8), np.uint8), value),
        lambda: handeye.Dataset(target=value),
        lambda: handeye.calibrate(value),
        lambda: handeye.calibrate(handeye.Dataset(target=value)),
        lambda: handeye.calibrate(dataset, method=value),
        lambda: handeye.calibrate(dataset, threads=value),
        lambda: handeye.calibrate(dataset, robot_sigma_mm=value, robot_sigma_deg=0),
        lambda: handeye.calibrate(dataset, refine_intrinsics=value),
        lambda: handeye.export(value, "urdf"),
        lambda: handeye.simulate(str(tmp_path), cameras=1, poses=1, visible_only=True, image_size=value),
        lambda: handeye.simulate(str(tmp_path), cameras=1, poses=1, visible_only=True, image_size=(64, 48),
                                 target=value),
    ]
    for call in calls:
        try:
            call()
        except Exception:  # noqa: BLE001 - any Python exception is fine; a crash is not
            pass


def test_nothing_is_written_over_an_input_as_the_cli_refuses(cell, cli_result, tmp_path):
    observations, result_path = cell["observations"], str(cell["dir"] / "cli_result.json")
    before = open(observations).read(), open(result_path).read()
    result = handeye.calibrate(observations, threads=2)
    dataset = handeye.Dataset.load(observations)
    for write, expected in [(lambda: result.save(observations), "path names the input INPUT"),
                            (lambda: dataset.save_observations(observations), "path names the input DATASET"),
                            (lambda: dataset.save(observations), "path names the input DATASET"),
                            (lambda: handeye.export(result_path, "urdf", result_path), "names the input RESULT"),
                            (lambda: result.save(str(tmp_path / "missing" / "r.json")), "does not exist")]:
        with pytest.raises(handeye.InputError, match=expected):
            write()
    assert (open(observations).read(), open(result_path).read()) == before
