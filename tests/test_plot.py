"""a2b.plot: files in every format, and the plotted data against the engine and the closed forms.

The tests read the data of the drawn lines (found by their ``gid``), never pixels. Figures are
small and sampled coarsely so that the module runs in a few seconds.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import a2b
from a2b.errors import A2bError, MissingDependencyError, ParameterError
from a2b.plot import (
    figure_format,
    plot_motions,
    plot_speeds,
    require_matplotlib,
    write_figure,
)
from a2b.scene import AXIS_COLOURS, closed_form_z, family_members, in_cylinder_group

from .conftest import pose_about_axis, random_pose

pytest.importorskip("matplotlib")

SAMPLES = 9
SMALL = {"samples": SAMPLES, "instants": 4, "figsize": (12.0, 4.2)}
MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "pdf": b"%PDF-"}
MODES = ("darboux", "cubic", "screw")


@pytest.fixture
def poses(rng):
    """A random start pose and an end pose a generic screw away from it (φ ≈ 100°)."""
    start = random_pose(rng)
    screw = pose_about_axis(1.75, rng.normal(size=3), rng.normal(size=3), 0.8)
    return start, screw @ start


def lines_by_gid(fig):
    found = {}
    for ax in fig.axes:
        for artist in ax.get_children():
            gid = artist.get_gid()
            if gid:
                found.setdefault(gid, []).append(artist)
    return found


def line(fig, gid):
    (artist,) = lines_by_gid(fig)[gid]
    return artist


def suptitle(fig):
    """The figure's title (``Figure.get_suptitle`` is new in matplotlib 3.8)."""
    return fig.get_suptitle() if hasattr(fig, "get_suptitle") else fig._suptitle.get_text()


def render(fig, path, fmt):
    with open(path, "wb") as fh:
        write_figure(fig, fh, fmt, dpi=40)
    data = path.read_bytes()
    assert len(data) > 1000
    if fmt == "svg":
        assert data.lstrip().startswith(b"<?xml") and b"<svg" in data[:2000]
    else:
        assert data.startswith(MAGIC[fmt])
    return data


def engine(start, end, mode, **params):
    motion = a2b.motion(start, end, mode, **params)
    ts = np.linspace(0.0, 1.0, SAMPLES)
    return motion, ts, motion.matrices(ts)


# -- files ----------------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", ["png", "svg"])
@pytest.mark.parametrize("mode", MODES)
def test_every_mode_renders(poses, tmp_path, mode, fmt):
    fig = plot_motions(*poses, mode, **SMALL)
    render(fig, tmp_path / f"{mode}.{fmt}", fmt)
    assert len(fig.axes) == 3


@pytest.mark.parametrize("fmt", ["png", "svg", "pdf"])
def test_compare_and_family_render(poses, tmp_path, fmt):
    small = dict(SMALL, figsize=(12.0, 8.0))  # a panel per motion: room for five panels
    render(plot_motions(*poses, list(MODES), **small), tmp_path / f"compare.{fmt}", fmt)
    render(
        plot_motions(*poses, ["darboux", "cubic"], family=True, **small),
        tmp_path / f"family.{fmt}",
        fmt,
    )


def test_svg_carries_the_gids(poses, tmp_path):
    data = render(plot_motions(*poses, "darboux", **SMALL), tmp_path / "d.svg", "svg")
    assert b'id="transmission-samples:darboux"' in data


def test_same_figure_same_bytes(poses, tmp_path):
    first = render(plot_motions(*poses, "cubic", **SMALL), tmp_path / "1.svg", "svg")
    second = render(plot_motions(*poses, "cubic", **SMALL), tmp_path / "2.svg", "svg")
    assert first == second


@pytest.mark.parametrize("name, fmt", [("a.png", "png"), ("b.SVG", "svg"), ("dir.x/c.pdf", "pdf")])
def test_figure_format_by_suffix(name, fmt):
    assert figure_format(name) == fmt


@pytest.mark.parametrize("name", ["a.jpg", "plot", "a.png.gz"])
def test_figure_format_rejects_other_suffixes(name):
    with pytest.raises(ParameterError, match=r"\.png, \.svg or \.pdf"):
        figure_format(name)


