"""The sections that time whole processes: resample, csv, mcap, ros2, startup and batch."""

from __future__ import annotations

import importlib.util
import json
import shutil
import sys
from pathlib import Path

import numpy as np
from bench_common import (
    Row,
    interleaved,
    interleaved_processes,
    log,
    poses_document,
    rate,
    test_poses,
    wander,
)

import a2b


def _resample_processes(
    n: int, repeats: int, work: Path, exe: list[str], trajectory: tuple
) -> list[Row]:
    """``a2b resample`` of the trajectory at 10 n times against ``a2b interpolate --samples
    10 n``, whole processes (issue 26: at most 1.3×)."""
    from a2b.io.floatrepr import format_rows

    times, quat, trans = trajectory
    rows: list[Row] = []
    tum = work / "wander.tum"
    table = np.column_stack([times, trans, quat[:, [1, 2, 3, 0]]])
    tum.write_bytes(b"# time tx ty tz qx qy qz qw\n" + format_rows(table, sep=" "))
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(*test_poses())))
    out, ref = work / "resampled.csv", work / "interpolated.csv"
    samples = 10 * n
    commands = {
        "resample": exe + ["resample", str(tum), "--rate", "1000", "-o", str(out)],
        "interpolate": exe
        + [
            "interpolate",
            str(poses),
            "--samples",
            str(samples),
            "--mode",
            "screw",
            "-o",
            str(ref),
        ],
    }
    log(f"resample: {n} poses to {samples} times, {repeats} interleaved repeats")
    result = interleaved_processes(
        commands, repeats, rss=True, outputs={"resample": out, "interpolate": ref}
    )
    (seconds, peak), (reference, _) = result["resample"], result["interpolate"]
    written = sum(1 for _ in open(out, "rb")) - 1
    rows.append(
        Row(
            "resample",
            f"a2b resample of {n} TUM poses to {written} CSV rows",
            f"{seconds:.2f} s, {peak / 2**20:.0f} MiB",
        )
    )
    rows.append(
        Row(
            "resample",
            f"a2b interpolate --samples {samples} (screw) to CSV",
            f"{reference:.2f} s",
        )
    )
    ratio = seconds / reference
    rows.append(
        Row(
            "resample",
            "resample vs interpolate, whole process",
            "",
            f"{ratio:.2f}",
            "≤ 1.3",
            ratio <= 1.3,
        )
    )
    return rows


def _segment_loops(cases: dict, n: int, times, quat, trans, matrices, middle) -> int:
    """Add the peers' per-segment ways (one interpolator per segment, in a Python loop) to
    ``cases``, timed on the first segments; returns how many."""
    loop = min(n - 1, 2000)
    if "scipy Slerp + interp" in cases:
        from scipy.spatial.transform import Rotation, Slerp

        def scipy_loop():
            for k in range(loop):
                pair = Rotation.from_quat(quat[k : k + 2, [1, 2, 3, 0]])
                Slerp(times[k : k + 2], pair)(middle[k]).as_matrix()
                np.interp(middle[k], times[k : k + 2], trans[k : k + 2, 0])

        cases["scipy Slerp per segment"] = scipy_loop
    if "pytransform3d batch ScLERP" in cases:
        from pytransform3d.transformations import (
            dual_quaternion_from_transform,
            dual_quaternion_sclerp,
            transform_from_dual_quaternion,
        )

        def pt3d_loop():
            for k in range(loop):
                a = dual_quaternion_from_transform(matrices[k])
                b = dual_quaternion_from_transform(matrices[k + 1])
                u = (middle[k] - times[k]) / (times[k + 1] - times[k])
                transform_from_dual_quaternion(dual_quaternion_sclerp(a, b, u))

        cases["pytransform3d ScLERP per segment"] = pt3d_loop
    return loop


