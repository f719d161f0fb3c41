"""The library's batch entry point: a table of jobs in, a table of samples out.

:func:`samples` takes a pandas DataFrame or a pyarrow Table of jobs, one row per motion, and
returns the samples of every job as the same kind of table, built and sampled in blocks
through the one motion core (:func:`a2b.jobs.sample`: the jobs of one kind and sample count
are one batched :func:`a2b.motion`), so a job gets exactly the samples, choices and errors of
the same job in a jobs file for ``a2b batch``. It needs pyarrow (the ``parquet`` extra).

The jobs table
--------------

=====================  ===============================================================
column                 meaning (a missing value, null or NaN, means "not given")
=====================  ===============================================================
``name``               text; default: ``job`` and the row's position, ``"job0"``,
                       ``"job1"``, … as in a jobs file (pandas: of a range index, so that a
                       Dask partition's rows keep their numbers), else the index label
``start_qw`` … ``_qz`` the start rotation, a quaternion w, x, y, z of any non-zero scale
``start_tx`` … ``_tz`` the start translation (all three, or none for zero)
``start``              instead: the 16 numbers of the 4x4 robotics matrix, row by row
                       (a list column, or arrays of shape (16,) or (4, 4))
``end_…``, ``end``     the end pose, in the same forms
``mode``               ``darboux``, ``cubic`` or ``screw``; default: the ``mode`` argument
``samples``            a whole number from 2 to 2**53; default: the ``samples`` argument
parameters             one column per motion parameter of :mod:`a2b.parameters`, named as
                       in a jobs file: ``delta``, ``kappa`` (radians), ``lam``, ``branch``
                       (+1/−1), ``pitch_start``, ``pitch_end``, ``long_way`` (bool),
                       ``a``, ``b``, ``frame`` (text); ``m`` (4 numbers), ``alpha``,
                       ``beta`` (6 numbers) and ``through`` (16 numbers, a matrix) as
                       list columns
=====================  ===============================================================

A problem is one :class:`a2b.errors.A2bError` line that names the job (``job NAME: ...``), or
the column for a table without the columns it needs. The samples table has the columns of
:mod:`a2b.io.parquet`: ``job`` (pandas: categorical; Arrow: dictionary), ``t``, ``time``
(with ``duration``), and the pose in ``layout``.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator

import numpy as np

from .errors import A2bError, ParameterError, PoseError
from .jobs import job_names
from .names import FRAMES, MAX_SAMPLES, MIN_SAMPLES
from .parameters import TABLE

__all__ = ["BLOCK_JOBS", "chunks", "chunks_of_blocks", "job_blocks", "samples", "samples_table"]

#: Jobs converted, built and sampled together: memory is bounded by them (``a2b batch
#: --chunk-size``).
BLOCK_JOBS = 1024

_QUAT = ("qw", "qx", "qy", "qz")
_TRANS = ("tx", "ty", "tz")
_POSE_COLUMNS = {"start", "end"} | {
    f"{end}_{c}" for end in ("start", "end") for c in _QUAT + _TRANS
}
_PARAMETERS = {p.name: p for p in TABLE}
_KNOWN = _POSE_COLUMNS | {"name", "mode", "samples"} | set(_PARAMETERS)


def samples(
    jobs,
    *,
    mode: str = "darboux",
    samples: int = 101,
    layout: str = "csv",
    duration: float | None = None,
    start_time: float = 0.0,
):
    """The samples of every job of a jobs table, as the same kind of table.

    Parameters
    ----------
    jobs : pandas.DataFrame or pyarrow.Table
        One job per row, with the columns of the module's table.
    mode, samples :
        For jobs that give none.
    layout : {"csv", "matrix", "study"}
        The pose columns: ``tx,ty,tz,qw,qx,qy,qz``, the 12 entries of ``[R | t]``, or the
        Study parameters ``p0 … q3`` (:data:`a2b.io.parquet.LAYOUTS`).
    duration, start_time : float
        With ``duration``, a ``time`` column ``t · duration + start_time`` in seconds.

    Returns
    -------
    pandas.DataFrame or pyarrow.Table
        The rows of every job in order, ``t`` evenly spaced in [0, 1] per job.

    Raises
    ------
    A2bError
        A missing or unknown column, a value of the wrong kind, an invalid pose, a parameter
        without a solution, a singular motion: one line that names the job.

    Examples
    --------
    >>> import pandas as pd, a2b.table
    >>> jobs = pd.DataFrame({"start_qw": [1.0], "start_qx": 0.0, "start_qy": 0.0,
    ...     "start_qz": 0.0, "end_qw": 0.0, "end_qx": 0.0, "end_qy": 0.0, "end_qz": 1.0,
    ...     "end_tx": 1.0, "end_ty": 0.0, "end_tz": 0.0})
    >>> a2b.table.samples(jobs, samples=3)[["job", "t", "tx"]].to_numpy().tolist()
    [['0', 0.0, 0.0], ['0', 0.5, 0.5], ['0', 1.0, 1.0]]
    """
    pieces = chunks(jobs, mode=mode, samples=samples, layout=layout)
    table = samples_table(pieces, layout, duration=duration, start_time=start_time)
    return table.to_pandas() if _is_pandas(jobs) else table


def chunks(jobs, *, mode: str = "darboux", samples: int = 101, layout: str = "csv"):
    """The samples of a jobs table as :class:`a2b.samples.Samples`, block by block, for a
    writer such as :func:`a2b.io.parquet.write_parquet` (memory bounded by the block)."""
    return chunks_of_blocks(job_blocks(jobs), mode=mode, samples=samples, layout=layout)


def chunks_of_blocks(
    blocks: Iterable, *, mode: str = "darboux", samples: int = 101, layout: str = "csv"
) -> Iterator:
    """The samples of :class:`a2b.io.jobfiles.JobBlock` s (from a table or a jobs file) as
    :class:`a2b.samples.Samples` in ``layout`` (a key of :data:`a2b.io.parquet.LAYOUTS`),
    through :func:`a2b.jobs.sample`."""
    from .io.parquet import LAYOUTS, REPRESENTATIONS
    from .jobs import sample

    if layout not in LAYOUTS:
        raise A2bError(f"unknown layout {layout!r}; expected one of {', '.join(LAYOUTS)}")
    return sample(blocks, mode=mode, samples=samples, representation=REPRESENTATIONS[layout])


def samples_table(
    chunks: Iterable, layout: str = "csv", *, duration: float | None = None, start_time=0.0
):
    """Samples as one pyarrow Table with the columns of :mod:`a2b.io.parquet`; with
    ``duration``, a ``time`` column ``t · duration + start_time`` (:func:`a2b.output.stamped`)."""
    import pyarrow as pa

    from .io.parquet import record_batch, schema
    from .output import stamped

    if duration is not None:
        chunks = stamped(chunks, duration, start_time)
    batches = [record_batch(c) for c in chunks]
    if not batches:
        return schema(layout, time=duration is not None).empty_table()
    return pa.Table.from_batches(batches).unify_dictionaries()


def _is_pandas(table) -> bool:
    return type(table).__module__.split(".")[0] == "pandas"


class _Columns:
    """The columns of a pandas DataFrame or a pyarrow Table, read alike: numbers as floats
    with NaN where missing, anything else as a list with ``None`` where missing."""

    def __init__(self, table):
        self.pandas = _is_pandas(table)
        if self.pandas:
            self.names = [str(c) for c in table.columns]
            self.size = len(table)
            self._get = lambda name: table[name]
            import pandas as pd

            index = table.index
            if isinstance(index, pd.RangeIndex) and index.step == 1:  # positions, as in a file
                self.labels = job_names([None] * len(table), index.start)
            else:
                self.labels = [str(label) for label in index]
        elif hasattr(table, "schema") and hasattr(table, "column"):
            self.names = list(table.schema.names)
            self.size = table.num_rows
            self._get = table.column
            self.labels = None
        else:
            raise A2bError(
                f"a jobs table must be a pandas DataFrame or a pyarrow Table, got "
                f"{type(table).__name__}"
            )

    def values(self, name: str) -> list:
        column = self._get(name)
        if hasattr(column, "to_pylist"):
            return column.to_pylist()
        return [None if _missing(v) else v for v in column.tolist()]

    def numbers(self, name: str) -> np.ndarray | None:
        """A column of numbers as floats, NaN where missing; ``None`` if it holds anything
        else (a caller then finds the row)."""
        column = self._get(name)
        if self.pandas and column.dtype.kind in "iuf":
            return column.to_numpy(dtype=float, na_value=np.nan)
        if not self.pandas:
            import pyarrow as pa
            import pyarrow.compute as pc

            if pa.types.is_integer(column.type) or pa.types.is_floating(column.type):
                return pc.fill_null(column.cast(pa.float64()), np.nan).to_numpy()
        values = self.values(name)
        try:
            out = np.array([np.nan if v is None else v for v in values], dtype=float)
        except (TypeError, ValueError):
            return None
        if any(isinstance(v, bool | str) for v in values):
            return None
        return out


def _missing(value) -> bool:
    if value is None or type(value).__name__ in ("NAType", "NaTType"):
        return True
    try:
        return bool(value != value)  # NaN, pandas.NA, NaT
    except (TypeError, ValueError):
        return False


def job_blocks(jobs, size: int = BLOCK_JOBS) -> Iterator:
    """The jobs of a table as :class:`a2b.io.jobfiles.JobBlock` s of ``size``, validated.

    Raises
    ------
    A2bError
        At the first problem, naming the job (or the column); the table is checked before the
        first block is given.
    """
    from .io.jobfiles import JobBlock

    columns = _Columns(jobs)
    unknown = sorted(set(columns.names) - _KNOWN)
    if unknown:
        raise A2bError(
            f"jobs table: unknown column {unknown[0]!r}; the columns are name, start_qw … "
            f"start_tz or start, end_qw … end_tz or end, mode, samples and the motion "
            f"parameters ({', '.join(_PARAMETERS)})"
        )
    names = _names(columns)
    start = _poses(columns, "start", names)
    end = _poses(columns, "end", names)
    modes = _texts(columns, "mode", names)
    counts = _counts(columns, names)
    parameters = _parameters(columns, names)
    for lo in range(0, columns.size, size):
        part = slice(lo, lo + size)
        yield JobBlock(
            start[part], end[part], modes[part], counts[part], parameters[part], names[part],
            checked=True,
        )  # fmt: skip


def _names(columns: _Columns) -> list[str]:
    labels = columns.labels or job_names([None] * columns.size, 0)
    if "name" not in columns.names:
        return labels
    given = columns.values("name")
    for i, name in enumerate(given):
        if name is not None and not isinstance(name, str):
            raise A2bError(f"job {labels[i]}: name: expected text, got {name!r}")
    return [label if name is None else name for name, label in zip(given, labels)]


def _poses(columns: _Columns, end: str, names: list) -> np.ndarray:
    """The ``start`` or ``end`` poses as checked robotics matrices ``(n, 4, 4)``."""
    from .poses import check_matrices, matrices_from_quat_trans, valid_matrices

    quat = [f"{end}_{c}" for c in _QUAT]
    trans = [f"{end}_{c}" for c in _TRANS]
    given = [c for c in quat + trans if c in columns.names]
    if given and end in columns.names:
        raise A2bError(f"jobs table: give the {end} pose once: columns {end} and {given[0]}")
    if end in columns.names:
        matrices = _vectors(columns, end, 16, names).reshape(-1, 4, 4)
        with np.errstate(all="ignore"):
            ok = valid_matrices(matrices)
        make = check_matrices
    else:
        needed = quat + (trans if any(c in columns.names for c in trans) else [])
        missing = [c for c in needed if c not in given]
        if missing:
            raise A2bError(
                f"jobs table: no column {missing[0]!r}: the {end} pose is {', '.join(quat)} "
                f"(and {', '.join(trans)}), or {end}: 16 numbers of a 4x4 matrix"
            )
        numbers = np.zeros((columns.size, 7))
        for k, c in enumerate(given):
            numbers[:, k] = _floats(columns, c, names)
        with np.errstate(all="ignore"):
            ok = np.isfinite(numbers).all(axis=1) & numbers[:, :4].any(axis=1)
        matrices = numbers

        def make(row):
            return matrices_from_quat_trans(row[:4], row[4:])

    for i in np.flatnonzero(~ok).tolist():
        try:
            make(matrices[i])
        except PoseError as e:
            raise PoseError(f"job {names[i]}: {end}: {e}") from None
    return (
        matrices
        if matrices.ndim == 3
        else matrices_from_quat_trans(matrices[:, :4], matrices[:, 4:])
    )


def _floats(columns: _Columns, name: str, names: list) -> np.ndarray:
    numbers = columns.numbers(name)
    if numbers is not None:
        return numbers
    values = columns.values(name)
    for i, v in enumerate(values):
        if v is not None and (isinstance(v, bool | str) or not _is_number(v)):
            raise A2bError(f"job {names[i]}: {name}: expected a number, got {v!r}")
    return np.array([np.nan if v is None else float(v) for v in values])


def _is_number(value) -> bool:
    try:
        float(value)
    except (TypeError, ValueError):
        return False
    return True


def _vectors(columns: _Columns, name: str, size: int, names: list, optional=False) -> np.ndarray:
    """A list column of ``size`` numbers per row as ``(n, size)``; NaN rows where missing
    (only if ``optional``)."""
    out = np.full((columns.size, size), np.nan)
    for i, v in enumerate(columns.values(name)):
        if v is None and optional:
            continue
        try:
            row = np.asarray(v, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            row = None
        if row is None or row.shape != (size,) or any(isinstance(x, bool | str) for x in _flat(v)):
            raise A2bError(f"job {names[i]}: {name}: expected {size} numbers, got {v!r}")
        out[i] = row
    return out


def _flat(value) -> list:
    if isinstance(value, list | tuple):
        return [x for item in value for x in _flat(item)]
    return [value]


def _texts(columns: _Columns, name: str, names: list) -> list:
    if name not in columns.names:
        return [None] * columns.size
    values = columns.values(name)
    for i, v in enumerate(values):
        if v is not None and not isinstance(v, str):
            raise A2bError(f"job {names[i]}: {name}: expected text, got {v!r}")
    return values


def _counts(columns: _Columns, names: list) -> list:
    if "samples" not in columns.names:
        return [None] * columns.size
    out = []
    for i, v in enumerate(columns.values("samples")):
        if v is None:
            out.append(None)
            continue
        whole = isinstance(v, int | np.integer | float | np.floating) and not isinstance(v, bool)
        if not whole or not float(v).is_integer() or not MIN_SAMPLES <= v <= MAX_SAMPLES:
            raise A2bError(
                f"job {names[i]}: samples: expected a whole number from {MIN_SAMPLES} to 2**53, "
                f"got {v!r}"
            )
        out.append(int(v))
    return out


def _parameters(columns: _Columns, names: list) -> list[dict]:
    """The parameters of every job, as a jobs file gives them (only those given)."""
    out: list[dict] = [{} for _ in range(columns.size)]
    for key in (k for k in _PARAMETERS if k in columns.names):
        kind = _PARAMETERS[key].kind
        if kind in ("number", "branch"):
            values = _floats(columns, key, names)
            for i in np.flatnonzero(~np.isnan(values)).tolist():
                value = float(values[i])
                if not np.isfinite(value) or (kind == "branch" and value not in (1.0, -1.0)):
                    expected = "+1 or -1" if kind == "branch" else "a finite number"
                    raise ParameterError(f"job {names[i]}: {key}: expected {expected}, got {value}")
                out[i][key] = int(value) if kind == "branch" else value
        elif kind in ("vector", "pose"):
            size = _PARAMETERS[key].size or 16
            values = _vectors(columns, key, size, names, optional=True)
            for i in np.flatnonzero(~np.isnan(values).any(axis=1)).tolist():
                out[i][key] = values[i] if kind == "pose" else tuple(values[i].tolist())
            if kind == "pose":
                _check_through(out, key, names)
        else:
            allowed = (True, False) if kind == "bool" else FRAMES
            for i, value in enumerate(columns.values(key)):
                if value is None:
                    continue
                if isinstance(value, np.bool_):
                    value = bool(value)
                if not isinstance(value, bool if kind == "bool" else str) or value not in allowed:
                    expected = "true or false" if kind == "bool" else " or ".join(FRAMES)
                    raise ParameterError(
                        f"job {names[i]}: {key}: expected {expected}, got {value!r}"
                    )
                out[i][key] = value
    return out


def _check_through(parameters: list[dict], key: str, names: list) -> None:
    """``through`` as a checked robotics matrix."""
    from .poses import check_matrices

    for i, given in enumerate(parameters):
        if key in given:
            try:
                given[key] = check_matrices(given[key].reshape(4, 4))
            except PoseError as e:
                raise PoseError(f"job {names[i]}: {key}: {e}") from None
