"""Fuzzing the input path at the readers (the commands: tests/test_fuzz_commands.py).

Every generated input is malformed *by construction* (a mutation that no valid file survives:
a wrong type, a wrong length, a missing or unknown or repeated key, a number that is no
finite double, a truncated or garbled text, bytes that are not UTF-8, deep nesting, ...), so
every case must end in one clear message:

* readers (:func:`read_pose`, :func:`read_poses`, :func:`read_jobs`, :func:`read_pose_list`)
  raise :class:`InputFileError` with one line that starts with the file name;
* ``a2b interpolate``, ``a2b fiber`` and ``a2b batch`` (in-process, click's ``CliRunner``)
  exit with status 1 and one line ``Error: ...`` on stderr (status 2 for malformed options),
  with no traceback and no output file, not even a temporary one.

The examples are derandomised (a fixed seed per test), so CI runs the same cases every time;
``A2B_FUZZ_EXAMPLES=200000 pytest -m fuzz`` runs a larger share of each class
(default 10 000 in all), and ``A2B_FUZZ_SEED=n`` explores other cases. Each test counts the
examples it actually ran and asserts its quota; ``test_total_cases`` asserts the sum.
"""

from __future__ import annotations

import io
import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from a2b.errors import A2bError, InputFileError
from a2b.io import jobfiles, poseschema

from .fuzzing import COUNTS, SHARES, TOTAL, run_fuzz, written

# -- the checks ---------------------------------------------------------------------------


def read_fully(kind: str, data: bytes, name: str):
    stream = io.BytesIO(data)
    if kind == "pose":
        return poseschema.read_pose(stream, name)
    if kind == "poses":
        return poseschema.read_poses(stream, name)
    if kind == "jobs":
        return list(jobfiles.read_jobs(stream, name))
    key = b"controls" if b"controls" in data else b"poses"
    return poseschema.read_pose_list(stream, key.decode(), name)


def expect_reader_error(kind: str, case) -> None:
    name, data, how = case
    with pytest.raises(InputFileError) as info:
        read_fully(kind, data, name)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{name}"), (how, message)


@pytest.mark.parametrize("kind", ["pose", "poses", "jobs", "pose_list"])
def test_fuzz_reader(kind):
    """read_pose, read_poses, read_jobs, read_pose_list: InputFileError, one line, the name."""
    run_fuzz(kind, written(kind), lambda case: expect_reader_error(kind, case))


# -- homogeneous inputs at every scale ---------------------------------------------------------


@pytest.mark.filterwarnings("ignore::a2b.errors.A2bWarning")  # near-zero rotations: expected
@settings(max_examples=300, derandomize=True, database=None, deadline=None)
@given(
    exponent=st.integers(-300, 300),
    kind=st.sampled_from(["quaternion", "study", "m", "weights"]),
    quaternion=st.lists(st.floats(-1, 1), min_size=4, max_size=4).filter(
        lambda q: 0.1 < math.hypot(*q)
    ),
    translation=st.lists(st.floats(-10, 10), min_size=3, max_size=3),
)
def test_homogeneous_inputs_at_every_scale(exponent, kind, quaternion, translation):
    """Quaternions, Study parameters, m and weights times 10^±300 mean what they meant."""
    import numpy as np

    import a2b
    from a2b.io.poseschema import read_poses
    from a2b.motions.bezier import bezier
    from a2b.poses import matrices_from_quat_trans, study_from_matrices

    scale = 10.0**exponent
    end = matrices_from_quat_trans(np.array(quaternion), np.array(translation))
    start = np.eye(4)
    if kind in ("quaternion", "study"):
        form = (
            {"quaternion_wxyz": [q * scale for q in quaternion], "translation": translation}
            if kind == "quaternion"
            else {"study": (study_from_matrices(end) * scale).tolist()}
        )
        text = json.dumps({"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end": form})
        got = read_poses(io.BytesIO(text.encode()), "p.json").end
        np.testing.assert_allclose(got, end, rtol=0, atol=1e-12 * (1 + np.abs(end).max()))
        return
    ts = np.linspace(0.0, 1.0, 5)
    if kind == "m":
        m = np.array([1.0, 0.2, -0.3, 0.5])
        try:
            plain = a2b.motion(start, end, "cubic", m=m).matrices(ts)
        except A2bError:
            return  # no motion for this m and these poses, at any scale
        scaled = a2b.motion(start, end, "cubic", m=m * scale).matrices(ts)
    else:
        weights = np.array([1.0, 3.0])
        try:
            plain = bezier([start, end], ts, weights=weights)
        except A2bError:
            return
        scaled = bezier([start, end], ts, weights=weights * scale)
    np.testing.assert_allclose(scaled, plain, rtol=0, atol=1e-9 * (1 + np.abs(plain).max()))


# -- the sum, over this file and tests/test_fuzz_commands.py (which pytest runs first) ---------


def test_total_cases():
    """At least A2B_FUZZ_EXAMPLES (10 000) malformed inputs ran, when the whole file ran."""
    if set(SHARES) - set(COUNTS):
        pytest.skip("not every fuzz test ran")
    total = sum(COUNTS.values())
    print(f"\nfuzz cases run: {total} ({', '.join(f'{k} {v}' for k, v in COUNTS.items())})")
    assert total >= TOTAL
