"""Pose files in: every malformed-input class is one line naming the file, key, line and column.

Each case runs the real command with ``-o``, and checks the exit status, the message and that
no output file (nor a temporary one) is left behind.
"""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from a2b.cli import cli
from a2b.errors import InputFileError
from a2b.io import jobfiles, poseschema

IDENTITY = "{quaternion_wxyz: [1, 0, 0, 0]}"
QUARTER = (
    "{quaternion_wxyz: [0.7071067811865476, 0, 0, 0.7071067811865476], translation: [1, 0, 0.5]}"
)

# (file name, content, expected fragments of the message: file:line:col, key, problem)
MALFORMED = [
    (
        "dup.yaml",
        f"start: {IDENTITY}\nend: {QUARTER}\nstart: {IDENTITY}\n",
        ["dup.yaml:3:1", "duplicate key 'start'"],
    ),
    (
        "dup.json",
        '{"start": {"quaternion_wxyz": [1, 0, 0, 0]},\n  '
        '"end": {"quaternion_wxyz": [1, 0, 0, 0],\n   "quaternion_wxyz": [1, 0, 0, 0]}}',
        ["dup.json:3:4", "duplicate key 'quaternion_wxyz'"],
    ),
    (
        "unknown.yaml",
        f"start: {IDENTITY}\nend: {QUARTER}\nparamters: {{delta: 1}}\n",
        ["unknown.yaml:3:1", "paramters", "did you mean 'parameters'"],
    ),
    (
        "unknown-pose.yaml",
        f"start: {{quaternion_wxyz: [1, 0, 0, 0], translaton: [0, 0, 0]}}\nend: {QUARTER}\n",
        ["unknown-pose.yaml:1:40", "start.translaton", "unknown key"],
    ),
    (
        "length.yaml",
        f"start: {IDENTITY}\nend:\n  quaternion_wxyz: [1, 0, 0]\n",
        ["length.yaml:3:3", "end.quaternion", "expected 4 numbers (w, x, y, z), got 3"],
    ),
    (
        "matrix.json",
        '{"start": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]}, "end": {"study": '
        "[1,0,0,0,0,0,0,0]}}",
        ["matrix.json:1:12", "start.matrix", "expected 4 rows of 4 numbers, got 3 rows"],
    ),
    (
        "study.yaml",
        f"start: {IDENTITY}\nend: {{study: [1, 0, 0, 0, 0, 0, 0]}}\n",
        ["study.yaml:2:7", "end.study", "expected 8 numbers"],
    ),
    (
        "string.yaml",
        f"start: {IDENTITY}\nend: {{quaternion_wxyz: [1, 0, zero, 0]}}\n",
        ["string.yaml:2:31", "end.quaternion_wxyz[2]", "expected a number, got the string 'zero'"],
    ),
    (
        "bool.json",
        '{"start": {"quaternion_wxyz": [1, 0, 0, 0]},\n '
        '"end": {"quaternion": {"w": 1, "x": 0, "y": true, "z": 0}}}',
        ["bool.json:2:", "end.quaternion.y", "got the boolean true"],
    ),
    (
        "nan.json",
        '{"start": {"quaternion_wxyz": [1, 0, 0, 0]},\n "end": {"quaternion_wxyz": [1, 0, 0, 0], '
        '"translation": [0, NaN, 0]}}',
        ["nan.json:2:", "end.translation[1]", "NaN is not allowed"],
    ),
    (
        "inf.yaml",
        f"start: {IDENTITY}\nend: {{quaternion_wxyz: [1, 0, 0, 0], translation: [.inf, 0, 0]}}\n",
        ["inf.yaml:2:", "end.translation[0]", "must be finite"],
    ),
    (
        "nan-param.yaml",
        f"start: {IDENTITY}\nend: {QUARTER}\nparameters:\n  delta: .nan\n",
        ["nan-param.yaml:4:3", "parameters.delta", "must be finite"],
    ),
    ("nostart.yaml", f"end: {QUARTER}\n", ["nostart.yaml:1:1", "missing 'start'"]),
    (
        "noend.json",
        '{"start": {"quaternion_wxyz": [1, 0, 0, 0]}}',
        ["noend.json:1:1", "missing 'end'"],
    ),
    (
        "twoforms.yaml",
        f"start: {{quaternion_wxyz: [1, 0, 0, 0], study: [1, 0, 0, 0, 0, 0, 0, 0]}}\nend: "
        f"{QUARTER}\n",
        ["twoforms.yaml:1:1", "start", "exactly one of"],
    ),
    (
        "mode.yaml",
        f"start: {IDENTITY}\nend: {QUARTER}\nmode: darbouks\n",
        ["mode.yaml:3:1", "mode", "expected one of darboux"],
    ),
    (
        "samples.yaml",
        f"start: {IDENTITY}\nend: {QUARTER}\nsamples: 2.5\n",
        ["samples.yaml:3:1", "samples", "expected a whole number of samples, at least 2, got 2.5"],
    ),
    (
        "branch.yaml",
        f"start: {IDENTITY}\nend: {QUARTER}\nparameters: {{lam: 2, branch: 0}}\n",
        ["branch.yaml:3:22", "parameters.branch", "+1 or -1"],
    ),
    (
        "vector.yaml",
        f"start: {IDENTITY}\nend: {QUARTER}\nparameters: {{m: [1, 0, 0]}}\n",
        ["vector.yaml:3:14", "parameters.m", "expected 4 numbers"],
    ),
    (
        "rotation.yaml",
        f"start: {{matrix: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]]}}\nend: "
        f"{QUARTER}\n",
        ["rotation.yaml:1:9", "start.matrix", "not orthogonal"],
    ),
    (
        "offquadric.yaml",
        f"start: {IDENTITY}\nend: {{study: [1, 0, 0, 0, 1, 0, 0, 0]}}\n",
        ["offquadric.yaml:2:7", "end.study", "Study condition", "kappa: true"],
    ),
    ("syntax.yaml", "start: [1, 0\nend: {}\n", ["syntax.yaml:", "invalid YAML"]),
    (
        "syntax.json",
        '{"start": {"quaternion_wxyz": [1, 0, 0, 0]},, "end": 1}',
        ["syntax.json:1:45", "invalid JSON"],
    ),
    ("empty.yaml", "", ["empty.yaml: the file is empty"]),
    (
        "list.yaml",
        "- 1\n- 2\n",
        ["list.yaml:1:1", "expected a mapping with start and end, got a list of 2"],
    ),
]

