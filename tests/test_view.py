"""`a2b view`: the page's content, and the page in a real browser (headless Chromium)."""

from __future__ import annotations

import html
import json
import os
import re
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import cli
from a2b.errors import A2bError
from a2b.io.poseschema import read_poses
from tests import browser

pytest.importorskip("plotly", reason="a2b view needs plotly (the [view] extra)")

from a2b.view import MAX_FRAMES, view_page  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
DOCS = ROOT / "docs"
MODES = ("darboux", "cubic", "screw")


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def figure_of(page: str) -> dict:
    """The figure the page hands to Plotly.newPlot."""
    text = re.search(r"const figure = (.*);\n  const plot", page, re.S).group(1)
    return json.loads(text.replace("<\\/", "</"))


def _quarter_turn():
    with open(SAMPLES / "quarter-turn.yaml", "rb") as f:
        job = read_poses(f)
    return job.start, job.end


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
def test_the_frames_are_the_motion(mode):
    """Frame k moves the body to the motion's pose at t_k: origin and axis tips."""
    start, end = _quarter_turn()
    figure = figure_of(view_page(start, end, mode, samples=11))
    motion = a2b.motion(start, end, mode)
    matrices = motion.matrices(np.linspace(0, 1, 11))
    assert [f["name"] for f in figure["frames"]] == [f"{t:.4g}" for t in np.linspace(0, 1, 11)]
    names = [figure["data"][i].get("name") for i in figure["frames"][0]["traces"]]
    assert names[:4] == [f"{mode}: x axis", f"{mode}: y axis", f"{mode}: z axis", mode]
    for frame, pose in zip(figure["frames"], matrices):
        x_axis, _y, _z, origin = frame["data"][:4]
        assert np.allclose([origin[k][0] for k in "xyz"], pose[:3, 3], atol=1e-12)
        tip = np.array([x_axis[k][1] for k in "xyz"])
        assert np.allclose(tip, pose[:3, 3] + pose[:3, 0], atol=1e-12)  # axes 1 long
        marker = frame["data"][4]  # on the transmission curve
        omega, z = motion.frame.transmission(pose[None])
        assert np.allclose([marker["x"][0], marker["y"][0]], [np.degrees(omega[0]), z[0]])


def test_the_page_is_self_contained_and_escapes_user_text():
    start, end = _quarter_turn()
    page = view_page(start, end, "darboux", title="</script><b>x</b>")
    assert "</script><b>" not in page and "&lt;/script&gt;" in page
    assert not re.search(r"<(script|link|img)[^>]+(src|href)=", page)  # nothing to fetch
    assert "Plotly.newPlot" in page and len(page) > 3_000_000  # plotly.js inlined
    many = figure_of(view_page(start, end, "screw", samples=1001))
    assert len(many["frames"]) == MAX_FRAMES


def test_compare_puts_each_motion_in_a_legend_group():
    start, end = _quarter_turn()
    figure = figure_of(view_page(start, end, ["darboux", "cubic", "screw"]))
    shown = [t["name"] for t in figure["data"] if t.get("showlegend", True)]
    assert shown == ["darboux", "cubic", "screw", "screw axis"]
    for mode in ("darboux", "cubic", "screw"):
        group = [t for t in figure["data"] if t.get("legendgroup") == mode]
        assert {t["type"] for t in group} == {"scatter3d", "scatter"}  # body and curve


def test_the_command_line(tmp_path, monkeypatch):
    out = tmp_path / "turn.html"
    result = run("view", SAMPLES / "quarter-turn.yaml", "--compare", "darboux,screw", "-o", out)
    assert result.exit_code == 0, result.output
    assert figure_of(out.read_text())["frames"]
    result = run("view", SAMPLES / "quarter-turn.yaml")
    assert result.exit_code == 2 and "give -o FILE.html" in result.output
    piped = run("view", SAMPLES / "quarter-turn.yaml", "-o", "-")
    assert piped.exit_code == 0 and piped.output.startswith("<!DOCTYPE html>")
    opened = []
    monkeypatch.setattr("webbrowser.open", lambda uri: opened.append(uri) or True)
    result = run("view", SAMPLES / "spline.yaml", "--space", "study", "--open", "-v")
    assert result.exit_code == 0, result.output
    assert opened and opened[0].startswith("file://") and opened[0].endswith(".html")
    Path(opened[0][len("file://") :]).unlink()
    result = run("view", SAMPLES / "reference.tum", "-o", tmp_path / "r.html")
    assert result.exit_code == 0, result.output
    assert "reference.tum: " in (tmp_path / "r.html").read_text()[:2000]
    result = run("view", SAMPLES / "reference.tum", "--mode", "cubic", "-o", tmp_path / "x.html")
    assert result.exit_code == 2 and "--mode is for poses files" in result.output


# -- in a real browser -----------------------------------------------------------------------


@pytest.fixture(scope="module")
def chromium():
    exe = browser.find()
    if exe is None:
        pytest.skip("Chromium is not installed (Debian: apt install chromium); .ci/run installs it")
    page = browser.Chromium(exe)
    yield page
    page.close()


