"""An interactive 3D page of a motion: one self-contained HTML file, drawn by plotly.js.

:func:`view_page` returns the page. It shows, on the left, a 3D scene with

* the moving frame (axes x, y, z in red, green, blue), animated along t with a play/pause
  button and a slider;
* the trajectories of body points (the tips of the frame's axes unless others are given);
* the screw axis of ``B A⁻¹`` (dashed), the poses A and B, and marked poses (the inner
  control or key poses of a curve);

on the right the transmission curve (ω, z) in canonical coordinates, with a marker that
follows t, and beside the plot a panel with the parameters of each motion. With several
motions (``--compare``), each is one body with its own colour, and clicking its legend entry
hides or shows everything that belongs to it.

The page inlines plotly.js from the ``plotly`` package (the ``[view]`` extra), unmodified, and
loads nothing from the network. The geometry is that of :mod:`a2b.plot`: the same tracks,
screw frame, cylinder-group test, closed forms and parameter summaries.
"""

from __future__ import annotations

import html
import json

import numpy as np

from .errors import ParameterError
from .plot import (
    A_COLOUR,
    AXIS_COLOURS,
    B_COLOUR,
    MissingDependencyError,
    _as_tracks,
    _body_points,
    _curve_title,
    _default_axis_length,
    _format_number,
    _screw_axis_segment,
    closed_form_z,
    essential_parameters,
    in_cylinder_group,
)

__all__ = ["MAX_FRAMES", "require_plotly", "view_page"]

#: Animation frames at most; more samples are drawn as lines but animated at fewer instants.
MAX_FRAMES = 201
#: Points per drawn line at most (a long trajectory file is thinned for drawing).
MAX_LINE_POINTS = 4001
_DASHES = ("solid", "dash", "dot", "dashdot")


def require_plotly():
    """plotly's Python package, which carries plotly.js, or a clear error."""
    try:
        import plotly.offline
    except ImportError as e:
        raise MissingDependencyError(
            "a2b view needs plotly, which carries plotly.js: pip install 'a2b-motions[view]'"
        ) from e
    return plotly.offline


def _picks(n: int, most: int) -> np.ndarray:
    """Indices of at most ``most`` samples of ``n``, evenly spread, first and last included."""
    return np.unique(np.round(np.linspace(0, n - 1, min(n, most))).astype(int))


def _line(points: np.ndarray) -> dict:
    """``x``, ``y``, ``z`` lists of points ``(K, 3)``, with ``None`` rows as gaps."""
    return {k: [None if v is None or not np.isfinite(v) else float(v) for v in points[:, j]]
            for j, k in enumerate("xyz")}  # fmt: skip


def _scene(points: np.ndarray, **props) -> dict:
    """A 3D line trace (``mode="lines"`` unless given) through ``points`` ``(K, 3)``."""
    return {"type": "scatter3d", "mode": "lines", **_line(points), **props}


def _axes(pose: np.ndarray, length: float) -> list[np.ndarray]:
    """The segments origin → tip of the three axes of ``pose``."""
    origin = pose[:3, 3]
    return [np.stack([origin, origin + length * pose[:3, j]]) for j in range(3)]


