"""The pose schema: what the mappings of pose files, jobs files and pose lists mean.

A pose is a mapping with exactly one of these forms (:data:`POSE_FORMS`)::

    {matrix: [[r11, r12, r13, t1], ..., [0, 0, 0, 1]], layout: robotics | paper}
    {quaternion: {w: .., x: .., y: .., z: ..}, translation: [x, y, z] | {x, y, z}}
    {quaternion_wxyz: [w, x, y, z], translation: ...}
    {quaternion_xyzw: [x, y, z, w], translation: ...}      # ROS order, read at this edge only
    {rpy_xyz: [roll, pitch, yaw], translation: ...}        # R = Rz(yaw) Ry(pitch) Rx(roll)
    {axis_angle: {axis: [x, y, z], angle: a}, translation: ...}
    {study: [p0, p1, p2, p3, q0, q1, q2, q3], kappa: false | true}

Angles are radians, or degrees with a ``deg`` suffix (``90deg``). ``translation`` defaults to
zero. ``kappa: true`` reads a Study vector off the Study quadric through the extended map κ.
A bare list under ``quaternion`` is an error: its order is the one thing a reader of the file
cannot tell, and reading ROS's x, y, z, w as w, x, y, z turns the identity into a half turn.

A *poses file* (``a2b interpolate``) is a mapping with ``start``, ``end`` and optionally
``mode``, ``samples`` and ``parameters`` (:data:`POSES_KEYS`); a job of a *jobs file*
(:mod:`a2b.io.jobfiles`) may also have a ``name`` (:data:`JOB_KEYS`); a *pose list*
(``a2b bezier``, ``a2b spline``) is a mapping with a list of poses under ``controls`` or
``poses`` and optionally ``space``, ``samples`` and ``parameters``.

This table is the one schema: the exact reading here, which words every error as
``poses.yaml:4:3: start.quaternion: expected 4 numbers (w, x, y, z), got 3``, and the fast
block path of :mod:`a2b.io.jobscan` both take the forms, keys and parameter kinds from it.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from typing import IO

import numpy as np

from ..errors import A2bError, InputFileError
from ..names import FRAMES, MAX_SAMPLES, MIN_SAMPLES, MODES
from ..parameters import BY_NAME, TABLE, degrees
from .documents import Document, NonFinite, Path, read_document, shorten, shorten_key

__all__ = [
    "JOB_KEYS",
    "PARAMETER_KINDS",
    "POSES_KEYS",
    "POSE_FORMS",
    "POSE_KEYS",
    "TRANSLATION",
    "Job",
    "Numbers",
    "PoseForm",
    "PoseList",
    "current_repairs",
    "describe",
    "job_from_node",
    "orthonormalizing",
    "pose_from_node",
    "read_motion_file",
    "read_pose",
    "read_pose_list",
    "read_poses",
]

POSES_KEYS = ("start", "end", "mode", "samples", "parameters")
JOB_KEYS = POSES_KEYS + ("name",)
#: Parameter name -> kind (``number``, ``branch``, ``pose``, ``bool``, ``frame``, or the count
#: of numbers of a vector), from the table of :mod:`a2b.parameters`.
PARAMETER_KINDS = {p.name: p.size if p.kind == "vector" else p.kind for p in TABLE}


@dataclass(frozen=True)
class Job:
    """One motion to sample: validated poses (robotics 4x4 matrices) and what the file says.

    ``mode`` and ``samples`` are ``None`` where the file does not give them; ``parameters``
    holds only the keys the file gives, with ``through`` already a 4x4 matrix.
    """

    start: np.ndarray
    end: np.ndarray
    mode: str | None = None
    samples: int | None = None
    parameters: dict = field(default_factory=dict)
    name: str | None = None
    #: The quaternions (w, x, y, z) of ``start`` and ``end`` as the file writes them, where it
    #: gives the pose as a quaternion (else ``None``): see :meth:`poses`.
    quaternions: tuple = (None, None)

    def poses(self) -> tuple:
        """``start`` and ``end`` for :func:`a2b.motion`: ``(quat_wxyz, translation)`` where the
        file gives a quaternion, so that the samples at t = 0 and 1 hold it bit for bit (a
        matrix does not keep it: :func:`a2b.api.given_quaternions`), else the matrix."""
        return tuple(
            pose if q is None else (q, pose[:3, 3])
            for pose, q in zip((self.start, self.end), self.quaternions)
        )


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _number(doc: Document, path: Path, v) -> float:
    if isinstance(v, NonFinite):
        raise doc.error(path, v.message())
    if not _is_number(v):
        raise doc.error(path, f"expected a number, got {describe(v)}")
    try:
        f = float(v)
    except OverflowError:  # an integer beyond the doubles
        raise doc.error(path, NonFinite(str(v)).message()) from None
    if not math.isfinite(f):
        raise doc.error(path, f"{v!r} is not allowed; numbers must be finite")
    return f


def describe(v) -> str:
    if isinstance(v, NonFinite):
        return f"the number {v.token}" if len(v.token) <= 24 else "a number too large for a double"
    if isinstance(v, bool):
        return f"the boolean {str(v).lower()}"
    if isinstance(v, str):
        return (
            f"the string {v!r}" if len(v) <= 60 else f"the string {v[:50]!r}… ({len(v)} characters)"
        )
    if v is None:
        return "nothing (null)"
    if isinstance(v, dict):
        return "a mapping"
    if isinstance(v, list):
        return f"a list of {len(v)}"
    return type(v).__name__


def _numbers(doc: Document, path: Path, v, n: int, what: str) -> list[float]:
    if not isinstance(v, list):
        raise doc.error(path, f"expected a list of {n} numbers {what}, got {describe(v)}".rstrip())
    if len(v) != n:
        raise doc.error(path, f"expected {n} numbers {what}, got {len(v)}".replace("  ", " "))
    return [_number(doc, path + (i,), x) for i, x in enumerate(v)]


def _list(doc: Document, path: Path, v, n: int) -> list:
    if not isinstance(v, list) or len(v) != n:
        got = f"{len(v)}" if isinstance(v, list) else describe(v)
        raise doc.error(path, f"expected a list of {n} angles, got {got}")
    return v


def _angle(doc: Document, path: Path, v) -> float:
    """An angle: a number (radians) or a string with a ``deg`` suffix (``45deg``)."""
    if isinstance(v, str) and degrees(v) is not None:
        return degrees(v)
    return _number(doc, path, v)


def _mapping(doc: Document, path: Path, v, what: str) -> dict:
    if not isinstance(v, dict):
        hint = ""
        if not path and isinstance(v, (str, int, float)) and not isinstance(v, bool):
            hint = (  # a file of numbers or a CSV header read as one YAML string
                " (a trajectory file? a2b resample reads TUM, KITTI, EuRoC, CSV and MCAP; "
                "a2b spline and bezier take their poses)"
            )
        raise doc.error(path, f"expected {what}, got {describe(v)}{hint}")
    return v


def _one_of(names) -> str:
    """``a, b or c``."""
    names = list(names)
    return ", ".join(names[:-1]) + " or " + names[-1] if len(names) > 1 else "".join(names)


def _check_keys(doc: Document, path: Path, mapping: dict, allowed: tuple, what: str) -> None:
    for key in mapping:
        if key not in allowed:
            hint = difflib.get_close_matches(str(key), allowed, n=1)
            suggestion = f"; did you mean {hint[0]!r}?" if hint else ""
            raise doc.error(
                path + (key,),
                f"unknown key {shorten_key(repr(key))} in {what} (expected {', '.join(allowed)})"
                f"{suggestion}",
            )


#: Set by :func:`orthonormalizing`: the residuals of the matrix poses repaired so far.
_REPAIRS: ContextVar[list | None] = ContextVar("a2b_repairs", default=None)


@contextmanager
def orthonormalizing() -> Iterator[list]:
    """Within this context, matrix poses that are orthogonal only to a few digits (up to
    :data:`a2b.poses.REPAIR_TOL`) are projected onto the nearest rotation
    (:func:`a2b.poses.orthonormalize`); the list yielded collects the residual of each repair.
    This is what ``--orthonormalize`` turns on."""
    repairs: list = []
    token = _REPAIRS.set(repairs)
    try:
        yield repairs
    finally:
        _REPAIRS.reset(token)


def current_repairs() -> list | None:
    """The residuals collected by the :func:`orthonormalizing` context in force, else None."""
    return _REPAIRS.get()


def _matrix_pose(rows: list, layout: str) -> np.ndarray:
    """A matrix pose, checked, or repaired within :func:`orthonormalizing`."""
    from ..poses import REPAIR_TOL, check_matrices, orthogonality_residuals, orthonormalize

    repairs = _REPAIRS.get()
    if repairs is None:
        return check_matrices(np.array(rows), layout=layout)
    pose = check_matrices(np.array(rows), layout=layout, tol=REPAIR_TOL)
    residual = float(orthogonality_residuals(pose[:3, :3]))
    if residual > 0.0:
        pose = orthonormalize(pose)
        repairs.append(residual)
    return pose


def pose_from_node(doc: Document, path: Path, v) -> np.ndarray:
    """Validate one pose mapping (any form of :data:`POSE_FORMS`) and return its robotics 4x4
    matrix; an error names the key, the line and the column."""
    pose = _mapping(doc, path, v, f"a pose mapping ({_one_of(POSE_FORMS)})")
    if "start" in pose or "end" in pose:
        raise doc.error(
            path,
            "expected one pose, got start and end poses (a poses file); give a file with one pose",
        )
    _check_keys(doc, path, pose, POSE_KEYS, "a pose")
    forms = [k for k in POSE_FORMS if k in pose]
    if len(forms) != 1:
        found = f"got {' and '.join(forms)}" if forms else "got none"
        raise doc.error(path, f"a pose needs exactly one of {', '.join(POSE_FORMS)} ({found})")
    form = POSE_FORMS[forms[0]]
    for key in POSE_EXTRAS:
        if key in pose and key not in form.extras:
            raise doc.error(path + (key,), f"{key!r} does not go with {form.key!r}")
    try:
        return form.read(doc, path, pose, form)
    except InputFileError:
        raise
    except A2bError as e:
        raise doc.error(path + (form.key,), str(e)) from e


def numbers_from_node(doc: Document, path: Path, v, spec: Numbers) -> list[float]:
    """The numbers of ``v`` written as ``spec`` says (a list, a mapping or either), in the
    order ``spec.wanted``."""
    if isinstance(v, dict) and "mapping" in spec.layouts:
        _check_keys(doc, path, v, tuple(spec.written), f"a {spec.what}")
        missing = [k for k in spec.written if k not in v]
        if missing:
            raise doc.error(path, f"the {spec.what} lacks {', '.join(missing)}")
        return [_number(doc, path + (k,), v[k]) for k in spec.wanted]
    if "list" not in spec.layouts:
        if isinstance(v, list):
            raise doc.error(path, spec.list_hint)
        keys = ", ".join(f"{k}: .." for k in spec.written)
        _mapping(doc, path, v, f"a mapping {{{keys}}}")
    written = _numbers(doc, path, v, len(spec.written), f"({', '.join(spec.written)})")
    return [written[i] for i in spec.pick]


def _translation(doc: Document, path: Path, pose: dict) -> np.ndarray:
    if "translation" not in pose:
        return np.zeros(3)
    here = path + ("translation",)
    return np.array(numbers_from_node(doc, here, pose["translation"], TRANSLATION))


def _quaternion_pose(doc: Document, path: Path, pose: dict, form: PoseForm) -> np.ndarray:
    from ..poses import matrices_from_quat_trans

    wxyz = numbers_from_node(doc, path + (form.key,), pose[form.key], form.numbers)
    return matrices_from_quat_trans(np.array(wxyz), _translation(doc, path, pose))


def _rpy_pose(doc: Document, path: Path, pose: dict, form: PoseForm) -> np.ndarray:
    from ..poses import matrices_from_quat_trans, quaternions_from_rpy_xyz

    here = path + (form.key,)
    rpy = [_angle(doc, here + (i,), x) for i, x in enumerate(_list(doc, here, pose[form.key], 3))]
    wxyz = quaternions_from_rpy_xyz(np.array(rpy))
    return matrices_from_quat_trans(wxyz, _translation(doc, path, pose))


def _axis_angle_pose(doc: Document, path: Path, pose: dict, form: PoseForm) -> np.ndarray:
    from ..poses import matrices_from_quat_trans, quaternions_from_axis_angle

    here = path + (form.key,)
    turn = _mapping(doc, here, pose[form.key], "{axis: [x, y, z], angle: ANGLE}")
    _check_keys(doc, here, turn, ("axis", "angle"), "an axis_angle")
    missing = [k for k in ("axis", "angle") if k not in turn]
    if missing:
        raise doc.error(here, f"the axis_angle lacks {', '.join(missing)}")
    axis = _numbers(doc, here + ("axis",), turn["axis"], 3, "(x, y, z)")
    angle = _angle(doc, here + ("angle",), turn["angle"])
    wxyz = quaternions_from_axis_angle(np.array(axis), angle)
    return matrices_from_quat_trans(wxyz, _translation(doc, path, pose))


def _matrix_form(doc: Document, path: Path, pose: dict, form: PoseForm) -> np.ndarray:
    rows = pose[form.key]
    if not isinstance(rows, list) or len(rows) != 4:
        got = f"{len(rows)} row{'s' * (len(rows) != 1)}" if isinstance(rows, list) else None
        raise doc.error(
            path + (form.key,), f"expected 4 rows of 4 numbers, got {got or describe(rows)}"
        )
    m = [_numbers(doc, path + (form.key, i), r, 4, "") for i, r in enumerate(rows)]
    layout = pose.get("layout", MATRIX_LAYOUTS[0])
    if layout not in MATRIX_LAYOUTS:
        raise doc.error(
            path + ("layout",), f"expected {' or '.join(MATRIX_LAYOUTS)}, got {describe(layout)}"
        )
    return _matrix_pose(m, layout)


def _study_form(doc: Document, path: Path, pose: dict, form: PoseForm) -> np.ndarray:
    from ..poses import matrices_from_study

    here = path + (form.key,)
    h = _numbers(doc, here, pose[form.key], 8, "(p0, p1, p2, p3, q0, q1, q2, q3)")
    through = pose.get("kappa", False)
    if not isinstance(through, bool):
        raise doc.error(path + ("kappa",), f"expected true or false, got {describe(through)}")
    try:
        return matrices_from_study(np.array(h), through_kappa=through)
    except A2bError as e:
        message = str(e)
        if "Study condition" in message:  # say how the file reads it through κ instead
            message += " (add kappa: true to read it through κ)"
        raise doc.error(here, message) from e


@dataclass(frozen=True)
class Numbers:
    """How a group of numbers may be written: a list in the order ``written``, a mapping with
    those keys, or either (``layouts``); the readers take them in the order ``wanted``."""

    what: str
    written: str
    wanted: str
    layouts: tuple[str, ...]
    #: The message for a list where only a mapping is read.
    list_hint: str = ""

    @property
    def pick(self) -> tuple[int, ...]:
        """Where each number of ``wanted`` sits in a list written in the order ``written``."""
        return tuple(self.written.index(k) for k in self.wanted)


@dataclass(frozen=True)
class PoseForm:
    """One form of a pose: its key, the keys that may go with it, how the numbers of a
    quaternion form are written (``None`` for the other forms), and its exact reader
    ``read(doc, path, pose, form) -> robotics 4x4 matrix``."""

    key: str
    extras: tuple[str, ...]
    numbers: Numbers | None
    read: Callable


TRANSLATION = Numbers("translation", "xyz", "xyz", ("list", "mapping"))
MATRIX_LAYOUTS = ("robotics", "paper")
_BARE_LIST = (
    "a bare list is ambiguous: a2b once read it as w, x, y, z, ROS writes x, y, z, w; write "
    "quaternion_wxyz: [w, x, y, z] or quaternion_xyzw: [x, y, z, w], or "
    "quaternion: {w: .., x: .., y: .., z: ..}"
)

#: The pose forms, the one schema of a pose: the exact reader (:func:`pose_from_node`) and the
#: fast block path of :mod:`a2b.io.jobscan` both read them from here.
POSE_FORMS = {
    form.key: form
    for form in (
        PoseForm("matrix", ("layout",), None, _matrix_form),
        PoseForm(
            "quaternion",
            ("translation",),
            Numbers("quaternion", "wxyz", "wxyz", ("mapping",), _BARE_LIST),
            _quaternion_pose,
        ),
        PoseForm(
            "quaternion_wxyz",
            ("translation",),
            Numbers("quaternion", "wxyz", "wxyz", ("list",)),
            _quaternion_pose,
        ),
        PoseForm(  # ROS order, converted here and nowhere else
            "quaternion_xyzw",
            ("translation",),
            Numbers("quaternion", "xyzw", "wxyz", ("list",)),
            _quaternion_pose,
        ),
        PoseForm("rpy_xyz", ("translation",), None, _rpy_pose),
        PoseForm("axis_angle", ("translation",), None, _axis_angle_pose),
        PoseForm("study", ("kappa",), None, _study_form),
    )
}
#: The keys that go with some forms only.
POSE_EXTRAS = tuple(dict.fromkeys(k for form in POSE_FORMS.values() for k in form.extras))
POSE_KEYS = tuple(POSE_FORMS) + POSE_EXTRAS


def _samples(doc: Document, path: Path, v) -> int | None:
    """A file's ``samples``: a whole number in ``[MIN_SAMPLES, MAX_SAMPLES]``, or ``None``."""
    if v is None:
        return None
    here = path + ("samples",)
    if not isinstance(v, int) or isinstance(v, bool):
        shown = describe(v) if not _is_number(v) else repr(v)
        raise doc.error(
            here, f"expected a whole number of samples, at least {MIN_SAMPLES}, got {shown}"
        )
    if v < MIN_SAMPLES:
        raise doc.error(here, f"expected at least {MIN_SAMPLES} samples (t = 0 and t = 1), got {v}")
    if v > MAX_SAMPLES:
        raise doc.error(
            here,
            f"expected at most 2**53 = {MAX_SAMPLES} samples (more evenly spaced t in [0, 1] "
            f"than doubles tell apart), got {shorten(str(v))}",
        )
    return v


