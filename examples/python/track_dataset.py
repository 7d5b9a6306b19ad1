#!/usr/bin/env python3
"""Feed an arttrack Tracker from arrays: a dataset folder (docs/datasets.md),
read with numpy and the standard library, fed in time order.

A dataset holds what a tracker receives from a robot: encoder readings
(joints.csv, s and rad), depth images (depth/*.png, 16-bit millimetres, with
their capture stamps and arrival times in depth/index.csv), the camera
(camera.yaml), the nominal URDF (robot.urdf), the tracker configuration
(tracker.yaml) and, optionally, the ground truth (ground_truth.csv).
`arttrack export` writes one from a simulated scenario:

    build/arttrack export scenarios/default.yaml --seed 5 --out /tmp/ds \\
        --set duration_s=3 --set camera.width=160 --set camera.height=120
    PYTHONPATH=build/python python3 examples/python/track_dataset.py /tmp/ds

It prints the estimate every half second and, with ground truth, each arm
joint's estimated encoder bias against the true one. The order of the calls
is `arttrack track`'s (joint readings at their time, images at their
arrival; at equal times joints first), so the estimates are the same numbers
as its estimate.csv (tests/python/test_tracker.py checks that).
"""
import argparse
import csv
import math
import os
import sys

import numpy as np

import arttrack


def read_simple_yaml(path):
    """The `key: value` lines of a flat YAML file (camera.yaml), as strings."""
    values = {}
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if ":" in line:
                key, value = line.split(":", 1)
                values[key.strip()] = value.strip()
    return values


def read_csv_columns(path):
    """A CSV file with one header line: (names, float64 array rows x columns)."""
    with open(path) as f:
        names = next(csv.reader(f))
    rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return names, rows


def read_dataset(folder):
    """Everything the tracker needs from a dataset folder, as arrays."""
    camera = read_simple_yaml(os.path.join(folder, "camera.yaml"))
    names, joints = read_csv_columns(os.path.join(folder, "joints.csv"))
    with open(os.path.join(folder, "depth", "index.csv")) as f:
        frames = [(float(r["stamp_s"]), float(r["arrival_s"]), os.path.join(folder, "depth", r["file"]))
                  for r in csv.DictReader(f)]
    truth_path = os.path.join(folder, "ground_truth.csv")
    truth = read_csv_columns(truth_path) if os.path.exists(truth_path) else None
    return {
        "camera": arttrack.Camera(int(camera["width"]), int(camera["height"]), float(camera["fx"]),
                                  float(camera["fy"]), float(camera["cx"]), float(camera["cy"])),
        "camera_frame": camera.get("frame", "camera_optical_frame"),
        "delay_s": float(camera.get("delay_s", 0)),
        "joint_names": names[1:],
        "joint_time_s": joints[:, 0],
        "joint_readings_rad": joints[:, 1:],
        "frames": frames,
        "truth": truth,
    }


def track(folder, method="full_fusion", on_estimate=None):
    """Tracks the dataset in `folder` with one synchronous tracker.

    Calls on_estimate(time_s, estimate) at every ground-truth time (or, without
    ground truth, at every image arrival), after that time's joints and images.
    Returns the tracker and the dataset as read_dataset gives it.
    """
    data = read_dataset(folder)
    model = arttrack.RobotModel.from_urdf_file(os.path.join(folder, "robot.urdf"),
                                               camera_frame=data["camera_frame"])
    overrides = {"method": method, "camera_frame": data["camera_frame"],
                 "timing.camera_delay_s": data["delay_s"], "timing.asynchronous": False}
    truth = data["truth"]
    if truth is not None:  # the end effectors the ground truth has poses of
        overrides["end_effectors"] = [n[:-3] for n in truth[0] if n.endswith("_qw")]
    config = arttrack.TrackerConfig.from_yaml_file(os.path.join(folder, "tracker.yaml"), overrides)
    tracker = arttrack.Tracker(model, config, data["joint_names"])
    # The camera is known before the stream: the meshes are simplified now,
    # not at the first image.
    tracker.prepare_camera(data["camera"])
    if method == "vision_only":  # it starts from the true configuration
        names, rows = truth
        tracker.set_initial_configuration(data["joint_names"],
                                          [rows[0, names.index(j)] for j in data["joint_names"]])

    # Joints at their time, images at their arrival, estimates at the truth
    # times; at equal times in that order.
    events = [(t, 0, i) for i, t in enumerate(data["joint_time_s"])]
    events += [(f[1], 1, i) for i, f in enumerate(data["frames"])]
    if truth is not None:
        events += [(t, 2, i) for i, t in enumerate(truth[1][:, 0])]
    events.sort()
    joints_seen = False
    for time_s, kind, i in events:
        if kind == 0:
            if method != "vision_only":
                tracker.add_joint_measurement(time_s, data["joint_readings_rad"][i])
            joints_seen = True
        elif kind == 1:
            stamp_s, _, path = data["frames"][i]
            tracker.add_depth_image(stamp_s, arttrack.read_depth_png(path), data["camera"])
            if truth is None and joints_seen and on_estimate:
                on_estimate(time_s, tracker.estimate())
        elif joints_seen and on_estimate:
            on_estimate(time_s, tracker.estimate())
    return tracker, data


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dataset", help="dataset folder (arttrack export writes one)")
    parser.add_argument("--method", default="full_fusion",
                        choices=["encoders_only", "camera_offset_only", "full_fusion", "vision_only"])
    args = parser.parse_args()

    last = [-math.inf]

    def show(time_s, e):
        if time_s - last[0] < 0.5:
            return
        last[0] = time_s
        ee = " ".join(f"{p[0, 3]:+.3f},{p[1, 3]:+.3f},{p[2, 3]:+.3f}" for p in e.T_camera_ee)
        print(f"t {time_s:5.2f} s  {e.health['state']:8s}  camera offset "
              f"{1e3 * np.linalg.norm(e.camera_offset[:3]):.1f} mm  end effectors in camera [m] {ee}")

    tracker, data = track(args.dataset, args.method, show)
    e = tracker.estimate()
    stats = tracker.stats()
    print(f"{stats['images_applied']} images applied, image update p50 "
          f"{np.median(stats['image_update_ms']):.1f} ms")
    if data["truth"] is not None:
        names, rows = data["truth"]
        print("joint                 est. bias  true bias [deg]")
        for j, name in enumerate(e.joint_names):
            if name + "_bias" in names and e.bias_std_rad[j] > 0:
                true = rows[-1, names.index(name + "_bias")]
                print(f"{name:20s} {math.degrees(e.bias_rad[j]):+9.2f}  {math.degrees(true):+9.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
