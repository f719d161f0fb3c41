"""The pose schema (``a2b.io.poseschema``): one table of pose forms, read the same by the
exact, positioned reader and by the fast block path of ``a2b.io.jobscan``."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

from a2b.errors import InputFileError
from a2b.io import jobfiles, jobscan, poseschema

QUARTER_WXYZ = [0.7071067811865476, 0.0, 0.0, 0.7071067811865476]


def written(form: str, wxyz=QUARTER_WXYZ, xyz=(1.0, 2.0, 3.0)) -> dict:
    """A pose in ``form``, written from the table's own description of it."""
    spec = poseschema.POSE_FORMS[form].numbers
    values = dict(zip("wxyz", wxyz))
    rotation = (
        {k: values[k] for k in spec.written}
        if spec.layouts == ("mapping",)
        else [values[k] for k in spec.written]
    )
    return {form: rotation, "translation": list(xyz)}


QUATERNION_FORMS = [k for k, f in poseschema.POSE_FORMS.items() if f.numbers is not None]


def test_the_quaternion_forms_are_those_of_the_table():
    assert QUATERNION_FORMS == ["quaternion", "quaternion_wxyz", "quaternion_xyzw"]
    assert poseschema.POSE_KEYS[-3:] == ("layout", "translation", "kappa")


@pytest.mark.parametrize("form", QUATERNION_FORMS)
def test_every_quaternion_form_reads_the_same_fast_and_exactly(form):
    pose = written(form)
    line = json.dumps({"start": pose, "end": written("quaternion_wxyz", [1, 0, 0, 0])})
    exact = jobfiles.json_line_job(line, "j.jsonl", 1, 0)
    scanned = jobscan.Scanned()
    assert scanned.add_fast(json.loads(line), line.count(":"), None)  # on the fast path
    (block,) = jobfiles.finish_block(scanned)
    np.testing.assert_array_equal(block.start[0], exact.start)
    np.testing.assert_allclose(exact.start[:3, 3], [1, 2, 3])
    np.testing.assert_allclose(exact.start[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)


def test_a_mapping_form_given_a_list_says_why():
    with pytest.raises(InputFileError, match=r"^p\.json:1:2: quaternion: a bare list is ambig"):
        poseschema.read_pose(io.BytesIO(b'{"quaternion": [1, 0, 0, 0]}'), "p.json")


def test_a_list_form_given_a_mapping_names_its_order():
    with pytest.raises(
        InputFileError, match=r"quaternion_xyzw: expected a list of 4 numbers \(x, y"
    ):
        poseschema.read_pose(io.BytesIO(b'{"quaternion_xyzw": {"x": 1}}'), "p.json")


def test_a_megabyte_key_is_named_in_a_bounded_line():
    key = "k" * 1_000_000
    with pytest.raises(InputFileError) as e:
        poseschema.read_poses(io.BytesIO(f'{{"{key}": 1}}'.encode()), "p.json")
    assert len(str(e.value)) < 400 and "(1000000 characters)" in str(e.value)