def _parameters(doc: Document, path: Path, v) -> dict:
    params = _mapping(doc, path, v, "a mapping of motion parameters")
    _check_keys(doc, path, params, tuple(PARAMETER_KINDS), "parameters")
    out = {}
    for key, value in params.items():
        kind = PARAMETER_KINDS[key]
        here = path + (key,)
        if value is None:
            continue
        if kind == "number":
            angle = (
                degrees(value) if isinstance(value, str) and BY_NAME[key].unit == "radian" else None
            )
            out[key] = angle if angle is not None else _number(doc, here, value)
        elif isinstance(kind, int):
            out[key] = tuple(_numbers(doc, here, value, kind, ""))
        elif kind == "branch":
            if not _is_number(value) or value not in (1, -1):
                raise doc.error(
                    here,
                    f"expected +1 or -1, got {describe(value) if not _is_number(value) else value}",
                )
            out[key] = int(value)
        elif kind == "bool":
            if not isinstance(value, bool):
                raise doc.error(here, f"expected true or false, got {describe(value)}")
            out[key] = value
        elif kind == "frame":
            if value not in FRAMES:
                raise doc.error(here, f"expected one of {', '.join(FRAMES)}, got {describe(value)}")
            out[key] = value
        else:  # pose
            out[key] = pose_from_node(doc, here, value)
    return out


