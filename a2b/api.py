"""The public Python API: :func:`motion`, :func:`interpolate` and :func:`describe`."""

from __future__ import annotations

import numpy as np

from .elements import anywhere
from .errors import ParameterError
from .frames import screw_frame
from .motions import REGISTRY
from .motions.base import Motion, check_ends, check_excursion, check_table
from .names import MODES
from .parameters import OF_MODE, TABLE
from .poses import (
    check_matrices,
    check_matrices_and_quaternions,
    pose_matrices,
    quaternions_from_rotations,
    study_from_quat_trans,
)
from .study import dots

#: mode -> the names of its parameters (the table of :mod:`a2b.parameters`).
PARAMETERS = OF_MODE
#: Trailing dimensions of the parameters that are arrays for one motion.
TRAILING = {p.name: p.trailing for p in TABLE if p.trailing}


def motion(start, end, mode: str = "darboux", **parameters) -> Motion:
    """The motions of the given mode from poses ``start`` to poses ``end``.

    Parameters
    ----------
    start, end : array_like, shape (..., 4, 4)
        Robotics-layout homogeneous matrices ``[[R, t], [0, 0, 0, 1]]``, validated with
        :func:`a2b.poses.check_matrices`; or scipy ``RigidTransform``/``Rotation`` objects, or
        tuples ``(quat_wxyz, translation)`` (:func:`a2b.poses.pose_matrices`). Their leading
        shapes broadcast to the shape ``S`` of the result, with the parameters'; one pair of
        4x4 matrices (and scalar parameters) gives a single motion, ``S = ()``.
    mode : {"darboux", "cubic", "screw"}
    **parameters
        darboux: ``delta, kappa, lam, branch, pitch_start, pitch_end, through, long_way``;
        cubic: ``m, alpha, beta, a, b, frame``; screw: none. ``None`` means "not given".
        Numbers (and ``m``, ``alpha``, ``beta``, ``through`` by their leading shape)
        broadcast with the poses: ``S`` is the broadcast shape of all of them. See
        :class:`a2b.motions.darboux.DarbouxMotion` and
        :class:`a2b.motions.cubic.CubicMotion`.

    Returns
    -------
    Motion
        Of shape ``S``, with ``matrices(ts)``, ``quat_trans(ts)``, ``study(ts)`` (each
        ``S + (N, ...)``), ``describe()`` and ``motion[i]``. Every element is the motion that
        its pair of poses and parameters give alone, with the same choices and warnings; in a
        batch, errors and warnings name the element (``motion i: ...``).

    Raises
    ------
    A2bError
        Invalid poses, unknown or conflicting parameters, parameters without a solution, or a
        motion that is singular for some ``t ∈ [0, 1]``.
    """
    a, b = pose_matrices(start), pose_matrices(end)
    quaternions = None
    if isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.shape == b.shape:
        both, quaternions = check_matrices_and_quaternions(np.array((a, b)))  # in one pass
        a, b = both
        quaternions = tuple(quaternions)
    else:
        a, b = check_matrices(a), check_matrices(b)
    result = checked_motion(a, b, mode, quaternions=quaternions, **parameters)
    if not (isinstance(start, tuple) or isinstance(end, tuple)):  # no quaternion given
        return result
    given = given_quaternions((start, end), (a, b), quaternions)
    if given is not None and given[0].shape == result.shape + (4,):
        result.given_ends = np.stack(given, axis=-2)
    return result


