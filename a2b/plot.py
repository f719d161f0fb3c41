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

import os
from collections.abc import Mapping

import numpy as np

from .errors import MissingDependencyError, ParameterError, quoted
from .motions import REGISTRY
from .motions.text import number_text
from .scene import (
    A_COLOUR,
    AXIS_COLOURS,
    B_COLOUR,
    MODE_COLOURS,
    OTHER_COLOURS,
    Scene,
    Track,
    closed_form_z,
    family_members,
    make_scene,
    screw_axis_segment,
    transmission_curve,
)

#: Output formats by file suffix.
FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}

#: Font sizes (points) of tick labels, axis labels, panel titles, legends and the figure's title:
#: readable at the default sizes, 15 × 5.2 and (compare) 15 × 9.6 inches, at 100 dpi.
TICK_SIZE, LABEL_SIZE, TITLE_SIZE, LEGEND_SIZE, SUPTITLE_SIZE = 9, 11, 13, 10, 15

#: What ``family`` may vary: one of the modes' ``family_kinds``.
FAMILY_KINDS = tuple(dict.fromkeys(k for m in REGISTRY.values() for k in m.motion.family_kinds))


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
        shown = f"suffix {quoted(suffix)}" if suffix else "no suffix"
        raise ParameterError(
            f"cannot tell the figure format from {quoted(os.fspath(path))} ({shown}); "
            "use a file name ending in .png, .svg or .pdf"
        )
    return FORMATS[suffix]


def write_figure(figure, fh, fmt: str, *, dpi: float | None = None) -> None:
    """Render ``figure`` to the binary file handle ``fh`` as ``fmt`` (png, svg or pdf).

    The handle is not closed. Dates and the software version are left out of the metadata
    so that the same figure gives the same bytes.
    """
    if fmt not in FORMATS.values():
        raise ParameterError(f"unknown figure format {quoted(fmt)}; expected png, svg or pdf")
    metadata = {"png": {"Software": None}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}[
        fmt
    ]
    matplotlib = require_matplotlib()
    with matplotlib.rc_context({"svg.hashsalt": "a2b"}):
        figure.savefig(fh, format=fmt, dpi=dpi, metadata=metadata)


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


def _draw_frames(ax, track: Track, ends, length: float, single: bool) -> list:
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
        What to draw: a mode name, a ``(mode, parameters)`` pair, a Motion, a sampler or
        samples, or a sequence of these (:func:`a2b.scene.make_tracks`); several are
        overlaid, one colour each, with a legend (the picture for choosing between
        interpolants).

        A sampler or samples get the transmission panel only when every sample lies in the
        cylinder group of A and B (:func:`a2b.scene.in_cylinder_group`), and then without a
        closed form.
        Motions outside the cylinder group (also the cubic motion in the ``given`` frame) are
        left out of that panel and named in a note under it; when no motion is in the
        group, the panel is omitted and the figure has two panels.
    points : array_like, shape (K, 3), optional
        Body points (coordinates in the moving frame) whose trajectories are drawn. Default:
        the tips of the moving frame's axes, at distance ``axis_length`` from its origin.
    family : bool or {"delta", "ab", "m"}
        Also draw the one-parameter family of transmission curves through A and B that each
        darboux and cubic motion belongs to (:func:`a2b.scene.family_members`), with the
        chosen member highlighted. ``True`` varies δ for darboux and ``(1 + b) / (1 + a)``
        for cubic; ``"m"`` varies ``m3 : m0`` for cubic instead.
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
    kinds = ", ".join(repr(k) for k in FAMILY_KINDS[:-1]) + f" or {FAMILY_KINDS[-1]!r}"
    if family not in (False, True, *FAMILY_KINDS):
        raise ParameterError(f"family must be True, False, {kinds}, got {family!r}")
    scene = make_scene(start, end, motions, points=points, samples=samples, instants=instants,
                       axis_length=axis_length, marks=marks, angle_unit=angle_unit,
                       length_unit=length_unit)  # fmt: skip
    if family and not any(t.motion is not None and t.motion.family_kinds for t in scene.tracks):
        raise ParameterError("a family of transmission curves needs a darboux or cubic motion")
    require_matplotlib()
    fig, frame_axes, ax_traj, ax_trans = _figure(scene, figsize)
    frame_pts, traj_pts = _draw_motions(scene, frame_axes, ax_traj)
    _draw_ends_and_marks(scene, frame_axes, ax_traj, frame_pts, traj_pts)
    for ax, pts in [(ax, frame_pts) for ax in frame_axes] + [(ax_traj, traj_pts)]:
        _finish_3d(scene, ax, pts)
    _panel_titles(scene, frame_axes, ax_traj, int(instants))
    if ax_trans is not None:  # panel 3: the transmission curve in canonical coordinates
        _draw_transmission(ax_trans, scene, family)
    fig.suptitle(title if title is not None else scene.figure_title(), fontsize=SUPTITLE_SIZE)
    _figure_notes(fig, scene)
    _keep_inside(fig)
    return fig