# -- the plotted data -----------------------------------------------------------------------


@pytest.mark.parametrize("mode", MODES)
def test_trajectories_are_the_engines_samples(poses, mode):
    start, end = poses
    _, _, mats = engine(start, end, mode)
    fig = plot_motions(start, end, mode, **SMALL)
    for k in range(3):  # default points: the tips of the unit axes
        drawn = np.array(line(fig, f"trajectory:{mode}:{k}").get_data_3d())
        np.testing.assert_allclose(drawn.T, mats[:, :3, k] + mats[:, :3, 3], atol=1e-12)


def test_custom_points(poses):
    start, end = poses
    points = np.array([[0.5, -1.0, 2.0], [0.0, 0.0, 0.0]])
    _, _, mats = engine(start, end, "screw")
    fig = plot_motions(start, end, "screw", points=points, **SMALL)
    for k, p in enumerate(points):
        drawn = np.array(line(fig, f"trajectory:screw:{k}").get_data_3d())
        np.testing.assert_allclose(drawn.T, mats[:, :3, :3] @ p + mats[:, :3, 3], atol=1e-12)
    assert "trajectory:screw:2" not in lines_by_gid(fig)


@pytest.mark.parametrize("mode", MODES)
def test_frames_at_the_instants(poses, mode):
    start, end = poses
    fig = plot_motions(start, end, mode, **SMALL)
    gids = lines_by_gid(fig)
    # Four instants: A and B are drawn once each, the two in between per motion.
    assert sorted(g for g in gids if g.startswith("frame:")) == sorted(
        f"frame:{name}:{axis}" for name in ("A", "B", f"{mode}:1", f"{mode}:2") for axis in "xyz"
    )
    inst = a2b.motion(start, end, mode).matrices(np.linspace(0, 1, 4))
    for i, pose in ((0, start), (1, inst[1]), (2, inst[2]), (3, end)):
        name = {0: "A", 3: "B"}.get(i, f"{mode}:{i}")
        for j, axis in enumerate("xyz"):
            (arrow,) = gids[f"frame:{name}:{axis}"]
            # Line3DCollection keeps its 3D segments (the shaft from tip to tail, then the
            # two head strokes) only in this private attribute; get_segments() holds the 2D
            # projection after drawing.
            tip, tail = np.asarray(arrow._segments3d)[0]
            np.testing.assert_allclose(
                [tail, tip], [pose[:3, 3], pose[:3, 3] + pose[:3, j]], atol=1e-12
            )


@pytest.mark.parametrize("unit", ["deg", "rad"])
@pytest.mark.parametrize("mode", MODES)
def test_transmission_samples_are_the_engines(poses, mode, unit):
    start, end = poses
    motion, _ts, mats = engine(start, end, mode)
    fig = plot_motions(start, end, mode, angle_unit=unit, **SMALL)
    omega, z = motion.frame.transmission(mats)
    x, y = line(fig, f"transmission-samples:{mode}").get_data()
    np.testing.assert_allclose(x, np.degrees(omega) if unit == "deg" else omega, atol=1e-9)
    np.testing.assert_allclose(y, z, atol=1e-12)
    # The samples start at A = (0, 0) and end at B = (φ, d).
    assert abs(omega[0]) < 1e-12 and abs(z[0]) < 1e-12
    assert omega[-1] == pytest.approx(motion.frame.phi) and z[-1] == pytest.approx(motion.frame.d)
    assert ("°" if unit == "deg" else "[rad]") in fig.axes[2].get_xlabel()


def test_darboux_closed_form_is_the_sine(poses):
    start, end = poses
    for delta in (0.0, 0.7):
        motion = a2b.motion(start, end, "darboux", delta=delta)
        info = motion.describe()
        fig = plot_motions(start, end, ("darboux", {"delta": delta}), angle_unit="rad", **SMALL)
        x, y = line(fig, "transmission-closed-form:darboux").get_data()
        sine = info["z0"] + info["lam"] * np.sin(x + info["kappa"])
        np.testing.assert_allclose(y, sine, atol=1e-12)
        # It passes through the samples, and the samples lie on it (Theorem 1).
        omega, z = motion.frame.transmission(motion.matrices(np.linspace(0, 1, SAMPLES)))
        np.testing.assert_allclose(
            z, info["z0"] + info["lam"] * np.sin(omega + info["kappa"]), atol=1e-12
        )
        assert x.min() < 0 < motion.frame.phi < x.max()


