"""An interactive 3D page of a motion: one self-contained HTML file, drawn by plotly.js.

:func:`view_page` returns the page. It shows, on the left, a 3D scene with

* the moving frame (axes x, y, z in red, green, blue), animated along t with a play/pause
  button and a slider (for a trajectory with times, the slider shows its seconds);
* the trajectories of body points (the tips of the frame's axes unless others are given);
* the screw axis of ``B A⁻¹`` (dashed), the poses A and B, and marked poses (the inner
  control or key poses of a curve);

on the right the transmission curve (ω, z) in canonical coordinates, with a marker that
follows t, and beside the plot a panel with the parameters of each motion. With several
motions (``--compare``), each is one body with its own colour, and clicking its legend entry
hides or shows everything that belongs to it.

The page inlines plotly.js from the ``plotly`` package (the ``[view]`` extra), unmodified, and
loads nothing from the network. What it shows is the scene of :mod:`a2b.scene`, as for
:mod:`a2b.plot`. User text (labels, titles, units, file names) reaches the page in its HTML,
escaped by :func:`html.escape`, and in the figure's JSON inside a script element, escaped by
:func:`script_json` so that it cannot end the script.
"""

from __future__ import annotations

import html
import json

import numpy as np

from .errors import MissingDependencyError, ParameterError
from .motions.text import number_text
from .scene import (
    A_COLOUR,
    AXIS_COLOURS,
    B_COLOUR,
    Scene,
    make_scene,
    screw_axis_segment,
    transmission_curve,
)

__all__ = ["MAX_FRAMES", "animation_steps", "require_plotly", "script_json", "view_page"]

#: Animation frames at most; more samples are drawn as lines but animated at fewer instants.
MAX_FRAMES = 201
#: Points per drawn line at most (a long trajectory file is thinned for drawing).
MAX_LINE_POINTS = 4001
_DASHES = ("solid", "dash", "dot", "dashdot")
#: Where the camera stands: 1.3 times plotly's (1.5, −1.5, 0.9) away, so that the cube's tick
#: labels fit in the scene's domain (at 1200 px the z labels were cut off at the left edge).
_EYE = {"x": 1.95, "y": -1.95, "z": 1.17}
#: Where each motion's name stands beside its body, so that the names of several bodies at
#: the same pose (A, B) do not cover each other; A's own label stands top left.
_NAME_POSITIONS = ("top right", "bottom right", "bottom left", "middle right", "middle left")
#: What JSON text must not hold inside an HTML script element: ``</script``, ``<!--`` and
#: ``<script`` change how the HTML parser reads the script, and U+2028/2029 end a line in
#: older JavaScript. Escaped as JSON string escapes, the same text to JavaScript.
_SCRIPT_ESCAPES = {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026",
                   "\u2028": "\\u2028", "\u2029": "\\u2029"}  # fmt: skip


def script_json(value) -> str:
    """``value`` as JSON text that is safe inside an HTML ``<script>`` element: no ``<``,
    ``>``, ``&``, U+2028 or U+2029 appears in it (each is written as its ``\\uXXXX`` escape,
    which JSON and JavaScript read as the same character)."""
    text = json.dumps(value)
    for char, escape in _SCRIPT_ESCAPES.items():
        text = text.replace(char, escape)
    return text


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


