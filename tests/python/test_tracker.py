"""A tracker fed from Python (examples/python/track_dataset.py) on a dataset
exported by `arttrack export`: the same numbers as `arttrack track`, and it
converges."""
import csv
import math

import numpy as np

import arttrack
import track_dataset  # examples/python


def estimates_of(dataset, method="full_fusion"):
    rows = []
    tracker, data = track_dataset.track(str(dataset), method, lambda t, e: rows.append((t, e)))
    return rows, tracker, data


def test_python_fed_tracker_equals_arttrack_track(cli, dataset, tmp_path):
    rows, _, _ = estimates_of(dataset)
    cli("track", dataset, "--methods", "full_fusion", "--out", tmp_path)
    with open(tmp_path / "estimate.csv") as f:
        expected = list(csv.DictReader(f))
    assert len(rows) == len(expected) == 91
    for (time_s, e), row in zip(rows, expected):
        assert time_s == float(row["time_s"])
        for j, name in enumerate(e.joint_names):  # shortest round-trip text: exact
            assert e.angle_rad[j] == float(row[name + "_rad"])
            assert e.angle_std_rad[j] == float(row[name + "_std_rad"])
            assert e.bias_rad[j] == float(row[name + "_bias_rad"])
        names = ["cam_x_m", "cam_y_m", "cam_z_m", "cam_roll_rad", "cam_pitch_rad", "cam_yaw_rad"]
        assert list(e.camera_offset) == [float(row[n]) for n in names]
        assert e.T_camera_ee[0][0, 3] == float(row["left_ee_x"])


def test_python_fed_tracker_converges(dataset):
    rows, tracker, data = estimates_of(dataset)
    e = tracker.estimate()
    names, truth = data["truth"]
    arm = [j for j, n in enumerate(e.joint_names) if "arm" in n]
    errors_deg = [math.degrees(e.bias_rad[j] - truth[-1, names.index(e.joint_names[j] + "_bias")])
                  for j in arm]
    assert max(abs(x) for x in errors_deg) < 1.0, errors_deg  # of an 8.6 degree bias
    assert e.health["state"] == "tracking"
    # Per link with geometry: its pinned surface shift, a few millimetres at
    # most on this exact robot (NaN where no image pinned it).
    links = e.health["links"]
    assert [l["link"] for l in links][:2] == ["base_link", "torso"]
    pinned = [l["shift_m"] for l in links if l["images"] > 0]
    assert pinned and max(pinned) < 0.003, links
    assert tracker.stats()["images_applied"] == 91
    # The pose and its covariance per end effector.
    assert e.T_camera_ee.shape == (2, 4, 4) and e.T_camera_ee_covariance.shape == (2, 6, 6)
    assert np.allclose(e.T_camera_ee[:, 3], [0, 0, 0, 1])
    # The end-effector fit's share: a few millimetres at most on this exact robot.
    assert e.ee_image_correction.shape == (2, 6, 1)
    assert np.linalg.norm(e.ee_image_correction[:, :3], axis=1).max() < 0.003
    # Its search along each hand ran at the images that fitted a hand.
    assert 0 <= e.health["hand_shifts_accepted"] <= e.health["hand_searches"]
    assert isinstance(e.health["unseen_priors_kept"], int)  # joints unseen kept at their prior
    # Images whose refinement step had a motion that moves no surface (a count).
    assert isinstance(e.health["images_with_unseen_motion"], int)
    assert e.health["images_with_unseen_motion"] >= 0
    assert e.health["hand_searches"] > 0
    # Each encoder's noise as its readings show it: every joint of this robot
    # has one, and the dataset's encoders are within a few hundredths of a degree.
    noise = e.health["encoder_noise_measured_rad"]
    assert noise.shape == (len(e.joint_names),)
    assert np.isfinite(noise).all() and (noise >= 0).all() and noise.max() < 0.002, noise
    cov = e.T_camera_ee_covariance
    assert np.allclose(cov, cov.transpose(0, 2, 1)) and (np.linalg.eigvalsh(cov) > -1e-12).all()
    # Left hand in the camera frame against the truth (ground_truth.csv), last row.
    true_x = truth[-1, names.index("left_ee_x")], truth[-1, names.index("left_ee_y")]
    assert math.dist(true_x, e.T_camera_ee[0][:2, 3]) < 0.01


def test_uint16_millimetres_equal_float32_metres(dataset):
    data = track_dataset.read_dataset(str(dataset))
    model = arttrack.RobotModel.from_urdf_file(str(dataset / "robot.urdf"))
    config = arttrack.TrackerConfig.from_yaml_file(str(dataset / "tracker.yaml"))
    trackers = [arttrack.Tracker(model, config, data["joint_names"]) for _ in range(2)]
    trackers[0].prepare_camera(data["camera"])  # built once, before the images or at the first
    assert trackers[0].stats()["geometry_builds"] == 1
    frames = data["frames"][:3]
    for i, t in enumerate(data["joint_time_s"][:70]):
        for tracker in trackers:
            tracker.add_joint_measurement(t, data["joint_readings_rad"][i])
        for stamp, arrival, path in frames:
            if arrival == t:
                metres = arttrack.read_depth_png(path)
                millimetres = np.round(metres.astype(np.float64) * 1000).astype(np.uint16)
                trackers[0].add_depth_image(stamp, metres, data["camera"])
                trackers[1].add_depth_image(stamp, millimetres, data["camera"])
    a, b = (tracker.estimate() for tracker in trackers)
    assert trackers[0].stats()["images_applied"] == 3
    assert [t.stats()["geometry_builds"] for t in trackers] == [1, 1]
    assert np.array_equal(a.angle_rad, b.angle_rad) and np.array_equal(a.bias_rad, b.bias_rad)
