#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-or-later
"""Converts ViSP's Franka hand-eye sets (apps/calibration/hand-eye/data-eye-in-hand
and data-eye-to-hand of lagadic/visp, 8 poses each, 640x480) into handeye-dataset/1
files that name the images by absolute path (never commit them), and prints the
result ViSP's own tutorial publishes for each, as a handeye-ground-truth/1 file
to compare with (`handeye evaluate RESULT REFERENCE`).

    bench/real-data/visp_franka.py HAND_EYE_FOLDER -o OUTDIR

What the conversion assumes, from ViSP's tutorials
(tutorial-calibration-extrinsic-eye-in-hand.dox, ...-eye-to-hand.dox):
- franka_pose_rPe_K.yaml is a vpPoseVector of the flange in the robot
  reference frame: tx ty tz (m) and a theta-u rotation vector (rad) = T_base_ee.
- franka_camera.xml: perspective projection without distortion (kud = 0).
- eye-in-hand: a 9x6 inner-corner chessboard of 23.6 mm squares fixed in the cell.
- eye-to-hand: one AprilTag 36h11 of 48 mm (its black square) on the flange, id 10:
  an AprilGrid of one tag with a one-bit black border and first_id 10.
"""
import argparse
import json
import os
import re
import math
import sys


def rotvec_to_matrix(r):
    """Rodrigues: the rotation matrix (rows) of a rotation vector."""
    theta = math.sqrt(sum(v * v for v in r))
    if theta < 1e-15:
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    x, y, z = (v / theta for v in r)
    c, s, C = math.cos(theta), math.sin(theta), 1 - math.cos(theta)
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]


def matrix(pose_vec):
    """4x4 nested list of a vpPoseVector [tx ty tz tux tuy tuz]."""
    R = rotvec_to_matrix(pose_vec[3:])
    return [R[0] + [pose_vec[0]], R[1] + [pose_vec[1]], R[2] + [pose_vec[2]], [0.0, 0.0, 0.0, 1.0]]


def pose_vector(path):
    """The six numbers of a vpPoseVector YAML file (rows: 6, cols: 1, data: - [x])."""
    with open(path) as f:
        values = [float(v) for v in re.findall(r"-\s*\[\s*([-+0-9.eE]+)\s*\]", f.read())]
    if len(values) != 6:
        sys.exit("%s: expected 6 values, found %d" % (path, len(values)))
    return matrix(values)


def camera(folder):
    with open(os.path.join(folder, "franka_camera.xml")) as f:
        xml = f.read()
    get = lambda tag: float(re.search(r"<%s>([^<]+)</%s>" % (tag, tag), xml).group(1))
    return {"name": "camera", "image_size": [int(get("image_width")), int(get("image_height"))],
            "intrinsics": {"fx": get("px"), "fy": get("py"), "cx": get("u0"), "cy": get("v0")},
            "distortion": {"model": "none"}}


def dataset(folder, setup, target):
    poses = []
    for k in range(1, 100):
        pose = os.path.join(folder, "franka_pose_rPe_%d.yaml" % k)
        if not os.path.exists(pose):
            break
        poses.append({"id": "%d" % k, "T_base_ee": pose_vector(pose),
                      "images": {"camera": os.path.join(folder, "franka_image-%d.png" % k)}})
    return {"format": "handeye-dataset/1", "setup": setup, "target": target,
            "cameras": [camera(folder)], "poses": poses}


def reference(setup, key, pose_vec):
    return {"format": "handeye-ground-truth/1", "setup": setup, key: {"camera": matrix(pose_vec)}}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="apps/calibration/hand-eye of a ViSP checkout")
    parser.add_argument("-o", "--outdir", required=True)
    args = parser.parse_args()
    root = os.path.abspath(args.folder)
    os.makedirs(args.outdir, exist_ok=True)
    sets = {
        "eye-in-hand": ("data-eye-in-hand", "eye_in_hand",
                        {"type": "checkerboard", "inner_corners": [9, 6], "square_size_m": 0.0236},
                        # eMc as ViSP's tutorial prints it: T_ee_cam.
                        ("T_ee_cam", [0.05771519632, -0.03392488515, -0.04227690244,
                                      0.001783530191, 0.009173747947, 1.581782359])),
        "eye-to-hand": ("data-eye-to-hand", "eye_to_hand",
                        {"type": "aprilgrid", "tags": [1, 1], "tag_size_m": 0.048, "tag_spacing": 0.3,
                         "family": "tag36h11", "border_bits": 1, "first_id": 10},
                        # rMc as ViSP's tutorial prints it: T_base_cam.
                        ("T_base_cam", [0.9540358034, -0.05123574465, 0.4762201018,
                                        -1.104108108, -1.112745553, 1.289540899])),
    }
    for name, (sub, setup, target, (key, published)) in sets.items():
        data = dataset(os.path.join(root, sub), setup, target)
        with open(os.path.join(args.outdir, name + ".json"), "w") as f:
            json.dump(data, f, indent=1)
        with open(os.path.join(args.outdir, name + "-visp.json"), "w") as f:
            json.dump(reference(setup, key, published), f, indent=1)
        print("wrote %s/%s.json (%d poses) and %s-visp.json (ViSP's published %s)"
              % (args.outdir, name, len(data["poses"]), name, key), file=sys.stderr)


if __name__ == "__main__":
    main()
