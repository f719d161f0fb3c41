"""Shared fixtures and helpers: seeded random poses and the checks the paper's theorems need."""

from __future__ import annotations

import io
import os
import shutil
import subprocess
import venv
from pathlib import Path

import numpy as np
import pytest

from a2b.poses import inverse_matrices, matrices_from_quat_trans


@pytest.fixture
def rng():
    return np.random.default_rng(20261121)


def random_pose(rng, scale=1.0):
    """A random robotics matrix with translation of size ``scale``."""
    quat = rng.normal(size=4)
    return matrices_from_quat_trans(quat, rng.normal(size=3) * scale)


def pose_about_axis(angle, axis, point, slide):
    """The screw displacement: rotation by ``angle`` about the line (axis, point), slide along
    it."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rot = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    out = np.eye(4)
    out[:3, :3] = rot
    out[:3, 3] = (np.eye(3) - rot) @ np.asarray(point, float) + slide * axis
    return out


def rigidity(matrices):
    """``max |R Rᵀ − I|`` and ``max |det R − 1|`` over samples, and the bottom-row error."""
    rot = matrices[..., :3, :3]
    ortho = np.abs(rot @ np.swapaxes(rot, -1, -2) - np.eye(3)).max()
    det = np.abs(np.linalg.det(rot) - 1).max()
    bottom = np.abs(matrices[..., 3, :] - [0, 0, 0, 1]).max()
    return max(ortho, det, bottom)


def commutator(matrices):
    """Largest ``|D_i D_j − D_j D_i|`` of the relative displacements ``C(t) C(0)⁻¹``."""
    rel = matrices @ inverse_matrices(matrices[0])
    return np.abs(rel[:, None] @ rel[None, :] - rel[None, :] @ rel[:, None]).max()


class NonSeekableStream(io.RawIOBase):
    """A writable stream like a pipe: no ``seek``, and ``tell`` fails. Collects what is written."""

    def __init__(self):
        self.data = bytearray()

    def writable(self):
        return True

    def write(self, b):
        self.data += b
        return len(b)

    def seekable(self):
        return False

    def tell(self):
        raise OSError("illegal seek")


#: Where the tests install the real clients that conflict with a2b's own environment.
TOOLS = Path(os.environ.get("A2B_TOOLS", Path.home() / ".cache" / "a2b-test-tools"))
#: The Python clients, in one venv of their own (evo pins its own numpy): evo (which brings
#: rosbags) and mcap-ros2-support.
CLIENTS = ("evo", "mcap-ros2-support")


@pytest.fixture(scope="session")
def clients() -> Path:
    """The ``bin`` directory of a venv with :data:`CLIENTS`, installed once from the package
    index; the test is skipped, with the reason, when they cannot be installed."""
    home = TOOLS / "evo"
    python = home / "bin" / "python"
    check = [str(python), "-c", "import evo, rosbags, mcap_ros2"]
    if python.exists() and subprocess.run(check, capture_output=True).returncode == 0:
        return home / "bin"
    try:
        if not python.exists():
            venv.create(home, with_pip=True)
        subprocess.run([str(home / "bin" / "pip"), "install", "-q", *CLIENTS], check=True,
                       capture_output=True, timeout=900)  # fmt: skip
    except (subprocess.SubprocessError, OSError) as e:
        shutil.rmtree(home, ignore_errors=True)
        pytest.skip(f"{', '.join(CLIENTS)} could not be installed from the package index: {e}")
    return home / "bin"


#: The heavy tests, each a pytest marker: README's `pytest` leaves them out (pyproject.toml's
#: addopts), `.ci/run` runs them as a second step, and `pytest -m ""` runs everything.
#: A test that uses one of these fixtures carries the marker without saying so.
HEAVY_FIXTURES = {"clients": "clients", "chromium": "browser"}
#: Files named ``test_fuzz_*.py`` carry the ``fuzz`` marker (10 000 generated inputs, minutes),
#: except these quick ones (a few hundred cases, seconds), which the default suite runs.
QUICK_FUZZ_FILES = {"test_fuzz_trajectories.py"}


def pytest_collection_modifyitems(config, items):
    for item in items:
        for fixture, marker in HEAVY_FIXTURES.items():
            if fixture in getattr(item, "fixturenames", ()):
                item.add_marker(marker)
        name = item.path.name
        if name.startswith("test_fuzz_") and name not in QUICK_FUZZ_FILES:
            item.add_marker("fuzz")


@pytest.fixture
def poses(tmp_path, rng):
    """A poses file of two seeded random poses: its path and the matrices a2b reads from it (the
    tests of the command line, tests/test_cli_*.py)."""
    from .clirun import write_poses

    start, end = random_pose(rng), random_pose(rng)
    path = tmp_path / "poses.json"
    a, b = write_poses(path, start, end)
    return path, a, b