def view_page(
    start,
    end,
    motions="darboux",
    *,
    points=None,
    samples: int = 101,
    angle_unit: str = "deg",
    length_unit: str | None = None,
    marks=None,
    title: str | None = None,
) -> str:
    """The HTML page of motions from A to B (see the module docstring).

    Parameters
    ----------
    start, end : array_like, shape (4, 4)
        The poses A and B.
    motions
        What to show, as for :func:`a2b.plot.plot_motions`: mode names, ``(mode,
        parameters)`` pairs, Motions, samplers or ``(label, matrices)`` samples.
    points : array_like, shape (K, 3), optional
        Body points whose trajectories are drawn; default the tips of the frame's axes.
    samples : int
        Samples per motion, ``t`` evenly spaced in [0, 1]; at most :data:`MAX_FRAMES` of them
        are animation frames.
    angle_unit : {"deg", "rad"}
        The unit of ω in the transmission panel.
    length_unit : str, optional
        The name of the length unit for the axis titles.
    marks : sequence of (str, (4, 4)), optional
        Further poses to show with a label.
    title : str, optional
        Replaces the generated title.

    Returns
    -------
    str
        A complete HTML document with plotly.js inlined.
    """
    from .frames import screw_frame
    from .poses import check_matrices

    plotly_offline = require_plotly()
    if angle_unit not in ("deg", "rad"):
        raise ParameterError(f"unknown angle unit {angle_unit!r}; expected deg or rad")
    if int(samples) != samples or samples < 2:
        raise ParameterError(f"samples must be an integer ≥ 2, got {samples!r}")
    a, b = check_matrices(start), check_matrices(end)
    if a.shape != (4, 4) or b.shape != (4, 4):
        raise ParameterError("start and end must each be one 4x4 matrix")
    frame = screw_frame(a, b)
    tracks = _as_tracks(a, b, motions, int(samples), 2)
    length = _default_axis_length(tracks)
    body, point_names, default_points = _body_points(points, length)
    marked = [(str(label), check_matrices(pose)) for label, pose in (marks or ())]
    single = len(tracks) == 1
    in_group = [in_cylinder_group(frame, t.mats) for t in tracks]
    scale = np.degrees if angle_unit == "deg" else np.asarray
    unit = " [" + length_unit + "]" if length_unit else ""

    data: list[dict] = []
    everything = [a[:3, 3], b[:3, 3]]

    def add(trace: dict) -> int:
        data.append(trace)
        return len(data) - 1

    # static: trajectories, origin paths, A, B, marks
    for track in tracks:
        keep = _picks(len(track.mats), MAX_LINE_POINTS)
        mats = track.mats[keep]
        world = np.einsum("nij,kj->kni", mats[:, :3, :3], body) + mats[None, :, :3, 3]
        everything += [world.reshape(-1, 3), mats[:, :3, 3]]
        for k, path in enumerate(world):
            colour = AXIS_COLOURS[k % 3] if single and default_points else track.colour
            dash = "solid" if single else _DASHES[k % 4]
            name = point_names[k] if single else f"{track.label}: {point_names[k]}"
            line = {"color": colour, "width": 4, "dash": dash}
            add(_scene(path, line=line, name=name, legendgroup=track.label, showlegend=single,
                       hoverinfo="name"))  # fmt: skip
        add({"type": "scatter3d", "mode": "lines", **_line(mats[:, :3, 3]),
             "line": {"color": track.colour if not single else "#595959", "width": 3},
             "name": track.label if not single else "origin", "legendgroup": track.label,
             "showlegend": not single, "hoverinfo": "name"})  # fmt: skip
    for pose, name, colour, width in [(a, "A", A_COLOUR, 8), (b, "B", B_COLOUR, 8)] + [
        (pose, label, "#404040", 4) for label, pose in marked
    ]:
        for j, segment in enumerate(_axes(pose, length)):
            add({"type": "scatter3d", "mode": "lines", **_line(segment),
                 "line": {"color": AXIS_COLOURS[j], "width": width}, "showlegend": False,
                 "hoverinfo": "skip", "opacity": 0.7})  # fmt: skip
        add({"type": "scatter3d", "mode": "markers+text", **_line(pose[None, :3, 3]),
             "text": [name], "textposition": "top left", "marker": {"size": 4, "color": colour},
             "textfont": {"color": colour, "size": 16 if len(name) == 1 else 12},
             "showlegend": False, "hoverinfo": "text"})  # fmt: skip
        everything += _axes(pose, length)
    points_all = np.concatenate([np.atleast_2d(p) for p in everything])
    lo, hi = points_all.min(axis=0), points_all.max(axis=0)
    centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-9) * 1.1
    box_lo, box_hi = centre - half, centre + half
    segment = _screw_axis_segment(frame, box_lo, box_hi) if any(t.mode for t in tracks) else None
    if segment is not None:
        add({"type": "scatter3d", "mode": "lines", **_line(segment),
             "line": {"color": "#737373", "width": 3, "dash": "dash"}, "name": "screw axis",
             "hoverinfo": "name"})  # fmt: skip

    # the transmission panel
    for track, ok in zip(tracks, in_group):
        if not ok:
            continue
        omega, z = frame.transmission(track.mats)
        if track.motion is not None and omega[-1] != omega[0]:
            dense = np.linspace(omega[0], omega[-1], 241)
            form = closed_form_z(track.motion, dense)
            if form is not None:
                add({"type": "scatter", "mode": "lines", "x": scale(dense).tolist(),
                     "y": form.tolist(), "line": {"color": track.colour, "width": 2},
                     "name": f"{track.label}: closed form", "legendgroup": track.label,
                     "showlegend": False, "xaxis": "x", "yaxis": "y"})  # fmt: skip
        keep = _picks(len(omega), MAX_LINE_POINTS)
        add({"type": "scatter", "mode": "markers", "x": scale(omega[keep]).tolist(),
             "y": z[keep].tolist(), "marker": {"color": track.colour, "size": 4},
             "name": f"{track.label}: samples", "legendgroup": track.label,
             "showlegend": False, "xaxis": "x", "yaxis": "y"})  # fmt: skip

    # the animated traces and their frames
    steps = _picks(int(samples), MAX_FRAMES)
    ts = np.linspace(0.0, 1.0, int(samples))[steps]
    animated: list[int] = []
    per_frame: list[list[dict]] = [[] for _ in steps]
    for track, ok in zip(tracks, in_group):
        mats = track.mats[steps]
        for j in range(3):
            line = {"color": AXIS_COLOURS[j], "width": 9}
            axis = _scene(_axes(mats[0], length)[j], line=line, hoverinfo="name",
                          name=f"{track.label}: {'xyz'[j]} axis", legendgroup=track.label,
                          showlegend=single)  # fmt: skip
            animated.append(add(axis))
            for f, pose in enumerate(mats):
                per_frame[f].append(_line(_axes(pose, length)[j]))
        animated.append(add({"type": "scatter3d", "mode": "markers+text",
                             "marker": {"size": 5, "color": track.colour},
                             "text": ["" if single else track.label], "textposition": "top right",
                             "textfont": {"color": track.colour}, "name": track.label,
                             "legendgroup": track.label, "showlegend": False,
                             "hoverinfo": "name", **_line(mats[:1, :3, 3])}))  # fmt: skip
        for f, pose in enumerate(mats):
            per_frame[f].append(_line(pose[None, :3, 3]))
        if ok:
            omega, z = frame.transmission(track.mats)
            animated.append(add({"type": "scatter", "mode": "markers", "xaxis": "x", "yaxis": "y",
                                 "x": [float(scale(omega[0]))], "y": [float(z[0])],
                                 "marker": {"color": track.colour, "size": 13, "symbol": "circle",
                                            "line": {"color": "white", "width": 2}},
                                 "name": f"{track.label} at t", "legendgroup": track.label,
                                 "showlegend": False}))  # fmt: skip
            for f, k in enumerate(steps):
                per_frame[f].append({"x": [float(scale(omega[k]))], "y": [float(z[k])]})
    frames = [
        {"name": f"{t:.4g}", "data": update, "traces": animated} for t, update in zip(ts, per_frame)
    ]

    angle = "°" if angle_unit == "deg" else " rad"
    layout = {
        "title": {"text": html.escape(title or _title(tracks, frame, angle_unit)), "x": 0.02,
                  "font": {"size": 18}},
        "font": {"size": 14},
        "scene": {"domain": {"x": [0.0, 0.6], "y": [0.12, 1.0]}, "aspectmode": "cube",
                  **{f"{k}axis": {"range": [float(box_lo[j]), float(box_hi[j])],
                                  "title": {"text": k + unit}}
                     for j, k in enumerate("xyz")},
                  "camera": {"eye": {"x": 1.5, "y": -1.5, "z": 0.9}}},
        "xaxis": {"domain": [0.68, 1.0], "anchor": "y",
                  "title": {"text": f"ω, rotation about the screw axis [{angle.strip()}]"}},
        "yaxis": {"domain": [0.3, 0.95], "anchor": "x",
                  "title": {"text": "z, translation along the axis" + unit}},
        "legend": {"x": 0.0, "y": 1.0, "bgcolor": "rgba(255,255,255,0.7)"},
        "margin": {"l": 10, "r": 10, "t": 60, "b": 10},
        "updatemenus": [{
            "type": "buttons", "direction": "left", "x": 0.0, "y": 0.0, "xanchor": "left",
            "yanchor": "bottom", "showactive": False, "pad": {"r": 10, "t": 10},
            "buttons": [
                {"label": "▶ play", "method": "animate",
                 "args": [None, {"frame": {"duration": 60, "redraw": True}, "fromcurrent": True,
                                 "transition": {"duration": 0}, "mode": "immediate"}]},
                {"label": "❚❚ pause", "method": "animate",
                 "args": [[None], {"frame": {"duration": 0, "redraw": False},
                                   "mode": "immediate", "transition": {"duration": 0}}]},
            ]}],
        "sliders": [{
            "x": 0.16, "y": 0.0, "len": 0.82, "xanchor": "left", "yanchor": "bottom",
            "currentvalue": {"prefix": "t = ", "font": {"size": 16, "color": "#222"},
                             "xanchor": "left"},
            "font": {"color": "rgba(0,0,0,0)"},  # no label under each of the many steps
            "ticklen": 0, "pad": {"t": 10, "b": 10},
            "steps": [{"label": frame_["name"], "method": "animate",
                       "args": [[frame_["name"]], {"frame": {"duration": 0, "redraw": True},
                                                   "mode": "immediate",
                                                   "transition": {"duration": 0}}]}
                      for frame_ in frames]}],
    }  # fmt: skip
    if not any(in_group):
        layout["xaxis"]["visible"] = layout["yaxis"]["visible"] = False
        note = ("no transmission curve: the motion is not in the<br>cylinder group of A and B "
                "(rotations about and slides along their screw axis)")  # fmt: skip
        layout["annotations"] = [
            {"text": note, "xref": "paper", "yref": "paper", "x": 0.84, "y": 0.6,
             "showarrow": False}
        ]  # fmt: skip
    return _PAGE.format(
        title=html.escape(title or _title(tracks, frame, angle_unit)),
        panel=_panel(tracks, frame, angle_unit),
        plotly=plotly_offline.get_plotlyjs(),
        # "</" cannot end the script early: user text (labels, titles) is in this JSON
        figure=json.dumps({"data": data, "layout": layout, "frames": frames}).replace("</", "<\\/"),
    )


