#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Python vs CLI on one observations file: the same numbers, and what calling
from Python costs.

    PYTHONPATH=build/python python3 bench/python_overhead.py OBS.json [--handeye build/tools/handeye]
        [--runs 3] [--threads 2]

Runs `handeye calibrate OBS -o R.json` and `handeye.calibrate(dataset)` on a
Dataset loaded once (in memory), alternately, --runs times each; checks that
the camera rows the CLI prints are the ones the Python result gives and that
the two result files agree in every string, flag and count and in every real
to 1e-7 (the joint solve's last bits depend on where its buffers lie in
memory, which differs between two processes),
and prints the median wall times and their ratio. Exit 1 when the results differ.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import handeye


def summary_rows(result):
    """The camera rows `handeye calibrate` prints (tools/calibrate.cc PrintSummary)."""
    rows = []
    for camera in result.cameras:
        t = 1000 * camera.T_cam[:3, 3]
        rows.append(f"{camera.name:<12} {t[0]:10.2f} {t[1]:10.2f} {t[2]:10.2f} {camera.rms_px:8.3f} {camera.views:6d}")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("observations")
    parser.add_argument("--handeye", default=os.path.join("build", "tools", "handeye"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()

    start = time.perf_counter()
    dataset = handeye.Dataset.load(args.observations)
    load_s = time.perf_counter() - start
    cli_s, python_s, cli_solve_s, python_solve_s = [], [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "result.json")
        for _ in range(args.runs):
            start = time.perf_counter()
            printed = subprocess.run([args.handeye, "calibrate", args.observations, "-o", out, "--threads",
                                      str(args.threads)], check=True, capture_output=True, text=True).stdout
            cli_s.append(time.perf_counter() - start)
            cli_solve_s.append(json.load(open(out))["solver"]["seconds"])
            start = time.perf_counter()
            result = handeye.calibrate(dataset, threads=args.threads)
            python_s.append(time.perf_counter() - start)
            python_solve_s.append(result.solver["seconds"])
        cli_text = open(out).read()
    differences, (where, largest) = handeye.result_differences(result.to_json(), cli_text, tolerance=1e-7)
    same = not differences
    rows = summary_rows(result)
    printed_same = all(row in printed.splitlines() for row in rows)
    cli, python = statistics.median(cli_s), statistics.median(python_s)
    print(f"views {len(dataset.views)}, poses {len(dataset.pose_ids)}, cameras {len(dataset.cameras)}")
    print(f"CLI calibrate from the file:      median {cli:.3f} s  ({', '.join(f'{s:.3f}' for s in cli_s)})")
    print(f"Python calibrate from memory:     median {python:.3f} s  ({', '.join(f'{s:.3f}' for s in python_s)})")
    print(f"the solve inside (solver.seconds): CLI median {statistics.median(cli_solve_s):.3f} s, Python median "
          f"{statistics.median(python_solve_s):.3f} s")
    print(f"Python Dataset.load (once):       {load_s:.3f} s")
    print(f"Python / CLI: {python / cli:.3f} (load included: {(python + load_s) / cli:.3f})")
    print(f"result files: the same but for reals within 1e-7: {'yes' if same else 'NO ' + str(differences[:3])} "
          f"(largest difference {largest:.3g} at {where or '-'})")
    print(f"camera rows as the CLI printed them: {'identical' if printed_same else 'DIFFERENT'}")
    print("\n".join("  " + row for row in rows))
    return 0 if same and printed_same else 1


if __name__ == "__main__":
    sys.exit(main())
