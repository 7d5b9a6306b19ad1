#!/usr/bin/env python3
"""The Python bindings' overhead on a tracker fed from Python (issue 31's
target: below 5% of the image update time). A benchmark, not a test.

    PYTHONPATH=build/python python3 tools/bench_python.py [--dataset DIR]
        [--duration S] [--width W --height H] [--repeat N]

Without --dataset it exports the default scenario (seed 5, S seconds at WxH,
default 5 s at 640x480, the scene's camera) into a temporary folder. Then:

- C++ feeding: arttrack.track_dataset (what `arttrack track` runs): its
  summary's timing of full fusion: image update and joint update p50/p99
  (measured inside C++);
- Python feeding: the same readings and images (images read into memory
  first) given to one Tracker from a Python loop, each call timed with
  time.perf_counter. An image's overhead is the wall time of its
  add_depth_image call less the update time the tracker itself measured for
  that image (stats()['image_update_ms']): the argument conversion, the copy
  of the array into the tracker's image, releasing and taking the GIL.
  A joint reading's overhead is its call's wall time less the C++ p50.

Prints p50 and p99 of each, and the image overhead as a share of the image
update time.
"""
import argparse
import os
import sys
import tempfile
import time

import numpy as np

import arttrack

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "python"))
import track_dataset  # noqa: E402  (examples/python: reads a dataset into arrays)


def percentiles(values):
    return np.percentile(values, 50), np.percentile(values, 99)


def python_fed(folder, data, images):
    model = arttrack.RobotModel.from_urdf_file(os.path.join(folder, "robot.urdf"),
                                               camera_frame=data["camera_frame"])
    config = arttrack.TrackerConfig.from_yaml_file(
        os.path.join(folder, "tracker.yaml"),
        {"method": "full_fusion", "timing.camera_delay_s": data["delay_s"]})
    tracker = arttrack.Tracker(model, config, data["joint_names"])
    tracker.prepare_camera(data["camera"])  # before the stream, as a live run does
    events = [(t, 0, i) for i, t in enumerate(data["joint_time_s"])]
    events += [(f[1], 1, i) for i, f in enumerate(data["frames"])]
    events.sort()
    joint_us, image_ms = [], []
    readings = data["joint_readings_rad"]
    clock = time.perf_counter
    for time_s, kind, i in events:
        if kind == 0:
            start = clock()
            tracker.add_joint_measurement(time_s, readings[i])
            joint_us.append(1e6 * (clock() - start))
        else:
            start = clock()
            tracker.add_depth_image(data["frames"][i][0], images[i], data["camera"])
            image_ms.append(1e3 * (clock() - start))
    stats = tracker.stats()
    if stats["images_applied"] != len(image_ms):
        sys.exit(f"bench_python: {stats['images_applied']} of {len(image_ms)} images applied "
                 "within their calls; the overhead per call cannot be told")
    return np.array(joint_us), np.array(image_ms), stats["image_update_ms"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dataset", help="a dataset folder (default: export one)")
    parser.add_argument("--duration", type=float, default=5)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--repeat", type=int, default=1, help="Python-fed passes over the data")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        folder = args.dataset
        if not folder:
            folder = os.path.join(tmp, "dataset")
            arttrack.export_dataset(arttrack.default_scenario_path(), folder, seed=5, overrides={
                "duration_s": args.duration, "camera.width": args.width,
                "camera.height": args.height})
        data = track_dataset.read_dataset(folder)
        images = [arttrack.read_depth_png(f[2]) for f in data["frames"]]
        h, w = images[0].shape

        timing = arttrack.track_dataset(folder, methods=["full_fusion"])["summary"]["timing"]
        cpp_joint_us = timing["joint_update_us"]["p50"], timing["joint_update_us"]["p99"]
        cpp_image_ms = timing["image_update_ms"]["p50"], timing["image_update_ms"]["p99"]

        joint_us, call_ms, update_ms = [], [], []
        for _ in range(args.repeat):
            j, c, u = python_fed(folder, data, images)
            joint_us.append(j), call_ms.append(c), update_ms.append(u)
        joint_us, call_ms, update_ms = map(np.concatenate, (joint_us, call_ms, update_ms))

    overhead_ms = call_ms - update_ms
    update = percentiles(update_ms)
    over = percentiles(overhead_ms)
    joint = percentiles(joint_us)
    print(f"dataset {folder}: {len(data['joint_time_s'])} joint readings, {len(images)} images "
          f"{w}x{h}; full fusion; {args.repeat} Python-fed pass(es)")
    print(f"C++ fed (track_dataset):  image update p50 {cpp_image_ms[0]:.2f} ms  p99 "
          f"{cpp_image_ms[1]:.2f} ms;  joint update p50 {cpp_joint_us[0]:.1f} us  p99 "
          f"{cpp_joint_us[1]:.1f} us")
    print(f"Python fed, in C++:       image update p50 {update[0]:.2f} ms  p99 {update[1]:.2f} ms")
    print(f"Python fed, whole call:   add_depth_image p50 {np.percentile(call_ms, 50):.2f} ms  "
          f"p99 {np.percentile(call_ms, 99):.2f} ms;  add_joint_measurement p50 {joint[0]:.1f} us"
          f"  p99 {joint[1]:.1f} us")
    print(f"Python overhead per image: p50 {1e3 * over[0]:.0f} us  p99 {1e3 * over[1]:.0f} us = "
          f"{100 * over[0] / update[0]:.2f}% / {100 * over[1] / update[0]:.2f}% of the p50 image "
          f"update")
    print(f"Python overhead per joint reading: p50 {joint[0] - cpp_joint_us[0]:.1f} us over C++'s "
          f"p50")
    return 0


if __name__ == "__main__":
    sys.exit(main())
