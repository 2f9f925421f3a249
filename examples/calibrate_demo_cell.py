#!/usr/bin/env python3
"""Calibrates the demo cell of scripts/demo from Python: simulate, detect, solve, compare with the truth."""
import json, sys
import numpy as np
import handeye

out = sys.argv[1] if len(sys.argv) > 1 else "out/demo_python"
sim = handeye.simulate(out, cell="small", cameras=4, poses=12, seed=1)  # the cell scripts/demo renders
dataset = handeye.Dataset.load(sim["dataset"])
dataset.detect(progress=lambda done, total: print(f"\rdetected {done}/{total}", end="", file=sys.stderr))
result = handeye.calibrate(dataset)  # the joint solve, as `handeye calibrate`
result.save(f"{out}/result.json")
truth = json.load(open(sim["ground_truth"]))["T_base_cam"]
for cam in result.cameras:
    off_mm = 1000 * np.linalg.norm(cam.T_cam[:3, 3] - np.array(truth[cam.name])[:3, 3])
    print(f"\n{cam.name}: rms {cam.rms_px:.3f} px, {off_mm:.2f} mm from the truth, sigma {cam.sigma['position_mm']:.2f} mm",
          end="")
print("".join("\nwarning: " + w for w in result.warnings))
sys.exit(0 if all(cam.calibrated and cam.rms_px < 1 for cam in result.cameras) else 1)
