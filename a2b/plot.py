"""Figures: the paper's three pictures of a motion, for any two poses (figures 1 and 3).

:func:`plot_motions` draws one figure with three panels:

1. **Moving frame.** The moving frame at a few instants (``instants``, default 8), its axes as
   arrows (x red, y green, z blue; between A and B one colour per motion when several are
   compared), and the screw axis of ``B A⁻¹`` dashed.
2. **Trajectories.** The trajectories of a few body points from A to B: by default the tips of
   the moving frame's axes, otherwise the points the caller gives in body coordinates.
3. **Transmission curve.** In canonical coordinates (``docs/math.md``): the rotation angle ω about
   and the translation z along the screw axis, both relative to A, so that A is ``(0, 0)`` and
   B is ``(φ, d)``. The engine's samples are drawn as dots and the closed form as a line
   through them: the sine ``z = z0 + λ sin(ω + κ)`` of a Darboux motion (Theorem 1), the
   tangent of eq. 17 and 18 for a cubic circular motion (Theorem 2) and the straight line
   ``z = d ω / φ`` of the screw motion. With ``family=True`` the one-parameter family of
   transmission curves through A and B is drawn behind the chosen member.

matplotlib is imported by the functions of this module when they draw, never on import, and
only through the Agg-based :class:`matplotlib.figure.Figure` (no pyplot, no GUI), so plotting
works headless and leaves matplotlib's global state alone.

Every drawn line carries a ``gid`` (written as ``id`` into SVG files) so that its data can be
found again: ``frame:<label>:<i>:<axis>`` (the arrow of axis x, y or z at instant ``i``; the
instants at A and B are drawn once, as ``frame:A:<axis>`` and ``frame:B:<axis>``),
``trajectory:<label>:<k>`` (body point ``k``), ``screw-axis``,
``transmission-samples:<label>``, ``transmission-closed-form:<label>`` and
``family:<label>:<j>`` (family member ``j``). ``<label>`` is the motion's label, the mode name
for the built-in modes.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from .errors import A2bError, ParameterError

ANGLE_UNITS = ("deg", "rad")

#: Output formats by file suffix.
FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}

#: Colours of the built-in modes when several are compared (chosen to be told apart from the
#: red, green and blue of the frame axes and by most colour-blind readers).
MODE_COLOURS = {"darboux": "#6a3d9a", "cubic": "#e66101", "screw": "#4d4d4d"}
_OTHER_COLOURS = ("#1b9e77", "#a6761d", "#e7298a", "#386cb0", "#666600")
AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")
A_COLOUR, B_COLOUR = "#b2182b", "#2166ac"

#: Font sizes (points) of tick labels, axis labels, panel titles, legends and the figure's title:
#: readable at the default sizes, 15 × 5.2 and (compare) 15 × 9.6 inches, at 100 dpi.
TICK_SIZE, LABEL_SIZE, TITLE_SIZE, LEGEND_SIZE, SUPTITLE_SIZE = 9, 11, 13, 10, 15

#: Relative tolerance for a sampled motion to count as a motion in the cylinder group of A and B.
CYLINDER_TOL = 1e-8

#: Family members on each side of the chosen one.
FAMILY_SIDE = 3


class MissingDependencyError(A2bError, ImportError):
    """matplotlib is not installed. An :class:`A2bError` (the CLI reports it in one line) and an
    :class:`ImportError` (for library callers who test for it)."""


def require_matplotlib():
    """Import matplotlib with the Agg backend and return it, or raise a clear error.

    Raises
    ------
    MissingDependencyError
        When matplotlib is not installed; the message says ``pip install 'a2b-motions[plot]'``.
    """
    try:
        import matplotlib
    except ImportError as exc:
        raise MissingDependencyError(
            "plotting needs matplotlib, which is not installed: pip install 'a2b-motions[plot]'"
        ) from exc
    return matplotlib


def figure_format(path) -> str:
    """The output format (``"png"``, ``"svg"`` or ``"pdf"``) for the suffix of ``path``.

    Raises
    ------
    ParameterError
        For any other suffix, naming the ones that work.
    """
    suffix = os.path.splitext(os.fspath(path))[1].lower()
    if suffix not in FORMATS:
        shown = f"suffix {suffix!r}" if suffix else "no suffix"
        raise ParameterError(
            f"cannot tell the figure format from {os.fspath(path)!r} ({shown}); "
            "use a file name ending in .png, .svg or .pdf"
        )
    return FORMATS[suffix]


def write_figure(figure, fh, fmt: str, *, dpi: float | None = None) -> None:
    """Render ``figure`` to the binary file handle ``fh`` as ``fmt`` (png, svg or pdf).

    The handle is not closed. Dates and the software version are left out of the metadata
    so that the same figure gives the same bytes.
    """
    if fmt not in FORMATS.values():
        raise ParameterError(f"unknown figure format {fmt!r}; expected png, svg or pdf")
    metadata = {"png": {"Software": None}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}[
        fmt
    ]
    matplotlib = require_matplotlib()
    with matplotlib.rc_context({"svg.hashsalt": "a2b"}):
        figure.savefig(fh, format=fmt, dpi=dpi, metadata=metadata)


# -- the data of one plotted motion ----------------------------------------------------------


@dataclass
class _Track:
    label: str
    mode: str | None
    motion: object | None  # an a2b Motion, or None for a sampled motion
    mats: np.ndarray  # (N, 4, 4) samples
    inst: np.ndarray  # (K, 4, 4) the instants shown in the frame panel
    colour: str
    params: dict = field(default_factory=dict)
    source: object | None = None  # the object sampled, when it is no mode (e.g. a BezierMotion)


def _format_number(x: float) -> str:
    text = f"{x:.3g}"
    return "0" if text in ("-0", "0") else text.replace("-", "−")


def _angle_text(angle: float, unit: str) -> str:
    if unit == "deg":
        return f"{_format_number(math.degrees(angle))}°"
    return f"{_format_number(angle)} rad"


def _param_text(value) -> str:
    if isinstance(value, (bool, str)):
        return str(value)
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        return _format_number(float(arr))
    return "(" + ", ".join(_format_number(v) for v in arr.ravel()) + ")"


def _as_tracks(start, end, motions, samples: int, instants: int) -> list[_Track]:
    from .api import MODES
    from .api import motion as make_motion
    from .motions.base import Motion
    from .poses import check_matrices

    one_pair = isinstance(motions, tuple) and len(motions) == 2 and isinstance(motions[0], str)
    if (
        one_pair
        or isinstance(motions, (str, Motion))
        or callable(getattr(motions, "matrices", None))
    ):
        motions = [motions]
    ts = np.linspace(0.0, 1.0, samples)
    t_inst = np.linspace(0.0, 1.0, instants)
    tracks = []
    others = iter(_OTHER_COLOURS * 4)
    for entry in motions:
        if isinstance(entry, str):
            entry = (entry, {})
        if isinstance(entry, Motion):
            mode, obj, params, label = entry.mode, entry, {}, entry.mode
        elif callable(getattr(entry, "matrices", None)):  # e.g. an a2b.motions.bezier.BezierMotion
            label = getattr(entry, "kind", None) or type(entry).__name__
            mode, obj, params = None, entry, {}
        elif isinstance(entry, tuple) and len(entry) == 2 and isinstance(entry[0], str):
            label, what = entry
            if isinstance(what, Mapping):
                if label not in MODES:
                    raise ParameterError(
                        f"unknown mode {label!r}; expected one of {', '.join(MODES)} "
                        "(or a (label, callable) or (label, matrices) pair)"
                    )
                params = {k: v for k, v in what.items() if v is not None}
                mode, obj = label, make_motion(start, end, label, **params)
            else:
                mode, obj, params = None, what, {}
        else:
            raise ParameterError(
                "each motion to plot is a mode name, a (mode, parameters) pair, an a2b Motion, "
                f"or a (label, callable) or (label, matrices) pair; got {type(entry).__name__}"
            )
        if hasattr(obj, "matrices") and callable(obj.matrices):
            mats, inst = obj.matrices(ts), obj.matrices(t_inst)
        elif callable(obj):
            mats = check_matrices(obj(ts))
            inst = check_matrices(obj(t_inst))
            if mats.shape != (samples, 4, 4) or inst.shape != (instants, 4, 4):
                raise ParameterError(
                    f"the sampler of {label!r} must return (len(ts), 4, 4) matrices, "
                    f"got shape {mats.shape} for {samples} parameters"
                )
        else:
            mats = check_matrices(obj)
            if mats.ndim != 3 or mats.shape[0] < 2:
                raise ParameterError(
                    f"the samples of {label!r} must have shape (N, 4, 4) with N ≥ 2, got "
                    f"{mats.shape}"
                )
            picks = np.round(
                np.linspace(0, mats.shape[0] - 1, min(instants, mats.shape[0]))
            ).astype(int)
            inst = mats[picks]
        colour = MODE_COLOURS.get(mode) if mode else None
        if colour is None or any(t.colour == colour for t in tracks):
            colour = next(others)
        source = None if mode or not hasattr(obj, "matrices") else obj
        tracks.append(
            _Track(label, mode, obj if mode else None, mats, inst, colour, params, source)
        )
    if not tracks:
        raise ParameterError("nothing to plot: give at least one motion")
    labels = [t.label for t in tracks]
    if len(set(labels)) != len(labels):
        # The same mode twice: tell them apart by their parameters, or number them.
        for i, t in enumerate(tracks):
            if labels.count(t.label) > 1:
                given = ", ".join(f"{k}={_param_text(v)}" for k, v in t.params.items())
                t.label = f"{t.label} ({given or 'defaults'})"
        labels = [t.label for t in tracks]
        for i, t in enumerate(tracks):
            if labels.count(t.label) > 1:
                t.label = f"{t.label} #{i + 1}"
    return tracks


# -- closed forms and families ---------------------------------------------------------------


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
        ``None`` when the motion has no transmission curve in the form ``z(ω)``: a pure
        translation (``φ = 0``) and the cubic motion in the ``given`` frame (not in a cylinder
        group). Otherwise, with ``φ`` and ``d`` the angle and translation of ``B A⁻¹``:

        * darboux: the sine of Theorem 1 (``docs/math.md``, correction 4),

          .. math::

             z = \\frac d2
               + \\frac{\\frac d2 \\sin(ω − φ/2) − δ (\\cos(ω − φ/2) − \\cos(φ/2))}{\\sin(φ/2)}

          with ``φ`` replaced by ``φ − 2π`` for the long way round;
        * cubic: eq. 17 solved for t and put into eq. 18, a scaled and shifted tangent:

          .. math:: t = \\frac{−2 m_0 \\sin\\frac ω2}{Q \\sin\\frac ω2 + P \\cos\\frac ω2},\\quad
                    z = \\frac{t d (1 + b)}{(1 − t)(1 + a) + t (1 + b)}

          where ``P = m3 (cos φ − 1) − m0 sin φ`` and ``Q = m0 (cos φ − 1) + m3 sin φ``
          (NaN where the tangent has its pole);
        * screw: the straight line ``z = d ω / φ``.

    References
    ----------
    H.-P. Schröcker, *From A to B*, Theorem 1, eq. 17 and 18, Theorem 2.
    """
    omega = np.asarray(omega, dtype=float)
    frame = motion.frame
    if frame.phi == 0.0:
        return None
    if motion.mode == "darboux":
        return motion.transmission(omega)
    if motion.mode == "screw":
        return frame.d * omega / frame.phi
    if motion.mode == "cubic":
        if motion.frame_name != "canonical":
            return None
        m0, m3 = motion.canonical_m()
        phi = frame.phi
        p = m3 * (math.cos(phi) - 1) - m0 * math.sin(phi)
        q = m0 * (math.cos(phi) - 1) + m3 * math.sin(phi)
        sin_h, cos_h = np.sin(omega / 2), np.cos(omega / 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = -2 * m0 * sin_h / (q * sin_h + p * cos_h)
            z = motion.z_of_t(t)
        return np.where(np.isfinite(z), z, np.nan)
    return None


def family_members(
    motion, kind: str | None = None
) -> tuple[str, list[tuple[float, object]], float]:
    """The one-parameter family of motions through A and B that ``motion`` belongs to.

    Parameters
    ----------
    motion : Motion
        A darboux or cubic (canonical frame) motion.
    kind : {"delta", "ab", "m"}, optional
        What varies. darboux: ``"delta"``, the fiber offset δ (the default). cubic: ``"ab"``
        (the default), the ratio ``(1 + b) / (1 + a)`` with ``a`` fixed, which alone decides
        ``z(t)`` (eq. 18); or ``"m"``, the ratio ``m3 : m0`` (through the weight ratio
        ``wB / wA``), which decides ``ω(t)`` (eq. 17).

    Returns
    -------
    name : str
        The varied parameter, for labels: ``"δ"``, ``"b"`` or ``"m3/m0"``.
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

    frame = motion.frame
    mode = motion.mode
    if mode not in ("darboux", "cubic") or frame.phi == 0.0:
        why = "a pure translation" if frame.phi == 0.0 else f"mode {mode}"
        raise ParameterError(f"there is no family of transmission curves to draw for {why}")
    kinds = {"darboux": ("delta",), "cubic": ("ab", "m")}[mode]
    kind = kind or kinds[0]
    if kind not in kinds:
        raise ParameterError(f"a {mode} family varies {' or '.join(kinds)}, not {kind!r}")
    ks = range(-FAMILY_SIDE, FAMILY_SIDE + 1)
    start, end = motion.start, motion.end
    if mode == "darboux":
        scale = abs(frame.d) or float(np.linalg.norm(frame.t_disp)) or 1.0
        step = 0.25 * scale / abs(math.tan(motion.phi_eff / 4))
        chosen = motion.delta
        members = [
            (
                chosen + k * step,
                make_motion(
                    start, end, "darboux", delta=chosen + k * step, long_way=motion.long_way
                ),
            )
            for k in ks
        ]
        return "δ", members, chosen
    if motion.frame_name != "canonical":
        raise ParameterError(
            "a cubic motion in the given frame is not in a cylinder group and has no transmission "
            "curve"
        )
    a = motion.psi_a - 1.0
    if kind == "ab":
        chosen = motion.psi_b / motion.psi_a
        members = [
            (
                chosen * 2.0**k,
                make_motion(
                    start, end, "cubic", m=motion.m, a=a, b=motion.psi_a * chosen * 2.0**k - 1.0
                ),
            )
            for k in ks
        ]
        return "(1+b)/(1+a)", members, chosen
    m0, m3 = motion.canonical_m()
    c = float(frame.r[0])
    s = float(np.linalg.norm(frame.r[1:]))
    ratio = (m0 * c + m3 * s) / m0  # wB / wA
    members = []
    for k in ks:
        m = np.array(motion.m, dtype=float)
        m[3] = m0 * (ratio * 2.0**k - c) / s
        members.append(
            (m[3] / m0, make_motion(start, end, "cubic", m=m, a=a, b=motion.psi_b - 1.0))
        )
    return "m3/m0", members, m3 / m0


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


def essential_parameters(motion, angle_unit: str = "deg") -> str:
    """A one-line summary of a motion's essential parameters, as in the figure's title."""
    info = motion.describe()
    if motion.mode == "darboux":
        if motion.frame.phi == 0.0:
            text = "pure translation, δ has no effect"
        else:
            text = f"δ = {_format_number(info['delta'])}"
            if info.get("kappa") is not None:
                text += (
                    f", z0 = {_format_number(info['z0'])}, λ = {_format_number(info['lam'])}, "
                    f"κ = {_angle_text(info['kappa'], angle_unit)}"
                )
        return text + (", long way round" if info["long_way"] else "")
    if motion.mode == "cubic":
        text = (
            f"m0:m3 = {_format_number(info['m0'])}:{_format_number(info['m3'])}, "
            f"a = {_format_number(info['a'])}, b = {_format_number(info['b'])}"
        )
        return text + (", given frame" if info["frame"] == "given" else "")
    if motion.mode == "screw":
        pitch = info["pitch"]
        return "pure translation" if pitch is None else f"pitch = {_format_number(pitch)} per rad"
    return ""


# -- drawing ---------------------------------------------------------------------------------


def _nice(x: float) -> float:
    """The number 1, 2 or 5 × 10^k nearest below ``x``."""
    exp = math.floor(math.log10(x))
    base = x / 10**exp
    return (5 if base >= 5 else 2 if base >= 2 else 1) * 10.0**exp


def _default_axis_length(tracks) -> float:
    origins = np.concatenate([t.mats[:, :3, 3] for t in tracks])
    extent = float(np.ptp(origins, axis=0).max())
    if extent == 0.0 or extent / 50 <= 1.0 <= 50 * extent:
        return 1.0
    return _nice(extent / 4)


def _body_points(points, axis_length: float) -> tuple[np.ndarray, list[str], bool]:
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
    names = [f"({', '.join(_format_number(v) for v in p)})" for p in pts]
    return pts, names, False


#: The largest coordinate drawn: matplotlib squares coordinates in its 3-D transforms.
DRAWABLE = 1e100


def _set_equal_3d(ax, points: np.ndarray, length_label: str) -> tuple[np.ndarray, np.ndarray]:
    """Cube limits around ``points`` and an equal box aspect; returns the cube's corners."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    with np.errstate(over="ignore", invalid="ignore"):
        centre = lo / 2 + hi / 2
        half = max(float((hi / 2 - lo / 2).max()), 1e-9) * 1.08
        corners = np.concatenate([centre - half, centre + half])
    if not (np.isfinite(corners).all() and np.abs(corners).max() <= DRAWABLE):
        raise ParameterError(
            f"the drawing reaches coordinates of {float(np.nanmax(np.abs(corners))):.3g}, "
            f"beyond the {DRAWABLE:g} that matplotlib's transforms can carry; give smaller "
            "body points or poses"
        )
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1.0, 1.0, 1.0), zoom=1.08)
    from matplotlib.ticker import MaxNLocator

    for axis, name in ((ax.xaxis, "x"), (ax.yaxis, "y"), (ax.zaxis, "z")):
        axis.set_major_locator(MaxNLocator(4))
        axis.set_label_text(f"{name}{length_label}", fontsize=LABEL_SIZE)
        axis.labelpad = 9
    ax.tick_params(labelsize=TICK_SIZE, pad=1)
    return centre - half, centre + half


