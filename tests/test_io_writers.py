"""Writers and their readers in pairs, and the repr-exact float formatter behind them."""

from __future__ import annotations

import io
import os

import numpy as np
import pytest

from a2b.errors import ParameterError
from a2b.formats import BY_NAME
from a2b.io import csvtable, mcapposes, parallel, trajectories, writers
from a2b.io.floatrepr import format_rows, integer_words, number_words, text_words
from a2b.output import stamped, text_ahead, write
from a2b.poses import matrices_from_quat_trans, rotations_from_quaternions, study_from_matrices
from a2b.samples import JobRuns, Samples

from .conftest import NonSeekableStream


def _reprs(values, sep=","):
    return "".join(sep.join(repr(float(v)) for v in row) + "\n" for row in values)


def test_format_rows_is_repr_for_special_values():
    values = np.array(
        [
            [
                0.0,
                -0.0,
                1.0,
                -1.0,
                0.1,
                0.5,
                1e16,
                1e15,
                1e-4,
                1e-5,
                123.456,
                np.nan,
                np.inf,
                -np.inf,
                5e-324,
                2.2250738585072014e-308,
                1.7976931348623157e308,
                1e300,
                -1e-300,
                9.999999999999999e15,
                0.30000000000000004,
                1e22,
                1 / 3,
                2 / 3,
                100.0,
                1234567890123456.8,
            ]
        ]
    )
    assert format_rows(values).decode() == _reprs(values)


@pytest.mark.parametrize("scale", [0, 3, 30, 200])
def test_format_rows_is_repr_for_random_values(rng, scale):
    values = rng.standard_normal((3000, 8)) * 10.0 ** rng.integers(-scale, scale + 1, (3000, 8))
    assert format_rows(values).decode() == _reprs(values)


def test_format_rows_reads_back_every_bit_pattern(rng):
    bits = rng.integers(0, 2**63, 40000, dtype=np.int64) * rng.choice([-1, 1], 40000)
    values = bits.view(np.float64).reshape(-1, 8)
    text = format_rows(values).decode()
    back = np.array([float(v) for v in text.replace("\n", ",").split(",")[:-1]]).reshape(
        values.shape
    )
    same = (back.view(np.int64) == values.view(np.int64)) | (np.isnan(back) & np.isnan(values))
    assert same.all()


def test_format_rows_is_repr_next_to_powers_of_two_and_ten():
    """Below a power of two the doubles are twice as dense; 10^k is often not a double."""
    values = [2.0**k * m for k in range(-1074, 1024) for m in (1, 3) if 2.0**k * m < np.inf]
    for k in range(-323, 309):
        p = float(f"1e{k}")
        values += [p, np.nextafter(p, 0), np.nextafter(p, np.inf), 5 * p, 9.999999999999999 * p]
    values = np.array(values)[:, None]
    assert format_rows(values).decode() == _reprs(values)


def test_format_rows_is_repr_for_short_decimals(rng):
    values = np.array(
        [
            [round(float(v), int(d)) for v, d in zip(row, digits)]
            for row, digits in zip(
                rng.normal(size=(3000, 8)) * 1000, rng.integers(0, 12, (3000, 8))
            )
        ]
    )
    integers = rng.integers(-(10**6), 10**6, (3000, 8)) * 10.0 ** rng.integers(-20, 20, (3000, 8))
    assert format_rows(values).decode() == _reprs(values)
    assert format_rows(integers).decode() == _reprs(integers)


def test_number_words_and_lengths(rng):
    values = np.concatenate(
        [
            rng.normal(size=2000) * 10.0 ** rng.integers(-300, 300, 2000),
            [0.0, -0.0, np.nan, np.inf, -np.inf, 5e-324, 100.0, 1e16, 1e-5, -2.5e-7],
        ]
    )
    words, lengths = number_words(values, lengths=True)
    texts = [repr(float(v)) for v in values]
    assert [row.tobytes().translate(None, b"\0").decode() for row in words] == texts
    assert lengths.tolist() == [len(t) for t in texts]
    assert not (words[:, 3] >> np.uint64(56)).any()  # the separator's byte is free


