"""Every command × every format over samples/, written by two checkouts: are the bytes equal?

    git worktree add /tmp/old 016d568
    python benchmarks/same_bytes.py /tmp/old          # this checkout against the old one

Each case runs ``python -m a2b ...`` with ``PYTHONPATH`` set to each checkout, in a
directory of its own, on this checkout's samples/, and compares standard output, the exit
status and every file written (a directory of tum or kitti files file by file). A case whose
bytes differ on purpose names the reason in :data:`EXPECTED`; the script exits 1 if any other
case differs.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: Named here, not taken from a2b.formats: the old checkout has no table.
FORMATS = ("csv", "matrix", "study", "tum", "kitti", "mcap", "ros2")
TIMED = ("tum", "mcap", "ros2")

#: Cases whose bytes differ on purpose, with the reason (a prefix of the case's name).
EXPECTED = {
    "resample mark": "--mark prints 1/0 (README), not 1.0/0.0 (issue 27)",
}


def cases() -> list[tuple[str, list[str]]]:
    """``(name, arguments)``; ``{out}`` is replaced by the output path."""
    out = []
    for poses in ("quarter-turn", "half-turn", "translation", "canonical"):
        for fmt in FORMATS:
            timing = ["--duration", "2.5", "--start-time", "7"] if fmt in TIMED else []
            args = ["interpolate", f"samples/{poses}.yaml", "--samples", "57", "--format", fmt]
            out.append((f"interpolate {poses} {fmt}", [*args, *timing, "-o", "{out}"]))
    for mode in ("cubic", "screw"):
        for fmt in ("csv", "matrix", "study"):
            args = ["interpolate", "samples/quarter-turn.yaml", "--mode", mode, "--format", fmt]
            out.append((f"interpolate {mode} {fmt}", [*args, "-o", "{out}"]))
    law = ["--max-speed", "0.5", "--max-accel", "1", "--rate", "50"]
    for fmt in FORMATS:
        velocities = ["--velocities"] if fmt in ("csv", "matrix", "study", "ros2") else []
        args = ["interpolate", "samples/quarter-turn.yaml", *law, *velocities, "--format", fmt]
        out.append((f"interpolate time-law {fmt}", [*args, "-o", "{out}"]))
    for command, sample in (("bezier", "planar-bezier.yaml"), ("spline", "spline.yaml")):
        for fmt in FORMATS:
            args = [command, f"samples/{sample}", "--samples", "33", "--format", fmt]
            out.append((f"{command} {fmt}", [*args, "-o", "{out}"]))
    out.append(("spline kitti input", ["spline", "samples/walk.kitti", "--orthonormalize",
                                       "--samples", "59", "-o", "{out}"]))  # fmt: skip
    for fmt in FORMATS:
        timing = ["--duration", "2", "--start-time", "10"] if fmt in TIMED else []
        args = ["batch", "samples/jobs.yaml", "--samples", "21", "--format", fmt, *timing]
        out.append((f"batch {fmt}", [*args, "-o", "{out}"]))
        out.append((f"batch jsonl {fmt}", ["batch", "samples/jobs.jsonl", "--format", fmt,
                                           "-o", "{out}"]))  # fmt: skip
    for fmt in FORMATS:
        args = ["resample", "samples/reference.tum", "--rate", "100", "--format", fmt]
        out.append((f"resample rate {fmt}", [*args, "-o", "{out}"]))
        args = ["resample", "samples/estimate.tum", "--at", "samples/reference.tum", "--clip"]
        out.append((f"resample at {fmt}", [*args, "--format", fmt, "-o", "{out}"]))
    for fmt in ("csv", "matrix", "study"):
        args = ["resample", "samples/reference.tum", "--times", "samples/stamps.txt", "--mark"]
        out.append((f"resample mark {fmt}", [*args, "--mode", "spline", "--format", fmt,
                                             "-o", "{out}"]))  # fmt: skip
    args = ["resample", "samples/walk.kitti", "--orthonormalize", "--input-rate", "5"]
    out.append(("resample kitti", [*args, "--rate", "30", "--format", "tum", "-o", "{out}"]))
    return out


def written(path: Path) -> dict[str, bytes]:
    """The bytes of ``path``, or of every file in it."""
    if path.is_dir():
        return {p.name: p.read_bytes() for p in sorted(path.iterdir())}
    return {"": path.read_bytes()} if path.exists() else {}


def ends_only(before: dict, after: dict) -> str | None:
    """The reason if text output differs in the rows of t = 0 and t = 1 only: they are A and
    B as given now, not as the motion's formula rounds them (issue 27)."""
    if before.keys() != after.keys():
        return None
    for old, new in zip(before.values(), after.values()):
        a, b = old.splitlines(), new.splitlines()
        if len(a) != len(b) or b"\0" in old:
            return None
        header = 0 if a[0][:1].isdigit() or a[0][:1] == b"-" else 1  # kitti has no header
        inner = [k for k in range(len(a)) if a[k] != b[k] and k not in (header, len(a) - 1)]
        if inner:
            return None
    return "the rows of t = 0 and 1 are A and B as given (issue 27)"


def run(checkout: Path, args: list[str], work: Path) -> tuple:
    out = work / ("dir" if any(a in ("tum", "kitti") for a in args) and args[0] == "batch"
                  else "out")  # fmt: skip
    args = [str(out) if a == "{out}" else str(ROOT / a) if a.startswith("samples/") else a
            for a in args]  # fmt: skip
    command = [sys.executable, "-m", "a2b", *args]
    env = {**os.environ, "PYTHONPATH": str(checkout)}  # run in `work`: `-m` puts it first
    done = subprocess.run(command, cwd=work, env=env, capture_output=True, timeout=600)
    return done.returncode, done.stdout, written(out), done.stderr


def main(old: str) -> int:
    unexpected = 0
    for name, args in cases():
        with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
            before = run(Path(old), args, Path(a))
            after = run(ROOT, args, Path(b))
        same = before[:3] == after[:3]
        reason = next((why for prefix, why in EXPECTED.items() if name.startswith(prefix)), None)
        if not same and name.startswith("interpolate") and before[0] == after[0]:
            reason = ends_only(before[2], after[2])
        status = "same" if same else f"differs: {reason}" if reason else "DIFFERS"
        size = sum(len(v) for v in after[2].values())
        print(f"{status:<10.60} {name} ({size} bytes, status {after[0]})")
        if not same and reason is None:
            unexpected += 1
            print("   old:", before[0], before[3][-300:], "\n   new:", after[0], after[3][-300:])
    print(f"{unexpected} unexpected difference(s)")
    return 1 if unexpected else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "/tmp/old"))
