"""What a figure of motions from A to B shows, for both renderers: :mod:`a2b.plot` (matplotlib)
and :mod:`a2b.view` (plotly).

:func:`make_scene` checks what to draw and samples it once: the tracks (each motion's samples
and the instants at which its moving frame is drawn, with a label and a colour), the body
points whose trajectories are drawn, the screw frame of A and B, which tracks lie in its
cylinder group, the marked poses, and the titles. :func:`transmission_curve` gives a track's
transmission curve in canonical coordinates and its closed form, and :func:`family_members`
the family of motions through A and B that a motion belongs to.

The behaviour of each mode (its closed form, its family, its summary) is the motion class's
(:data:`a2b.motions.REGISTRY`); this module asks the class, never the name. It uses numpy and
the motions only: no matplotlib, no plotly.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from .errors import ParameterError, quoted
from .motions.text import angle_text, number_text

ANGLE_UNITS = ("deg", "rad")

#: Colours of the built-in modes when several are compared (chosen to be told apart from the
#: red, green and blue of the frame axes and by most colour-blind readers).
MODE_COLOURS = {"darboux": "#6a3d9a", "cubic": "#e66101", "screw": "#4d4d4d"}
#: Colours of the other motions, and of a mode's second track.
OTHER_COLOURS = ("#1b9e77", "#a6761d", "#e7298a", "#386cb0", "#666600")
AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")
A_COLOUR, B_COLOUR = "#b2182b", "#2166ac"

#: Relative tolerance for a sampled motion to count as a motion in the cylinder group of A and B.
CYLINDER_TOL = 1e-8

#: Family members on each side of the chosen one.
FAMILY_SIDE = 3

#: The samples of a closed form drawn over a track's ω range.
DENSE = 241


@dataclass
class Track:
    """One motion to draw.

    Attributes
    ----------
    label : str
        Its name in legends and ``gid``s: the mode name for the built-in modes.
    mode : str or None
        The mode of an :func:`a2b.motion`, else None.
    motion : Motion or None
        The motion of a mode, else None.
    mats : ndarray, shape (N, 4, 4)
        The samples.
    inst : ndarray, shape (K, 4, 4)
        The instants at which the moving frame is drawn.
    colour : str
    params : dict
        The parameters given for a mode.
    source : object or None
        The object sampled when it is no mode (e.g. a BezierMotion).
    times : ndarray, shape (N,), or None
        The times of the samples (seconds) of a trajectory, when known.
    """

    label: str
    mode: str | None
    motion: object | None
    mats: np.ndarray
    inst: np.ndarray
    colour: str
    params: dict = field(default_factory=dict)
    source: object | None = None
    times: np.ndarray | None = None


@dataclass
class Scene:
    """Everything a figure of motions from A to B shows (see :func:`make_scene`)."""

    start: np.ndarray
    end: np.ndarray
    frame: object  # a2b.frames.ScrewFrame
    tracks: list[Track]
    in_group: list[bool]
    axis_length: float
    body: np.ndarray  # (K, 3) body points
    point_names: list[str]
    default_points: bool
    marks: list[tuple[str, np.ndarray]]
    angle_unit: str
    length_unit: str | None

    @property
    def single(self) -> bool:
        return len(self.tracks) == 1

    @property
    def has_transmission(self) -> bool:
        return any(self.in_group)

    @property
    def show_axis(self) -> bool:
        """The screw axis of B A⁻¹ belongs to the modes and to motions about it, not to a
        curve through other poses."""
        return self.has_transmission or any(t.mode for t in self.tracks)

    @property
    def length_label(self) -> str:
        """`` [unit]`` for axis titles, or nothing."""
        return f" [{self.length_unit}]" if self.length_unit else ""

    def trajectories(self, track: Track, mats: np.ndarray | None = None) -> np.ndarray:
        """The paths ``(K, N, 3)`` of the body points under ``mats`` (default: all samples).

        Raises
        ------
        ParameterError
            When a path overflows double precision, naming its body point.
        """
        mats = track.mats if mats is None else mats
        with np.errstate(over="ignore", invalid="ignore"):
            world = np.einsum("nij,kj->kni", mats[:, :3, :3], self.body)
            world += mats[None, :, :3, 3]
        if not np.isfinite(world).all():
            k = int(np.argmax(~np.isfinite(world).reshape(len(world), -1).all(axis=1)))
            raise ParameterError(
                f"the trajectory of the body point {self.point_names[k]} overflows double "
                "precision; give points of a size the poses can carry"
            )
        return world

    def ends_text(self) -> str:
        """``φ = …, d = …``: the screw of B A⁻¹."""
        return f"φ = {angle_text(self.frame.phi, self.angle_unit)}, d = {number_text(self.frame.d)}"

    def figure_title(self) -> str:
        """The title of :func:`a2b.plot.plot_motions`."""
        angles = self.ends_text()
        first = self.tracks[0]
        if self.single and curve_title(first) is not None:
            return curve_title(first)
        if self.single:
            what = f"{first.label} motion" if first.mode else first.label
            extra = first.motion.summary(self.angle_unit) if first.motion is not None else ""
            return (
                f"{what}: {extra}   (A to B: {angles})" if extra else f"{what}   (A to B: {angles})"
            )
        return f"{', '.join(t.label for t in self.tracks)} from A to B   ({angles})"

    def page_title(self) -> str:
        """The title of :func:`a2b.view.view_page`."""
        if self.single and curve_title(self.tracks[0]):
            return curve_title(self.tracks[0])
        names = ", ".join(t.label for t in self.tracks)
        return f"{names} motion{'s' * (not self.single)}, A to B: {self.ends_text()}"


def make_scene(
    start,
    end,
    motions,
    *,
    points=None,
    samples: int,
    instants: int,
    axis_length: float | None = None,
    marks=None,
    angle_unit: str = "deg",
    length_unit: str | None = None,
) -> Scene:
    """Check and sample what to draw (the arguments of :func:`a2b.plot.plot_motions`).

    Raises
    ------
    A2bError
        Invalid poses, motions, parameters, ``points``, ``angle_unit``, ``samples``,
        ``instants``, ``axis_length`` or ``marks``.
    """
    from .frames import screw_frame
    from .poses import check_matrices

    if angle_unit not in ANGLE_UNITS:
        raise ParameterError(f"unknown angle unit {quoted(angle_unit)}; expected deg or rad")
    for name, value in (("samples", samples), ("instants", instants)):
        if not (isinstance(value, numbers.Real) and float(value).is_integer() and value >= 2):
            raise ParameterError(f"{name} must be an integer ≥ 2, got {value!r}")
    a, b = check_matrices(start), check_matrices(end)
    if a.shape != (4, 4) or b.shape != (4, 4):
        raise ParameterError("start and end must each be one 4x4 matrix")
    frame = screw_frame(a, b)
    tracks = make_tracks(a, b, motions, int(samples), int(instants))
    _check_span(np.concatenate([t.mats[:, :3, 3] for t in tracks]))
    if axis_length is None:
        axis_length = default_axis_length(tracks)
    elif not (math.isfinite(axis_length) and axis_length > 0):
        raise ParameterError(f"axis_length must be a positive number, got {axis_length!r}")
    body, point_names, default_points = body_points(points, float(axis_length))
    marked = [(str(label), check_matrices(pose)) for label, pose in (marks or ())]
    if any(pose.shape != (4, 4) for _, pose in marked):
        raise ParameterError("each mark is a (label, 4x4 pose) pair")
    in_group = [in_cylinder_group(frame, t.mats) for t in tracks]
    return Scene(a, b, frame, tracks, in_group, float(axis_length), body, point_names,
                 default_points, marked, angle_unit, length_unit)  # fmt: skip


# -- the tracks --------------------------------------------------------------------------------


def _param_text(value) -> str:
    if isinstance(value, (bool, str)):
        return str(value)
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        return number_text(float(arr))
    return "(" + ", ".join(number_text(v) for v in arr.ravel()) + ")"


def _as_entry(entry, start, end) -> tuple[str, str | None, object, dict]:
    """``(label, mode, the object to sample, parameters)`` of one entry of ``motions``."""
    from .api import MODES
    from .api import motion as make_motion
    from .motions.base import Motion

    if isinstance(entry, str):
        entry = (entry, {})
    if isinstance(entry, Motion):
        return entry.mode, entry.mode, entry, {}
    if callable(getattr(entry, "matrices", None)):  # e.g. an a2b.motions.bezier.BezierMotion
        return getattr(entry, "kind", None) or type(entry).__name__, None, entry, {}
    if isinstance(entry, tuple) and len(entry) == 2 and isinstance(entry[0], str):
        label, what = entry
        if not isinstance(what, Mapping):
            return label, None, what, {}
        if label not in MODES:
            raise ParameterError(
                f"unknown mode {quoted(label)}; expected one of {', '.join(MODES)} "
                "(or a (label, callable) or (label, matrices) pair)"
            )
        params = {k: v for k, v in what.items() if v is not None}
        return label, label, make_motion(start, end, label, **params), params
    raise ParameterError(
        "each motion to plot is a mode name, a (mode, parameters) pair, an a2b Motion, "
        f"or a (label, callable) or (label, matrices) pair; got {type(entry).__name__}"
    )


def _sampled(obj, label: str, samples: int, instants: int) -> tuple[np.ndarray, np.ndarray]:
    """The samples ``(samples, 4, 4)`` and the instants ``(≤ instants, 4, 4)`` of ``obj``."""
    from .poses import check_matrices

    ts = np.linspace(0.0, 1.0, samples)
    t_inst = np.linspace(0.0, 1.0, instants)
    if hasattr(obj, "matrices") and callable(obj.matrices):
        return obj.matrices(ts), obj.matrices(t_inst)
    if callable(obj):
        mats = check_matrices(obj(ts))
        inst = check_matrices(obj(t_inst))
        if mats.shape != (samples, 4, 4) or inst.shape != (instants, 4, 4):
            raise ParameterError(
                f"the sampler of {quoted(label)} must return (len(ts), 4, 4) matrices, "
                f"got shape {mats.shape} for {samples} parameters"
            )
        return mats, inst
    mats = check_matrices(obj)
    if mats.ndim != 3 or mats.shape[0] < 2:
        raise ParameterError(
            f"the samples of {quoted(label)} must have shape (N, 4, 4) with N ≥ 2, got {mats.shape}"
        )
    picks = np.round(np.linspace(0, mats.shape[0] - 1, min(instants, mats.shape[0]))).astype(int)
    return mats, mats[picks]


def make_tracks(start, end, motions, samples: int, instants: int) -> list[Track]:
    """The tracks of ``motions``, one entry or a sequence of entries, labels made distinct.

    Each entry is one of

    * a mode name, ``"darboux"``, ``"cubic"`` or ``"screw"``;
    * a pair ``(mode, parameters)``, the parameters of :func:`a2b.motion` as a dict;
    * a :class:`a2b.motions.base.Motion` made by :func:`a2b.motion`;
    * any other object with a ``matrices(ts)`` method, such as an
      :class:`a2b.motions.bezier.BezierMotion`, labelled by its ``kind`` attribute;
    * a pair ``(label, sampler)``: any callable taking ``ts`` of shape ``(N,)`` in ``[0, 1]``
      and returning robotics matrices ``(N, 4, 4)`` (for instance a Bézier motion through
      several control poses);
    * a pair ``(label, matrices)``: precomputed samples ``(N, 4, 4)``, taken as equally spaced
      in t; the instants of the frame panel are the nearest samples.

    Raises
    ------
    ParameterError
        For an entry of none of these kinds, an unknown mode, a sampler returning the wrong
        shape, or no entry.
    """
    from .motions.base import Motion

    one_pair = isinstance(motions, tuple) and len(motions) == 2 and isinstance(motions[0], str)
    if (
        one_pair
        or isinstance(motions, (str, Motion))
        or callable(getattr(motions, "matrices", None))
    ):
        motions = [motions]
    tracks = []
    others = iter(OTHER_COLOURS * 4)
    for entry in motions:
        label, mode, obj, params = _as_entry(entry, start, end)
        mats, inst = _sampled(obj, label, samples, instants)
        colour = MODE_COLOURS.get(mode) if mode else None
        if colour is None or any(t.colour == colour for t in tracks):
            colour = next(others)
        source = None if mode or not hasattr(obj, "matrices") else obj
        tracks.append(Track(label, mode, obj if mode else None, mats, inst, colour, params, source))
    if not tracks:
        raise ParameterError("nothing to plot: give at least one motion")
    _distinct_labels(tracks)
    return tracks


def _distinct_labels(tracks: list[Track]) -> None:
    """The same mode twice: tell them apart by their parameters, or number them."""
    labels = [t.label for t in tracks]
    if len(set(labels)) == len(labels):
        return
    for t in tracks:
        if labels.count(t.label) > 1:
            given = ", ".join(f"{k}={_param_text(v)}" for k, v in t.params.items())
            t.label = f"{t.label} ({given or 'defaults'})"
    labels = [t.label for t in tracks]
    for i, t in enumerate(tracks):
        if labels.count(t.label) > 1:
            t.label = f"{t.label} #{i + 1}"


def curve_title(track: Track) -> str | None:
    """The title of a Bézier motion or spline, from its ``describe()``; else ``None``."""
    if track.mode is not None or track.source is None:
        return None
    describe = getattr(track.source, "describe", None)
    info = describe() if callable(describe) else None
    if not isinstance(info, dict) or not {"kind", "space", "degree", "segments"} <= set(info):
        return None
    space = f"{info['space']} space"
    segments = info["segments"]
    if "spline" in str(info["kind"]).lower():
        return f"C¹ spline of {segments} cubic segment{'s' * (segments != 1)} ({space})"
    return f"Bézier motion of degree {info['degree']} ({space})"


# -- closed forms and families -----------------------------------------------------------------


def closed_form_z(motion, omega) -> np.ndarray | None:
    """The closed-form transmission curve ``z(ω)`` of a motion, in canonical coordinates.

    Parameters
    ----------
    motion : Motion
        A motion made by :func:`a2b.motion`.
    omega : array_like, shape (N,)
        Rotation angles about the screw axis, in radians, measured from A.

    Returns
    -------
    ndarray, shape (N,), or None
        The motion's :meth:`~a2b.motions.base.Motion.transmission`: the sine of Theorem 1 for
        a Darboux motion, the tangent of eq. 17 and 18 for a cubic one, the line
        ``z = d ω / φ`` of the screw motion. ``None`` when the motion has no transmission
        curve in the form ``z(ω)``: a pure translation (``φ = 0``) and the cubic motion in
        the ``given`` frame (not in a cylinder group).

    References
    ----------
    H.-P. Schröcker, *From A to B*, Theorem 1, eq. 17 and 18, Theorem 2.
    """
    omega = np.asarray(omega, dtype=float)
    if motion.frame.phi == 0.0:
        return None
    return motion.transmission(omega)


def family_members(
    motion, kind: str | None = None
) -> tuple[str, list[tuple[float, object]], float]:
    """The one-parameter family of motions through A and B that ``motion`` belongs to.

    Parameters
    ----------
    motion : Motion
        A darboux or cubic (canonical frame) motion.
    kind : str, optional
        What varies, one of the motion's ``family_kinds`` (the first by default). darboux:
        ``"delta"``, the fiber offset δ. cubic: ``"ab"``, the ratio ``(1 + b) / (1 + a)``
        with ``a`` fixed, which alone decides ``z(t)`` (eq. 18); or ``"m"``, the ratio
        ``m3 : m0`` (through the weight ratio ``wB / wA``), which decides ``ω(t)`` (eq. 17).

    Returns
    -------
    name : str
        The varied parameter, for labels: ``"δ"``, ``"(1+b)/(1+a)"`` or ``"m3/m0"``.
    members : list of (value, Motion)
        ``2 * FAMILY_SIDE + 1`` motions, ordered by value; the middle one has the chosen
        value. δ steps so that the curves' midpoints are a quarter of the length scale
        (|d|, else the size of the displacement, else 1) apart; the ratios step by factors of 2.
    chosen : float
        The value of the given motion.

    Raises
    ------
    ParameterError
        For a screw motion, a pure translation, a cubic motion in the given frame, or a
        ``kind`` the mode does not have.
    """
    from .api import motion as make_motion

    kinds = motion.family_kinds
    if not kinds or motion.frame.phi == 0.0:
        why = "a pure translation" if motion.frame.phi == 0.0 else f"mode {motion.mode}"
        raise ParameterError(f"there is no family of transmission curves to draw for {why}")
    kind = kind or kinds[0]
    if kind not in kinds:
        raise ParameterError(
            f"a {motion.mode} family varies {' or '.join(kinds)}, not {quoted(kind)}"
        )
    name, members, chosen = motion.family(kind, FAMILY_SIDE)
    start, end = motion.start, motion.end
    return (
        name,
        [(value, make_motion(start, end, motion.mode, **params)) for value, params in members],
        chosen,
    )


def in_cylinder_group(frame, matrices, tol: float = CYLINDER_TOL) -> bool:
    """Whether every pose of ``matrices`` (N, 4, 4) is in the cylinder group of the frame's A and B.

    A pose X is in it when ``X A⁻¹`` is a rotation about and a translation along the screw
    axis ``(u, c)``: its rotation axis is ``u`` and its translation is ``(I − R) c + z u``.
    """
    from .poses import quat_trans_from_matrices, rotations_from_quaternions
    from .study import quat_conj, quat_mul

    quat, trans = quat_trans_from_matrices(np.asarray(matrices, dtype=float))
    rel = quat_mul(quat, quat_conj(frame.p_start))
    u, c = frame.axis_direction, frame.axis_point
    vec = rel[..., 1:]
    off_axis = vec - (vec @ u)[..., None] * u
    rot = rotations_from_quaternions(rel)
    t_e = trans - rot @ frame.t_start
    expected = c - rot @ c + (t_e @ u)[..., None] * u
    scale = max(1.0, float(np.abs(t_e).max()), float(np.abs(c).max()))
    rot_res = float(np.abs(off_axis).max(initial=0.0))
    trans_res = float(np.abs(t_e - expected).max(initial=0.0)) / scale
    return rot_res <= tol and trans_res <= tol


@dataclass
class Curve:
    """A track's transmission curve: its samples ``(omega, z)`` and, for a motion of a mode,
    its closed form ``closed`` over ``dense`` (None when there is none)."""

    track: Track
    omega: np.ndarray
    z: np.ndarray
    dense: np.ndarray | None
    closed: np.ndarray | None


def transmission_curve(scene: Scene, track: Track, margin: float = 0.0) -> Curve:
    """The transmission curve of ``track`` (in the cylinder group), the closed form drawn
    ``margin`` times the ω range beyond both ends."""
    omega, z = scene.frame.transmission(track.mats)
    lo, hi = float(omega[0]), float(omega[-1])
    dense = closed = None
    if track.motion is not None and hi != lo:
        extra = margin * (hi - lo)
        dense = np.linspace(lo - extra, hi + extra, DENSE)
        closed = closed_form_z(track.motion, dense)
    return Curve(track, omega, z, dense, closed)


# -- sizes and the screw axis ------------------------------------------------------------------


def _nice(x: float) -> float:
    """The number 1, 2 or 5 × 10^k nearest below ``x``."""
    exp = math.floor(math.log10(x))
    base = x / 10**exp
    return (5 if base >= 5 else 2 if base >= 2 else 1) * 10.0**exp


def _check_span(origins: np.ndarray) -> None:
    """Refuse origins ``(N, 3)`` whose span overflows a double (±1.5e308)."""
    with np.errstate(over="ignore", invalid="ignore"):
        span = np.ptp(origins, axis=0)
    if not np.isfinite(span).all():
        raise ParameterError(
            f"the poses reach coordinates of {float(np.abs(origins).max()):.3g}, too far apart "
            "to draw: their span overflows a double"
        )


def default_axis_length(tracks: list[Track]) -> float:
    """1, unless the origins span more than 50 units or less than 1/50: then a round number
    near a quarter of their span."""
    origins = np.concatenate([t.mats[:, :3, 3] for t in tracks])
    extent = float(np.ptp(origins, axis=0).max())
    if extent == 0.0 or extent / 50 <= 1.0 <= 50 * extent:
        return 1.0
    return _nice(extent / 4)


def body_points(points, axis_length: float) -> tuple[np.ndarray, list[str], bool]:
    """The body points ``(K, 3)``, their names, and whether they are the default axis tips."""
    if points is None:
        pts = axis_length * np.eye(3)
        return pts, [f"{name}-axis tip" for name in "xyz"], True
    pts = np.asarray(points, dtype=float)
    if pts.ndim == 1:
        pts = pts[None]
    if pts.ndim != 2 or pts.shape[1] != 3 or pts.shape[0] == 0:
        raise ParameterError(f"points must have shape (K, 3), got {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise ParameterError("points contain NaN or infinity")
    names = [f"({', '.join(number_text(v) for v in p)})" for p in pts]
    return pts, names, False


def screw_axis_segment(frame, lo: np.ndarray, hi: np.ndarray) -> np.ndarray | None:
    """The part of the screw axis inside the box ``[lo, hi]`` (2, 3), or None if it misses it."""
    u, c = frame.axis_direction, frame.axis_point
    s_min, s_max = -np.inf, np.inf
    for i in range(3):
        if abs(u[i]) < 1e-12:
            if not lo[i] <= c[i] <= hi[i]:
                return None
            continue
        s1, s2 = sorted(((lo[i] - c[i]) / u[i], (hi[i] - c[i]) / u[i]))
        s_min, s_max = max(s_min, s1), min(s_max, s2)
    if not s_min < s_max:
        return None
    return np.stack([c + s_min * u, c + s_max * u])


__all__ = [
    "ANGLE_UNITS",
    "Curve",
    "Scene",
    "Track",
    "body_points",
    "closed_form_z",
    "curve_title",
    "default_axis_length",
    "family_members",
    "in_cylinder_group",
    "make_scene",
    "make_tracks",
    "screw_axis_segment",
    "transmission_curve",
]