def test_integer_words(rng):
    values = np.concatenate(
        [[0, 1, 9, 10, 99, 100, 999_999_999, 10**15, 10**16 - 1], rng.integers(0, 10**12, 500)]
    )
    words = integer_words(values)
    assert [row.tobytes().translate(None, b"\0").decode() for row in words] == [
        str(int(v)) for v in values
    ]
    with pytest.raises(ValueError, match="integers in"):
        integer_words(np.array([-1]))


def test_format_rows_separator_and_prefix():
    values = np.array([[0.25, -3.0], [1e-7, 2.0]])
    assert format_rows(values, sep=" ") == b"0.25 -3.0\n1e-07 2.0\n"
    assert format_rows(values, prefix=["a", "b"]) == b"a,0.25,-3.0\nb,1e-07,2.0\n"
    assert format_rows(np.empty((0, 3))) == b""
    assert format_rows(values, prefix=np.array([b"x;", b"y;"])) == b"x;0.25,-3.0\ny;1e-07,2.0\n"
    with pytest.raises(ValueError, match="NUL"):
        format_rows(values, prefix=["a\0", "b"])
    with pytest.raises(ValueError, match="one character"):
        format_rows(values, sep=", ")


def _chunks(rng, n, size):
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    trans = rng.normal(size=(n, 3))
    mats = matrices_from_quat_trans(quat, rng.normal(size=(n, 3)))  # valid poses: read back
    study = study_from_matrices(mats) * rng.uniform(0.5, 2.0, size=(n, 1))
    t = np.linspace(0, 1, n)
    return [
        Samples(
            t[i : i + size],
            quat[i : i + size],
            trans[i : i + size],
            mats[i : i + size],
            study[i : i + size],
        )
        for i in range(0, n, size)
    ], (t, quat, trans, mats, study)


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study", "tum", "kitti", "mcap"])
def test_writer_reader_pairs(rng, fmt):
    chunks, (t, quat, trans, mats, study) = _chunks(rng, 25, 7)
    stream = io.BytesIO()
    write(list(stamped(chunks, 2.0, 3.0)), stream, fmt)
    stream.seek(0)
    if fmt == "csv":
        got_t, got_q, got_tr = trajectories.read_csv(stream)
        assert (
            np.array_equal(got_t, t)
            and np.array_equal(got_q, quat)
            and np.array_equal(got_tr, trans)
        )
    elif fmt == "matrix":
        got_t, got_m = trajectories.read_matrix_csv(stream)
        assert np.array_equal(got_t, t) and np.array_equal(got_m, mats)
    elif fmt == "study":
        got_t, got_s = trajectories.read_study_csv(stream)
        assert np.array_equal(got_t, t) and np.array_equal(got_s, study)
    elif fmt == "tum":
        got_time, got_q, got_tr = trajectories.read_tum(stream)
        assert np.array_equal(got_time, 2.0 * t + 3.0)
        assert np.array_equal(got_q, quat) and np.array_equal(got_tr, trans)
    elif fmt == "kitti":
        assert np.array_equal(trajectories.read_kitti(stream), mats)
    else:
        got_time, got_q, got_tr = mcapposes.read_mcap(stream)
        assert np.allclose(got_time, 2.0 * t + 3.0, atol=1e-9, rtol=0)
        assert np.array_equal(got_q, quat) and np.array_equal(got_tr, trans)


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study", "tum", "kitti"])
def test_text_made_ahead_is_written_as_it_is(rng, fmt):
    """Chunks whose lines were made ahead (:func:`writers.chunk_text`) write the bytes the
    writer makes of them; a chunk without them, or with another format's, is formatted."""
    chunks, _ = _chunks(rng, 25, 7)
    chunks = list(stamped(chunks, 2.0, 3.0))
    chunks[0].original = np.arange(7) % 2.0
    for chunk in chunks[1:]:
        chunk.original = np.zeros(len(chunk.t))
    plain = io.BytesIO()
    write(chunks, plain, fmt)
    other = "kitti" if fmt != "kitti" else "csv"
    for k, chunk in enumerate(chunks):
        chunk.text = [None, None, writers.chunk_text(other, chunk)][k % 3]
        if k % 3 == 0:
            text_ahead(BY_NAME[fmt])(chunk)
    assert text_ahead(BY_NAME["mcap"]) is None and text_ahead(BY_NAME["ros2"]) is None
    ahead = io.BytesIO()
    write(chunks, ahead, fmt)
    assert ahead.getvalue() == plain.getvalue()
    assert chunks[0].text[0] == fmt and chunks[0].text[1][0].dtype == np.uint8