def animation_steps(samples: int) -> int:
    """How many of ``samples`` samples are animation frames: at most :data:`MAX_FRAMES`."""
    return len(_picks(int(samples), MAX_FRAMES))


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
    times=None,
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
    times : array_like, shape (samples,), optional
        The times in seconds of the samples (of a trajectory): the slider shows them, from
        the first, instead of t.

    Returns
    -------
    str
        A complete HTML document with plotly.js inlined.

    Raises
    ------
    A2bError
        Invalid poses, motions or parameters (:func:`a2b.scene.make_scene`), ``times`` of
        another length than ``samples`` or not increasing.
    MissingDependencyError
        When plotly is not installed.
    """
    plotly_offline = require_plotly()
    scene = make_scene(start, end, motions, points=points, samples=samples, instants=2,
                       marks=marks, angle_unit=angle_unit, length_unit=length_unit)  # fmt: skip
    steps = _picks(int(samples), MAX_FRAMES)
    labels, prefix = _step_labels(steps, int(samples), times)
    data: list[dict] = []
    box = _static_traces(scene, data)
    _transmission_traces(scene, data)
    frames = _animated_traces(scene, data, steps, labels)
    title = title or scene.page_title()
    return _PAGE.format(
        title=html.escape(title),
        panel=_panel(scene),
        plotly=plotly_offline.get_plotlyjs(),
        figure=script_json(
            {"data": data, "layout": _layout(scene, box, frames, prefix, title), "frames": frames}
        ),  # fmt: skip
    )


def _step_labels(steps: np.ndarray, samples: int, times) -> tuple[list[str], str]:
    """The slider's label of each step and its prefix: ``t = 0.25``, or with ``times`` the
    seconds from the first sample, with as many digits as tell the steps apart."""
    if times is None:
        return [f"{t:.4g}" for t in np.linspace(0.0, 1.0, samples)[steps]], "t = "
    times = np.asarray(times, dtype=float)
    if times.shape != (samples,) or not (np.isfinite(times).all() and np.all(np.diff(times) > 0)):
        raise ParameterError(f"times must be {samples} increasing finite numbers, one a sample")
    since = times[steps] - times[0]
    for digits in range(4, 18):
        labels = [f"{s:.{digits}g} s" for s in since]
        if len(set(labels)) == len(labels):
            break
    return labels, "time = " if times[0] == 0 else "time from the first stamp = "


def _static_traces(scene: Scene, data: list) -> tuple[np.ndarray, np.ndarray]:
    """The trajectories, the origin paths, A, B, the marks and the screw axis; returns the
    corners of the 3D scene's cube."""
    a, b, length, single = scene.start, scene.end, scene.axis_length, scene.single
    everything = [a[:3, 3], b[:3, 3]]
    for track in scene.tracks:
        mats = track.mats[_picks(len(track.mats), MAX_LINE_POINTS)]
        world = scene.trajectories(track, mats)
        everything += [world.reshape(-1, 3), mats[:, :3, 3]]
        for k, path in enumerate(world):
            colour = AXIS_COLOURS[k % 3] if single and scene.default_points else track.colour
            dash = "solid" if single else _DASHES[k % 4]
            name = scene.point_names[k] if single else f"{track.label}: {scene.point_names[k]}"
            line = {"color": colour, "width": 4, "dash": dash}
            data.append(_scene(path, line=line, name=name, legendgroup=track.label,
                               showlegend=single, hoverinfo="name"))  # fmt: skip
        data.append({"type": "scatter3d", "mode": "lines", **_line(mats[:, :3, 3]),
                     "line": {"color": track.colour if not single else "#595959", "width": 3},
                     "name": track.label if not single else "origin", "legendgroup": track.label,
                     "showlegend": not single, "hoverinfo": "name"})  # fmt: skip
    for pose, name, colour, width in [(a, "A", A_COLOUR, 8), (b, "B", B_COLOUR, 8)] + [
        (pose, label, "#404040", 4) for label, pose in scene.marks
    ]:
        for j, segment in enumerate(_axes(pose, length)):
            data.append({"type": "scatter3d", "mode": "lines", **_line(segment),
                         "line": {"color": AXIS_COLOURS[j], "width": width}, "showlegend": False,
                         "hoverinfo": "skip", "opacity": 0.7})  # fmt: skip
        data.append({"type": "scatter3d", "mode": "markers+text", **_line(pose[None, :3, 3]),
                     "text": [name], "textposition": "top left",
                     "marker": {"size": 4, "color": colour},
                     "textfont": {"color": colour, "size": 16 if len(name) == 1 else 12},
                     "showlegend": False, "hoverinfo": "text"})  # fmt: skip
        everything += _axes(pose, length)
    box = _cube(np.concatenate([np.atleast_2d(p) for p in everything]))
    segment = screw_axis_segment(scene.frame, *box) if scene.show_axis else None
    if segment is not None:
        data.append({"type": "scatter3d", "mode": "lines", **_line(segment),
                     "line": {"color": "#737373", "width": 3, "dash": "dash"},
                     "name": "screw axis", "hoverinfo": "name"})  # fmt: skip
    return box