def _figure(scene: Scene, figsize):
    """The figure and its panels: ``(figure, frame panels, trajectory panel, transmission
    panel or None)``. One motion: three panels in a row. Several: a small frame panel per
    motion above the trajectories and the transmission curve (their frames in one panel would
    be a tangle)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    tracks, single, has_transmission = scene.tracks, scene.single, scene.has_transmission
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
    return fig, frame_axes, ax_traj, ax_trans


_STYLES = ("-", "--", ":", "-.")


def _draw_motions(scene: Scene, frame_axes, ax_traj) -> tuple[list, list]:
    """Panel 1, the moving frame at the instants, and panel 2, the trajectories of the body
    points; returns the points drawn in each, for the limits."""
    frame_pts, traj_pts = [], []
    ends = (scene.start, scene.end)
    for k, track in enumerate(scene.tracks):
        frame_pts += _draw_frames(frame_axes[k % len(frame_axes)], track, ends,
                                  scene.axis_length, True)  # fmt: skip
        world = scene.trajectories(track)
        for k, path in enumerate(world):
            if scene.single:
                colour = (
                    AXIS_COLOURS[k]
                    if scene.default_points
                    else OTHER_COLOURS[k % len(OTHER_COLOURS)]
                )
                style = "-"
            else:
                colour, style = track.colour, _STYLES[k % len(_STYLES)]
            (line,) = ax_traj.plot(*path.T, color=colour, linestyle=style, linewidth=1.6)
            line.set_gid(f"trajectory:{track.label}:{k}")
            traj_pts.append(path)
    return frame_pts, traj_pts


def _draw_ends_and_marks(scene: Scene, frame_axes, ax_traj, frame_pts, traj_pts) -> None:
    """The frames of A and B in every 3-D panel, and the marked poses with their labels."""
    length = scene.axis_length
    for pose, name in ((scene.start, "A"), (scene.end, "B")):
        for ax in frame_axes:
            frame_pts.append(
                _draw_frame(ax, pose, length, AXIS_COLOURS, f"frame:{name}", linewidth=2.4)
            )
        traj_pts.append(_draw_frame(ax_traj, pose, length, AXIS_COLOURS, f"end-frame:{name}",
                                    linewidth=1.2, alpha=0.6))  # fmt: skip
    for j, (pose_label, pose) in enumerate(scene.marks):
        # neighbouring marks label to alternate sides, so that close poses' labels do not meet
        side = {"ha": "left", "va": "top"} if j % 2 else {"ha": "right", "va": "bottom"}
        text = f"  {pose_label}" if j % 2 else f"{pose_label}  "
        for ax, pts, gid in ((frame_axes[0], frame_pts, "mark"), (ax_traj, traj_pts, "end-mark")):
            pts.append(_draw_frame(ax, pose, length, AXIS_COLOURS, f"{gid}:{pose_label}",
                                   linewidth=1.0, alpha=0.45))  # fmt: skip
            ax.scatter(*pose[:3, 3, None], color="0.25", s=14, depthshade=False, zorder=5)
            ax.text(*pose[:3, 3], text, color="0.25", fontsize=LABEL_SIZE, zorder=6, **side)


def _finish_3d(scene: Scene, ax, pts: list) -> None:
    """Equal limits around what a 3-D panel shows, the screw axis, A and B, and the view."""
    lo, hi = _set_equal_3d(ax, np.concatenate(pts), scene.length_label)
    axis_seg = screw_axis_segment(scene.frame, lo, hi) if scene.show_axis else None
    if axis_seg is not None:
        (line,) = ax.plot(*axis_seg.T, color="0.45", linestyle=(0, (6, 3)), linewidth=1.0)
        line.set_gid("screw-axis")
    # A's label left of its point, B's right: apart even where the two poses' origins meet
    ends = ((scene.start, "A  ", A_COLOUR, "right"), (scene.end, "  B", B_COLOUR, "left"))
    for pose, text, colour, ha in ends:
        ax.scatter(*pose[:3, 3, None], color=colour, s=28, depthshade=False, zorder=5)
        ax.text(*pose[:3, 3], text, color=colour, fontsize=13, fontweight="bold", ha=ha,
                va="top", zorder=6)  # fmt: skip
    ax.view_init(elev=22, azim=-58)


def _panel_titles(scene: Scene, frame_axes, ax_traj, instants: int) -> None:
    """The titles of the 3-D panels and their legends: the axes and the body points."""
    from matplotlib.lines import Line2D

    if scene.single:
        frame_axes[0].set_title(f"Moving frame at {instants} instants", fontsize=TITLE_SIZE)
    else:
        for ax, track in zip(frame_axes, scene.tracks):
            ax.set_title(f"{track.label}: moving frame at {instants} instants",
                         fontsize=TITLE_SIZE, color=track.colour)  # fmt: skip
    ax_traj.set_title("Trajectories of body points", fontsize=TITLE_SIZE)
    legend_axis = [
        Line2D([], [], color=AXIS_COLOURS[j], label=f"{n} axis") for j, n in enumerate("xyz")
    ]
    if scene.show_axis:
        legend_axis.append(Line2D([], [], color="0.45", linestyle=(0, (6, 3)), label="screw axis"))
    frame_axes[0].legend(handles=legend_axis, loc="upper left", fontsize=LEGEND_SIZE, frameon=False)
    if scene.single:
        handles = [
            Line2D([], [], color=line.get_color(), label=name)
            for line, name in zip(ax_traj.get_lines(), scene.point_names)
        ]
    else:
        handles = [
            Line2D([], [], color="0.2", linestyle=_STYLES[k % len(_STYLES)], label=name)
            for k, name in enumerate(scene.point_names)
        ]
    if scene.default_points:
        length = scene.axis_length
        points_title = None if length == 1 else f"axes drawn {number_text(length)} long"
    else:
        points_title = "body point"
    ax_traj.legend(handles=handles, loc="upper left", fontsize=LEGEND_SIZE, frameon=False,
                   title=points_title, title_fontsize=LEGEND_SIZE)  # fmt: skip


def _figure_notes(fig, scene: Scene) -> None:
    """Under the panels: why there is no transmission curve, or the legend of the motions."""
    from matplotlib.lines import Line2D

    if not scene.has_transmission and scene.show_axis:  # in the room the layout keeps
        fig.supxlabel(
            "no transmission curve: the motion is not in the cylinder group of A and B "
            "(rotations about and translations along their screw axis)",
            fontsize=LEGEND_SIZE,
            color="0.3",
        )
    if scene.single:
        return
    handles = []
    for track in scene.tracks:
        extra = track.motion.summary(scene.angle_unit) if track.motion is not None else ""
        label = f"{track.label} ({extra})" if extra else track.label
        handles.append(Line2D([], [], color=track.colour, linewidth=2.5, label=label))
    fig.legend(handles=handles, loc="outside lower center", ncol=min(len(handles), 3),
               fontsize=LABEL_SIZE, frameon=False)  # fmt: skip


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


def _draw_transmission(ax, scene: Scene, family) -> None:
    """Panel 3: each track's samples of ω and z, its closed form and its family; A and B."""
    from matplotlib.lines import Line2D

    scale = np.degrees if scene.angle_unit == "deg" else (lambda w: np.asarray(w, float))
    notes, ends, handles = [], [], []
    for track, ok in zip(scene.tracks, scene.in_group):
        if not ok:
            notes.append(f"{track.label}: not in the cylinder group of A and B")
            continue
        curve = transmission_curve(scene, track, margin=0.12)
        ends.append((curve.omega[-1], curve.z[-1]))
        handles += _draw_curve(ax, curve, scene, family, scale)
    samples = f"samples of the motion{'s' if len(ends) > 1 else ''}"
    handles.append(Line2D([], [], linestyle="none", marker="o", markersize=4, color="0.3",
                          label=samples))  # fmt: skip
    _mark_ends(ax, ends, scale)
    unit = "°" if scene.angle_unit == "deg" else "rad"
    xlabel = f"ω, rotation about the screw axis [{unit}]"
    if notes:  # under the axis label, where the layout keeps room for it
        xlabel += "\n" + "\n".join(notes)
    ax.set_xlabel(xlabel, fontsize=LABEL_SIZE)
    ax.set_ylabel(f"z, translation along the screw axis{scene.length_label}", fontsize=LABEL_SIZE)
    ax.tick_params(labelsize=TICK_SIZE)
    ax.set_title("Transmission curve (canonical coordinates)", fontsize=TITLE_SIZE)
    ax.grid(True, linewidth=0.4, alpha=0.5)
    ax.axhline(0.0, color="0.6", linewidth=0.6)
    ax.axvline(0.0, color="0.6", linewidth=0.6)
    ax.legend(handles=handles, fontsize=LEGEND_SIZE - 1, loc="best", frameon=True, framealpha=0.85)


