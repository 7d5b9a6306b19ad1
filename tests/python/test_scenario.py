"""The testbed from Python against the arttrack program: the same scenario
and seed give the same numbers."""
import csv
import json

import numpy as np
import pytest

import arttrack
from conftest import SHORT, SOURCE_DIR, set_args

METHODS = ["encoders_only", "full_fusion"]


def read_columns(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def test_run_scenario_equals_arttrack_run(cli, tmp_path):
    result = arttrack.run_scenario(overrides=SHORT, seed=3, runs=2, methods=METHODS)
    cli("run", "--seed", 3, "--runs", 2, "--methods", ",".join(METHODS), "--out", tmp_path,
        *set_args(SHORT))
    header, rows = read_columns(tmp_path / "timeseries.csv")
    series = result["timeseries"]
    assert list(series) == header
    assert len(rows) == 2 * 2 * 61  # runs x methods x scored instants (30 Hz, 2 s)
    for c, name in enumerate(header):
        column = [row[c] for row in rows]
        if series[name].dtype.kind == "U":
            assert list(series[name]) == column, name
        else:  # full precision in the file: the same doubles, NaN where NaN
            assert np.array_equal(series[name], np.array(column, dtype=float), equal_nan=True), name
    with open(tmp_path / "summary.json") as f:
        summary = json.load(f)
    for key in ("scenario", "runs", "seeds", "end_effectors", "methods", "dropped"):
        assert result["summary"][key] == summary[key], key  # timing is wall time: not compared
    assert result["summary"]["reproduce"]["overrides"] == summary["reproduce"]["overrides"]


def test_run_scenario_writes_the_outputs(tmp_path):
    out = tmp_path / "run"
    overrides = [f"{k}={v}" for k, v in SHORT.items()]  # the list form of --set
    result = arttrack.run_scenario(overrides=overrides, runs=1, methods="encoders_only", out=str(out))
    assert [p.split("/")[-1] for p in result["files"][:3]] == [
        "summary.json", "timeseries.csv", "report.html"]
    with pytest.raises(arttrack.UsageError, match="holds a previous run's outputs"):
        arttrack.run_scenario(overrides=overrides, runs=1, methods="encoders_only", out=str(out))
    arttrack.run_scenario(overrides=overrides, runs=1, methods="encoders_only", out=str(out),
                          force=True)


def test_render_scene(cli, tmp_path):
    scene = SOURCE_DIR / "models" / "arm7_scene.yaml"
    r = arttrack.render_scene(str(scene), time_s=0.2)
    cli("render", scene, "--time", 0.2, "--out", tmp_path)
    for key, png in (("scene_depth", "sim_depth.png"), ("model_depth", "model_depth.png")):
        # The program's PNG: whole millimetres (rounded half away from zero), 0 = no return.
        z = r[key].astype(np.float64)
        mm = np.where(z > 0, np.minimum(np.floor(z * 1000 + 0.5), 65535), 0)
        written = arttrack.read_depth_png(str(tmp_path / png))
        assert np.array_equal(written, (mm * 1e-3).astype(np.float32)), key
    camera = r["camera"]
    for key in ("scene_depth", "robot_depth", "model_depth"):
        assert r[key].shape == (camera.height, camera.width) and r[key].dtype == np.float32
    robot = r["robot_depth"] > 0
    drawn = r["model_depth"] > 0
    assert robot.sum() > 1000
    # The tracker's render agrees with MuJoCo's robot where both see it.
    both = robot & drawn
    assert both.sum() > 0.9 * robot.sum()
    assert np.median(np.abs(r["robot_depth"][both] - r["model_depth"][both])) < 2e-3
    assert r["drawn_triangles"] <= r["model_triangles"]
    # A scene's robot is its URDF: nothing simulated differs from the tracker's.
    assert r["model_mismatch"] == "none" and r["simulated_urdf"].endswith("arm7.urdf")
    # Its true angles then, by joint: arm7's seven and its fingers, finite.
    assert {f"arm7_joint{k}" for k in range(1, 8)} <= set(r["joint_angles"])
    assert all(np.isfinite(a) for a in r["joint_angles"].values())


def test_export_and_track_dataset(dataset, tmp_path):
    exported = arttrack.export_dataset(str(SOURCE_DIR / "scenarios" / "default.yaml"),
                                       str(tmp_path / "ds"), overrides={**SHORT, "duration_s": 3},
                                       seed=5)
    assert exported["frames_delivered"] == 91 and exported["joint_rows"] == 3001
    for name in ("joints.csv", "ground_truth.csv", "depth/index.csv"):  # the CLI's bytes
        assert (tmp_path / "ds" / name).read_bytes() == (dataset / name).read_bytes(), name
    with pytest.raises(arttrack.UsageError, match="holds a previous run's outputs"):
        arttrack.export_dataset(str(SOURCE_DIR / "scenarios" / "default.yaml"), str(tmp_path / "ds"))

    tracked = arttrack.track_dataset(str(dataset), methods=["encoders_only"])
    estimate = tracked["estimate"]
    assert set(estimate["method"]) == {"encoders_only"}
    assert len(estimate["time_s"]) == 91 and tracked["frames_missing"] == 0
    assert tracked["summary"]["methods"]["encoders_only"]["translation_m"]["p50"] > 0