def job_from_node(doc: Document, path: Path, v, allowed: tuple) -> Job:
    job = _mapping(doc, path, v, "a mapping with start and end")
    if any(k in job for k in POSE_FORMS) and "start" not in job and "end" not in job:
        raise doc.error(
            path, "this is one pose, but start and end poses are needed (see a2b interpolate -h)"
        )
    if "start" not in job and "end" not in job:
        for key, command in (("controls", "a2b bezier"), ("poses", "a2b spline")):
            if key in job:
                raise doc.error(
                    path, f"this is a list of {key} ({command}), but start and end poses are needed"
                )
    _check_keys(doc, path, job, allowed, "a poses file" if allowed is POSES_KEYS else "a job")
    for key in ("start", "end"):
        if key not in job:
            raise doc.error(path, f"missing {key!r}: a poses file needs start and end poses")
    mode = job.get("mode")
    if mode is not None and mode not in MODES:
        raise doc.error(
            path + ("mode",), f"expected one of {', '.join(MODES)}, got {describe(mode)}"
        )
    samples = _samples(doc, path, job.get("samples"))
    name = job.get("name")
    if name is not None and (isinstance(name, bool) or not isinstance(name, (str, int))):
        raise doc.error(path + ("name",), f"expected a string, got {describe(name)}")
    if isinstance(name, str):
        _check_name(doc, path + ("name",), name)
    return Job(
        start=pose_from_node(doc, path + ("start",), job["start"]),
        end=pose_from_node(doc, path + ("end",), job["end"]),
        mode=mode,
        samples=samples,
        parameters=_parameters(doc, path + ("parameters",), job.get("parameters") or {}),
        name=None if name is None else str(name),
        quaternions=tuple(_given_quaternion(doc, path + (k,), job[k]) for k in ("start", "end")),
    )


