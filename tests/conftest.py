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


def tool_venv(name: str, packages: tuple, check: str) -> Path:
    """The ``bin`` directory of the venv ``TOOLS/name`` with ``packages``, installed once from
    the package index (``check`` is Python that imports them); the calling test is skipped,
    with the reason, when they cannot be installed."""
    home = TOOLS / name
    python = home / "bin" / "python"
    probe = [str(python), "-c", check]
    if python.exists() and subprocess.run(probe, capture_output=True).returncode == 0:
        return home / "bin"
    try:
        if not python.exists():
            venv.create(home, with_pip=True)
        subprocess.run([str(home / "bin" / "pip"), "install", "-q", *packages], check=True,
                       capture_output=True, timeout=900)  # fmt: skip
    except (subprocess.SubprocessError, OSError) as e:
        shutil.rmtree(home, ignore_errors=True)
        pytest.skip(f"{', '.join(packages)} could not be installed from the package index: {e}")
    return home / "bin"


@pytest.fixture(scope="session")
def clients() -> Path:
    """The ``bin`` directory of a venv with :data:`CLIENTS` (:func:`tool_venv`)."""
    return tool_venv("evo", CLIENTS, "import evo, rosbags, mcap_ros2")


def evo_full_check(clients: Path, bag: Path, tmp_path: Path) -> str:
    """``evo_traj bag2 BAG /a2b/pose --full_check``: asserts that evo read the file and that
    every check it makes passed, and returns what it printed (for the counts)."""
    env = dict(os.environ, MPLBACKEND="Agg", HOME=str(tmp_path))
    done = subprocess.run(
        [str(clients / "evo_traj"), "bag2", str(bag), "/a2b/pose", "--full_check",
         "--no_warnings"],
        capture_output=True, text=True, env=env, timeout=300, cwd=tmp_path,
    )  # fmt: skip
    out = done.stdout + done.stderr
    assert done.returncode == 0, out
    for check in ("SE(3) conform", "array shapes", "nr. of stamps", "quaternions", "timestamps"):
        line = next(line for line in out.splitlines() if line.strip().startswith(check))
        assert line.split()[-1] in ("yes", "ok"), line
    return out


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
