"""Shared fixtures of the Python binding tests (ctest label `python`).

ctest sets PYTHONPATH to the build's python/ folder and ARTTRACK_CLI to the
arttrack program, whose outputs the bindings are checked against.
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest

SOURCE_DIR = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(SOURCE_DIR / "examples" / "python"))

# Short scenarios: 2-3 simulated seconds at 160x120 (each run about a second).
SHORT = {"duration_s": 2, "camera.width": 160, "camera.height": 120}


def set_args(overrides):
    """The --set arguments of the arttrack program for an overrides dict."""
    args = []
    for key, value in overrides.items():
        args += ["--set", f"{key}={value}"]
    return args


@pytest.fixture(scope="session")
def cli():
    """Runs the arttrack program; returns the CompletedProcess (text output)."""
    program = os.environ.get("ARTTRACK_CLI")
    if not program:
        pytest.fail("ARTTRACK_CLI is not set: run these tests through ctest (label python)")

    def run(*args, check=True):
        result = subprocess.run([program, *map(str, args)], capture_output=True, text=True)
        if check and result.returncode != 0:
            pytest.fail(f"arttrack {' '.join(map(str, args))} exited {result.returncode}: "
                        f"{result.stderr}")
        return result
    return run


@pytest.fixture(scope="session")
def dataset(cli, tmp_path_factory):
    """A dataset exported by `arttrack export`: 3 s of the default scenario at
    160x120, seed 5."""
    folder = tmp_path_factory.mktemp("data") / "default_5"
    cli("export", SOURCE_DIR / "scenarios" / "default.yaml", "--seed", 5, "--out", folder,
        *set_args({**SHORT, "duration_s": 3}))
    return folder