def _draw_frame(ax, pose: np.ndarray, length: float, colours, gid: str, **style) -> np.ndarray:
    """The axes of one pose as three arrows; returns their origin and tips (4, 3)."""
    origin = pose[:3, 3]
    style = {"arrow_length_ratio": 0.22, **style}
    for j, name in enumerate("xyz"):
        arrow = ax.quiver(*origin, *(length * pose[:3, j]), color=colours[j], **style)
        arrow.set_gid(f"{gid}:{name}")
    return np.vstack([origin, origin + length * pose[:3, :3].T])


def _draw_frames(ax, track: _Track, ends, length: float, single: bool) -> list:
    """The moving frame of ``track`` at its instants, except where it is at A or B (``ends``)."""
    drawn = []
    last = len(track.inst) - 1
    for i, pose in enumerate(track.inst):
        if (i == 0 and np.allclose(pose, ends[0], atol=1e-9)) or (
            i == last and np.allclose(pose, ends[1], atol=1e-9)
        ):
            continue  # drawn once, as A or B
        # Several motions: one colour each, and no arrow heads, which would clutter the view.
        style = (
            {"linewidth": 1.3}
            if single
            else {"linewidth": 1.1, "alpha": 0.85, "arrow_length_ratio": 0.0}
        )
        colours = AXIS_COLOURS if single else (track.colour,) * 3
        drawn.append(_draw_frame(ax, pose, length, colours, f"frame:{track.label}:{i}", **style))
    (path,) = ax.plot(
        *track.mats[:, :3, 3].T,
        color="0.35" if single else track.colour,
        linewidth=1.0,
        alpha=0.8,
    )
    path.set_gid(f"origin:{track.label}")
    return drawn


