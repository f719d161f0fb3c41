"""The Python API example in README.md runs and does what it says."""

import textwrap
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_python_api_example_runs():
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## Python API") :]
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    assert namespace["poses"].shape == (101, 4, 4)
    assert namespace["quat_wxyz"].shape == (101, 4)
    assert namespace["study"].shape == (101, 8)
    assert len(namespace["fiber"]["points"][0]) == 13
    assert {"m0", "m3", "a", "b"} <= set(namespace["info"])


def test_the_write_example_runs(tmp_path, monkeypatch):
    """README's ``a2b.write`` lines, after the first example, write what they say."""
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## Python API") :]
    blocks = [b.split("```", 1)[0] for b in section.split("```python\n")[1:]]
    example = next(b for b in blocks if "a2b.write(" in b)
    namespace: dict = {}
    exec(compile(blocks[0], "README.md", "exec"), namespace)
    monkeypatch.chdir(tmp_path)
    exec(compile(textwrap.dedent(example), "README.md", "exec"), namespace)
    lines = (tmp_path / "turn.tum").read_text().splitlines()
    assert lines[0] == "# time tx ty tz qx qy qz qw" and len(lines) == 12
    assert lines[-1].startswith("2.0 ")
    assert (tmp_path / "timed.mcap").read_bytes().startswith(b"\x89MCAP0\r\n")