def test_darboux_long_way_closed_form(poses):
    start, end = poses
    motion = a2b.motion(start, end, "darboux", long_way=True, delta=-0.3)
    info = motion.describe()
    fig = plot_motions(
        start, end, ("darboux", {"long_way": True, "delta": -0.3}), angle_unit="rad", **SMALL
    )
    x, y = line(fig, "transmission-closed-form:darboux").get_data()
    np.testing.assert_allclose(y, info["z0"] + info["lam"] * np.sin(x + info["kappa"]), atol=1e-12)
    xs, _ = line(fig, "transmission-samples:darboux").get_data()
    assert xs[-1] == pytest.approx(motion.frame.phi - 2 * math.pi)


def _t_of_omega(motion, omega):
    """Invert eq. 17 (monotone in t on [0, 1]) by bisection, with the engine's tan_half_omega."""
    lo, hi = np.zeros_like(omega), np.ones_like(omega)
    target = np.tan(omega / 2)
    rising = motion.tan_half_omega(np.array([1.0]))[0] > 0
    for _ in range(60):
        mid = (lo + hi) / 2
        below = (motion.tan_half_omega(mid) < target) == rising
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return (lo + hi) / 2


@pytest.mark.parametrize(
    "params", [{}, {"a": 0.5, "b": -0.25}, {"m": [1.0, 0.2, -0.1, 0.3], "b": 1.5}]
)
def test_cubic_closed_form_is_eq_17_and_18(poses, params):
    start, end = poses
    motion = a2b.motion(start, end, "cubic", **params)
    fig = plot_motions(start, end, ("cubic", params), angle_unit="rad", **SMALL)
    x, y = line(fig, "transmission-closed-form:cubic").get_data()
    inside = (x >= 0) & (x <= motion.frame.phi)
    assert inside.sum() > 100
    t = _t_of_omega(motion, x[inside])
    np.testing.assert_allclose(y[inside], motion.z_of_t(t), atol=1e-9)
    # Those closed-form points are poses of the motion: the engine's (ω, z) at the same t.
    omega, z = motion.frame.transmission(motion.matrices(t))
    np.testing.assert_allclose(omega, x[inside], atol=1e-9)
    np.testing.assert_allclose(z, y[inside], atol=1e-9)


def test_screw_closed_form_is_a_line(poses):
    start, end = poses
    frame = a2b.motion(start, end, "screw").frame
    fig = plot_motions(start, end, "screw", **SMALL)
    x, y = line(fig, "transmission-closed-form:screw").get_data()
    np.testing.assert_allclose(y, frame.d * np.radians(x) / frame.phi, atol=1e-12)


def test_compare_overlays_the_modes(poses):
    start, end = poses
    fig = plot_motions(start, end, list(MODES), **SMALL)
    gids = lines_by_gid(fig)
    colours = set()
    for mode in MODES:
        _, _, mats = engine(start, end, mode)
        samples = line(fig, f"transmission-samples:{mode}")
        assert f"transmission-closed-form:{mode}" in gids
        drawn = np.array(line(fig, f"trajectory:{mode}:0").get_data_3d())
        np.testing.assert_allclose(drawn.T, mats[:, :3, 0] + mats[:, :3, 3], atol=1e-12)
        colours.add(samples.get_color())
    assert len(colours) == 3
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert [text.split(" ")[0] for text in legend] == list(MODES)
    assert "δ = 0" in legend[0] and "m0:m3" in legend[1] and "pitch" in legend[2]