def _library_resample_rows(medians: dict, n: int, loop: int) -> list[Row]:
    rows: list[Row] = []
    rows.append(
        Row(
            "resample",
            f"a2b: {n - 1} segments resampled once each (screw)",
            rate(n - 1, medians["a2b"]),
        )
    )
    for peer in ("scipy Slerp per segment", "pytransform3d ScLERP per segment"):
        if peer not in medians:
            rows.append(Row("resample", peer, "not installed"))
            continue
        ratio = medians[peer] / medians["a2b"]
        rows.append(
            Row("resample", f"{peer} (loop of {loop}, per segment)", rate(n - 1, medians[peer]))
        )
        rows.append(Row("resample", f"a2b vs {peer}", "", f"{ratio:.1f}×", "≥ 5×", ratio >= 5))
    for peer in ("scipy Slerp + interp", "pytransform3d batch ScLERP"):
        if peer not in medians:
            rows.append(Row("resample", peer, "not installed"))
            continue
        ratio = medians[peer] / medians["a2b"]
        rows.append(Row("resample", f"{peer}, same segments", rate(n - 1, medians[peer])))
        rows.append(Row("resample", f"a2b vs {peer} (vectorised, no target)", "", f"{ratio:.2f}×"))
    return rows


def resample_section(n: int, repeats: int, work: Path, exe: list[str] | None) -> list[Row]:
    """``a2b resample`` as a process against ``a2b interpolate``; and the library against
    scipy's Slerp + interp and pytransform3d's batch ScLERP on the same segments."""
    from a2b.poses import matrices_from_quat_trans
    from a2b.resample import Resampler

    times, quat, trans = wander(n)
    if exe is not None:
        rows = _resample_processes(n, repeats, work, exe, (times, quat, trans))
    else:
        rows = [Row("resample", "the a2b command is not installed", "not measured")]

    matrices = matrices_from_quat_trans(quat, trans)
    middle = times[:-1] + 0.005  # one new time in each of the n − 1 segments

    def ours():
        resampler = Resampler(times, matrices, "screw", quat_wxyz=quat, checked=True)
        return resampler.sample(resampler.locate(middle))

    cases = {"a2b": ours}
    try:
        from scipy.spatial.transform import Rotation, Slerp
    except ImportError:
        pass
    else:

        def scipy_slerp():
            rotations = Slerp(times, Rotation.from_quat(quat[:, [1, 2, 3, 0]]))(middle)
            out = np.zeros((len(middle), 4, 4))
            out[:, :3, :3] = rotations.as_matrix()
            for axis in range(3):
                out[:, axis, 3] = np.interp(middle, times, trans[:, axis])
            out[:, 3, 3] = 1.0
            return out

        cases["scipy Slerp + interp"] = scipy_slerp
    try:
        from pytransform3d.trajectories import (
            dual_quaternions_from_transforms,
            dual_quaternions_sclerp,
            transforms_from_dual_quaternions,
        )
    except ImportError:
        pass
    else:

        def pt3d():
            k = np.searchsorted(times, middle, side="right") - 1
            u = (middle - times[k]) / (times[k + 1] - times[k])
            dq = dual_quaternions_from_transforms(matrices)
            a, b = dq[k], dq[k + 1]
            b[np.sum(a[:, :4] * b[:, :4], axis=1) < 0] *= -1
            return transforms_from_dual_quaternions(dual_quaternions_sclerp(a, b, u))

        cases["pytransform3d batch ScLERP"] = pt3d
    loop = _segment_loops(cases, n, times, quat, trans, matrices, middle)
    for f in cases.values():
        f()
    medians = interleaved(cases, repeats)
    for peer in ("scipy Slerp per segment", "pytransform3d ScLERP per segment"):
        if peer in medians:
            medians[peer] *= (n - 1) / loop
    return rows + _library_resample_rows(medians, n, loop)


def csv_columns(start: np.ndarray, end: np.ndarray, n: int) -> np.ndarray:
    """The eight columns of the CSV, computed exactly as the command computes them."""
    motion = a2b.motion(start, end, "darboux")
    ts = np.linspace(0.0, 1.0, n)
    try:
        from a2b.output import motion_samples

        parts = [(c.t, c.trans, c.quat_wxyz) for c in motion_samples(motion, n, "quat_trans")]
        return np.column_stack([np.concatenate([p[i] for p in parts]) for i in range(3)])
    except ImportError:
        quat, trans = motion.quat_trans(ts)
        return np.column_stack([ts, trans, quat])


