"""Draw docs/timed-speeds.png: the speed and the acceleration along the path of the origin of the
moving frame over time, for the three modes on samples/quarter-turn.yaml, timed by the
jerk-limited law of README's "Timed motions" (max speed 1, accel 2, jerk 5). Run from the
repository root: ``python docs/timed_speeds.py``."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import a2b  # noqa: E402
from a2b.io.readers import read_poses  # noqa: E402
from a2b.timelaw import timing  # noqa: E402

with open("samples/quarter-turn.yaml", "rb") as stream:
    job = read_poses(stream)
fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 5), sharex=True, layout="constrained")
for mode, colour in (("darboux", "tab:blue"), ("cubic", "tab:orange"), ("screw", "tab:green")):
    timed = timing(a2b.motion(job.start, job.end, mode), max_speed=1, max_accel=2, max_jerk=5)
    times = timed.times(samples=801)
    rates = timed.rates(times)
    top.plot(times, rates["speed"], color=colour, label=f"{mode} ({timed.duration:.3f} s)")
    bottom.plot(times, rates["accel"], color=colour)
top.axhline(1, color="grey", lw=0.8, ls="--")
bottom.axhline(2, color="grey", lw=0.8, ls="--")
bottom.axhline(-2, color="grey", lw=0.8, ls="--")
top.set_ylabel("speed [m/s]")
bottom.set_ylabel("accel. along path [m/s²]")
bottom.set_xlabel("time [s]")
top.legend()
top.set_title("quarter-turn.yaml, jerk-limited: --max-speed 1 --max-accel 2 --max-jerk 5")
fig.savefig("docs/timed-speeds.png", dpi=100)