@pytest.mark.parametrize(
    "mode, kind, count", [("darboux", True, 7), ("cubic", True, 7), ("cubic", "m", 7)]
)
def test_family_through_a_and_b(poses, mode, kind, count):
    start, end = poses
    motion = a2b.motion(start, end, mode)
    fig = plot_motions(start, end, mode, family=kind, angle_unit="rad", **SMALL)
    _name, members, chosen = family_members(motion, None if kind is True else kind)
    assert len(members) == count and members[count // 2][0] == pytest.approx(chosen)
    ends = np.array([0.0, motion.frame.phi])
    for j, (_, member) in enumerate(members):
        x, y = line(fig, f"family:{mode}:{j}").get_data()
        expected = closed_form_z(member, x)
        shown = np.isfinite(y)
        assert shown.sum() > 50
        np.testing.assert_allclose(y[shown], expected[shown], atol=1e-12)
        # Every member runs from A to B, as a motion and as a curve.
        np.testing.assert_allclose(member.matrices([0.0, 1.0]), [start, end], atol=1e-9)
        np.testing.assert_allclose(closed_form_z(member, ends), [0.0, motion.frame.d], atol=1e-9)
    # The chosen member is the highlighted closed form, drawn on top.
    x, y = line(fig, f"family:{mode}:{count // 2}").get_data()
    _xc, yc = line(fig, f"transmission-closed-form:{mode}").get_data()
    np.testing.assert_allclose(yc, y, atol=1e-12)
    assert (
        line(fig, f"transmission-closed-form:{mode}").get_linewidth()
        > 2 * line(fig, f"family:{mode}:0").get_linewidth()
    )


def test_equal_aspect_and_labels(poses):
    fig = plot_motions(*poses, "darboux", length_unit="mm", **SMALL)
    for ax in fig.axes[:2]:
        spans = [np.ptp(lim) for lim in (ax.get_xlim(), ax.get_ylim(), ax.get_zlim())]
        np.testing.assert_allclose(spans, spans[0])
        np.testing.assert_allclose(ax.get_box_aspect(), ax.get_box_aspect()[0])
        assert ax.get_xlabel() == "x [mm]"
    assert fig.axes[2].get_ylabel().endswith("[mm]")
    assert fig.axes[2].get_xlabel().endswith("[°]")
    title = suptitle(fig)
    assert title.startswith("darboux motion: δ = 0") and "φ = " in title


def test_title_states_essential_parameters(poses):
    cubic = suptitle(plot_motions(*poses, ("cubic", {"a": 0.5}), **SMALL))
    assert cubic.startswith("cubic motion: m0:m3 = ") and "a = 0.5, b = 0" in cubic
    screw = suptitle(plot_motions(*poses, "screw", angle_unit="rad", **SMALL))
    assert screw.startswith("screw motion: pitch = ") and " rad" in screw


def test_two_of_a_mode_get_their_parameters_as_labels(poses):
    fig = plot_motions(*poses, [("darboux", {}), ("darboux", {"delta": 0.5})], **SMALL)
    gids = lines_by_gid(fig)
    assert "transmission-samples:darboux (defaults)" in gids
    assert "transmission-samples:darboux (delta=0.5)" in gids


# -- sampled motions (Bézier and the like) ----------------------------------------------------


def test_sampler_in_the_cylinder_group(poses):
    start, end = poses
    darboux = a2b.motion(start, end, "darboux", delta=0.3)
    fig = plot_motions(start, end, [("mine", darboux.matrices)], **SMALL)
    omega, z = darboux.frame.transmission(darboux.matrices(np.linspace(0, 1, SAMPLES)))
    x, y = line(fig, "transmission-samples:mine").get_data()
    np.testing.assert_allclose(np.radians(x), omega, atol=1e-12)
    np.testing.assert_allclose(y, z, atol=1e-12)
    assert "transmission-closed-form:mine" not in lines_by_gid(fig)
    assert suptitle(fig).startswith("mine ")


def test_samples_outside_the_cylinder_group_have_no_transmission_panel(poses):
    start, end = poses
    given = a2b.motion(start, end, "cubic", frame="given")
    mats = given.matrices(np.linspace(0, 1, 12))
    assert not in_cylinder_group(given.frame, mats)
    fig = plot_motions(start, end, [("measured", mats)], **SMALL)
    assert len(fig.axes) == 2
    drawn = np.array(line(fig, "trajectory:measured:1").get_data_3d())
    np.testing.assert_allclose(drawn.T, mats[:, :3, 1] + mats[:, :3, 3], atol=1e-12)
    assert sum(g.startswith("frame:measured:") for g in lines_by_gid(fig)) == 2 * 3
    # With a motion that is in the group the panel is back, and the other one is named.
    fig = plot_motions(start, end, [("cubic", {"frame": "given"}), "darboux"], **SMALL)
    assert len(fig.axes) == 4  # a frame panel each, the trajectories, the transmission curve
    assert "transmission-samples:cubic" not in lines_by_gid(fig)
    assert "cubic: not in the cylinder group" in fig.axes[-1].get_xlabel()


def test_bezier_motion(rng):
    from a2b.motions.bezier import bezier_motion

    controls = [random_pose(rng) for _ in range(4)]
    motion = bezier_motion(controls)
    fig = plot_motions(controls[0], controls[-1], motion, **SMALL)
    mats = motion.matrices(np.linspace(0, 1, SAMPLES))
    drawn = np.array(line(fig, f"trajectory:{motion.kind}:2").get_data_3d())
    np.testing.assert_allclose(drawn.T, mats[:, :3, 2] + mats[:, :3, 3], atol=1e-12)


def test_sampler_must_return_matrices(poses):
    with pytest.raises(ParameterError, match=r"\(len\(ts\), 4, 4\)"):
        plot_motions(*poses, [("bad", lambda ts: np.stack([np.eye(4)] * 2))], **SMALL)


# -- special poses and errors ---------------------------------------------------------------


def test_pure_translation_and_identical_poses():
    shift = np.eye(4)
    shift[:3, 3] = [1.0, 2.0, 0.5]
    fig = plot_motions(np.eye(4), shift, list(MODES), family=True, **dict(SMALL, figsize=(12, 8)))
    x, y = line(fig, "transmission-samples:darboux").get_data()
    np.testing.assert_allclose(x, 0.0, atol=1e-12)
    np.testing.assert_allclose(y, np.linspace(0, math.sqrt(5.25), SAMPLES), atol=1e-12)
    assert not any(
        g.startswith(("family:", "transmission-closed-form:")) for g in lines_by_gid(fig)
    )
    fig = plot_motions(np.eye(4), np.eye(4), list(MODES), **dict(SMALL, figsize=(12.0, 8.0)))
    assert len(fig.axes) == 5  # a frame panel per motion, trajectories, transmission


def test_large_scene_scales_the_axes(poses):
    start, end = poses
    start, end = start.copy(), end.copy()
    start[:3, 3] *= 1000
    end[:3, 3] *= 1000
    _, _, mats = engine(start, end, "darboux")
    fig = plot_motions(start, end, "darboux", **SMALL)
    tip = np.array(line(fig, "trajectory:darboux:0").get_data_3d()).T - mats[:, :3, 3]
    length = np.linalg.norm(tip, axis=1)
    assert np.allclose(length, length[0]) and length[0] > 10
    assert plot_motions(start, end, "darboux", axis_length=1.0, **SMALL)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"angle_unit": "grad"}, "angle unit"),
        ({"points": [[1.0, 2.0]]}, r"shape \(K, 3\)"),
        ({"samples": 1}, "samples must be an integer"),
        ({"family": "x"}, "family must be"),
        ({"axis_length": -1.0}, "axis_length"),
    ],
)
def test_invalid_arguments(poses, kwargs, match):
    with pytest.raises(ParameterError, match=match):
        plot_motions(*poses, "darboux", **kwargs)