def _cube(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The corners of a cube around ``points``, a tenth larger.

    Raises
    ------
    ParameterError
        When the cube overflows a double (poses near ±1.8e308).
    """
    lo, hi = points.min(axis=0), points.max(axis=0)
    with np.errstate(over="ignore", invalid="ignore"):
        centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-9) * 1.1
        corners = (centre - half, centre + half)
    if not np.isfinite(corners).all():
        raise ParameterError(
            f"the poses reach coordinates of {float(np.abs(points).max()):.3g}, too far apart "
            "to draw: the size of the scene overflows a double"
        )
    return corners


def _transmission_traces(scene: Scene, data: list) -> None:
    """The transmission panel: each track's closed form and samples."""
    scale = np.degrees if scene.angle_unit == "deg" else np.asarray
    for track, ok in zip(scene.tracks, scene.in_group):
        if not ok:
            continue
        curve = transmission_curve(scene, track)
        if curve.closed is not None:
            data.append({"type": "scatter", "mode": "lines", "x": scale(curve.dense).tolist(),
                         "y": curve.closed.tolist(), "line": {"color": track.colour, "width": 2},
                         "name": f"{track.label}: closed form", "legendgroup": track.label,
                         "showlegend": False, "xaxis": "x", "yaxis": "y"})  # fmt: skip
        keep = _picks(len(curve.omega), MAX_LINE_POINTS)
        data.append({"type": "scatter", "mode": "markers", "x": scale(curve.omega[keep]).tolist(),
                     "y": curve.z[keep].tolist(), "marker": {"color": track.colour, "size": 4},
                     "name": f"{track.label}: samples", "legendgroup": track.label,
                     "showlegend": False, "xaxis": "x", "yaxis": "y"})  # fmt: skip


def _animated_traces(scene: Scene, data: list, steps: np.ndarray, labels: list) -> list[dict]:
    """The moving frame, the body's name and the marker on the transmission curve of each
    track at the first step, and the animation frames that move them."""
    scale = np.degrees if scene.angle_unit == "deg" else np.asarray
    single, length = scene.single, scene.axis_length
    animated: list[int] = []
    per_frame: list[list[dict]] = [[] for _ in steps]

    def add(trace: dict) -> None:
        animated.append(len(data))
        data.append(trace)

    for n, (track, ok) in enumerate(zip(scene.tracks, scene.in_group)):
        mats = track.mats[steps]
        for j in range(3):
            add(_scene(_axes(mats[0], length)[j], line={"color": AXIS_COLOURS[j], "width": 9},
                       hoverinfo="name", name=f"{track.label}: {'xyz'[j]} axis",
                       legendgroup=track.label, showlegend=single))  # fmt: skip
            for f, pose in enumerate(mats):
                per_frame[f].append(_line(_axes(pose, length)[j]))
        add({"type": "scatter3d", "mode": "markers+text",
             "marker": {"size": 5, "color": track.colour},
             "text": ["" if single else track.label],
             "textposition": _NAME_POSITIONS[n % len(_NAME_POSITIONS)],
             "textfont": {"color": track.colour}, "name": track.label,
             "legendgroup": track.label, "showlegend": False,
             "hoverinfo": "name", **_line(mats[:1, :3, 3])})  # fmt: skip
        for f, pose in enumerate(mats):
            per_frame[f].append(_line(pose[None, :3, 3]))
        if ok:
            omega, z = scene.frame.transmission(track.mats)
            add({"type": "scatter", "mode": "markers", "xaxis": "x", "yaxis": "y",
                 "x": [float(scale(omega[0]))], "y": [float(z[0])],
                 "marker": {"color": track.colour, "size": 13, "symbol": "circle",
                            "line": {"color": "white", "width": 2}},
                 "name": f"{track.label} at t", "legendgroup": track.label,
                 "showlegend": False})  # fmt: skip
            for f, k in enumerate(steps):
                per_frame[f].append({"x": [float(scale(omega[k]))], "y": [float(z[k])]})
    return [{"name": name, "data": update, "traces": animated}
            for name, update in zip(labels, per_frame)]  # fmt: skip


def _layout(scene: Scene, box, frames: list, prefix: str, title: str) -> dict:
    """The page's layout: the 3D scene, the transmission panel, play and pause, the slider."""
    angle = "°" if scene.angle_unit == "deg" else " rad"
    unit = scene.length_label
    box_lo, box_hi = box
    # a curve through other poses has no transmission panel and no note: the scene takes the
    # width
    right = 0.6 if scene.has_transmission or scene.show_axis else 1.0
    layout = {
        "title": {"text": html.escape(title), "x": 0.02, "font": {"size": 18}},
        "font": {"size": 14},
        "scene": {"domain": {"x": [0.0, right], "y": [0.12, 1.0]}, "aspectmode": "cube",
                  **{f"{k}axis": {"range": [float(box_lo[j]), float(box_hi[j])],
                                  "title": {"text": k + unit}}
                     for j, k in enumerate("xyz")},
                  "camera": {"eye": _EYE}},
        "xaxis": {"domain": [0.68, 1.0], "anchor": "y",
                  "title": {"text": f"ω, rotation about the screw axis [{angle.strip()}]"}},
        "yaxis": {"domain": [0.3, 0.95], "anchor": "x",
                  "title": {"text": "z, translation along the axis" + unit}},
        "legend": {"x": 0.0, "y": 1.0, "bgcolor": "rgba(255,255,255,0.7)"},
        "margin": {"l": 10, "r": 10, "t": 60, "b": 10},
        "updatemenus": [_PLAY],
        "sliders": [_slider(frames, prefix)],
    }  # fmt: skip
    if not scene.has_transmission:
        layout["xaxis"]["visible"] = layout["yaxis"]["visible"] = False
    if not scene.has_transmission and scene.show_axis:  # not for a curve through other poses
        note = ("no transmission curve: the motion is not in the<br>cylinder group of A and B "
                "(rotations about and slides along their screw axis)")  # fmt: skip
        layout["annotations"] = [
            {"text": note, "xref": "paper", "yref": "paper", "x": 0.84, "y": 0.6,
             "showarrow": False}
        ]  # fmt: skip
    return layout


_PLAY = {
    "type": "buttons", "direction": "left", "x": 0.0, "y": 0.0, "xanchor": "left",
    "yanchor": "bottom", "showactive": False, "pad": {"r": 10, "t": 10},
    "buttons": [
        {"label": "▶ play", "method": "animate",
         "args": [None, {"frame": {"duration": 60, "redraw": True}, "fromcurrent": True,
                         "transition": {"duration": 0}, "mode": "immediate"}]},
        {"label": "❚❚ pause", "method": "animate",
         "args": [[None], {"frame": {"duration": 0, "redraw": False},
                           "mode": "immediate", "transition": {"duration": 0}}]},
    ]}  # fmt: skip


def _slider(frames: list, prefix: str) -> dict:
    """One step per animation frame; the current step's label after ``prefix``."""
    return {
        "x": 0.16, "y": 0.0, "len": 0.82, "xanchor": "left", "yanchor": "bottom",
        "currentvalue": {"prefix": prefix, "font": {"size": 16, "color": "#222"},
                         "xanchor": "left"},
        "font": {"color": "rgba(0,0,0,0)"},  # no label under each of the many steps
        "ticklen": 0, "pad": {"t": 10, "b": 10},
        "steps": [{"label": frame["name"], "method": "animate",
                   "args": [[frame["name"]], {"frame": {"duration": 0, "redraw": True},
                                              "mode": "immediate",
                                              "transition": {"duration": 0}}]}
                  for frame in frames]}  # fmt: skip


def _panel(scene: Scene) -> str:
    """The side panel: each motion's essential parameters and the numbers of ``describe()``."""
    rows = []
    for track in scene.tracks:
        rows.append(f'<h2 style="color:{track.colour}">{html.escape(track.label)}</h2>')
        source = track.motion if track.motion is not None else track.source
        if track.motion is not None:
            rows.append(f"<p>{html.escape(track.motion.summary(scene.angle_unit))}</p>")
        info = source.describe() if source is not None and hasattr(source, "describe") else {}
        items = []
        for key, value in info.items():
            if isinstance(value, (list, tuple, np.ndarray)) and not 0 < np.asarray(value).size <= 8:
                continue  # long tables, and empty lists (no warnings, no choices)
            if isinstance(value, (float, int, np.floating)) and not isinstance(value, bool):
                value = number_text(float(value))
            elif isinstance(value, (list, tuple, np.ndarray)):
                try:
                    value = "(" + ", ".join(number_text(float(v)) for v in value) + ")"
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