def test_batch_csv_quotes_job_names(rng):
    chunks, (t, quat, _, _, _) = _chunks(rng, 4, 4)
    chunks[0].job = ["plain", 'with "quotes"', "with, comma", "plain"]
    stream = io.BytesIO()
    writers.write_batch_csv(stream, chunks)
    stream.seek(0)
    names, values = csvtable.read_batch_csv(stream)
    assert names == chunks[0].job
    assert np.array_equal(values[:, 0], t) and np.array_equal(values[:, 4:], quat)


def test_mcap_writer_needs_no_seek(rng):
    pipe = NonSeekableStream()
    chunks, _ = _chunks(rng, 10, 4)
    writers.write_mcap(pipe, chunks)
    got_time, _, _ = mcapposes.read_mcap(io.BytesIO(bytes(pipe.data)))
    assert len(got_time) == 10


@pytest.mark.parametrize("workers", [1, 3])
def test_many_blocks_in_order_with_helpers(rng, monkeypatch, workers):
    """Blocks formatted on threads come out in order, for plain and batch CSV."""
    monkeypatch.setattr(parallel, "WORKERS", workers)
    chunks, (t, quat, trans, _, _) = _chunks(rng, 20000, 6000)
    stream = io.BytesIO()
    writers.write_csv(stream, chunks)
    stream.seek(0)
    got_t, got_q, got_tr = trajectories.read_csv(stream)
    assert (
        np.array_equal(got_t, t) and np.array_equal(got_q, quat) and np.array_equal(got_tr, trans)
    )
    for c in chunks:
        c.job = [f"job {int(v * 7)}" for v in c.t]
    stream = io.BytesIO()
    writers.write_batch_csv(stream, chunks)
    stream.seek(0)
    names, values = csvtable.read_batch_csv(stream)
    assert names == [f"job {int(v * 7)}" for v in t]
    assert np.array_equal(values[:, 0], t) and np.array_equal(values[:, 4:], quat)


def test_formatting_error_reaches_the_caller(monkeypatch):
    monkeypatch.setattr(parallel, "WORKERS", 2)

    def broken(*args, **kwargs):
        raise RuntimeError("formatter failed")

    monkeypatch.setattr(writers, "format_rows", broken)
    chunk = Samples(np.zeros(3), np.tile([1.0, 0, 0, 0], (3, 1)), np.zeros((3, 3)))
    with pytest.raises(RuntimeError, match="formatter failed"):
        writers.write_csv(io.BytesIO(), [chunk])


def test_batch_job_name_with_nul_is_an_error():
    chunk = Samples(np.zeros(1), np.array([[1.0, 0, 0, 0]]), np.zeros((1, 3)), job=["a\0b"])
    with pytest.raises(ParameterError, match="NUL"):
        writers.write_batch_csv(io.BytesIO(), [chunk])


def _square_out_of_order(x):
    import time

    time.sleep(0.002 * (x % 3))  # finish out of order
    return x * x


def _fail_at_five(x):
    if x == 5:
        raise ParameterError("five")
    return x


@pytest.mark.parametrize("workers", [1, 2, 3])
def test_in_order_keeps_the_order(monkeypatch, workers):
    monkeypatch.setattr(parallel, "WORKERS", workers)
    assert list(parallel.in_order(_square_out_of_order, range(40))) == [x * x for x in range(40)]
    assert list(parallel.in_order(_square_out_of_order, [])) == []


def test_in_order_raises_at_the_failing_item(monkeypatch):
    monkeypatch.setattr(parallel, "WORKERS", 2)
    got = []
    with pytest.raises(ParameterError, match="five"):
        got.extend(parallel.in_order(_fail_at_five, range(20)))
    assert got == [0, 1, 2, 3, 4]  # the items before it, in order
    it = parallel.in_order(_fail_at_five, range(20))
    assert [next(it) for _ in range(5)] == [0, 1, 2, 3, 4]
    with pytest.raises(ParameterError, match="five"):
        next(it)