READY = "document.body && document.body.dataset.ready === 'yes'"
PLAY = (
    "(() => { const r = document.querySelector('.updatemenu-button').getBoundingClientRect();"
    " return [r.x + r.width / 2, r.y + r.height / 2]; })()"
)


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw", "compare"])
def test_the_page_plays_in_a_browser_offline(tmp_path, chromium, mode):
    """Loads with no console error and no request but its own file (the browser's proxy is
    a closed port: the network is off); play moves the drawn body; a screenshot."""
    page = tmp_path / f"{mode}.html"
    args = ["--compare", "darboux,cubic,screw"] if mode == "compare" else ["--mode", mode]
    args += ["--samples", "21"]  # fewer frames: swiftshader draws a frame in about 0.1 s
    assert run("view", SAMPLES / "quarter-turn.yaml", *args, "-o", page).exit_code == 0
    chromium.events.clear()
    chromium.open(page.as_uri(), READY)
    assert chromium.problems() == []
    assert chromium.requests() == [page.as_uri()]
    body = "darboux" if mode == "compare" else mode
    index = chromium.evaluate(
        f"document.getElementById('plot').data.findIndex(d => d.name === '{body}' "
        "&& d.mode === 'markers+text')"
    )
    where = f"document.getElementById('plot').data[{index}]"
    origin = f"[{where}.x[0], {where}.y[0], {where}.z[0]]"
    before, first = chromium.evaluate(origin), chromium.screenshot()
    chromium.click(*chromium.evaluate(PLAY))
    time.sleep(1.0)
    during, second = chromium.evaluate(origin), chromium.screenshot()
    assert during != before and second != first  # the body moved, and so did the pixels
    start, end = _quarter_turn()
    deadline = time.monotonic() + 60
    while not np.allclose(chromium.evaluate(origin), end[:3, 3]):  # it plays on to B
        assert time.monotonic() < deadline, chromium.evaluate(origin)
        time.sleep(0.25)
    assert chromium.problems() == []
    shot = chromium.screenshot()
    assert shot.startswith(b"\x89PNG")
    (tmp_path / f"view-{mode}.png").write_bytes(shot)
    if os.environ.get("A2B_WRITE_DOCS"):  # regenerate the screenshots of docs/
        (DOCS / f"view-{mode}.png").write_bytes(second)


# -- what a new user saw ---------------------------------------------------------------------


def _loop(n=40):
    """A curve off the cylinder group of its ends: turning about z while going straight."""
    angles = np.linspace(0.0, 1.5 * np.pi, n)
    mats = np.repeat(np.eye(4)[None], n, axis=0)
    mats[:, 0, 3], mats[:, 1, 3] = angles, np.sin(angles)
    mats[:, :2, :2] = np.stack([[np.cos(angles), -np.sin(angles)],
                                [np.sin(angles), np.cos(angles)]]).transpose(2, 0, 1)  # fmt: skip
    return mats


def test_a_trajectory_gets_the_width_and_no_transmission_note():
    mats = _loop()
    layout = figure_of(view_page(mats[0], mats[-1], [("trajectory", mats)], samples=40))["layout"]
    assert "annotations" not in layout and layout["scene"]["domain"]["x"][1] == 1.0
    start, end = _quarter_turn()  # a mode keeps the note, right of its scene
    lifted = end.copy()
    lifted[:3, 3] += [0.3, -0.2, 0.1]
    layout = figure_of(view_page(start, lifted, ("cubic", {"frame": "given"})))["layout"]
    assert "no transmission curve" in layout["annotations"][0]["text"]
    assert layout["annotations"][0]["x"] > layout["scene"]["domain"]["x"][1]


def test_compared_names_stand_apart():
    start, end = _quarter_turn()
    data = figure_of(view_page(start, end, ["darboux", "cubic", "screw"]))["data"]
    names = [t for t in data if t.get("mode") == "markers+text" and t["text"][0] in MODES]
    assert [t["text"][0] for t in names] == list(MODES)
    assert len({t["textposition"] for t in names}) == 3
    assert all(t["textposition"] != "top left" for t in names)  # where A's label stands


def test_a_trajectory_slider_shows_seconds(tmp_path):
    out = tmp_path / "r.html"
    assert run("view", SAMPLES / "reference.tum", "-o", out).exit_code == 0
    slider = figure_of(out.read_text())["layout"]["sliders"][0]
    assert slider["currentvalue"]["prefix"] == "time from the first stamp = "
    labels = [step["label"] for step in slider["steps"]]
    assert labels[:3] == ["0 s", "0.1 s", "0.2 s"] and labels[-1] == "5.9 s"
    start, end = _quarter_turn()  # a motion: t
    slider = figure_of(view_page(start, end, "screw", samples=3))["layout"]["sliders"][0]
    assert slider["currentvalue"]["prefix"] == "t = "
    assert [s["label"] for s in slider["steps"]] == ["0", "0.5", "1"]