def _screw_axis_segment(frame, lo: np.ndarray, hi: np.ndarray) -> np.ndarray | None:
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


def plot_motions(
    start,
    end,
    motions="darboux",
    *,
    points=None,
    family: bool | str = False,
    angle_unit: str = "deg",
    length_unit: str | None = None,
    samples: int = 61,
    instants: int = 8,
    axis_length: float | None = None,
    figsize: tuple[float, float] | None = None,
    title: str | None = None,
    marks=None,
):
    """Draw the moving frame, the trajectories and the transmission curve of motions from A to B.

    Parameters
    ----------
    start, end : array_like, shape (4, 4)
        The poses A and B (robotics layout). They define the screw axis of ``B A⁻¹`` and the
        canonical coordinates of the transmission panel.
    motions : str, tuple, Motion, callable or sequence of these
        What to draw; several entries are overlaid, one colour each, with a legend (the
        picture for choosing between interpolants). Each entry is one of

        * a mode name, ``"darboux"``, ``"cubic"`` or ``"screw"``;
        * a pair ``(mode, parameters)``, the parameters of :func:`a2b.motion` as a dict;
        * a :class:`a2b.motions.base.Motion` made by :func:`a2b.motion`;
        * any other object with a ``matrices(ts)`` method, such as an
          :class:`a2b.motions.bezier.BezierMotion`, labelled by its ``kind`` attribute;
        * a pair ``(label, sampler)``: any callable taking ``ts`` of shape ``(N,)`` in
          ``[0, 1]`` and returning robotics matrices ``(N, 4, 4)`` (for instance a Bézier
          motion through several control poses);
        * a pair ``(label, matrices)``: precomputed samples ``(N, 4, 4)``, taken as equally
          spaced in t; the instants of the frame panel are the nearest samples.

        A sampler or samples get the transmission panel only when every sample lies in the
        cylinder group of A and B (:func:`in_cylinder_group`), and then without a closed form.
        Motions outside the cylinder group (also the cubic motion in the ``given`` frame) are
        left out of that panel and named in a note under it; when no motion is in the
        group, the panel is omitted and the figure has two panels.
    points : array_like, shape (K, 3), optional
        Body points (coordinates in the moving frame) whose trajectories are drawn. Default:
        the tips of the moving frame's axes, at distance ``axis_length`` from its origin.
    family : bool or {"delta", "ab", "m"}
        Also draw the one-parameter family of transmission curves through A and B that each
        darboux and cubic motion belongs to (:func:`family_members`), with the chosen member
        highlighted. ``True`` varies δ for darboux and ``(1 + b) / (1 + a)`` for cubic;
        ``"m"`` varies ``m3 : m0`` for cubic instead.
    angle_unit : {"deg", "rad"}
        Unit of ω on the transmission panel's axis and of the angles in the title.
    length_unit : str, optional
        Name of the poses' length unit for the axis labels, e.g. ``"m"``. Default: the labels
        name only the coordinate (x, y, z) and the poses' own unit is meant.
    samples : int
        Number of equally spaced parameters ``ts = linspace(0, 1, samples)`` at which each
        motion is sampled for the trajectories and the transmission samples (at least 2).
    instants : int
        Number of equally spaced instants at which the moving frame is drawn (at least 2).
    axis_length : float, optional
        Length of the drawn frame axes in the poses' length unit. Default 1 (the frame's
        unit axes), unless the origins of the moving frame span more than 50 units or less
        than 1/50 of a unit, in which case a round number near a quarter of that span.
    figsize : (float, float), optional
        Figure size in inches; default 15 × 5.2 for three panels, 10.5 × 5.2 for two.
    title : str, optional
        Replaces the generated title (the modes, their essential parameters, φ and d; for a
        single Bézier motion or spline, its kind, degree or segments and space).
    marks : sequence of (str, array_like (4, 4)), optional
        Further poses to mark with a label, such as the inner control poses of a Bézier motion
        or the key poses of a spline: a thin frame and the label at its origin, in both 3-D
        panels (``gid`` ``mark:<label>:<axis>``).

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot; save it with :func:`write_figure` or ``figure.savefig``. Its
        axes are, in order, the frame panel, the trajectory panel and (if drawn) the
        transmission panel; the lines carry the ``gid`` values listed in the module docstring.

    Raises
    ------
    A2bError
        Invalid poses or parameters (from :func:`a2b.motion`), invalid ``points``,
        ``angle_unit``, ``samples`` or ``instants``, a sampler returning the wrong shape.
    MissingDependencyError
        When matplotlib is not installed.

    Examples
    --------
    >>> import numpy as np
    >>> from a2b.plot import plot_motions, write_figure
    >>> b = np.eye(4); b[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]; b[:3, 3] = [1, 0, 1]
    >>> fig = plot_motions(np.eye(4), b, ["darboux", ("cubic", {"a": 0.5}), "screw"])
    >>> len(fig.axes)
    3
    """
    from .frames import screw_frame
    from .poses import check_matrices

    if angle_unit not in ANGLE_UNITS:
        raise ParameterError(f"unknown angle unit {angle_unit!r}; expected deg or rad")
    if family not in (False, True, "delta", "ab", "m"):
        raise ParameterError(f"family must be True, False, 'delta', 'ab' or 'm', got {family!r}")
    for name, value in (("samples", samples), ("instants", instants)):
        if int(value) != value or value < 2:
            raise ParameterError(f"{name} must be an integer ≥ 2, got {value!r}")
    a = check_matrices(start)
    b = check_matrices(end)
    if a.shape != (4, 4) or b.shape != (4, 4):
        raise ParameterError("start and end must each be one 4x4 matrix")
    frame = screw_frame(a, b)
    tracks = _as_tracks(a, b, motions, int(samples), int(instants))
    if family and not any(t.mode in ("darboux", "cubic") for t in tracks):
        raise ParameterError("a family of transmission curves needs a darboux or cubic motion")
    if axis_length is None:
        axis_length = _default_axis_length(tracks)
    elif not (math.isfinite(axis_length) and axis_length > 0):
        raise ParameterError(f"axis_length must be a positive number, got {axis_length!r}")
    body, point_names, default_points = _body_points(points, float(axis_length))
    marked = [(str(label), check_matrices(pose)) for label, pose in (marks or ())]
    if any(pose.shape != (4, 4) for _, pose in marked):
        raise ParameterError("each mark is a (label, 4x4 pose) pair")

    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    single = len(tracks) == 1
    in_group = [in_cylinder_group(frame, t.mats) for t in tracks]
    has_transmission = any(in_group)
    length_label = f" [{length_unit}]" if length_unit else ""

    # One motion: three panels in a row. Several: a small frame panel per motion above the
    # trajectories and the transmission curve (their frames in one panel would be a tangle).
    if figsize is None:
        if single:
            figsize = (15.0, 5.2) if has_transmission else (10.5, 5.2)
        else:
            figsize = (max(15.0, 5.0 * len(tracks)), 9.6)
    fig = Figure(figsize=figsize, layout="constrained")
    # 3D panels draw their z label outside the box the layout knows: room between panels
    width, height = figsize
    fig.get_layout_engine().set(w_pad=min(0.12, 0.008 * width), h_pad=min(0.25, 0.05 * height),
                                wspace=0.06, hspace=0.06)  # fmt: skip
    FigureCanvasAgg(fig)
    if single:
        grid = fig.add_gridspec(1, 3 if has_transmission else 2)
        frame_axes = [fig.add_subplot(grid[0, 0], projection="3d")]
        ax_traj = fig.add_subplot(grid[0, 1], projection="3d")
        ax_trans = fig.add_subplot(grid[0, 2]) if has_transmission else None
    else:
        n = len(tracks)
        grid = fig.add_gridspec(2, 2 * n)
        frame_axes = [fig.add_subplot(grid[0, 2 * k : 2 * k + 2], projection="3d")
                      for k in range(n)]  # fmt: skip
        ax_traj = fig.add_subplot(grid[1, : n if has_transmission else 2 * n], projection="3d")
        ax_trans = fig.add_subplot(grid[1, n:]) if has_transmission else None
    ax_frames = frame_axes[0]

    # Panel 1: the moving frame at the instants, and panel 2: trajectories of body points.
    frame_pts, traj_pts = [], []
    styles = ("-", "--", ":", "-.")
    for k, track in enumerate(tracks):
        frame_pts += _draw_frames(frame_axes[k % len(frame_axes)], track, (a, b),
                                  float(axis_length), True)  # fmt: skip
        with np.errstate(over="ignore", invalid="ignore"):
            world = np.einsum("nij,kj->kni", track.mats[:, :3, :3], body)
            world += track.mats[None, :, :3, 3]
        if not np.isfinite(world).all():
            k = int(np.argmax(~np.isfinite(world).reshape(len(world), -1).all(axis=1)))
            raise ParameterError(
                f"the trajectory of the body point {point_names[k]} overflows double precision; "
                "give points of a size the poses can carry"
            )
        for k, path in enumerate(world):
            if single:
                colour = (
                    AXIS_COLOURS[k] if default_points else _OTHER_COLOURS[k % len(_OTHER_COLOURS)]
                )
                style = "-"
            else:
                colour, style = track.colour, styles[k % len(styles)]
            (line,) = ax_traj.plot(*path.T, color=colour, linestyle=style, linewidth=1.6)
            line.set_gid(f"trajectory:{track.label}:{k}")
            traj_pts.append(path)
    for pose, name in ((a, "A"), (b, "B")):
        for ax in frame_axes:
            frame_pts.append(
                _draw_frame(ax, pose, axis_length, AXIS_COLOURS, f"frame:{name}", linewidth=2.4)
            )
        traj_pts.append(
            _draw_frame(
                ax_traj,
                pose,
                axis_length,
                AXIS_COLOURS,
                f"end-frame:{name}",
                linewidth=1.2,
                alpha=0.6,
            )
        )
    for j, (pose_label, pose) in enumerate(marked):
        # neighbouring marks label to alternate sides, so that close poses' labels do not meet
        side = {"ha": "left", "va": "top"} if j % 2 else {"ha": "right", "va": "bottom"}
        text = f"  {pose_label}" if j % 2 else f"{pose_label}  "
        for ax, pts, gid in ((ax_frames, frame_pts, "mark"), (ax_traj, traj_pts, "end-mark")):
            pts.append(
                _draw_frame(
                    ax,
                    pose,
                    axis_length,
                    AXIS_COLOURS,
                    f"{gid}:{pose_label}",
                    linewidth=1.0,
                    alpha=0.45,
                )
            )
            ax.scatter(*pose[:3, 3, None], color="0.25", s=14, depthshade=False, zorder=5)
            ax.text(*pose[:3, 3], text, color="0.25", fontsize=LABEL_SIZE, zorder=6, **side)
    # The screw axis of B A⁻¹ belongs to the modes and to motions about it, not to a curve
    # through other poses.
    show_axis = has_transmission or any(t.mode for t in tracks)
    for ax, pts in [(ax, frame_pts) for ax in frame_axes] + [(ax_traj, traj_pts)]:
        lo, hi = _set_equal_3d(ax, np.concatenate(pts), length_label)
        axis_seg = _screw_axis_segment(frame, lo, hi) if show_axis else None
        if axis_seg is not None:
            (line,) = ax.plot(*axis_seg.T, color="0.45", linestyle=(0, (6, 3)), linewidth=1.0)
            line.set_gid("screw-axis")
        # A's label left of its point, B's right: apart even where the two poses' origins meet
        for pose, text, colour, ha in ((a, "A  ", A_COLOUR, "right"), (b, "  B", B_COLOUR, "left")):
            ax.scatter(*pose[:3, 3, None], color=colour, s=28, depthshade=False, zorder=5)
            ax.text(*pose[:3, 3], text, color=colour, fontsize=13, fontweight="bold", ha=ha,
                    va="top", zorder=6)  # fmt: skip
        ax.view_init(elev=22, azim=-58)
    if single:
        ax_frames.set_title(f"Moving frame at {int(instants)} instants", fontsize=TITLE_SIZE)
    else:
        for ax, track in zip(frame_axes, tracks):
            ax.set_title(f"{track.label}: moving frame at {int(instants)} instants",
                         fontsize=TITLE_SIZE, color=track.colour)  # fmt: skip
    ax_traj.set_title("Trajectories of body points", fontsize=TITLE_SIZE)
    legend_axis = [
        Line2D([], [], color=AXIS_COLOURS[j], label=f"{n} axis") for j, n in enumerate("xyz")
    ]
    if show_axis:
        legend_axis.append(Line2D([], [], color="0.45", linestyle=(0, (6, 3)), label="screw axis"))
    ax_frames.legend(handles=legend_axis, loc="upper left", fontsize=LEGEND_SIZE, frameon=False)
    if single:
        handles = [
            Line2D([], [], color=line.get_color(), label=name)
            for line, name in zip(ax_traj.get_lines(), point_names)
        ]
    else:
        handles = [
            Line2D([], [], color="0.2", linestyle=styles[k % len(styles)], label=name)
            for k, name in enumerate(point_names)
        ]
    if default_points:
        points_title = (
            None if axis_length == 1 else f"axes drawn {_format_number(axis_length)} long"
        )
    else:
        points_title = "body point"
    ax_traj.legend(
        handles=handles,
        loc="upper left",
        fontsize=LEGEND_SIZE,
        frameon=False,
        title=points_title,
        title_fontsize=LEGEND_SIZE,
    )

    # Panel 3: the transmission curve in canonical coordinates.
    if ax_trans is not None:
        _draw_transmission(
            ax_trans, frame, tracks, in_group, family, angle_unit, length_label, single
        )

    # Title and legend.
    angles = f"φ = {_angle_text(frame.phi, angle_unit)}, d = {_format_number(frame.d)}"
    if title is None:
        if single and _curve_title(tracks[0]) is not None:
            title = _curve_title(tracks[0])
        elif single:
            track = tracks[0]
            what = f"{track.label} motion" if track.mode else track.label
            extra = (
                essential_parameters(track.motion, angle_unit) if track.motion is not None else ""
            )
            title = (
                f"{what}: {extra}   (A to B: {angles})" if extra else f"{what}   (A to B: {angles})"
            )
        else:
            title = f"{', '.join(t.label for t in tracks)} from A to B   ({angles})"
    fig.suptitle(title, fontsize=SUPTITLE_SIZE)
    if not has_transmission and show_axis:  # under the panels, in the room the layout keeps
        fig.supxlabel(
            "no transmission curve: the motion is not in the cylinder group of A and B "
            "(rotations about and translations along their screw axis)",
            fontsize=LEGEND_SIZE,
            color="0.3",
        )
    if not single:
        handles = []
        for track in tracks:
            extra = (
                essential_parameters(track.motion, angle_unit) if track.motion is not None else ""
            )
            handles.append(
                Line2D(
                    [],
                    [],
                    color=track.colour,
                    linewidth=2.5,
                    label=f"{track.label} ({extra})" if extra else track.label,
                )
            )
        fig.legend(
            handles=handles,
            loc="outside lower center",
            ncol=min(len(handles), 3),
            fontsize=LABEL_SIZE,
            frameon=False,
        )
    _keep_inside(fig)
    return fig


