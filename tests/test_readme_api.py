"""The Python API example in README.md runs and does what it says."""

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