def _given_quaternion(doc: Document, path: Path, pose: dict) -> np.ndarray | None:
    """The quaternion (w, x, y, z) of a pose that :func:`pose_from_node` validated, as the
    file writes it, if the pose is given as a quaternion; else ``None``."""
    forms = [POSE_FORMS[k] for k in POSE_FORMS if k in pose]
    if forms[0].read is not _quaternion_pose:
        return None
    form = forms[0]
    return np.array(numbers_from_node(doc, path + (form.key,), pose[form.key], form.numbers))


def _check_name(doc: Document, path: Path, name: str) -> None:
    """A job's name is written into the ``job`` column: no NUL, and text that UTF-8 can write
    (JSON's ``\\udcff`` escapes a lone surrogate, which it cannot)."""
    if "\0" in name:
        raise doc.error(path, f"{name!r} contains a NUL character")
    try:
        name.encode("utf-8")
    except UnicodeEncodeError as e:
        raise doc.error(
            path, f"{name!r} is no text UTF-8 can write: a lone surrogate, {name[e.start]!r}"
        ) from None


# --------------------------------------------------------------------------------------------
# Public pose-file readers


def read_pose(stream: IO, name: str | None = None) -> np.ndarray:
    """Read a file holding one pose mapping (``a2b fiber``, ``--through``).

    Returns
    -------
    ndarray, shape (4, 4)
        The pose, robotics layout.

    Raises
    ------
    InputFileError
        Naming the file, the key and the line and column.
    """
    doc = read_document(stream, name)
    return pose_from_node(doc, (), doc.data)


