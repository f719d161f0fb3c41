"""Parquet: samples as columns, through pyarrow (the optional extra ``a2b-motions[parquet]``).

=========  ================================================================================
column     type and meaning
=========  ================================================================================
job        ``dictionary<values=string, indices=int32>``: the job's name (batches only)
t          ``double``: the motion parameter in [0, 1] (of the samples as given)
time       ``double``: seconds, ``t · duration + start_time`` (only where the output is timed)
pose       ``double`` each, named as a2b's CSV headers: ``tx,ty,tz,qw,qx,qy,qz`` (layout
           ``csv``), ``r11,r12,r13,tx,…,tz`` (``matrix``), ``p0,…,p3,q0,…,q3`` (``study``)
twist      ``double`` each, ``vx,vy,vz,wx,wy,wz`` (when the samples carry velocities)
original   ``bool``: the row is a pose of a resampled trajectory (when the samples say)
=========  ================================================================================

The numbers are the doubles of the CSV output bit for bit (the CSV writes each as its
shortest round-trip text). The file's key-value metadata holds, as JSON: ``a2b.layout``,
``a2b.units`` (column -> unit: ``length`` is the unit of the input translations, ``s``,
``rad/s``, ``length/s``, ``""`` for none) and ``a2b.motion`` (what the caller states about the
motion: its mode, parameters, sample count, duration …); ``a2b.version`` names the writer.

:func:`write_parquet` streams: each row group holds at most :data:`ROW_GROUP_ROWS` rows, so
memory stays bounded for any count. It writes into a binary stream (a pipe works); for a file
that appears whole or not at all, give it the stream of :func:`a2b.io.atomic.atomic_output`.
:func:`read_parquet` reads a file back into the samples it was written from.

The samples come as an iterable of column blocks with the attributes of
:class:`a2b.io.writers.Chunk`: ``t (n,)``; the pose in the layout's representation
(``quat_wxyz (n, 4)`` and ``trans (n, 3)``, or ``matrices (n, 4, 4)``, or ``study (n, 8)``);
optionally ``job`` (a list of names or :class:`a2b.io.writers.JobRuns`), ``time (n,)``,
``twist (n, 6)`` and ``original (n,)``. What the first block carries decides the columns.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from typing import IO

import numpy as np

from .trajectories import CSV_HEADER, MATRIX_HEADER, STUDY_HEADER
from .writers import Chunk, JobRuns

__all__ = [
    "LAYOUTS",
    "ROW_GROUP_ROWS",
    "TWIST_COLUMNS",
    "file_metadata",
    "read_parquet",
    "record_batch",
    "schema",
    "write_parquet",
]

#: Layout -> the names of the pose columns, those of a2b's CSV headers.
LAYOUTS = {
    layout: tuple(header.split(",")[1:])
    for layout, header in (("csv", CSV_HEADER), ("matrix", MATRIX_HEADER), ("study", STUDY_HEADER))
}
#: The velocity columns, as in the CSV layouts.
TWIST_COLUMNS = ("vx", "vy", "vz", "wx", "wy", "wz")
#: The most rows in one row group: about 10 MB of numbers in the matrix layout.
ROW_GROUP_ROWS = 1 << 17

_UNITS = {
    "t": "",
    "time": "s",
    **dict.fromkeys(("tx", "ty", "tz"), "length"),
    **dict.fromkeys(("q0", "q1", "q2", "q3"), "length"),  # the dual part of a Study vector
    **dict.fromkeys(("vx", "vy", "vz"), "length/s"),
    **dict.fromkeys(("wx", "wy", "wz"), "rad/s"),
}


def _pyarrow():
    try:
        import pyarrow as pa
    except ImportError:  # pragma: no cover - the extra is missing
        from ..errors import A2bError

        raise A2bError("Parquet needs pyarrow: pip install 'a2b-motions[parquet]'") from None
    return pa


def schema(
    layout: str = "csv",
    *,
    job: bool = True,
    time: bool = False,
    twist: bool = False,
    original: bool = False,
    motion: Mapping | None = None,
):
    """The Arrow schema of samples in ``layout`` (``csv``, ``matrix``, ``study``), with the
    columns and the key-value metadata of the module's table; ``motion`` goes into
    ``a2b.motion``."""
    pa = _pyarrow()
    from .. import __version__

    if layout not in LAYOUTS:
        raise ValueError(f"unknown layout {layout!r}; expected one of {', '.join(LAYOUTS)}")
    names = ["job"] * job + ["t"] + ["time"] * time + list(LAYOUTS[layout])
    names += list(TWIST_COLUMNS) * twist
    fields = [
        pa.field(n, pa.dictionary(pa.int32(), pa.string()) if n == "job" else pa.float64())
        for n in names
    ]
    if original:
        fields.append(pa.field("original", pa.bool_()))
    metadata = {
        "a2b.version": json.dumps(__version__),
        "a2b.layout": json.dumps(layout),
        "a2b.units": json.dumps({n: _UNITS.get(n, "") for n in names if n != "job"}),
        "a2b.motion": json.dumps(dict(motion or {}), default=_plain),
    }
    return pa.schema(fields, metadata=metadata)


def _plain(value):
    """JSON for numpy values in the motion's parameters."""
    if isinstance(value, np.ndarray | np.generic):
        return value.tolist()
    raise TypeError(f"cannot write {type(value).__name__} into the metadata")


