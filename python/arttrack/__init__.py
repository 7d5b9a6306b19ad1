"""arttrack: probabilistic articulated real-time tracking of a robot manipulator,
and its MuJoCo testbed (docs/python.md).

The tracker: RobotModel, TrackerConfig, Camera, Tracker (and its Estimate).
The testbed: run_scenario, render_scene, export_dataset, track_dataset,
read_depth_png. Errors: InputError and UsageError, both ValueError.
Units: seconds, radians, metres.
"""
from ._arttrack import *  # noqa: F401,F403
from ._arttrack import __doc__ as _module_doc, __version__  # noqa: F401

__all__ = [
    "RobotModel", "TrackerConfig", "Camera", "Tracker", "Estimate",
    "InputError", "UsageError",
    "run_scenario", "render_scene", "export_dataset", "track_dataset",
    "read_depth_png", "default_scenario_path",
]