def test_in_order_holds_a_bounded_window(monkeypatch):
    """At most two items per thread are taken ahead of the one yielded."""
    monkeypatch.setattr(parallel, "WORKERS", 2)
    taken = []

    def items():
        for i in range(100):
            taken.append(i)
            yield i

    it = parallel.in_order(_square_out_of_order, items())
    next(it)
    assert len(taken) <= 2 * 2 + 1


def test_in_order_streams_share_one_pool_and_nest(monkeypatch):
    """A stream made on the pool feeds one formatted on it (as resample feeds its writer):
    both in order, on the same threads, no more of them than workers; a task that calls
    in_order itself does its items in its own thread instead of waiting for the pool."""
    import threading

    monkeypatch.setattr(parallel, "WORKERS", 2)
    seen = set()

    def made(x):
        seen.add(threading.current_thread())
        return _square_out_of_order(x)

    def formatted(x):
        seen.add(threading.current_thread())
        return -x

    assert list(parallel.in_order(formatted, parallel.in_order(made, range(60)))) == [
        -x * x for x in range(60)
    ]
    assert len(seen) == 2 and threading.current_thread() not in seen

    def nested(x):
        here = threading.current_thread()
        inner = list(parallel.in_order(lambda y: (y, threading.current_thread()), range(5)))
        return [y for y, _ in inner] == list(range(5)) and {t for _, t in inner} == {here}

    assert all(parallel.in_order(nested, range(8)))


@pytest.mark.skipif(not hasattr(os, "fork"), reason="os.fork is POSIX")
def test_a_forked_child_makes_its_own_pool(monkeypatch):
    """The parent's threads do not exist in a forked child: its first in_order makes a pool."""
    monkeypatch.setattr(parallel, "WORKERS", 2)
    assert list(parallel.in_order(_square_out_of_order, range(6))) == [x * x for x in range(6)]
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: report, then leave without running the parent's cleanups
        ok = list(parallel.in_order(_square_out_of_order, range(6))) == [x * x for x in range(6)]
        os.write(write, b"1" if ok else b"0")
        os._exit(0)
    os.close(write)
    assert os.read(read, 1) == b"1"
    os.waitpid(pid, 0)


def test_format_rows_takes_prefix_words():
    """A prefix of text words, as number_words makes them, is the same text as strings."""
    values = np.array([[0.25, -3.0], [1e-07, 2.0], [5.5, 0.0]])
    names = ["a", "long name, 17 ch", "é"]
    words = text_words(np.array([n.encode() + b"," for n in names]))
    assert words.dtype == np.uint64 and words.shape == (3, 3)
    assert format_rows(values, prefix=words) == format_rows(values, prefix=names)
    spaced = np.zeros((3, 2), np.uint64)  # zero bytes anywhere are skipped
    spaced[:, 1] = words[:, 0]
    assert format_rows(values, prefix=spaced).startswith(b"a,0.25,")
    with pytest.raises(ValueError, match="prefixes for 3 rows"):
        format_rows(values, prefix=words[:2])


