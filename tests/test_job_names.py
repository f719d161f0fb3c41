"""Default job names: unnamed batch jobs are ``job0``, ``job1``, …, text that dataframes keep as
text beside named jobs (issue 28)."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from a2b.cli import cli

from .conftest import random_pose


def _job(rng, **extra) -> dict:
    def pose():
        matrix = random_pose(rng)
        return {"matrix": matrix.tolist()}

    return {"start": pose(), "end": pose(), "samples": 3, **extra}


@pytest.fixture
def batch_csv(tmp_path, rng):
    """A batch CSV of two unnamed jobs and a named one."""
    jobs = [_job(rng), _job(rng, name="lift"), _job(rng)]
    path = tmp_path / "jobs.json"
    path.write_text(json.dumps(jobs))
    out = tmp_path / "out.csv"
    result = CliRunner().invoke(cli, ["batch", str(path), "-o", str(out)])
    assert result.exit_code == 0, result.output
    return out


def test_unnamed_jobs_are_job_and_their_index(batch_csv):
    names = [line.split(",", 1)[0] for line in batch_csv.read_text().splitlines()[1:]]
    assert names == ["job0"] * 3 + ["lift"] * 3 + ["job2"] * 3


def test_polars_reads_the_job_column_as_text(batch_csv):
    polars = pytest.importorskip("polars")
    frame = polars.read_csv(batch_csv)
    assert frame.schema["job"] == polars.String
    assert frame["job"].to_list() == ["job0"] * 3 + ["lift"] * 3 + ["job2"] * 3
    assert frame.height == 9


def test_pandas_reads_the_job_column_as_text(batch_csv):
    pandas = pytest.importorskip("pandas")
    frame = pandas.read_csv(batch_csv)
    assert frame["job"].tolist() == ["job0"] * 3 + ["lift"] * 3 + ["job2"] * 3
    assert frame["tx"].dtype == float