SAMPLES = Path(__file__).resolve().parent.parent / "samples"


@pytest.mark.parametrize("name, content, fragments", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_input(tmp_path, name, content, fragments):
    path = tmp_path / name
    path.write_text(content)
    out = tmp_path / "out.csv"
    result = CliRunner().invoke(cli, ["interpolate", str(path), "-o", str(out)])
    assert result.exit_code == 1, result.output
    message = result.output
    assert message.startswith("Error: ") and message.count("\n") == 1, message
    assert "Traceback" not in message
    for fragment in fragments:
        assert fragment in message, (fragment, message)
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


def test_missing_file_is_a_usage_error(tmp_path):
    result = CliRunner().invoke(cli, ["interpolate", str(tmp_path / "nope.yaml")])
    assert result.exit_code == 2
    assert "nope.yaml" in result.output


def test_every_pose_form_reads_the_same_pose():
    q = [0.5, 0.5, -0.5, 0.5]
    t = [1.0, -2.0, 0.25]
    forms = [
        {"quaternion_wxyz": q, "translation": t},
        {"quaternion": dict(zip("wxyz", q)), "translation": dict(zip("xyz", t))},
        {"quaternion_xyzw": q[1:] + q[:1], "translation": t},
    ]
    mats = []
    for form in forms:
        mats.append(poseschema.read_pose(io.BytesIO(json.dumps(form).encode()), "p.json"))
    from a2b.poses import paper_from_robotics, study_from_matrices

    m = mats[0]
    mats.append(
        poseschema.read_pose(io.BytesIO(json.dumps({"matrix": m.tolist()}).encode()), "p.json")
    )
    paper = {"matrix": paper_from_robotics(m).tolist(), "layout": "paper"}
    mats.append(poseschema.read_pose(io.BytesIO(json.dumps(paper).encode()), "p.json"))
    h = study_from_matrices(m)
    mats.append(
        poseschema.read_pose(io.BytesIO(json.dumps({"study": (3 * h).tolist()}).encode()), "p.json")
    )
    off = h.copy()
    off[4:] += 0.7 * h[:4]  # another point of the κ-fiber: off the Study quadric
    mats.append(
        poseschema.read_pose(
            io.BytesIO(json.dumps({"study": off.tolist(), "kappa": True}).encode()), "p.json"
        )
    )
    for other in mats[1:]:
        assert np.allclose(other, m, atol=1e-14)


def test_yaml_reads_exponents_and_json_reads_tabs():
    text = "quaternion_wxyz: [1e0, 0, 0, 0]\ntranslation: [1e-3, 2E+2, -.5e1]\n"
    m = poseschema.read_pose(io.BytesIO(text.encode()), "p.yaml")
    assert m[:3, 3].tolist() == [0.001, 200.0, -5.0]
    text = '{\n\t"quaternion_wxyz": [1, 0, 0, 0],\n\t"translation": [1, 2, 3]\n}'
    m = poseschema.read_pose(io.BytesIO(text.encode()), "p.json")
    assert m[:3, 3].tolist() == [1.0, 2.0, 3.0]


def test_content_detection_without_suffix():
    yaml_text = b"quaternion_wxyz: [1, 0, 0, 0]\n"
    json_text = b'{"quaternion_wxyz": [1, 0, 0, 0], "translation": [0, 0, 1]}'
    flow_yaml = b"{quaternion_wxyz: [1, 0, 0, 0], translation: [0, 0, 2]}"
    assert poseschema.read_pose(io.BytesIO(yaml_text), "<stdin>")[2, 3] == 0.0
    assert poseschema.read_pose(io.BytesIO(json_text), "<stdin>")[2, 3] == 1.0
    assert poseschema.read_pose(io.BytesIO(flow_yaml), "<stdin>")[2, 3] == 2.0


def test_jobs_errors_name_the_job_and_line(tmp_path):
    good = {"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end": {"quaternion_wxyz": [1, 0, 0, 0]}}
    bad = {"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end": {"quaternion_wxyz": [1, 0, 0]}}
    text = "\n".join(json.dumps(j) for j in (good, good, bad)) + "\n"
    jobs = jobfiles.read_jobs(io.BytesIO(text.encode()), "jobs.jsonl")
    assert jobs.count is None
    it = iter(jobs)
    next(it), next(it)
    with pytest.raises(
        InputFileError, match=r"^jobs\.jsonl:3:54: job 2: end\.quaternion_wxyz: expected 4 numbers"
    ):
        next(it)
    yaml_text = (
        "- start: {quaternion_wxyz: [1, 0, 0, 0]}\n  end: {quaternion_wxyz: [1, 0, 0, 0]}\n- "
        "start: {}\n"
    )
    jobs = jobfiles.read_jobs(io.BytesIO(yaml_text.encode()), "jobs.yaml")
    assert jobs.count == 2
    with pytest.raises(InputFileError, match=r"^jobs\.yaml:3:3: job 1: missing 'end'"):
        list(jobs)
    with pytest.raises(
        InputFileError, match=r"^jobs\.json:1:1: expected a list of jobs, got a mapping"
    ):
        jobfiles.read_jobs(io.BytesIO(b'{"start": 1}'), "jobs.json")


def test_a_poses_file_where_one_pose_belongs_and_back(tmp_path):
    runner = CliRunner()
    result = runner.invoke(cli, ["fiber", str(SAMPLES / "quarter-turn.yaml")])
    assert result.exit_code == 1 and "expected one pose, got start and end poses" in result.output
    result = runner.invoke(cli, ["interpolate", str(SAMPLES / "pose.yaml")])
    assert (
        result.exit_code == 1
        and "this is one pose, but start and end poses are needed" in result.output
    )
    result = runner.invoke(cli, ["batch", str(SAMPLES / "quarter-turn.yaml")])
    assert result.exit_code == 1 and "expected a list of jobs, got a mapping" in result.output


# -- numbers, text and nesting that a hand or another program may produce --------------------

EXACT_ERRORS = [
    ("big.json", b'{"quaternion_wxyz": [1' + b"0" * 400 + b", 0, 0, 0]}",
     "big.json:1:22: quaternion_wxyz[0]: 100000000000…000000 (401 digits) is too large for a "
     "double; "
     "numbers must be finite (|x| < 1.8e308)"),
    ("digits.yaml", b"quaternion_wxyz: [1" + b"0" * 5000 + b", 0, 0, 0]\n",
     "digits.yaml:1:19: quaternion_wxyz[0]: 100000000000…000000 (5001 digits) is too large for a "
     "double; numbers must be finite (|x| < 1.8e308)"),
    ("exp.json", b'{"quaternion_wxyz": [1e999, 0, 0, 0]}',
     "exp.json:1:22: quaternion_wxyz[0]: 1e999 is too large for a double; numbers must be finite "
     "(|x| < 1.8e308)"),
    ("exp.yaml", b"quaternion_wxyz: [1, 0, 0, -1.5e+400]\n",
     "exp.yaml:1:28: quaternion_wxyz[3]: -1.5e+400 is too large for a double; numbers must be "
     "finite "
     "(|x| < 1.8e308)"),
    ("inf.yaml", b"quaternion_wxyz: [1, 0, 0, 0]\ntranslation: [-.Inf, 0, 0]\n",
     "inf.yaml:2:15: translation[0]: -.Inf is not allowed; numbers must be finite"),
    ("sexagesimal.yaml", b"quaternion_wxyz: [1:20, 0, 0, 0]\n",
     "sexagesimal.yaml:1:19: quaternion_wxyz[0]: expected a number, got the string '1:20'"),
    ("underscore.yaml", b"quaternion_wxyz: [1_000, 0, 0, 0]\n",
     "underscore.yaml:1:19: quaternion_wxyz[0]: expected a number, got the string '1_000'"),
    ("yes.yaml", b"study: [1, 0, 0, 0, 0, 0, 0, 0]\nkappa: yes\n",
     "yes.yaml:2:1: kappa: expected true or false, got the string 'yes'"),
    ("latin1.yaml", b"quaternion_wxyz: [1, 0, 0, 0]\n# caf\xe9\n",
     "latin1.yaml:2:6: not UTF-8 text (byte 0xe9)"),
    ("control.yaml", b"quaternion_wxyz: [1, 0,\x07 0, 0]\n",
     "control.yaml:1:24: invalid YAML: control characters are not allowed (#x0007)"),
    ("deep.yaml", b"[" * 50_000 + b"]" * 50_000,
     "deep.yaml:1:101: nested too deeply (a2b reads at most 100 levels)"),
    ("deep.json", b"[" * 50_000 + b"]" * 50_000,
     "deep.json: invalid JSON: nested too deeply to read"),
    ("key.json", b'{"quaternion_wxyz": [1, 0, 0, 0], "a\\nb": 1}',
     "key.json:1:35: 'a\\nb': unknown key 'a\\nb' in a pose (expected matrix, quaternion, "
     "quaternion_wxyz, quaternion_xyzw, rpy_xyz, axis_angle, study, layout, translation, "
     "kappa)"),
]  # fmt: skip


@pytest.mark.parametrize("name, data, message", EXACT_ERRORS, ids=[e[0] for e in EXACT_ERRORS])
def test_exact_messages_for_what_is_no_number_or_no_text(name, data, message):
    with pytest.raises(InputFileError) as info:
        poseschema.read_pose(io.BytesIO(data), name)
    assert str(info.value) == message


def test_yaml_1_2_numbers_are_numbers():
    text = b"quaternion_wxyz: [0x1, 0o0, -0, +0.0]\ntranslation: [1e3, .5, -2.]\n"
    m = poseschema.read_pose(io.BytesIO(text), "p.yaml")
    assert m[:3, 3].tolist() == [1000.0, 0.5, -2.0]


def test_samples_must_be_at_least_two_and_at_most_2_to_the_53(tmp_path):
    base = f"start: {IDENTITY}\nend: {QUARTER}\n"
    with pytest.raises(
        InputFileError,
        match=r"p.yaml:3:1: samples: expected at least 2 samples \(t = 0 and t = 1\), got 1",
    ):
        poseschema.read_poses(io.BytesIO((base + "samples: 1\n").encode()), "p.yaml")
    with pytest.raises(
        InputFileError, match=r"samples: expected at most 2\*\*53 = 9007199254740992 samples"
    ):
        poseschema.read_poses(io.BytesIO((base + f"samples: {2**53 + 1}\n").encode()), "p.yaml")
    assert (
        poseschema.read_poses(io.BytesIO((base + f"samples: {2**53}\n").encode()), "p.yaml").samples
        == 2**53
    )


def test_an_empty_jobs_file_is_an_error():
    with pytest.raises(InputFileError, match=r"^jobs.jsonl: no jobs"):
        list(jobfiles.read_jobs(io.BytesIO(b"\n\n"), "jobs.jsonl"))
    with pytest.raises(
        InputFileError, match=r"^jobs.json:1:1: expected a list of jobs, got an empty list"
    ):
        jobfiles.read_jobs(io.BytesIO(b"[]"), "jobs.json")
    with pytest.raises(InputFileError, match=r"^jobs.jsonl:2:1: not UTF-8 text \(byte 0xff\)"):
        list(
            jobfiles.read_jobs(
                io.BytesIO(
                    b'{"start": {"quaternion_wxyz": [1, 0, 0, 0]}, '
                    b'"end": {"quaternion_wxyz": [1, 0, 0, 0]}}\n\xff\n'
                ),
                "jobs.jsonl",
            )
        )


def test_read_pose_list_and_read_motion_file():
    text = (
        b"controls:\n  - quaternion_wxyz: [1, 0, 0, 0]\n"
        b"  - {quaternion_wxyz: [0, 0, 0, 1], translation: [1, 0, 0]}\n"
        b"space: study\nparameters: {weights: [1, 2]}\n"
    )
    curve = poseschema.read_pose_list(io.BytesIO(text), "controls", "c.yaml")
    assert curve.key == "controls" and curve.poses.shape == (2, 4, 4)
    assert (
        curve.space == "study"
        and curve.samples is None
        and curve.parameters == {"weights": (1.0, 2.0)}
    )
    assert isinstance(poseschema.read_motion_file(io.BytesIO(text), "c.yaml"), poseschema.PoseList)
    job = poseschema.read_motion_file(
        io.BytesIO(f"start: {IDENTITY}\nend: {QUARTER}\n".encode()), "p.yaml"
    )
    assert isinstance(job, poseschema.Job)
    with pytest.raises(
        InputFileError,
        match=r"^c.yaml:1:1: this is a list of controls \(a2b bezier\), "
        r"but start and end poses are needed",
    ):
        poseschema.read_poses(io.BytesIO(text), "c.yaml")
    with pytest.raises(
        InputFileError,
        match=r"^p.yaml:1:1: this is a poses file \(start and end\); "
        r"this command needs a list of poses under 'poses'",
    ):
        poseschema.read_pose_list(
            io.BytesIO(f"start: {IDENTITY}\nend: {QUARTER}\n".encode()), "poses", "p.yaml"
        )
    with pytest.raises(
        InputFileError, match=r"^c.yaml:1:1: controls: expected a list of at least two poses, got 1"
    ):
        poseschema.read_pose_list(
            io.BytesIO(b"controls:\n  - quaternion_wxyz: [1, 0, 0, 0]\n"), "controls", "c.yaml"
        )


@pytest.mark.parametrize(
    "name_json, problem",
    [
        (r'"\udcff"', r"'\\udcff' is no text UTF-8 can write: a lone surrogate, '\\udcff'"),
        (r'"a\u0000b"', r"'a\\x00b' contains a NUL character"),
    ],
)
@pytest.mark.parametrize("suffix", ["jsonl", "json"])
def test_a_job_name_a2b_cannot_write_is_an_input_error(name_json, problem, suffix):
    """A name goes into the job column: a NUL or a lone surrogate (which JSON can escape, and
    UTF-8 cannot write) is an error at the name, not a failure when the CSV is written."""
    good = '{"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end": {"quaternion_wxyz": [1, 0, 0, 0]}}'
    bad = (
        f'{{"name": {name_json}, "start": {{"quaternion_wxyz": [1, 0, 0, 0]}}, '
        '"end": {"quaternion_wxyz": [1, 0, 0, 0]}}'
    )
    text = f"{good}\n{bad}\n" if suffix == "jsonl" else f"[{good},\n{bad}]\n"
    where = "2:2"  # at the key
    with pytest.raises(InputFileError, match=rf"^jobs\.{suffix}:{where}: job 1: name: {problem}$"):
        for block in jobfiles.read_jobs(io.BytesIO(text.encode()), f"jobs.{suffix}").blocks(8):
            pass


def test_invalid_json_lines_are_placed_on_their_own_line():
    """A line cut short is reported at its end, not at the start of the next line; json's
    message for a control character loses its dangling "at"."""
    good = '{"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end": {"quaternion_wxyz": [1, 0, 0, 0]}}'
    for ending in ("\n", "\r\n"):
        text = ending.join([good, good[:-1], good]) + ending
        with pytest.raises(
            InputFileError,
            match=rf"^jobs\.jsonl:2:{len(good)}: invalid JSON: Expecting ',' delimiter$",
        ):
            list(jobfiles.read_jobs(io.BytesIO(text.encode()), "jobs.jsonl"))
    control = '{"name": "a\tb", ' + good[1:]
    with pytest.raises(
        InputFileError, match=r"^jobs\.jsonl:1:12: invalid JSON: Invalid control character$"
    ):
        list(jobfiles.read_jobs(io.BytesIO(control.encode()), "jobs.jsonl"))