def test_engine_errors_pass_through(poses):
    with pytest.raises(A2bError, match="unknown mode"):
        plot_motions(*poses, ("helix", {}))
    with pytest.raises(A2bError, match="does not take"):
        plot_motions(*poses, ("screw", {"delta": 1.0}))


def test_missing_matplotlib_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(MissingDependencyError, match=r"pip install 'a2b-motions\[plot\]'") as info:
        require_matplotlib()
    assert isinstance(info.value, A2bError) and isinstance(info.value, ImportError)


def test_import_does_not_load_matplotlib():
    code = "import sys, a2b.plot; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# -- rates over time ----------------------------------------------------------------------------


@pytest.mark.parametrize("constant", [False, True])
def test_speeds_are_the_timed_rates(poses, constant):
    """The drawn lines are the law's own rates at times even over its duration; the limits are
    dashed at their values, every drawn rate stays within them, and the binding one is reached."""
    limits = {"speed": 1.0, "accel": 2.0, "angular_speed": 1.5}
    timed = {
        m: a2b.timing(
            a2b.motion(*poses, m),
            max_speed=1.0,
            max_accel=2.0,
            max_angular_speed=1.5,
            constant_speed=constant,
        )
        for m in MODES
    }
    fig = plot_speeds(timed, limits=limits, samples=201)
    for mode, law in timed.items():
        times = law.times(samples=201)
        rates = law.rates(times)
        for key in ("speed", "accel", "angular_speed"):
            drawn = line(fig, f"{key}:{mode}")
            np.testing.assert_allclose(drawn.get_xdata(), times, rtol=0, atol=0)
            np.testing.assert_allclose(drawn.get_ydata(), rates[key], rtol=0, atol=0)
            assert np.max(np.abs(drawn.get_ydata())) <= limits[key] * (1 + 1e-9)
        assert str(law.binding) in limits
        assert np.max(np.abs(rates[str(law.binding)])) >= limits[str(law.binding)] * (1 - 1e-3)
        assert (
            f"{mode}: {float(law.duration):.4g} s"
            in [t.get_text() for t in fig.axes[0].get_legend().get_texts()][list(timed).index(mode)]
        )
    dashed = sorted(float(a.get_ydata()[0]) for a in lines_by_gid(fig)["limit:accel"])
    assert dashed == [-2.0, 2.0]
    assert [float(a.get_ydata()[0]) for a in lines_by_gid(fig)["limit:speed"]] == [1.0]
    assert "angular speed" in fig.axes[2].get_ylabel()


