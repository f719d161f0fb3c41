"""`a2b view`: the page's content, and the page in a real browser (headless Chromium)."""

from __future__ import annotations

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
from a2b.io.poseschema import read_poses
from tests import browser

pytest.importorskip("plotly", reason="a2b view needs plotly (the [view] extra)")

from a2b.view import MAX_FRAMES, view_page  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
DOCS = ROOT / "docs"


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
