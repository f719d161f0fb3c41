"""Instructions per single-motion call, counted by valgrind: a figure that load does not move.

Usage::

    python benchmarks/instructions.py                    # this checkout, every mode, and scipy
    python benchmarks/instructions.py --tree /tmp/old    # another checkout (an A/B)

On a shared machine, timings of a 300 µs call drift by tens of per cent with the load; the
number of instructions it executes does not (it varies by about 1 %). For every case the
script runs a child process twice under ``valgrind --tool=callgrind``, once with 20 warm-up
calls and once with 100 calls more, and divides the difference by 100: start-up and imports
cancel. BLAS runs on one thread (``OPENBLAS_NUM_THREADS=1``), as a spinning second thread would
add instructions of its own. The cases are those of ``run.py``'s ``core`` section: one
``a2b.interpolate`` of 101 samples per mode, and scipy's ``Slerp`` plus a linear translation
into ``(101, 4, 4)``.

Instructions are not time: a call that touches more code also misses the cache more (see
``docs/benchmarks.md``). They are the count that a change of the code moves, and nothing else.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: The child: imports, 20 warm-up calls, then ``count`` timed ones of the case.
CHILD = """
import sys
sys.path.insert(0, {here!r})
import numpy as np
from bench_common import test_poses
import a2b
start, end = test_poses()
ts = np.linspace(0.0, 1.0, 101)
case, count = sys.argv[1], int(sys.argv[2])
if case == "scipy":
    from run import peer_cases
    call = peer_cases(start, end, ts)["scipy Slerp + lerp"]
else:
    def call():
        return a2b.interpolate(start, end, ts, case)
for _ in range(20 + count):
    call()
"""

CASES = ("darboux", "screw", "cubic", "scipy")


def instructions(tree: Path, case: str, count: int) -> int:
    """Instructions of a child process that makes ``count`` calls of ``case`` after warm-up."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    done = subprocess.run(
        [
            "valgrind",
            "--tool=callgrind",
            "--callgrind-out-file=/dev/null",
            sys.executable,
            "-P",
            "-c",
            CHILD.format(here=str(HERE)),
            case,
            str(count),
        ],
        env=env,
        capture_output=True,
        text=True,
        check=True,
    )
    found = re.search(r"Collected : (\d+)", done.stderr)
    if found is None:
        raise RuntimeError(f"valgrind reported no count: {done.stderr[-500:]}")
    return int(found.group(1))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", type=Path, default=HERE.parent, help="the checkout to count")
    parser.add_argument("--calls", type=int, default=100, help="calls counted (default 100)")
    args = parser.parse_args(argv)
    if shutil.which("valgrind") is None:
        print("valgrind is not installed (apt install valgrind): nothing counted")
        return 1
    tree = args.tree.resolve()
    print(f"tree: {tree}")
    counts = {}
    for case in CASES:
        base = instructions(tree, case, 0)
        counts[case] = (instructions(tree, case, args.calls) - base) / args.calls
        print(f"{case:8s} {counts[case] / 1e3:8.0f} k instructions per call")
    for mode in CASES[:-1]:
        print(f"{mode} / scipy: {counts[mode] / counts['scipy']:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
