#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""`handeye advise` on a real capture, against poses it did not see.

Splits an observations file (handeye-observations/1, from `handeye detect`)
into a first capture A (every STRIDE-th pose, FIRST of them) and held-out
poses B (all the others), calibrates A, and asks `advise` for ADDED poses
with B's robot poses as the only candidates (a cell whose region is B's
taught poses). The poses it picks (matched to B's by their T_base_ee: a plan
numbers its poses afresh) are then added with their real views and the
capture solved again. Prints, per camera: the σ A's solve reported,
what `advise` says A's views give (`now`), the σ it forecasts after its
proposals, and the σ the solve of A + proposals then reported; with a
ground-truth file, both solves' true errors.

    bench/real-data/advise_held_out.py OBS.json [--ground-truth GT.json]
        [--first 20] [--added 8] [--stride 5] [--handeye build/tools/handeye]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def run(args, **kwargs):
    done = subprocess.run(args, capture_output=True, text=True, **kwargs)
    if done.returncode not in (0, 3, 4):
        sys.exit(f"{' '.join(args)} exited {done.returncode}:\n{done.stderr}")
    return done


def subset(obs, ids):
    keep = set(ids)
    out = dict(obs)
    out["poses"] = [p for p in obs["poses"] if p["id"] in keep]
    out["observations"] = [o for o in obs["observations"] if o["pose"] in keep]
    return out


def cell_for(obs, result, taught):
    """The cell `advise --cell` takes: the cameras and target where A's
    solve put them, the region B's robot poses."""
    mount = "T_base_cam" if obs["setup"] == "eye_to_hand" else "T_ee_cam"
    cameras = []
    for camera in obs["cameras"]:
        solved = result["cameras"].get(camera["name"])
        if not solved or not solved.get("calibrated"):
            continue
        entry = {k: camera[k] for k in ("name", "image_size", "intrinsics", "distortion") if k in camera}
        entry[mount] = solved[mount]
        entry["pose_uncertainty"] = {"position_m": 0.01, "rotation_deg": 0.5}
        cameras.append(entry)
    holder = "T_ee_target" if obs["setup"] == "eye_to_hand" else "T_base_target"
    return {"format": "handeye-cell/1", "setup": obs["setup"], "target": obs["target"],
            "cameras": cameras, holder: result[holder],
            "target_pose_uncertainty": {"position_m": 0.01, "rotation_deg": 0.5},
            "region": {"taught_poses": [{"id": p["id"], "T_base_ee": p["T_base_ee"]} for p in taught]},
            "view": {"margin_px": 0, "max_view_angle_deg": 80, "min_square_px": 4}}


def closest(pose, candidates):
    def distance(a, b):
        return sum((a[i][j] - b[i][j]) ** 2 for i in range(3) for j in range(4))
    return min(candidates, key=lambda c: distance(c["T_base_ee"], pose))["id"]


def errors(handeye, result, truth):
    if not truth:
        return {}
    done = run([handeye, "evaluate", result, truth, "--json"])
    return {name: c["translation_mm"] for name, c in json.loads(done.stdout)["cameras"].items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("observations")
    parser.add_argument("--ground-truth")
    parser.add_argument("--first", type=int, default=20)
    parser.add_argument("--added", type=int, default=8)
    parser.add_argument("--stride", type=int, default=5)
    parser.add_argument("--handeye", default="build/tools/handeye")
    parser.add_argument("--calibrate-flags", default="")
    args = parser.parse_args()
    handeye = os.path.realpath(args.handeye)
    obs = json.load(open(args.observations))
    ids = [p["id"] for p in obs["poses"]]
    first = ids[::args.stride][:args.first]
    taught = [p for p in obs["poses"] if p["id"] not in set(first)]
    work = tempfile.mkdtemp(prefix="handeye-advise-held-out.")
    flags = args.calibrate_flags.split()

    def solve(name, pose_ids):
        path = os.path.join(work, name + ".obs.json")
        json.dump(subset(obs, pose_ids), open(path, "w"))
        result = os.path.join(work, name + ".result.json")
        done = run([handeye, "calibrate", path, "-o", result, "--quiet"] + flags)
        if not os.path.exists(result):
            sys.exit(f"capture {name} ({len(pose_ids)} poses): {done.stderr.strip()}")
        return path, result, json.load(open(result))

    obs_a, result_a_path, result_a = solve("a", first)
    cell = os.path.join(work, "cell.json")
    json.dump(cell_for(obs, result_a, taught), open(cell, "w"))
    plan = os.path.join(work, "next.json")
    advice = run([handeye, "advise", result_a_path, "--dataset", obs_a, "--cell", cell,
                  "--poses", str(args.added), "-o", plan])
    if not os.path.exists(plan):
        sys.exit(f"advise proposed no poses: {(advice.stdout + advice.stderr).strip()}")
    now = {}
    for line in advice.stdout.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[0] in result_a["cameras"]:
            now[parts[0]] = float(parts[1])
    proposals = json.load(open(plan))["poses"]
    chosen = [closest(p["T_base_ee"], taught) for p in proposals]
    forecast = {name: s["position_mm"] for name, s in proposals[-1]["sigma_after"].items()}
    _, result_ab_path, result_ab = solve("ab", first + chosen)
    error_a = errors(handeye, result_a_path, args.ground_truth)
    error_ab = errors(handeye, result_ab_path, args.ground_truth)
    print(f"A: {len(first)} poses (every {args.stride}th), advise picked {len(chosen)} of "
          f"{len(taught)} held-out poses: {' '.join(chosen)}")
    print("| camera | σ A reported mm | advise now mm | now / reported | forecast after mm | "
          "σ A+picked reported mm | forecast / reported | true error A mm | true error A+picked mm |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, camera in result_a["cameras"].items():
        if not camera.get("calibrated") or name not in forecast:
            continue
        sigma_a = camera["sigma"]["position_mm"]
        sigma_ab = result_ab["cameras"][name]["sigma"]["position_mm"]
        print(f"| {name} | {sigma_a:.3f} | {now.get(name, float('nan')):.3f} | "
              f"{now.get(name, float('nan')) / sigma_a:.2f} | {forecast[name]:.3f} | {sigma_ab:.3f} | "
              f"{forecast[name] / sigma_ab:.2f} | {error_a.get(name, float('nan')):.3f} | "
              f"{error_ab.get(name, float('nan')):.3f} |")


if __name__ == "__main__":
    main()