def test_a_long_trajectory_is_drawn(tmp_path):
    """Thousands of poses (the frames' quaternions against one in bulk) make a page of at most
    201 frames."""
    rng = np.random.default_rng(4)
    count = 3000
    quat = rng.normal(size=(count, 4)) + [0, 0, 0, 4]  # xyzw, near the identity
    rows = np.column_stack(
        [np.arange(count) * 0.01, np.cumsum(rng.normal(size=(count, 3)), 0), quat]
    )
    path, out = tmp_path / "long.tum", tmp_path / "long.html"
    path.write_text("".join(" ".join(repr(float(v)) for v in row) + "\n" for row in rows))
    result = run("view", path, "-o", out)
    assert result.exit_code == 0, result.output
    assert len(figure_of(out.read_text())["frames"]) == MAX_FRAMES


def test_times_are_checked():
    mats = _loop(5)
    with pytest.raises(A2bError, match="times must be 5 increasing finite numbers"):
        view_page(mats[0], mats[-1], [("loop", mats)], samples=5, times=[0, 1, 1, 2, 3])


def test_thinning_is_stated_under_verbose(tmp_path):
    out = tmp_path / "t.html"
    result = run("view", SAMPLES / "quarter-turn.yaml", "--samples", "1000", "-v", "-o", out)
    assert result.exit_code == 0, result.output
    assert "animation: 201 of the 1000 samples as frames (at most 201)" in result.output
    assert len(figure_of(out.read_text())["frames"]) == 201
    quiet = run("view", SAMPLES / "quarter-turn.yaml", "--samples", "201", "-v", "-o", out)
    assert "animation" not in quiet.output


def test_a_span_beyond_a_double_is_one_error_line(tmp_path):
    huge = tmp_path / "huge.tum"
    huge.write_text("0 1e308 0 0 0 0 0 1\n1 -1.5e308 0 0 0 0 0 1\n2 1.5e308 0 0 0 0 0 1\n")
    result = run("view", huge, "-o", tmp_path / "h.html")
    assert result.exit_code == 1
    assert result.output == (
        "Error: the poses reach coordinates of 1.5e+308, too far apart to draw: their span "
        "overflows a double\n"
    )
    assert not (tmp_path / "h.html").exists()


# -- the page under attack -------------------------------------------------------------------

#: Text that ends or changes a script element if it reaches one unescaped.
HOSTILE = "<!--<script></script><b>&amp;\u2028\u2029"


def _script(page: str) -> str:
    return re.search(r"const figure = (.*);\n  const plot", page, re.S).group(1)


def _hostile_pages(tmp_path):
    """A page for every place user text reaches: a label, a mark, a unit, a title, a file."""
    start, end = _quarter_turn()
    mats = _loop(6)
    yield "label", view_page(mats[0], mats[-1], [(HOSTILE, mats)], samples=6)
    yield "mark", view_page(start, end, "darboux", marks=[(HOSTILE, start)], samples=3)
    yield "unit", view_page(start, end, "darboux", length_unit=HOSTILE, samples=3)
    yield "title", view_page(start, end, "darboux", title=HOSTILE, samples=3)
    source = tmp_path / "<!--<script>.tum"  # the file name is in the title
    source.write_text((SAMPLES / "reference.tum").read_text())
    out = tmp_path / "file.html"
    assert run("view", source, "-o", out).exit_code == 0
    yield "file", out.read_text()


def test_user_text_cannot_end_the_script(tmp_path):
    for place, page in _hostile_pages(tmp_path):
        script = _script(page)
        for bad in ("<", ">", "&", "\u2028", "\u2029"):
            assert bad not in script, (place, bad)
        assert page.count("<script") == 2 and page.count("</script>") == 2, place
        text = json.dumps(figure_of(page), ensure_ascii=False)  # the same text, read back
        assert HOSTILE in text or html.escape(HOSTILE) in text or place == "file"


@pytest.mark.parametrize("place", ["label", "mark", "unit", "title", "file"])
def test_hostile_pages_render_in_a_browser(tmp_path, chromium, place):
    page = dict(_hostile_pages(tmp_path))[place]
    path = tmp_path / f"{place}.html"
    path.write_text(page)
    chromium.events.clear()
    chromium.open(path.as_uri(), READY)  # the page's last script ran to its end
    assert chromium.problems() == []
    assert chromium.evaluate("document.getElementById('plot').data.length") > 5


def test_z_ticks_stay_on_the_page_at_1200_px(tmp_path):
    exe = browser.find()
    if exe is None:
        pytest.skip("Chromium is not installed (Debian: apt install chromium); .ci/run installs it")
    from PIL import Image

    page = tmp_path / "turn.html"
    assert run("view", SAMPLES / "quarter-turn.yaml", "-o", page).exit_code == 0
    narrow = browser.Chromium(exe, width=1200, height=800)
    try:
        narrow.open(page.as_uri(), READY)
        time.sleep(0.5)
        shot = narrow.screenshot()
    finally:
        narrow.close()
    (tmp_path / "turn-1200.png").write_bytes(shot)
    image = np.asarray(Image.open(tmp_path / "turn-1200.png").convert("L"))
    # the strip along the left edge of the 3D scene, below the legend and above the slider,
    # holds no ink: a tick label that reached it was cut off
    strip = image[240:700, 0:16]
    assert strip.min() > 200, np.argwhere(strip <= 200)[:5]