def _keep_inside(fig) -> None:
    """Constrained layout places a 3D panel before its projection places the axis labels, so
    a label can end up off the canvas: pad the layout by the overhang and draw again. (The
    labels are measured one by one: not every matplotlib counts them in a 3D panel's tight
    box.)"""
    from matplotlib.transforms import Bbox

    engine = fig.get_layout_engine()
    for _ in range(2):
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        boxes = [fig.get_tightbbox(renderer).transformed(fig.dpi_scale_trans)]
        for ax in fig.axes:
            for axis in (ax.xaxis, ax.yaxis, getattr(ax, "zaxis", None)):
                if axis is not None and axis.label.get_text():
                    boxes.append(axis.label.get_window_extent(renderer))
        tight = Bbox.union(boxes)  # pixels
        width, height = fig.bbox.width, fig.bbox.height
        over_x = max(0.0, -tight.x0, tight.x1 - width) / fig.dpi
        over_y = max(0.0, -tight.y0, tight.y1 - height) / fig.dpi
        if over_x == 0 and over_y == 0:
            return
        pads = engine.get()
        engine.set(w_pad=pads["w_pad"] + over_x + 0.02, h_pad=pads["h_pad"] + over_y + 0.02)


def _curve_title(track: _Track) -> str | None:
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