def csv_section(
    n: int, repeats: int, work: Path, exe: list[str], baseline: Path | None = None
) -> tuple[list[Row], float | None]:
    start, end = test_poses()
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(start, end)))
    out_csv, ref_csv, columns = work / "out.csv", work / "savetxt.csv", work / "columns.npy"
    expected = csv_columns(start, end, n)
    np.save(columns, expected)
    savetxt = (
        "import sys, numpy as np; "
        "np.savetxt(sys.argv[2], np.load(sys.argv[1]), fmt='%.17g', delimiter=',')"
    )
    commands = {
        "a2b": exe + ["interpolate", str(poses), "--samples", str(n), "-o", str(out_csv)],
        "savetxt": [sys.executable, "-c", savetxt, str(columns), str(ref_csv)],
    }
    # the CSV writers the issue names as possible dependencies, when they are importable
    for name, script in CSV_LIBRARIES.items():
        if importlib.util.find_spec(name) is not None:
            commands[name] = [sys.executable, "-c", script, str(columns), str(work / f"{name}.csv")]
    outputs = {"a2b": out_csv, "savetxt": ref_csv}
    outputs.update({name: work / f"{name}.csv" for name in CSV_LIBRARIES})
    if baseline is not None:  # both as python -m a2b, each from its own tree
        for name, tree in (
            ("this checkout", Path(a2b.__file__).parent.parent),
            ("baseline", baseline),
        ):
            outputs[name] = work / f"{name}.csv"
            # -P: python -m would put the working directory first on sys.path, and from a
            # checkout's root time that checkout twice
            commands[name] = ["env", f"PYTHONPATH={tree}", sys.executable, "-P", "-m", "a2b"]
            commands[name] += [
                "interpolate",
                str(poses),
                "--samples",
                str(n),
                "-o",
                str(outputs[name]),
            ]
    log(f"csv: {n} rows, {repeats} interleaved repeats of {', '.join(commands)}")
    result = interleaved_processes(commands, repeats, outputs=outputs)
    a2b_s, sav_s = result["a2b"][0], result["savetxt"][0]
    exact, mismatches, header = read_back(out_csv, expected)
    ratio = a2b_s / sav_s
    rows = [
        Row(
            "csv",
            f"a2b interpolate --samples {n} -o out.csv (whole process)",
            f"{a2b_s:.2f} s, {rate(n, a2b_s)} rows",
        ),
        Row(
            "csv",
            "numpy.savetxt(fmt='%.17g'), same 8 columns, separate process",
            f"{sav_s:.2f} s, {rate(n, sav_s)} rows",
        ),
        Row("csv", "a2b time / savetxt time", "", f"{ratio:.3f}", "≤ 0.2", ratio <= 0.2),
        Row(
            "csv",
            f"read back bit for bit ({header})",
            "all values" if exact else f"{mismatches} differ",
            "",
            "all",
            exact,
        ),
    ]
    rows += _library_rows(result, work, expected, n, sav_s)
    if baseline is not None:
        rows += _baseline_rows(result, outputs, baseline)
    for path in work.glob("*.csv"):
        path.unlink()
    return rows, n / a2b_s


def _library_rows(result: dict, work: Path, expected: np.ndarray, n: int, sav_s: float) -> list:
    rows = []
    for name in CSV_LIBRARIES:
        if name not in result:
            rows.append(Row("csv", f"{name} CSV writer, same 8 columns", "not installed"))
            continue
        seconds = result[name][0]
        same = read_back(work / f"{name}.csv", expected)[0]
        rows.append(
            Row(
                "csv",
                f"{name} CSV writer, same 8 columns, separate process"
                + ("" if same else " (does NOT read back bit for bit)"),
                f"{seconds:.2f} s, {rate(n, seconds)} rows",
                f"{seconds / sav_s:.3f} of savetxt",
            )
        )
    return rows


def _baseline_rows(result: dict, outputs: dict, baseline: Path) -> list:
    """Issue 26: this checkout's CSV against a baseline tree's (a727f64), the same work.

    The bytes need not be the same: the core's values changed since a727f64 in the last digits
    (exact end poses, other summation orders), and a number's shortest text changes with it.
    The same rows and the same size within 1 % say that both wrote the same table."""
    ours, theirs = result["this checkout"][0], result["baseline"][0]
    mine, other = outputs["this checkout"].read_bytes(), outputs["baseline"].read_bytes()
    same_work = mine.count(b"\n") == other.count(b"\n") and abs(len(mine) - len(other)) <= (
        0.01 * len(other)
    )
    ratio = theirs / ours
    note = "same bytes" if mine == other else f"{len(mine)} vs {len(other)} bytes, same rows"
    return [
        Row("csv", "python -m a2b interpolate, this checkout", f"{ours:.2f} s"),
        Row("csv", f"python -m a2b interpolate, baseline {baseline}", f"{theirs:.2f} s"),
        Row(
            "csv",
            f"baseline time / this checkout's time ({note if same_work else 'NOT the same table'})",
            "",
            f"{ratio:.2f}",
            "≥ 1.0",
            ratio >= 1.0 and same_work,
        ),
    ]