def given_quaternions(poses: tuple, matrices: tuple, made: tuple | None = None) -> tuple | None:
    """The unit quaternions of A and B where a pose was given as a tuple
    ``(quat_wxyz, translation)``, for :attr:`a2b.motions.base.Motion.given_ends`: the
    quaternion as given (divided by its norm only if that differs from 1 by more than 4 ulp,
    so a unit quaternion keeps its bits), at the sign of the one its matrix gives; the other
    pose's from its matrix. ``None`` if neither was given so, or the shapes differ.

    The motion itself is built from the matrices, as for matrices given (its quaternions
    agree with these to a few ulp); only its samples at t = 0 and 1 take these. ``made``:
    the matrices' own quaternions, where the caller has them already."""
    given = [pose[0] if isinstance(pose, tuple) and len(pose) == 2 else None for pose in poses]
    if given[0] is None is given[1] or matrices[0].shape != matrices[1].shape:
        return None
    out = []
    if made is None:
        made = tuple(quaternions_from_rotations(m[..., :3, :3]) for m in matrices)
    for q, own in zip(given, made):
        if q is None or np.shape(q) != own.shape:
            out.append(own)
            continue
        q = np.asarray(q, dtype=float)
        norm = np.sqrt(dots(q, q))[..., None]
        q = np.where(np.abs(norm - 1.0) > 4 * np.finfo(float).eps, q / norm, q)
        sign = np.where(dots(q, own) < 0.0, -1.0, 1.0)
        out.append(sign[..., None] * q + 0.0)
    return tuple(out)


def checked_motion(a, b, mode: str = "darboux", /, quaternions=None, **parameters) -> Motion:
    """:func:`motion` of poses that are validated already (:func:`a2b.poses.check_matrices`),
    as a trajectory's reader or :class:`a2b.resample.Resampler` validated them once;
    ``quaternions``, of the shape of ``a`` and ``b``, as for :func:`a2b.frames.screw_frame`."""
    if mode not in MODES:
        raise ParameterError(f"unknown mode {mode!r}; expected one of {', '.join(MODES)}")
    unknown = sorted(set(parameters) - set(PARAMETERS[mode])) if parameters else None
    if unknown:
        allowed = ", ".join(PARAMETERS[mode]) or "none"
        raise ParameterError(
            f"mode {mode} does not take {', '.join(unknown)} (its parameters: {allowed})"
        )
    params = {key: value for key, value in parameters.items() if value is not None}
    shapes = {"start": a.shape[:-2], "end": b.shape[:-2]}
    for key, item in params.items():
        if not isinstance(item, str):
            shapes[key] = np.shape(item)[: max(np.ndim(item) - TRAILING.get(key, 0), 0)]
    try:
        shape = (
            a.shape[:-2]
            if len(set(shapes.values())) == 1
            else np.broadcast_shapes(*shapes.values())
        )
    except ValueError:
        described = ", ".join(f"{key} {value}" for key, value in shapes.items())
        raise ParameterError(f"the leading shapes do not broadcast: {described}") from None
    if quaternions is not None and not shape == a.shape[:-2] == b.shape[:-2]:
        quaternions = None  # made again for the broadcast poses
    if a.shape[:-2] != shape:
        a = np.broadcast_to(a, shape + (4, 4))
    if b.shape[:-2] != shape:
        b = np.broadcast_to(b, shape + (4, 4))
    with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported below, as an error
        return _build(a, b, mode, params, quaternions)


def _build(a, b, mode, params, quaternions=None) -> Motion:
    kind = REGISTRY[mode].motion
    frame = screw_frame(a, b, quaternions, axes=kind.frame_axes or bool(params))
    result = kind.from_parameters(a, b, frame, params)
    check_table(result.table, result.shape)
    if params:  # the defaults of every mode reach their ends to 2e-15 and stay within 0.5 of
        check_ends(result)  # the excursion ratio: only a parameter can upset either
        check_excursion(result)  # (docs/math.md, "How far a motion strays")
    return result


