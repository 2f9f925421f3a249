# SPDX-License-Identifier: GPL-2.0-or-later
"""Do two handeye-result/1 files say the same? (CLI against Python, or one run
against another.)"""

import json


def _leaves(value, path=""):
    """(JSON pointer, value) of every number, string, flag and null."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _leaves(item, f"{path}/{key}")
    elif isinstance(value, list):
        for index, item in enumerate(value):
            yield from _leaves(item, f"{path}/{index}")
    else:
        yield path, value


def result_differences(text, other_text, tolerance=1e-8, ignore=("/solver/seconds", "/provenance/input"),
                       covariance_tolerance=1e-6):
    """Where two result files (JSON text) disagree: a list of (path, value,
    other value), empty when they have the same keys, strings, flags and counts
    and every real within `tolerance` (absolute up to 1, relative above).

    On one thread, the CLI and the module agree bit for bit (`tolerance=0`).
    With several, Ceres sums the joint solve's Schur complement in the order
    the threads finish, so two runs differ in the last bits. The entries of a
    covariance matrix (under a key that begins with `covariance`) are compared to
    `covariance_tolerance` instead: a covariance inverts JᵀJ, whose condition
    number magnifies those last-bit differences of the solution (two CLI runs
    of one 3-camera cell, 1 and 2 threads, agree to 1e-12 in every residual
    and to 1.8e-8 in the covariance entries). `ignore` leaves out the solve's
    wall time and the input's name by default. Also returns, as the second
    value, the largest difference between reals seen (path, size).
    """
    ours, theirs = dict(_leaves(json.loads(text))), dict(_leaves(json.loads(other_text)))
    differences, largest = [], ("", 0.0)
    for path in sorted(ours.keys() | theirs.keys()):
        if path in ignore:
            continue
        a, b = ours.get(path, "<missing>"), theirs.get(path, "<missing>")
        if isinstance(a, float) and isinstance(b, float):
            if abs(a - b) > largest[1]:
                largest = (path, abs(a - b))
            allowed = covariance_tolerance if "/covariance" in path else tolerance
            if abs(a - b) <= allowed * max(1.0, abs(a)):
                continue
        elif a == b and type(a) is type(b):
            continue
        differences.append((path, a, b))
    return differences, largest