#: Whole-process scripts for the CSV writers the issue compares: columns.npy -> CSV.
CSV_LIBRARIES = {
    "polars": (
        "import sys, numpy as np, polars as pl; a = np.load(sys.argv[1]); "
        "names = ['t', 'tx', 'ty', 'tz', 'qw', 'qx', 'qy', 'qz']; "
        "pl.DataFrame({k: a[:, i] for i, k in enumerate(names)}).write_csv(sys.argv[2])"
    ),
    "pyarrow": (
        "import sys, numpy as np, pyarrow as pa, pyarrow.csv as csv; a = np.load(sys.argv[1]); "
        "names = ['t', 'tx', 'ty', 'tz', 'qw', 'qx', 'qy', 'qz']; "
        "csv.write_csv(pa.table({k: a[:, i] for i, k in enumerate(names)}), sys.argv[2])"
    ),
}


def read_back(path: Path, expected: np.ndarray) -> tuple[bool, str, str]:
    """Whether a CSV (with a header line) reads back as ``expected`` bit for bit, with Python's
    correctly rounded ``float``; the number of differing values; the header."""
    with open(path) as f:
        header = f.readline().strip()
        values = np.array([[float(x) for x in line.split(",")] for line in f])
    if values.shape != expected.shape:
        return False, f"shape {values.shape} instead of {expected.shape}", header
    same = np.array_equal(values.view(np.int64), expected.view(np.int64))
    return same, str(int((values.view(np.int64) != expected.view(np.int64)).sum())), header


#: The same MCAP with the ``mcap`` package's ``Writer``: a2b samples the motion (as in a2b's
#: own command), then every sample becomes the same two JSON messages, zstd chunks of about the
#: same size. argv: poses.json, samples, output.
MCAP_LIBRARY = """
import json, sys
import numpy as np
from mcap.writer import CompressionType, Writer
import a2b
from a2b.io.poseschema import read_poses
from a2b.io.mcapwriter import _json_schema as _schema

job = read_poses(open(sys.argv[1], "rb"))
n = int(sys.argv[2])
quat, trans = a2b.motion(job.start, job.end, "darboux").quat_trans(np.linspace(0.0, 1.0, n))
ns = np.rint(np.linspace(0.0, 1.0, n) * 1e9).astype(np.int64).tolist()
with open(sys.argv[3], "wb") as f:
    w = Writer(f, chunk_size=2 << 20, compression=CompressionType.ZSTD)
    w.start(profile="", library="peer")
    ids = []
    for name, topic in (("foxglove.PoseInFrame", "/a2b/pose"), ("foxglove.FrameTransform", "/tf")):
        schema = w.register_schema(name=name, encoding="jsonschema", data=_schema(name))
        ids.append(w.register_channel(topic=topic, message_encoding="json", schema_id=schema))
    for i, (t, (x, y, z), (qw, qx, qy, qz)) in enumerate(zip(ns, trans.tolist(), quat.tolist())):
        stamp = {"sec": t // 1_000_000_000, "nsec": t % 1_000_000_000}
        xyz, xyzw = {"x": x, "y": y, "z": z}, {"x": qx, "y": qy, "z": qz, "w": qw}
        pose = {"timestamp": stamp, "frame_id": "world",
                "pose": {"position": xyz, "orientation": xyzw}}
        tf = {"timestamp": stamp, "parent_frame_id": "world", "child_frame_id": "a2b",
              "translation": xyz, "rotation": xyzw}
        for channel, message in zip(ids, (pose, tf)):
            data = json.dumps(message, separators=(",", ":")).encode()
            w.add_message(channel, log_time=t, data=data, publish_time=t, sequence=i)
    w.finish()
"""