def _draw_transmission(ax, frame, tracks, in_group, family, angle_unit, length_label, single):
    from matplotlib.lines import Line2D

    scale = (lambda w: np.degrees(w)) if angle_unit == "deg" else (lambda w: np.asarray(w, float))
    notes, ends = [], []
    handles = []
    curves = []  # (track, omega, z) for limits
    for track, ok in zip(tracks, in_group):
        if not ok:
            notes.append(f"{track.label}: not in the cylinder group of A and B")
            continue
        omega, z = frame.transmission(track.mats)
        curves.append((omega, z))
        ends.append((omega[-1], z[-1]))
        lo, hi = float(omega[0]), float(omega[-1])
        motion = track.motion
        cf = None
        if motion is not None and hi != lo:
            margin = 0.12 * (hi - lo)
            dense = np.linspace(lo - margin, hi + margin, 241)
            cf = closed_form_z(motion, dense)
        span_z = max(float(np.ptp(z)), abs(frame.d), 1e-9)
        bound = (float(z.min()) - 0.6 * span_z, float(z.max()) + 0.6 * span_z)
        if family and motion is not None and motion.mode in ("darboux", "cubic") and cf is not None:
            kind = family if isinstance(family, str) else None
            if motion.mode == "darboux":
                kind = None if kind in ("ab", "m") else kind
            elif kind == "delta":
                kind = None
            name, members, _chosen = family_members(motion, kind)
            for j, (value, member) in enumerate(members):
                zf = closed_form_z(member, dense)
                zf = np.where((zf >= bound[0]) & (zf <= bound[1]), zf, np.nan)
                (line,) = ax.plot(
                    scale(dense),
                    zf,
                    color=track.colour if not single else "0.55",
                    alpha=0.35 if not single else 0.8,
                    linewidth=0.9,
                )
                line.set_gid(f"family:{track.label}:{j}")
            values = [v for v, _ in members]
            handles.append(
                Line2D(
                    [],
                    [],
                    color=track.colour if not single else "0.55",
                    linewidth=0.9,
                    label=f"{track.label if not single else 'family'}: {name} from "
                    f"{_format_number(min(values))} to {_format_number(max(values))}",
                )
            )
        if cf is not None:
            cf = np.where((cf >= bound[0]) & (cf <= bound[1]), cf, np.nan)
            (line,) = ax.plot(
                scale(dense), cf, color=track.colour, linewidth=2.4 if family else 1.8, zorder=3
            )
            line.set_gid(f"transmission-closed-form:{track.label}")
            form = {"darboux": "sine", "cubic": "tangent", "screw": "line"}[motion.mode]
            handles.append(
                Line2D(
                    [],
                    [],
                    color=track.colour,
                    linewidth=1.8,
                    label=f"{track.label}: closed form ({form})"
                    + (", chosen" if family and motion.mode != "screw" else ""),
                )
            )
        (line,) = ax.plot(
            scale(omega),
            z,
            linestyle="none",
            marker="o",
            markersize=3.2,
            color=track.colour,
            markeredgecolor="white",
            markeredgewidth=0.4,
            zorder=4,
        )
        line.set_gid(f"transmission-samples:{track.label}")
    handles.append(
        Line2D(
            [],
            [],
            linestyle="none",
            marker="o",
            markersize=4,
            color="0.3",
            label=f"samples of the motion{'s' if len(curves) > 1 else ''}",
        )
    )
    ax.plot([0.0], [0.0], marker="o", markersize=7, color=A_COLOUR, zorder=5)
    ax.annotate(
        "A",
        (0.0, 0.0),
        xytext=(-10, 6),
        textcoords="offset points",
        color=A_COLOUR,
        fontsize=13,
        fontweight="bold",
        ha="right",
    )
    shown = []
    for omega_b, z_b in ends:
        if any(abs(omega_b - o) < 1e-9 and abs(z_b - zz) < 1e-9 for o, zz in shown):
            continue
        shown.append((omega_b, z_b))
        ax.plot([scale(omega_b)], [z_b], marker="o", markersize=7, color=B_COLOUR, zorder=5)
        ax.annotate(
            "B",
            (scale(omega_b), z_b),
            xytext=(8, -14),
            textcoords="offset points",
            color=B_COLOUR,
            fontsize=13,
            fontweight="bold",
        )
    unit = "°" if angle_unit == "deg" else "rad"
    xlabel = f"ω, rotation about the screw axis [{unit}]"
    if notes:  # under the axis label, where the layout keeps room for it
        xlabel += "\n" + "\n".join(notes)
    ax.set_xlabel(xlabel, fontsize=LABEL_SIZE)
    ax.set_ylabel(f"z, translation along the screw axis{length_label}", fontsize=LABEL_SIZE)
    ax.tick_params(labelsize=TICK_SIZE)
    ax.set_title("Transmission curve (canonical coordinates)", fontsize=TITLE_SIZE)
    ax.grid(True, linewidth=0.4, alpha=0.5)
    ax.axhline(0.0, color="0.6", linewidth=0.6)
    ax.axvline(0.0, color="0.6", linewidth=0.6)
    ax.legend(handles=handles, fontsize=LEGEND_SIZE - 1, loc="best", frameon=True, framealpha=0.85)