def _draw_curve(ax, curve, scene: Scene, family, scale) -> list:
    """One track's family, closed form and samples; returns their legend handles."""
    from matplotlib.lines import Line2D

    track, motion, z, handles = curve.track, curve.track.motion, curve.z, []
    span_z = max(float(np.ptp(z)), abs(scene.frame.d), 1e-9)
    bound = (float(z.min()) - 0.6 * span_z, float(z.max()) + 0.6 * span_z)
    if family and motion is not None and motion.family_kinds and curve.closed is not None:
        handles.append(_draw_family(ax, curve, bound, family, scene.single, scale))
    if curve.closed is not None:
        cf = np.where((curve.closed >= bound[0]) & (curve.closed <= bound[1]), curve.closed, np.nan)
        (line,) = ax.plot(scale(curve.dense), cf, color=track.colour,
                          linewidth=2.4 if family else 1.8, zorder=3)  # fmt: skip
        line.set_gid(f"transmission-closed-form:{track.label}")
        label = f"{track.label}: closed form ({motion.transmission_form})"
        label += ", chosen" if family and motion.family_kinds else ""
        handles.append(Line2D([], [], color=track.colour, linewidth=1.8, label=label))
    (line,) = ax.plot(scale(curve.omega), z, linestyle="none", marker="o", markersize=3.2,
                      color=track.colour, markeredgecolor="white", markeredgewidth=0.4,
                      zorder=4)  # fmt: skip
    line.set_gid(f"transmission-samples:{track.label}")
    return handles