def test_job_runs_stand_for_the_list_of_names():
    runs = JobRuns(["a", "b", "a"], [2, 1, 3])
    assert list(runs) == ["a", "a", "b", "a", "a", "a"] and len(runs) == 6
    assert JobRuns.of(list(runs)).names == ["a", "b", "a"]
    assert JobRuns.of(runs) is runs
    joined = JobRuns.join([runs, JobRuns(["c"], [4])])
    assert list(joined) == list(runs) + ["c"] * 4
    with pytest.raises(ValueError, match="2 names for 1 runs"):
        JobRuns(["a", "b"], [1])


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study"])
def test_batch_csv_is_the_rows_formatted_one_by_one(rng, fmt):
    """With the lead or without it, every line is the job, then repr of every number."""
    counts = [5, 5, 5, 3, 5]
    t = np.concatenate([np.linspace(0.0, 1.0, c) for c in counts])
    n = len(t)
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1)[:, None]
    trans = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-8, 8, size=(n, 1))
    mats = np.zeros((n, 4, 4))
    mats[:, :3, :3] = rotations_from_quaternions(quat)
    mats[:, :3, 3] = trans
    mats[:, 3, 3] = 1.0
    study = rng.normal(size=(n, 8))
    names = ["a", "b, c", "d", "e", "f"]
    job = JobRuns(names, counts)
    # one chunk with one pattern of t and one without; and a list of names for a job column
    chunks = [
        Samples(
            t[:15], quat[:15], trans[:15], mats[:15], study[:15],
            job=JobRuns(names[:3], counts[:3]),
        ),
        Samples(
            t[15:], quat[15:], trans[15:], mats[15:], study[15:],
            job=list(JobRuns(names[3:], counts[3:])),
        ),
    ]  # fmt: skip
    stream = io.BytesIO()
    writers.write_batch_csv(stream, chunks, fmt)
    columns = {
        "csv": np.column_stack([t, trans, quat]),
        "matrix": np.column_stack([t, mats[:, :3, :].reshape(n, 12)]),
        "study": np.column_stack([t, study]),
    }[fmt]
    lines = stream.getvalue().decode().splitlines()[1:]
    assert lines == [
        ",".join([writers._csv_field(name), *(repr(float(v)) for v in row)])
        for name, row in zip(job, columns)
    ]


def test_a_batch_chunk_without_rows_writes_nothing():
    empty = Samples(np.empty(0), np.empty((0, 4)), np.empty((0, 3)), job=[])
    stream = io.BytesIO()
    writers.write_batch_csv(stream, [empty])
    assert stream.getvalue() == b"job,t,tx,ty,tz,qw,qx,qy,qz\n"


def test_long_names_go_out_in_bounded_pieces(monkeypatch):
    """A long name makes pieces of fewer rows: names in one piece stay within NAME_BYTES."""
    monkeypatch.setattr(writers, "NAME_BYTES", 1000)
    t = np.tile(np.linspace(0, 1, 50), 3)
    runs = JobRuns(["a", "x" * 300, "b"], [50, 50, 50])
    rows = np.column_stack([t, np.zeros((150, 3)), np.tile([1.0, 0, 0, 0], (150, 1))])
    pieces = list(writers._batch_pieces(rows, runs))
    for _, leads, counts in pieces:
        assert sum(len(lead) * c for lead, c in zip(leads, counts)) <= 1000 or sum(counts) == 1
    assert sum(sum(counts) for _, _, counts in pieces) == 150
    chunk = Samples(t, rows[:, 4:], rows[:, 1:4], job=runs)
    stream = io.BytesIO()
    writers.write_batch_csv(stream, [chunk])
    stream.seek(0)
    names, values = csvtable.read_batch_csv(stream)
    assert names == list(runs)
    assert np.array_equal(values[:, 0], t)


def test_in_order_does_a_single_item_in_the_calling_thread(monkeypatch):
    """A command of one block (101 samples) starts no thread; more items go to the pool, in
    order."""
    import threading

    from a2b.io import parallel

    monkeypatch.setattr(parallel, "WORKERS", 2)
    here = threading.current_thread()
    assert list(parallel.in_order(lambda x: threading.current_thread(), [0])) == [here]
    assert list(parallel.in_order(lambda x: x * 2, [])) == []
    threads = list(parallel.in_order(lambda x: threading.current_thread(), range(4)))
    assert here not in threads
    assert list(parallel.in_order(lambda x: x * 2, range(50))) == [2 * x for x in range(50)]


def test_an_eager_stream_starts_its_first_item_before_the_second_is_made(monkeypatch):
    """``eager``: the first item is at work on the pool while the second is still being made
    (a trajectory's next piece parsed); without it, the stream waits for two items first."""
    import threading

    monkeypatch.setattr(parallel, "WORKERS", 2)
    started = threading.Event()

    def items():
        yield 0
        yield started.wait(timeout=0.5)  # True once item 0 is being worked on

    def work(item):
        started.set()
        return item

    assert list(parallel.in_order(work, items(), eager=True)) == [0, True]
    started.clear()
    assert list(parallel.in_order(work, items())) == [0, False]  # waited for nothing
    assert list(parallel.in_order(work, [], eager=True)) == []