def mcap_section(n: int, repeats: int, work: Path, exe: list[str]) -> list[Row]:
    start, end = test_poses()
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(start, end)))
    out = work / "out.mcap"
    command = exe + [
        "interpolate",
        str(poses),
        "--samples",
        str(n),
        "--format",
        "mcap",
        "-o",
        str(out),
    ]
    log(f"mcap: {n} poses, {repeats} repeats")
    seconds = interleaved_processes({"mcap": command}, repeats, outputs={"mcap": out})["mcap"][0]
    counts = ""
    try:
        from mcap.reader import make_reader

        with open(out, "rb") as f:
            stats = make_reader(f).get_summary().statistics
        counts = f", {stats.message_count} messages on {stats.channel_count} channels"
    except Exception as e:  # noqa: BLE001 - a summary we cannot read is reported, not fatal
        counts = f", summary not read: {e}"
    size = out.stat().st_size / 2**20
    out.unlink(missing_ok=True)
    per_second = n / seconds
    rows = [
        Row(
            "mcap",
            f"a2b interpolate --samples {n} --format mcap (whole process{counts}, {size:.0f} MiB)",
            f"{seconds:.2f} s, {rate(n, seconds)} poses",
            "",
            "≥ 500 k/s",
            per_second >= 500_000,
        )
    ]
    peer_n = max(n // 10, 1000)  # the peer takes about 10 µs a message: a tenth of the poses
    script = work / "mcap_peer.py"
    script.write_text(MCAP_LIBRARY)
    peer = [sys.executable, str(script), str(poses), str(peer_n), str(out)]
    log(f"mcap: the mcap package's Writer, {peer_n} poses, {repeats} repeats")
    peer_seconds = interleaved_processes({"peer": peer}, repeats, outputs={"peer": out})["peer"][0]
    out.unlink(missing_ok=True)
    peer_rate = peer_n / peer_seconds
    rows.append(
        Row(
            "mcap",
            f"mcap package's Writer, same messages, json.dumps, zstd ({peer_n} poses, whole "
            "process)",
            f"{peer_seconds:.2f} s, {rate(peer_n, peer_seconds)} poses",
        )
    )
    rows.append(
        Row(
            "mcap",
            "a2b's chunk builder vs the mcap package's Writer (poses/s)",
            "",
            f"{per_second / peer_rate:.1f}×",
            "≥ 2× (to stay)",
            per_second / peer_rate >= 2,
        )
    )
    return rows


#: The same ROS 2 messages (PoseStamped on /a2b/pose, TFMessage on /tf) with a peer's writer:
#: a2b samples the motion, as in a2b's own command, then the peer serialises and writes every
#: message. argv: poses.json, samples, output, rosbags|mcap_ros2.
ROS2_PEERS = """
import sys
import numpy as np
import a2b
from a2b.io.poseschema import read_poses
from a2b.io.ros2 import schema_text

job = read_poses(open(sys.argv[1], "rb"))
n, out, peer = int(sys.argv[2]), sys.argv[3], sys.argv[4]
quat, trans = a2b.motion(job.start, job.end, "darboux").quat_trans(np.linspace(0.0, 1.0, n))
ns = np.rint(np.linspace(0.0, 1.0, n) * 1e9).astype(np.int64).tolist()
rows = zip(ns, trans.tolist(), quat.tolist())
if peer == "rosbags":
    from pathlib import Path
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    T = {name.split("/")[-1]: kind for name, kind in store.types.items()}
    pose_t, tf_t = "geometry_msgs/msg/PoseStamped", "tf2_msgs/msg/TFMessage"
    with Writer(Path(out), version=8, storage_plugin=StoragePlugin.MCAP) as w:
        pose_c = w.add_connection("/a2b/pose", pose_t, typestore=store)
        tf_c = w.add_connection("/tf", tf_t, typestore=store)
        for t, (x, y, z), (qw, qx, qy, qz) in rows:
            stamp = T["Time"](sec=t // 1_000_000_000, nanosec=t % 1_000_000_000)
            header = T["Header"](stamp=stamp, frame_id="world")
            q = T["Quaternion"](x=qx, y=qy, z=qz, w=qw)
            p = T["Pose"](position=T["Point"](x=x, y=y, z=z), orientation=q)
            pose = T["PoseStamped"](header=header, pose=p)
            transform = T["Transform"](translation=T["Vector3"](x=x, y=y, z=z), rotation=q)
            stamped = T["TransformStamped"](
                header=header, child_frame_id="a2b", transform=transform
            )
            tf = T["TFMessage"](transforms=[stamped])
            w.write(pose_c, t, store.serialize_cdr(pose, pose_t))
            w.write(tf_c, t, store.serialize_cdr(tf, tf_t))
else:
    from mcap_ros2.writer import Writer

    with open(out, "wb") as f:
        w = Writer(f)
        schemas = [
            w.register_msgdef(name.replace("/", "/msg/"), schema_text(name).decode())
            for name in ("geometry_msgs/PoseStamped", "tf2_msgs/TFMessage")
        ]
        pose_s, tf_s = schemas
        for i, (t, (x, y, z), (qw, qx, qy, qz)) in enumerate(rows):
            stamp = {"sec": t // 1_000_000_000, "nanosec": t % 1_000_000_000}
            header = {"stamp": stamp, "frame_id": "world"}
            q, xyz = {"x": qx, "y": qy, "z": qz, "w": qw}, {"x": x, "y": y, "z": z}
            pose = {"header": header, "pose": {"position": xyz, "orientation": q}}
            transform = {"translation": xyz, "rotation": q}
            stamped = {"header": header, "child_frame_id": "a2b", "transform": transform}
            tf = {"transforms": [stamped]}
            w.write_message("/a2b/pose", pose_s, pose, log_time=t, publish_time=t, sequence=i)
            w.write_message("/tf", tf_s, tf, log_time=t, publish_time=t, sequence=i)
        w.finish()
"""


def ros2_section(n: int, repeats: int, work: Path, exe: list[str]) -> list[Row]:
    """``--format ros2`` (whole process) against ``--format mcap`` (JSON) in the same
    interleaved runs, and against rosbags' and mcap-ros2-support's writers (whole processes
    that sample with a2b, then serialise and write with the peer)."""
    start, end = test_poses()
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(start, end)))
    commands, outputs = {}, {}
    for fmt in ("ros2", "mcap"):
        outputs[fmt] = work / f"{fmt}.mcap"
        commands[fmt] = exe + [
            "interpolate",
            str(poses),
            "--samples",
            str(n),
            "--format",
            fmt,
            "-o",
            str(outputs[fmt]),
        ]
    log(f"ros2: {n} poses, ros2 and mcap (JSON) interleaved, {repeats} repeats")
    seconds = {k: v[0] for k, v in interleaved_processes(commands, repeats, outputs).items()}
    rows = [
        Row(
            "ros2",
            f"a2b interpolate --samples {n} --format ros2 (whole process: PoseStamped, "
            "TFMessage, and the Path of every pose)",
            f"{seconds['ros2']:.2f} s, {rate(n, seconds['ros2'])} poses",
            "",
            "≥ 1 M/s",
            n / seconds["ros2"] >= 1_000_000,
        ),
        Row(
            "ros2",
            f"a2b interpolate --samples {n} --format mcap (JSON, same run)",
            f"{seconds['mcap']:.2f} s, {rate(n, seconds['mcap'])} poses",
            f"ros2 {seconds['mcap'] / seconds['ros2']:.1f}× faster",
        ),
    ]
    peer_n = max(n // 10, 1000)  # the peers take 10 to 50 µs a pose: a tenth of the poses
    script = work / "ros2_peer.py"
    script.write_text(ROS2_PEERS)
    for peer, name in (
        ("rosbags", "rosbags' Writer (serialize_cdr)"),
        ("mcap_ros2", "mcap-ros2-support's Writer"),
    ):
        out = work / f"{peer}.out"
        try:
            __import__(peer)
        except ImportError:
            rows.append(Row("ros2", name, "not installed (pip install -e '.[bench]')"))
            continue
        argv = [sys.executable, str(script), str(poses), str(peer_n), str(out), peer]
        log(f"ros2: {name}, {peer_n} poses, {repeats} repeats")
        peer_seconds = interleaved_processes({peer: argv}, repeats, outputs={peer: out})[peer][0]
        shutil.rmtree(out, ignore_errors=True)
        out.unlink(missing_ok=True)
        ratio = (n / seconds["ros2"]) / (peer_n / peer_seconds)
        rows.append(
            Row(
                "ros2",
                f"{name}, same messages ({peer_n} poses, whole process)",
                f"{peer_seconds:.2f} s, {rate(peer_n, peer_seconds)} poses",
                f"a2b {ratio:.0f}× faster",
            )
        )
    return rows


#: Start-up against ``import numpy`` (issue 26: ``a2b --version`` stays at most 0.55×).
STARTUP_VS_NUMPY = {"a2b --version": 0.55, "a2b --help": 1.3}


def startup_section(repeats: int, exe: list[str]) -> list[Row]:
    commands = {
        "a2b --version": exe + ["--version"],
        "a2b --help": exe + ["--help"],
        'python -c "import numpy"': [sys.executable, "-c", "import numpy"],
    }
    log(f"startup: {repeats} interleaved repeats")
    interleaved_processes(commands, 2)  # warm the file cache
    result = interleaved_processes(commands, repeats)
    base = result['python -c "import numpy"'][0]
    rows = [
        Row("startup", name, f"{seconds * 1e3:.0f} ms") for name, (seconds, _) in result.items()
    ]
    for name in ("a2b --version", "a2b --help"):
        ratio = result[name][0] / base
        need = STARTUP_VS_NUMPY[name]
        rows.append(
            Row(
                "startup",
                f"{name} / import numpy",
                "",
                f"{ratio:.2f}",
                f"≤ {need:g}",
                ratio <= need,
            )
        )
    return rows


#: Fewest interleaved rounds of the batch section: its ratio is sensitive to drift and noise.
BATCH_MIN_ROUNDS = 7


def batch_section(
    jobs: int, samples: int, n: int, repeats: int, work: Path, exe: list[str]
) -> list[Row]:
    """``a2b batch`` against the ``csv`` section's single-motion command (``n`` samples, same
    poses), the two interleaved here so that the machine's drift slows both alike."""
    rng = np.random.default_rng(4)
    path = work / "jobs.jsonl"
    with open(path, "w") as f:
        for i in range(jobs):
            quats, trans = rng.normal(size=(2, 4)), rng.normal(size=(2, 3))
            job = {
                "name": f"job{i}",
                "start": {"quaternion_wxyz": quats[0].tolist(), "translation": trans[0].tolist()},
                "end": {"quaternion_wxyz": quats[1].tolist(), "translation": trans[1].tolist()},
            }
            f.write(json.dumps(job) + "\n")
    out = work / "batch.csv"
    start, end = test_poses()
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(start, end)))
    single_out = work / "out.csv"
    commands = {
        "batch": exe + ["batch", str(path), "--samples", str(samples), "-o", str(out)],
        "single": exe + ["interpolate", str(poses), "--samples", str(n), "-o", str(single_out)],
    }
    rounds = max(repeats, BATCH_MIN_ROUNDS)
    log(
        f"batch: {jobs} jobs × {samples} samples and single-motion CSV of {n} rows, "
        f"{rounds} interleaved rounds (at least {BATCH_MIN_ROUNDS}: the ratio is sensitive)"
    )
    result = interleaved_processes(
        commands, rounds, rss=True, outputs={"batch": out, "single": single_out}
    )
    seconds, peak = result["batch"]
    single_s = result["single"][0]
    with open(out, "rb") as f:
        lines = sum(1 for _ in f)
    out.unlink(missing_ok=True)
    single_out.unlink(missing_ok=True)
    rows_out = jobs * samples
    ratio = rows_out / seconds / (n / single_s)
    rows = [
        Row(
            "batch",
            f"a2b batch {jobs} jobs × {samples} samples -o batch.csv ({lines - 1} rows)",
            f"{seconds:.2f} s, {rate(rows_out, seconds)} rows",
        ),
        Row(
            "batch",
            f"a2b interpolate --samples {n} -o out.csv (single motion, interleaved with batch)",
            f"{single_s:.2f} s, {rate(n, single_s)} rows",
        ),
        Row(
            "batch",
            "peak resident memory of a2b batch (GNU time %M)",
            f"{peak / 1e6:.0f} MB",
            "",
            "≤ 150 MB",
            peak <= 150e6,
        ),
        Row(
            "batch",
            "rows/s vs single-motion CSV rows/s (interleaved)",
            "",
            f"{ratio:.2f}",
            "≥ 0.8",
            ratio >= 0.8,
        ),
    ]
    return rows


# ------------------------------------------------------------------------------------------