def test_speeds_refuses_batches_and_nothing(poses):
    batch = a2b.timing(a2b.motion(np.stack([poses[0]] * 2), np.stack([poses[1]] * 2)), duration=1)
    with pytest.raises(ParameterError, match="single timed motions"):
        plot_speeds({"b": batch})
    with pytest.raises(ParameterError, match="at least one"):
        plot_speeds({})
    with pytest.raises(ParameterError, match="samples"):
        plot_speeds(a2b.timing(a2b.motion(*poses), duration=1), samples=1)


# -- a figure reads at a glance ----------------------------------------------------------------


def drawn_texts(fig) -> list:
    """``(text, window extent)`` of every text the figure draws, recorded as it draws."""
    from matplotlib.text import Text

    drawn, original = [], Text.draw

    def draw(self, renderer):
        original(self, renderer)
        if self.get_visible() and self.get_text().strip():
            drawn.append((self.get_text(), self.get_window_extent(renderer)))

    Text.draw = draw
    try:
        fig.canvas.draw()
    finally:
        Text.draw = original
    return drawn


def _figures_a2b_plot_makes():
    """Every kind of figure `a2b plot` draws, at the size it draws it: each mode, --compare,
    --family (both kinds), the given frame (no transmission panel), units, custom points,
    a Bézier motion and a spline with their marked poses, on the samples and generic poses."""
    from a2b.cli.options import curve_motion
    from a2b.io.poseschema import read_motion_file

    root = Path(__file__).resolve().parent.parent / "samples"
    with open(root / "quarter-turn.yaml", "rb") as f:
        quarter = read_motion_file(f)
    with open(root / "half-turn.yaml", "rb") as f:
        half = read_motion_file(f)
    rng = np.random.default_rng(17)
    generic = []
    for _ in range(2):
        start = random_pose(rng)
        generic.append((start, pose_about_axis(1.75, rng.normal(size=3), rng.normal(size=3), 0.8)
                        @ start))  # fmt: skip
    for name, (start, end) in [("quarter", (quarter.start, quarter.end)),
                               ("half", (half.start, half.end)),
                               ("generic 1", generic[0]), ("generic 2", generic[1])]:  # fmt: skip
        for mode in MODES:
            yield f"{name} {mode}", lambda s=start, e=end, m=mode: plot_motions(s, e, m)
        yield f"{name} compare", lambda s=start, e=end: plot_motions(s, e, list(MODES))
        yield (
            f"{name} family",
            lambda s=start, e=end: plot_motions(
                s, e, ["darboux", "cubic"], family=True, angle_unit="rad", length_unit="mm"
            ),
        )
        yield (
            f"{name} family of m",
            lambda s=start, e=end: plot_motions(
                s, e, "cubic", family="m", points=[(0.5, 0.5, 0.0), (0.0, 0.0, 2.0)]
            ),
        )
        yield (
            f"{name} given frame",
            lambda s=start, e=end: plot_motions(s, e, ("cubic", {"frame": "given"})),
        )
    limits = {"max_speed": 1.0, "max_accel": 2.0, "max_jerk": 5.0}
    timed = {m: a2b.timing(a2b.motion(quarter.start, quarter.end, m), **limits) for m in MODES}
    shown = {k[4:]: v for k, v in limits.items()}
    yield "speeds", lambda t=timed, lim=shown: plot_speeds(t, limits=lim, length_unit="m")
    for file in ("planar-bezier.yaml", "spline.yaml"):
        with open(root / file, "rb") as f:
            curve = read_motion_file(f)
        prefix = "C" if curve.key == "controls" else "P"
        marks = [(f"{prefix}{i}", pose) for i, pose in enumerate(curve.poses)][1:-1]
        for space in ("matrix", "study"):
            motion = curve_motion(curve, space, [])
            yield (
                f"{file} {space}",
                lambda c=curve, m=motion, k=marks: plot_motions(
                    c.poses[0], c.poses[-1], m, marks=k
                ),
            )