def interpolate(start, end, ts, mode: str = "darboux", **parameters) -> np.ndarray:
    """Sample the motion from ``start`` to ``end`` at the parameters ``ts``.

    Parameters
    ----------
    start, end : array_like, shape (..., 4, 4)
        Robotics-layout poses, broadcast against each other to the shape ``S`` of the motions.
    ts : array_like, shape (N,), or int
        Sample parameters, or a count of evenly spaced ones in [0, 1]. ``t = 0`` gives ``start`` and
        ``t = 1`` gives ``end``; values
        outside ``[0, 1]`` extrapolate along the same motion (and are checked for
        singularities on the extended range).
    mode, **parameters
        As for :func:`motion`.

    Returns
    -------
    ndarray, shape S + (N, 4, 4)

    Examples
    --------
    >>> import numpy as np, a2b
    >>> b = np.eye(4); b[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]; b[2, 3] = 1.0
    >>> a2b.interpolate(np.eye(4), b, [0.0, 0.5, 1.0], mode="darboux").shape
    (3, 4, 4)
    """
    result = motion(start, end, mode, **parameters)
    return pin_ends(result, ts, {"matrices": result.matrices(ts)})["matrices"]


def pin_ends(motion, ts, poses: dict) -> dict:
    """``poses`` of ``motion`` at ``ts`` (fields of :class:`a2b.samples.Samples`, each
    ``S + (N, ...)``) with the rows at t = 0 and t = 1 holding the end poses as the motion
    holds them (``motion.start``, ``motion.end``), not as its formula rounds them: the
    translations, the matrices whole, and the Study parameters' dual part from the
    translation. (The quaternions, and the Study parameters' primal part, are those the
    motion was built from already: :meth:`a2b.motions.base.Motion.quat_trans`.) Anything
    without end poses of its shape (a segment table) is returned as it is."""

    start, end = getattr(motion, "start", None), getattr(motion, "end", None)
    shape = tuple(getattr(motion, "shape", (None,)))
    if start is None or end is None or getattr(start, "shape", None) != shape + (4, 4):
        return poses
    ts = np.asarray(ts, dtype=float)
    for t, pose in ((0.0, start), (1.0, end)):
        at = ts == t
        if ts.ndim == 1:  # shared by every motion: the same columns of all
            (found,) = at.nonzero()
            if len(found):
                _pin_columns(poses, found, np.asarray(pose))
            continue
        if not anywhere(at):
            continue
        lead = next(iter(poses.values())).shape[: len(shape) + 1]
        at = np.broadcast_to(at, lead)
        pose = np.broadcast_to(np.asarray(pose)[..., None, :, :], lead + (4, 4))[at]
        if poses.get("trans") is not None:
            poses["trans"][at] = pose[:, :3, 3]
        if poses.get("matrices") is not None:
            poses["matrices"][at] = pose
        if poses.get("study") is not None:
            poses["study"][at] = study_from_quat_trans(poses["study"][at][:, :4], pose[:, :3, 3])
    return poses


def _pin_columns(poses: dict, found: np.ndarray, pose: np.ndarray) -> None:
    """:func:`pin_ends` for parameters ``(N,)`` shared by every motion: the samples ``found``
    (their indices) of every field take ``pose`` ``S + (4, 4)``."""

    if len(found) == 1:  # one sample at t: a basic index, the cheapest
        at = int(found[0])
    else:
        at, pose = found, pose[..., None, :, :]
    if poses.get("trans") is not None:
        poses["trans"][..., at, :] = pose[..., :3, 3]
    if poses.get("matrices") is not None:
        poses["matrices"][..., at, :, :] = pose
    if poses.get("study") is not None:
        study = poses["study"]
        study[..., at, :] = study_from_quat_trans(study[..., at, :4], pose[..., :3, 3])


def describe(start, end, mode: str = "darboux", **parameters) -> dict:
    """The canonical frame and the essential parameters of a motion, as plain data.

    Always: ``mode, phi, phi_degrees, d, axis_point, axis_direction, singular_t, choices``.
    darboux: ``delta, z0, lam, kappa, pitch_start, pitch_end, fiber_offsets, long_way,
    rotation_angle`` (``None`` where undefined, e.g. for a pure translation).
    cubic: ``frame, m, m0, m3, a, b, psi_start, psi_end, weights, in_cylinder_group``.
    screw: ``pitch``.
    """
    return motion(start, end, mode, **parameters).describe()
