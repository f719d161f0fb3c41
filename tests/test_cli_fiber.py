"""``a2b fiber``: the κ and μ maps, JSON and human output, usage errors, the basis it states.

Through click's CliRunner."""

from __future__ import annotations

import json

import pytest

from a2b.io import poseschema

from .clirun import run
from .conftest import random_pose


@pytest.fixture
def pose_file(tmp_path, rng):
    path = tmp_path / "pose.json"
    pose = random_pose(rng)
    path.write_text(json.dumps({"matrix": pose.tolist()}))
    with open(path, "rb") as f:
        return path, poseschema.read_pose(f)


def test_fiber_kappa_json(pose_file):
    path, _ = pose_file
    result = run("fiber", path, "--offsets", "0,0.5,-2", "--json")
    assert result.exit_code == 0
    got = json.loads(result.output)
    assert got["map"] == "kappa"
    assert len(got["points"]) == 3 and all(len(p) == 8 for p in got["points"])
    assert max(got["residuals"]) < 1e-12
    assert got["s"] == [0.0, 0.5, -2.0]


def test_fiber_mu_json(pose_file):
    path, _ = pose_file
    result = run(
        "fiber",
        path,
        "--map",
        "mu",
        "--m",
        "1,0.3,-0.2,0.5",
        "--alpha",
        "0,0,0,0,0,0",
        "--alpha",
        "1,2,0,0,0,0.5",
        "--json",
    )
    assert result.exit_code == 0, result.output
    got = json.loads(result.output)
    assert got["basis_name"] == "paper" and not got["paper_basis_degenerate"]
    assert len(got["basis"]) == 6 and all(len(f) == 10 for f in got["basis"])
    assert len(got["points"]) == 2 and all(len(p) == 13 for p in got["points"])
    assert max(got["residuals"]) < 1e-9


def test_fiber_mu_says_when_the_paper_basis_degenerates(pose_file):
    path, _ = pose_file
    result = run("fiber", path, "--map", "mu", "--m", "1,0,0,0.5")
    assert result.exit_code == 0
    assert "degenerates" in result.output and "RREF" in result.output
    got = json.loads(run("fiber", path, "--map", "mu", "--m", "1,0,0,0.5", "--json").output)
    assert got["paper_basis_degenerate"] and got["basis_name"] == "rref"
    result = run("fiber", path, "--map", "mu", "--m", "1,0,0,0.5", "--basis", "paper")
    assert result.exit_code == 1 and "degenerates" in result.output


def test_fiber_human_table(pose_file):
    path, _ = pose_file
    result = run("fiber", path)
    assert result.exit_code == 0
    assert "maps back" in result.output and "εp" in result.output


def test_fiber_usage_errors(pose_file):
    path, _ = pose_file
    assert run("fiber", path, "--map", "mu").exit_code == 2
    assert run("fiber", path, "--alpha", "0,0,0,0,0,0").exit_code == 2
    assert run("fiber", path, "--map", "mu", "--m", "1,0,0,0", "--offsets", "1").exit_code == 2


def test_fiber_states_the_kernel_basis_it_chose(pose_file):
    path, _ = pose_file
    out = run("fiber", path, "--map", "mu", "--m", "1,0,0,0.5").output
    assert "Choices a2b made:" in out and "used the RREF basis" in out
    assert "Choices a2b made: none" in run("fiber", path).output