def file_metadata(schema) -> dict:
    """The a2b metadata of an Arrow schema (of a file): ``layout``, ``units``, ``motion``,
    ``version``, decoded from JSON; ``{}`` for a file that a2b did not write."""
    raw = schema.metadata or {}
    return {
        key.decode()[4:]: json.loads(value) for key, value in raw.items() if key.startswith(b"a2b.")
    }


def _pose_columns(layout: str, chunk) -> list[np.ndarray]:
    """The pose of ``chunk`` as the columns of ``layout``, in the order of its header."""
    if layout == "csv":
        return [*chunk.trans.T, *chunk.quat_wxyz.T]
    if layout == "matrix":
        return list(chunk.matrices[:, :3, :].reshape(len(chunk.t), 12).T)
    return list(chunk.study.T)


def _job_column(job, rows: int):
    """A job column (names, or :class:`JobRuns`) as a dictionary array of ``rows`` rows."""
    pa = _pyarrow()
    runs = JobRuns.of(job)
    if sum(runs.counts) != rows:
        raise ValueError(f"a job column of {sum(runs.counts)} rows for {rows} samples")
    encoded = pa.array(runs.names, pa.string()).dictionary_encode()
    indices = np.repeat(encoded.indices.to_numpy(), runs.counts).astype(np.int32)
    return pa.DictionaryArray.from_arrays(pa.array(indices), encoded.dictionary)


def record_batch(
    chunk, layout: str = "csv", *, duration: float | None = None, start_time: float = 0.0
):
    """One block of samples (see the module) as an Arrow record batch of :func:`schema`'s
    columns. ``duration``: add ``time = t · duration + start_time`` if the block has none."""
    pa = _pyarrow()
    n = len(chunk.t)
    time = getattr(chunk, "time", None)
    if time is None and duration is not None:
        time = chunk.t * duration + start_time
    job, twist = getattr(chunk, "job", None), getattr(chunk, "twist", None)
    original = getattr(chunk, "original", None)
    columns = [chunk.t] + [time] * (time is not None) + _pose_columns(layout, chunk)
    columns += list(twist.T) if twist is not None else []
    arrays = [pa.array(np.ascontiguousarray(c, dtype=float)) for c in columns]
    if job is not None:
        arrays.insert(0, _job_column(job, n))
    if original is not None:
        arrays.append(pa.array(np.asarray(original, dtype=bool)))
    kinds = {"job": job, "time": time, "twist": twist, "original": original}
    shape = schema(layout, **{k: v is not None for k, v in kinds.items()})
    return pa.RecordBatch.from_arrays(arrays, schema=shape.remove_metadata())


