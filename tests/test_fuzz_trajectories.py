"""Malformed trajectory files thrown at :func:`a2b.io.trajectories.read_trajectory`.

Valid files of every text format, with their lines, fields and bytes mutated: each is either
read (poses that pass every check) or refused with one :class:`InputFileError` of one bounded
line that names the file; nothing else escapes. ``A2B_FUZZ_EXAMPLES`` scales the count, as
for ``tests/test_fuzz.py``.
"""

from __future__ import annotations

import io
import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from a2b.errors import InputFileError
from a2b.formats import BY_NAME, INPUT_NAMES
from a2b.io.trajectories import read_trajectory

EXAMPLES = max(200, int(os.environ.get("A2B_FUZZ_EXAMPLES", "10000")) // 20)

VALID = {
    "tum": "# time tx ty tz qx qy qz qw\n0 0 0 0 0 0 0 1\n0.5 1 2 3 0 0 0.6 0.8\n",
    "kitti": "1 0 0 0 0 1 0 0 0 0 1 0\n0 -1 0 1 1 0 0 2 0 0 1 3\n",
    "euroc": "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],"
    "q_RS_y [],q_RS_z []\n1000000000,0,0,0,1,0,0,0\n1500000000,1,2,3,0.8,0,0,0.6\n",
    "csv": "t,tx,ty,tz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,original\n"
    "0,0,0,0,1,0,0,0,0,0,0,0,0,0,1\n1,1,2,3,0.8,0,0,0.6,1,1,1,0,0,1,0\n",
    "matrix": "t,r11,r12,r13,tx,r21,r22,r23,ty,r31,r32,r33,tz\n0,1,0,0,0,0,1,0,0,0,0,1,0\n"
    "1,0,-1,0,1,1,0,0,2,0,0,1,3\n",
    "study": "t,p0,p1,p2,p3,q0,q1,q2,q3\n0,1,0,0,0,0,0,0,0\n1,0,0,0,1,0,0,0,0\n",
}
TOKENS = [
    "", " ", ",", "\t", "#", "\r", "\r\n", "\n", "\ufeff", "\0", "nan", "inf", "-0", "1e999",
    "1e-320", "0x10", "1_0", "1.5.5", "é", "\x1b[31m", "\u202e", "qw", "tx", "#timestamp",
    "[ns]", "t", "job", "9" * 30, "1" * 400, "-1",
]  # fmt: skip


@st.composite
def mutated(draw):
    fmt = draw(st.sampled_from(sorted(VALID)))
    text = VALID[fmt]
    for _ in range(draw(st.integers(1, 4))):
        how = draw(st.sampled_from(["insert", "replace", "cut", "repeat", "swap"]))
        at = draw(st.integers(0, len(text)))
        if how == "insert":
            text = text[:at] + draw(st.sampled_from(TOKENS)) + text[at:]
        elif how == "replace":
            end = draw(st.integers(at, min(len(text), at + 8)))
            text = text[:at] + draw(st.sampled_from(TOKENS)) + text[end:]
        elif how == "cut":
            text = text[:at]
        elif how == "repeat":
            lines = text.splitlines(True)
            if lines:
                i = draw(st.integers(0, len(lines) - 1))
                text = "".join(lines[: i + 1] + [lines[i]] * draw(st.integers(1, 3)) + lines[i:])
        else:
            fields = text.split(",")
            if len(fields) > 2:
                i = draw(st.integers(0, len(fields) - 2))
                fields[i], fields[i + 1] = fields[i + 1], fields[i]
                text = ",".join(fields)
    data = text.encode("utf-8", "surrogatepass")
    if draw(st.booleans()):
        at = draw(st.integers(0, len(data)))
        data = data[:at] + bytes([draw(st.integers(0, 255))]) + data[at:]
    given_fmt = draw(st.sampled_from([None, fmt, *TEXT_FORMATS]))
    return fmt, data, given_fmt


#: The trajectory formats that are text (MCAP is fuzzed in tests/test_hardening_mcap.py).
TEXT_FORMATS = [name for name in INPUT_NAMES if not BY_NAME[name].binary]


@settings(
    max_examples=EXAMPLES, derandomize=True, database=None, deadline=None,
    suppress_health_check=list(HealthCheck),
)  # fmt: skip
@given(mutated())
def test_a_mutated_trajectory_is_read_or_one_bounded_error(case):
    fmt, data, given_fmt = case
    name = f"fuzz.{fmt}.txt"
    try:
        path = read_trajectory(io.BytesIO(data), name, given_fmt, rate=None, minimum=0)
    except InputFileError as e:
        message = str(e)
        assert message.startswith(name) and "\n" not in message and len(message) < 600, message
        return
    assert np.isfinite(path.times).all() and (np.diff(path.times) > 0).all()
    assert np.isfinite(path.matrices).all()


def test_every_valid_sample_reads():
    for fmt, text in VALID.items():
        path = read_trajectory(io.BytesIO(text.encode()), f"a.{fmt}.txt", fmt)
        assert len(path) == 2, fmt