def read_poses(stream: IO, name: str | None = None) -> Job:
    """Read a poses file: ``start``, ``end`` and optional ``mode``, ``samples``, ``parameters``.

    Raises
    ------
    InputFileError
        Naming the file, the key and the line and column.
    """
    doc = read_document(stream, name)
    return job_from_node(doc, (), doc.data, POSES_KEYS)


#: Curve spaces and kernel bases of a pose list (``a2b bezier``, ``a2b spline``).
SPACES = ("matrix", "study")
BASES = ("paper", "rref", "auto")
#: The parameters a pose list may give, per list key: name -> kind ("m": 4 numbers,
#: "per-pose": one number per pose, "per-pose-6": 6 numbers per pose, "basis": a basis name).
#: The names are those of :func:`a2b.motions.bezier.bezier_motion` and ``spline_motion``.
POSE_LIST_PARAMETERS = {
    "controls": {
        "m": "m",
        "weights": "per-pose",
        "alphas": "per-pose-6",
        "basis": "basis",
        "offsets": "per-pose",
    },
    "poses": {"m": "m"},
}


@dataclass(frozen=True)
class PoseList:
    """The poses of a pose-list file (robotics matrices ``(k, 4, 4)``) and what it says.

    ``key`` is the list's key, ``controls`` (a Bézier curve) or ``poses`` (a spline).
    ``space`` and ``samples`` are ``None`` where the file does not give them; ``parameters``
    holds only the keys the file gives.
    """

    key: str
    poses: np.ndarray
    space: str | None = None
    samples: int | None = None
    parameters: dict = field(default_factory=dict)


