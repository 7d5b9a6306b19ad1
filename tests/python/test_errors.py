"""Errors cross into Python as exceptions with the C++ message: InputError
(a ValueError) for bad input, UsageError (a ValueError, not an InputError)
for arguments the arttrack program refuses as usage errors."""
import numpy as np
import pytest

import arttrack
from conftest import SOURCE_DIR

URDF = str(SOURCE_DIR / "models" / "dual_arm.urdf")


def test_exception_classes():
    assert issubclass(arttrack.InputError, ValueError)
    assert issubclass(arttrack.UsageError, ValueError)
    assert not issubclass(arttrack.UsageError, arttrack.InputError)
    assert not issubclass(arttrack.InputError, arttrack.UsageError)


@pytest.mark.parametrize("key, value", [("camera.latncy_s", "0.1"), ("encoders[5].offset_deg", "1"),
                                        ("tracker_overrides", "{particle_filter.particles: -3}")])
def test_scenario_errors_carry_the_programs_message(cli, key, value):
    printed = cli("run", "--set", "duration_s=1", "--set", f"{key}={value}", "--out", "unused",
                  check=False)
    assert printed.returncode == 1
    with pytest.raises(arttrack.InputError) as error:
        arttrack.run_scenario(overrides={"duration_s": 1, key: value})
    assert printed.stderr.strip() == "arttrack: error: " + str(error.value)


def test_usage_errors():
    with pytest.raises(arttrack.UsageError, match="runs: must be >= 1"):
        arttrack.run_scenario(runs=0)
    with pytest.raises(arttrack.UsageError, match="runs: must be at most 100000"):
        arttrack.run_scenario(runs=100001)
    with pytest.raises(arttrack.UsageError, match="seed: must be >= 0"):
        arttrack.export_dataset("s.yaml", "out", seed=-1)
    with pytest.raises(arttrack.UsageError, match="methods: must not be empty"):
        arttrack.run_scenario(methods=[])
    with pytest.raises(arttrack.UsageError, match="has an empty item"):
        arttrack.track_dataset("d", methods="full_fusion,")
    with pytest.raises(arttrack.InputError, match="'full_fuson'"):
        arttrack.run_scenario(methods=["full_fuson"])


def test_configuration_errors_and_overrides(tmp_path):
    with pytest.raises(arttrack.InputError, match="key 'particle_filter.partcles' is not a known key"):
        arttrack.TrackerConfig({"particle_filter.partcles": 5})
    with pytest.raises(arttrack.InputError, match=r"override 'depth_model\[0\]=1'"):
        arttrack.TrackerConfig(["depth_model[0]=1"])
    with pytest.raises(arttrack.InputError, match="nothing.yaml: file not found"):
        arttrack.TrackerConfig.from_yaml_file(str(tmp_path / "nothing.yaml"))
    with pytest.raises(TypeError):
        arttrack.TrackerConfig({"particle_filter.particles": object()})
    # Values of every kind, written as YAML; str values are YAML text as after --set's '='.
    config = arttrack.TrackerConfig({"particle_filter.particles": 40, "method": "encoders_only",
                                     "end_effectors": ["tool", "flange"],
                                     "uncertainty.model_error": False,
                                     "depth_model.noise_std_m": 0.0125,
                                     "joints.per_joint": "{elbow: {bias_decay_per_s: 0.5}}"})
    assert config["particle_filter.particles"] == 40
    assert config.method == "encoders_only" and config.end_effectors == ["tool", "flange"]
    assert config["uncertainty.model_error"] is False
    assert config["depth_model.noise_std_m"] == 0.0125
    assert config["joints.per_joint.elbow.bias_decay_per_s"] == 0.5
    again = arttrack.TrackerConfig.from_yaml_file(str(SOURCE_DIR / "tracker" / "config" / "default.yaml"))
    assert again.with_overrides(["particle_filter.particles=40"])["particle_filter.particles"] == 40
    assert "particles: 40" in config.yaml


def test_model_and_tracker_errors(tmp_path):
    with pytest.raises(arttrack.InputError, match="missing.urdf"):
        arttrack.RobotModel.from_urdf_file(str(tmp_path / "missing.urdf"))
    model = arttrack.RobotModel.from_urdf_file(URDF)
    joints = model.physical_joint_names
    config = arttrack.TrackerConfig({"particle_filter.threads": 1})
    with pytest.raises(arttrack.InputError, match="nojoint"):
        arttrack.Tracker(model, config, joints[:-1] + ["nojoint"])
    tracker = arttrack.Tracker(model, config, joints)
    tracker.add_joint_measurement(1.0, np.zeros(len(joints)))
    with pytest.raises(arttrack.InputError):
        tracker.add_joint_measurement(0.5, np.zeros(len(joints)))  # backwards in time
    with pytest.raises(arttrack.InputError):
        tracker.add_joint_measurement(2.0, np.zeros(len(joints) + 1))  # wrong count
    camera = arttrack.Camera.from_vertical_fov(160, 120, 0.8)
    with pytest.raises(arttrack.InputError):
        tracker.add_depth_image(1.0, np.zeros((100, 160), np.float32), camera)  # wrong size
    with pytest.raises(arttrack.InputError, match="pixel"):
        tracker.add_depth_image(1.0, np.full((120, 160), -1, np.float32), camera)
    with pytest.raises(TypeError, match="int32"):
        tracker.add_depth_image(1.0, np.zeros((120, 160), np.int32), camera)
    with pytest.raises(TypeError, match="2-D"):
        tracker.add_depth_image(1.0, np.zeros(160, np.float32), camera)
    assert tracker.stats()["joint_measurements"] == 1
