#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Converts ros-industrial/industrial_calibration's examples/data/test_set_charuco
(one static camera, a ChArUco board on the robot, 16 poses) into a
handeye-dataset/1 file beside a copy of nothing: the images stay where they are
and the dataset names them by absolute path (never commit them).

    bench/real-data/industrial_calibration_charuco.py FOLDER -o DATASET.json

FOLDER holds cal_data.yaml, images/ and poses/. What the conversion assumes,
from that repository's documentation (page_extrinsic_hand_eye_calibration.dox):
- `static_camera: true`: each pose file is the robot's flange (the target
  mount) in the robot base, x y z in metres and a quaternion qx qy qz qw:
  our T_base_ee of an eye_to_hand cell.
- The camera is "a pinhole model camera, without distortion" with the given
  fx fy cx cy (their tool has no distortion model; the images are 1600x1200).
- target_finder CharucoGridTargetFinder rows 7, cols 5: OpenCV's board of
  squares (cols, rows) = [5, 7]; chessboard_dim the square, aruco_marker_dim the
  marker, dictionary 10 = DICT_6X6_250 (OpenCV's enum value).
"""
import argparse
import json
import os
import sys

import yaml

DICTIONARIES = {0: "DICT_4X4_50", 1: "DICT_4X4_100", 2: "DICT_4X4_250", 3: "DICT_4X4_1000",
                4: "DICT_5X5_50", 5: "DICT_5X5_100", 6: "DICT_5X5_250", 7: "DICT_5X5_1000",
                8: "DICT_6X6_50", 9: "DICT_6X6_100", 10: "DICT_6X6_250", 11: "DICT_6X6_1000"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()
    folder = os.path.abspath(args.folder)
    with open(os.path.join(folder, "cal_data.yaml")) as f:
        config = yaml.safe_load(f)
    if not config.get("static_camera", False):
        sys.exit("only the static-camera (eye_to_hand) form is converted")
    finder = config["target_finder"]
    if finder["type"] != "CharucoGridTargetFinder":
        sys.exit("target %s is not a ChArUco grid" % finder["type"])
    k = config["intrinsics"]
    poses = []
    for i, entry in enumerate(config["data"]):
        with open(os.path.join(folder, entry["pose"])) as f:
            p = yaml.safe_load(f)
        poses.append({
            "id": "%02d" % i,
            "T_base_ee": {"translation_m": [p["x"], p["y"], p["z"]],
                          "quaternion_xyzw": [p["qx"], p["qy"], p["qz"], p["qw"]]},
            "images": {"camera": os.path.join(folder, entry["image"])},
        })
    dataset = {
        "format": "handeye-dataset/1",
        "setup": "eye_to_hand",
        "target": {"type": "charuco", "squares": [finder["cols"], finder["rows"]],
                   "square_size_m": finder["chessboard_dim"],
                   "marker_size_m": finder["aruco_marker_dim"],
                   "dictionary": DICTIONARIES[finder["dictionary"]]},
        "cameras": [{"name": "camera", "image_size": [1600, 1200],
                     "intrinsics": {"fx": k["fx"], "fy": k["fy"], "cx": k["cx"], "cy": k["cy"]},
                     "distortion": {"model": "none"}}],
        "poses": poses,
    }
    with open(args.output, "w") as f:
        json.dump(dataset, f, indent=1)
    print("wrote %s (%d poses)" % (args.output, len(poses)), file=sys.stderr)


if __name__ == "__main__":
    main()