def read_pose_list(stream: IO, key: str, name: str | None = None) -> PoseList:
    """Read a file with a list of at least two poses under ``key`` (``controls`` or ``poses``).

    The mapping may also give ``space`` (matrix or study), ``samples`` and ``parameters``
    (:data:`POSE_LIST_PARAMETERS`). Every pose may be in any pose form; errors name the file,
    the line and column and the key, e.g.
    ``curve.yaml:7:5: controls[2].quaternion: expected 4 numbers (w, x, y, z), got 3``.

    Raises
    ------
    InputFileError
    """
    if key not in POSE_LIST_PARAMETERS:
        raise ValueError(f"key must be one of {', '.join(POSE_LIST_PARAMETERS)}, got {key!r}")
    return _pose_list(read_document(stream, name), key)


def _pose_list(doc: Document, key: str) -> PoseList:
    top = _mapping(doc, (), doc.data, f"a mapping with {key}")
    if "start" in top and "end" in top and key not in top:
        raise doc.error(
            (),
            f"this is a poses file (start and end); this command needs a list of poses under "
            f"{key!r}",
        )
    _check_keys(doc, (), top, (key, "space", "samples", "parameters"), f"a {key} file")
    if key not in top:
        raise doc.error((), f"missing {key!r}: a list of at least two poses")
    items = top[key]
    if not isinstance(items, list) or len(items) < 2:
        got = f"{len(items)}" if isinstance(items, list) else describe(items)
        raise doc.error((key,), f"expected a list of at least two poses, got {got}")
    poses = np.stack([pose_from_node(doc, (key, i), item) for i, item in enumerate(items)])
    k = len(items)
    space = top.get("space")
    if space is not None and space not in SPACES:
        raise doc.error(("space",), f"expected one of {', '.join(SPACES)}, got {describe(space)}")
    samples = _samples(doc, (), top.get("samples"))
    given = _mapping(
        doc, ("parameters",), top.get("parameters") or {}, "a mapping of curve parameters"
    )
    kinds = POSE_LIST_PARAMETERS[key]
    _check_keys(doc, ("parameters",), given, tuple(kinds), "parameters")
    parameters = {}
    for pname, value in given.items():
        here = ("parameters", pname)
        kind = kinds[pname]
        if value is None:
            continue
        if kind == "m":
            parameters[pname] = tuple(_numbers(doc, here, value, 4, "(m0, m1, m2, m3)"))
        elif kind == "per-pose":
            parameters[pname] = tuple(_numbers(doc, here, value, k, f"(one per pose in {key})"))
        elif kind == "per-pose-6":
            if not isinstance(value, list) or len(value) != k:
                got = len(value) if isinstance(value, list) else describe(value)
                raise doc.error(
                    here, f"expected {k} lists of 6 numbers (one per pose in {key}), got {got}"
                )
            rows = [_numbers(doc, here + (i,), row, 6, "(α0 … α5)") for i, row in enumerate(value)]
            parameters[pname] = tuple(tuple(row) for row in rows)
        else:
            if value not in BASES:
                raise doc.error(here, f"expected one of {', '.join(BASES)}, got {describe(value)}")
            parameters[pname] = value
    return PoseList(key, poses, space, samples, parameters)


def read_motion_file(stream: IO, name: str | None = None) -> Job | PoseList:
    """Read a poses file (``start``, ``end``) or a pose list (``controls`` or ``poses``).

    The top-level keys tell which: ``controls`` makes a Bézier curve's :class:`PoseList`,
    ``poses`` a spline's, anything else is read as a poses file (:func:`read_poses`).
    """
    doc = read_document(stream, name)
    if isinstance(doc.data, dict):
        for key in POSE_LIST_PARAMETERS:
            if key in doc.data:
                return _pose_list(doc, key)
    return job_from_node(doc, (), doc.data, POSES_KEYS)