def _title(tracks, frame, angle_unit: str) -> str:
    angle = (f"{_format_number(np.degrees(frame.phi))}°" if angle_unit == "deg"
             else f"{_format_number(frame.phi)} rad")  # fmt: skip
    ends = f"A to B: φ = {angle}, d = {_format_number(frame.d)}"
    if len(tracks) == 1 and _curve_title(tracks[0]):
        return _curve_title(tracks[0])
    names = ", ".join(t.label for t in tracks)
    return f"{names} motion{'s' * (len(tracks) > 1)}, {ends}"


def _panel(tracks, frame, angle_unit: str) -> str:
    """The side panel: each motion's essential parameters and the numbers of ``describe()``."""
    rows = []
    for track in tracks:
        rows.append(f'<h2 style="color:{track.colour}">{html.escape(track.label)}</h2>')
        source = track.motion if track.motion is not None else track.source
        if track.motion is not None:
            rows.append(f"<p>{html.escape(essential_parameters(track.motion, angle_unit))}</p>")
        info = source.describe() if source is not None and hasattr(source, "describe") else {}
        items = []
        for key, value in info.items():
            if isinstance(value, (list, tuple, np.ndarray)) and not 0 < np.asarray(value).size <= 8:
                continue  # long tables, and empty lists (no warnings, no choices)
            if isinstance(value, (float, int, np.floating)) and not isinstance(value, bool):
                value = _format_number(float(value))
            elif isinstance(value, (list, tuple, np.ndarray)):
                try:
                    value = "(" + ", ".join(_format_number(float(v)) for v in value) + ")"
                except (TypeError, ValueError):  # words: the choices a2b made
                    value = "; ".join(map(str, value))
            items.append(f"<tr><th>{html.escape(str(key))}</th>"
                         f"<td>{html.escape(str(value))}</td></tr>")  # fmt: skip
        if items:
            rows.append("<table>" + "".join(items) + "</table>")
    return "\n".join(rows)


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<style>
  body {{ margin: 0; font-family: system-ui, sans-serif; display: flex; height: 100vh; }}
  #plot {{ flex: 1; min-width: 0; }}
  aside {{ width: 19rem; overflow: auto; padding: 0.8rem 1rem; border-left: 1px solid #ddd;
          font-size: 14px; }}
  aside h2 {{ font-size: 16px; margin: 0.8rem 0 0.3rem; }}
  aside th {{ text-align: left; font-weight: normal; color: #555; padding-right: 0.6rem; }}
  aside td {{ font-variant-numeric: tabular-nums; }}
</style>
<script>{plotly}</script>
</head>
<body>
<div id="plot"></div>
<aside>
<h1 style="font-size:17px">Parameters</h1>
{panel}
<p style="color:#666">Drag to turn the view, scroll to zoom; the slider moves t; the legend
hides or shows a part (with several motions, a motion).</p>
</aside>
<script>
  const figure = {figure};
  const plot = document.getElementById("plot");
  Plotly.newPlot(plot, figure.data, figure.layout, {{displaylogo: false, responsive: true}})
    .then(() => Plotly.addFrames(plot, figure.frames))
    .then(() => {{ document.body.dataset.ready = "yes"; }});
</script>
</body>
</html>
"""
