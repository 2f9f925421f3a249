# SPDX-License-Identifier: GPL-2.0-or-later
"""Shared fixtures: small simulated cells (rendered once per session) and the
CLI next to the module, to compare the two."""

import json
import os
import subprocess

import pytest

import handeye

HANDEYE = os.environ.get("HANDEYE_BINARY", "handeye")


def run_cli(*args, check=True):
    """Runs the handeye program; returns (exit code, stdout, stderr)."""
    done = subprocess.run([HANDEYE, *map(str, args)], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"handeye {' '.join(map(str, args))} exited {done.returncode}:\n{done.stderr}")
    return done.returncode, done.stdout, done.stderr


def assert_same_result(text, expected_text, input_path=None):
    """Two result files agree bit for bit: the same keys, strings, flags and
    counts, and every real number equal. Both sides solve on one thread: with
    several, Ceres sums the Schur complement in the order the threads finish
    and the last bits differ (two CLI runs with the default of all cores differ
    too; `result_differences` has tolerances for those). The solve's wall
    time is left out; the input's name is compared when given."""
    if input_path is not None:
        assert json.loads(text)["provenance"]["input"] == input_path
    differences, _ = handeye.result_differences(text, expected_text, tolerance=0, covariance_tolerance=0)
    assert differences == []


@pytest.fixture(scope="session")
def tmp_root(tmp_path_factory):
    """A folder of this session's own (ctest runs the test files side by side)."""
    return tmp_path_factory.mktemp("handeye")


@pytest.fixture(scope="session")
def cell(tmp_root):
    """3 cameras, 10 poses of the small cell at 960x540, simulated by the
    module and detected by the CLI: {dir, dataset, observations, truth}."""
    out = tmp_root / "cell"
    sim = handeye.simulate(str(out / "sim"), cell="small", cameras=3, poses=10, seed=4, image_size=(960, 540),
                           threads=2)
    observations = str(out / "observations.json")
    run_cli("detect", sim["dataset"], "-o", observations, "--threads", 2)
    return {"dir": out, "dataset": sim["dataset"], "observations": observations, "truth": sim["ground_truth"]}


@pytest.fixture(scope="session")
def cli_result(cell):
    """`handeye calibrate` of the cell's observations on one thread (see
    assert_same_result): the result file's text."""
    path = cell["dir"] / "cli_result.json"
    run_cli("calibrate", cell["observations"], "-o", path, "--threads", 1)
    return path.read_text()