def _draw_family(ax, curve, bound, family, single: bool, scale):
    """The family of the track's motion behind its closed form; returns its legend handle."""
    from matplotlib.lines import Line2D

    track = curve.track
    kind = family if family in track.motion.family_kinds else None
    name, members, _chosen = family_members(track.motion, kind)
    colour = track.colour if not single else "0.55"
    for j, (_value, member) in enumerate(members):
        zf = closed_form_z(member, curve.dense)
        zf = np.where((zf >= bound[0]) & (zf <= bound[1]), zf, np.nan)
        (line,) = ax.plot(scale(curve.dense), zf, color=colour,
                          alpha=0.35 if not single else 0.8, linewidth=0.9)  # fmt: skip
        line.set_gid(f"family:{track.label}:{j}")
    values = [v for v, _ in members]
    return Line2D([], [], color=colour, linewidth=0.9,
                  label=f"{track.label if not single else 'family'}: {name} from "
                  f"{number_text(min(values))} to {number_text(max(values))}")  # fmt: skip


def _mark_ends(ax, ends: list, scale) -> None:
    """A at the origin, and B at the end of each curve (once where the curves meet)."""
    ax.plot([0.0], [0.0], marker="o", markersize=7, color=A_COLOUR, zorder=5)
    ax.annotate("A", (0.0, 0.0), xytext=(-10, 6), textcoords="offset points", color=A_COLOUR,
                fontsize=13, fontweight="bold", ha="right")  # fmt: skip
    shown = []
    for omega_b, z_b in ends:
        if any(abs(omega_b - o) < 1e-9 and abs(z_b - zz) < 1e-9 for o, zz in shown):
            continue
        shown.append((omega_b, z_b))
        ax.plot([scale(omega_b)], [z_b], marker="o", markersize=7, color=B_COLOUR, zorder=5)
        ax.annotate("B", (scale(omega_b), z_b), xytext=(8, -14), textcoords="offset points",
                    color=B_COLOUR, fontsize=13, fontweight="bold")  # fmt: skip


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
    others = iter(OTHER_COLOURS * (1 + len(timed) // len(OTHER_COLOURS)))
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
    "FORMATS",
    "figure_format",
    "plot_motions",
    "plot_speeds",
    "require_matplotlib",
    "write_figure",
]