def write_parquet(
    stream: IO[bytes],
    chunks: Iterable,
    layout: str = "csv",
    *,
    motion: Mapping | None = None,
    duration: float | None = None,
    start_time: float = 0.0,
    row_group_rows: int = ROW_GROUP_ROWS,
) -> int:
    """Write samples into ``stream`` as one Parquet file; return the number of rows.

    Parameters
    ----------
    stream : binary stream
        Written from start to end (no seek), not closed.
    chunks : iterable of column blocks
        As the module describes; the first decides the columns, and every later one must
        carry the same.
    layout : {"csv", "matrix", "study"}
        The pose columns (the representation each block must hold).
    motion : mapping, optional
        What to state about the motion in the metadata ``a2b.motion``: mode, parameters,
        samples, duration, … (numbers, strings, lists, numpy arrays).
    duration, start_time : float
        With ``duration``, a ``time`` column ``t · duration + start_time`` in seconds.
    row_group_rows : int
        The most rows in one row group (and in memory at once, besides one block).
    """
    import pyarrow.parquet as pq

    pa = _pyarrow()
    chunks = iter(chunks)
    first = next(chunks, None)
    if first is None:
        shape = schema(layout, job=False, time=duration is not None, motion=motion)
        pq.write_table(shape.empty_table(), stream)
        return 0
    batch = record_batch(first, layout, duration=duration, start_time=start_time)
    names = batch.schema.names
    flags = {k: k in names for k in ("job", "time", "original")} | {"twist": "vx" in names}
    shape = schema(layout, **flags, motion=motion)
    pending: list = []  # batches of fewer than row_group_rows rows in all
    held = rows = 0
    with pq.ParquetWriter(stream, shape) as writer:
        while batch is not None:
            if batch.schema.names != names:
                raise ValueError(f"a block with columns {batch.schema.names}, expected {names}")
            pending.append(batch)
            held += batch.num_rows
            if held >= row_group_rows:  # whole row groups out, the rest kept for the next
                table = pa.Table.from_batches(pending, shape)
                whole = held - held % row_group_rows
                writer.write_table(table.slice(0, whole), row_group_size=row_group_rows)
                pending, held, rows = table.slice(whole).to_batches(), held - whole, rows + whole
            chunk = next(chunks, None)
            batch = None
            if chunk is not None:
                batch = record_batch(chunk, layout, duration=duration, start_time=start_time)
        if held:
            writer.write_table(pa.Table.from_batches(pending, shape), row_group_size=held)
            rows += held
    return rows


def read_parquet(source) -> tuple[Chunk, np.ndarray | None, dict]:
    """Read a Parquet file of samples (a path or a binary stream) back.

    Returns
    -------
    samples : Chunk
        ``t``, the pose in the file's layout (``quat_wxyz`` and ``trans``, ``matrices`` or
        ``study``), ``job`` as :class:`JobRuns` (if the file has the column), ``twist`` and
        ``original`` (if it has them).
    time : ndarray or None
        The ``time`` column in seconds, if the file has one.
    metadata : dict
        :func:`file_metadata` of the file.
    """
    import pyarrow.parquet as pq

    from ..errors import InputFileError

    table = pq.read_table(source)
    metadata = file_metadata(table.schema)
    layout = metadata.get("layout")
    if layout not in LAYOUTS:
        raise InputFileError(f"{_name(source)}: not a Parquet file of a2b samples (no layout)")
    columns = {name: _numbers(table, name) for name in table.schema.names if name != "job"}
    pose = np.column_stack([columns[name] for name in LAYOUTS[layout]])
    samples = Chunk(columns["t"])
    if layout == "csv":
        samples.trans, samples.quat_wxyz = pose[:, :3].copy(), pose[:, 3:].copy()
    elif layout == "matrix":
        samples.matrices = np.zeros((len(pose), 4, 4))
        samples.matrices[:, :3, :] = pose.reshape(-1, 3, 4)
        samples.matrices[:, 3, 3] = 1.0
    else:
        samples.study = pose
    if "job" in table.schema.names:
        samples.job = _runs(table)
    if "vx" in columns:
        samples.twist = np.column_stack([columns[name] for name in TWIST_COLUMNS])
    if "original" in columns:
        samples.original = columns["original"].astype(bool)
    return samples, columns.get("time"), metadata


def _name(source) -> str:
    return str(getattr(source, "name", source))


def _numbers(table, name: str) -> np.ndarray:
    return table.column(name).to_numpy()


def _runs(table) -> JobRuns:
    """The ``job`` column of a table as runs of equal names."""
    pa = _pyarrow()
    column = table.unify_dictionaries().column("job").combine_chunks()
    if not pa.types.is_dictionary(column.type):
        column = column.dictionary_encode()
    if column.null_count:
        raise ValueError("the job column has null names")
    codes = column.indices.to_numpy(zero_copy_only=False)
    if not len(codes):
        return JobRuns([], [])
    starts = np.flatnonzero(np.r_[True, codes[1:] != codes[:-1]])
    names = column.dictionary.to_pylist()
    return JobRuns([names[c] for c in codes[starts]], np.diff(np.r_[starts, len(codes)]).tolist())