# -- rates over time -----------------------------------------------------------------------------

#: The panels of :func:`plot_speeds`: the key of :meth:`a2b.timelaw.TimedMotion.rates` (and of
#: the limit drawn with it) and the axis label (``{L}`` the length unit).
SPEED_PANELS = (
    ("speed", "speed [{L}/s]"),
    ("accel", "accel. along path [{L}/s²]"),
    ("angular_speed", "angular speed [rad/s]"),
)


def plot_speeds(
    timed,
    *,
    limits: Mapping | None = None,
    length_unit: str | None = None,
    samples: int = 801,
    figsize: tuple[float, float] | None = None,
    title: str | None = None,
):
    """Draw the rates of timed motions over time: the speed of the time law's point, its
    acceleration along the path and the angular speed, three panels sharing the time axis.

    Parameters
    ----------
    timed : TimedMotion or mapping of label to TimedMotion
        Single timed motions (:func:`a2b.timing`); several are overlaid, one colour each
        (the mode colours for darboux, cubic and screw), the legend giving each duration and
        binding limit.
    limits : mapping, optional
        The limits to draw as dashed lines, by the keys of :data:`a2b.timelaw.LIMITS`
        (``speed``, ``accel``, ``angular_speed``; ``accel`` is drawn at ``±``).
    length_unit : str, optional
        The poses' length unit, for the axis labels (``length`` when not given).
    samples : int
        Samples per motion, evenly spaced in time over its duration.

    Lines carry a ``gid``: ``<key>:<label>`` (for example ``speed:darboux``) and
    ``limit:<key>``. Returns a :class:`matplotlib.figure.Figure`.
    """
    if not isinstance(timed, Mapping):
        motion = timed.motion
        timed = {getattr(motion, "mode", None) or getattr(motion, "kind", None) or "motion": timed}
    if not timed:
        raise ParameterError("plot_speeds needs at least one timed motion")
    if any(t.shape for t in timed.values()):
        raise ParameterError("plot_speeds draws single timed motions, not batches")
    if not (isinstance(samples, (int, np.integer)) and samples >= 2):
        raise ParameterError(f"samples must be an integer of at least 2, got {samples!r}")
    limits = dict(limits or {})
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize or (10.0, 7.5), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(SPEED_PANELS), 1, sharex=True)
    unit = length_unit or "length"
    others = iter(_OTHER_COLOURS * (1 + len(timed) // len(_OTHER_COLOURS)))
    for label, law in timed.items():
        colour = MODE_COLOURS.get(label) or next(others)
        times = law.times(samples=samples)
        rates = law.rates(times)
        binding = law.binding or "duration"
        legend = f"{label}: {float(law.duration):.4g} s, binding {binding.replace('_', ' ')}"
        for ax, (key, _) in zip(axes, SPEED_PANELS):
            ax.plot(times, rates[key], color=colour, lw=1.6, gid=f"{key}:{label}", label=legend)
    for ax, (key, text) in zip(axes, SPEED_PANELS):
        if limits.get(key) is not None:
            value = float(limits[key])
            for sign in (1, -1) if key == "accel" else (1,):
                ax.axhline(sign * value, color="0.45", lw=0.9, ls="--", gid=f"limit:{key}")
        ax.set_ylabel(text.replace("{L}", unit), fontsize=LABEL_SIZE)
        ax.tick_params(labelsize=TICK_SIZE)
        ax.grid(True, linewidth=0.4, alpha=0.5)
        ax.axhline(0.0, color="0.6", linewidth=0.6)
    axes[-1].set_xlabel("time [s]", fontsize=LABEL_SIZE)
    axes[0].legend(fontsize=LEGEND_SIZE, loc="best", frameon=True, framealpha=0.85)
    if title is None:
        first = next(iter(timed.values()))
        point = (
            "" if not np.any(first.point) else f" of ({', '.join(f'{x:g}' for x in first.point)})"
        )
        title = f"Speeds of the point{point} under the {first.profile.kind} time law"
        shown = ", ".join(f"max {k.replace('_', ' ')} {v:g}" for k, v in limits.items() if v)
        title += f": {shown}" if shown else ""
    fig.suptitle(title, fontsize=TITLE_SIZE)
    return fig


__all__ = [
    "ANGLE_UNITS",
    "FORMATS",
    "MissingDependencyError",
    "closed_form_z",
    "essential_parameters",
    "family_members",
    "figure_format",
    "in_cylinder_group",
    "plot_motions",
    "plot_speeds",
    "require_matplotlib",
    "write_figure",
]