@pytest.mark.parametrize("name, make", list(_figures_a2b_plot_makes()), ids=lambda v: v
                         if isinstance(v, str) else "")  # fmt: skip
def test_no_text_overlaps_another_or_leaves_the_canvas(name, make):
    fig = make()
    texts = drawn_texts(fig)
    width, height = fig.bbox.width, fig.bbox.height
    outside = [t for t, box in texts
               if box.x0 < 0 or box.y0 < 0 or box.x1 > width or box.y1 > height]  # fmt: skip
    assert outside == []
    overlaps = [
        (a, b)
        for i, (a, box_a) in enumerate(texts)
        for b, box_b in texts[i + 1 :]
        if min(box_a.x1, box_b.x1) - max(box_a.x0, box_b.x0) > 1
        and min(box_a.y1, box_b.y1) - max(box_a.y0, box_b.y0) > 1
    ]
    assert overlaps == []
    sizes = {t: fig.dpi for t, _ in texts}  # drawn at the figure's dpi, 100
    assert sizes and fig.get_size_inches()[0] >= 10


def test_compare_draws_each_motion_in_a_panel_of_its_own(poses):
    fig = plot_motions(*poses, list(MODES), samples=SAMPLES, instants=4)
    titles = [ax.get_title() for ax in fig.axes]
    assert titles[:3] == [f"{mode}: moving frame at 4 instants" for mode in MODES]
    for ax, mode in zip(fig.axes[:3], MODES):
        gids = {artist.get_gid() for artist in ax.get_children() if artist.get_gid()}
        assert any(g.startswith(f"frame:{mode}:") for g in gids)  # its own frames only
        assert not any(g.startswith("frame:") and g.split(":")[1] in set(MODES) - {mode}
                       for g in gids)  # fmt: skip
        arrows = [a for a in ax.get_children() if (a.get_gid() or "").endswith(":x")]
        assert {tuple(np.round(a.get_edgecolor()[0][:3], 3)) for a in arrows} == {
            tuple(np.round(matplotlib_rgb(AXIS_COLOURS[0]), 3))
        }  # x axes red, as the legend says
    assert titles[3:] == [
        "Trajectories of body points",
        "Transmission curve (canonical coordinates)",
    ]


def matplotlib_rgb(colour):
    from matplotlib.colors import to_rgb

    return to_rgb(colour)
