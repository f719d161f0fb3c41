"""One motion core for any number of pose pairs: every element of a batch is the motion alone.

Seeded property tests over every mode and every kind of parameter, for 0, 1 and 3 leading
dimensions, with the rare cases (half turns, pure translations, B = A, p(t) near 0, overflow)
mixed into the batches: samples, choices, warnings and errors of each element are those of the
same motion built alone.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import a2b
from a2b.errors import A2bError, A2bWarning, ParameterError, SingularMotionError
from a2b.jobs import sample

from .conftest import pose_about_axis, random_pose

TS = np.array([0.0, 0.1, 0.37, 0.5, 0.9, 1.0])
RTOL = 1e-15


def special_pairs(rng):
    """Pairs that take the rare branches of the core."""
    a = random_pose(rng)
    half = pose_about_axis(np.pi, [0.3, -1, 2], [1, 0, 0], 0.4) @ a
    half_d0 = pose_about_axis(np.pi, [1, 2, 0], [0, 1, 0], 0.0) @ a
    shift = np.eye(4)
    shift[:3, 3] = [0.3, -0.2, 1.0]
    tiny = pose_about_axis(1e-9, [0, 0, 1], [1, 2, 3], 0.5) @ a
    return [(a, half), (a, half_d0), (a, shift @ a), (a, a.copy()), (a, tiny)]


def pairs(rng, count):
    out = special_pairs(rng)
    while len(out) < count:
        out.append((random_pose(rng, 2.0), random_pose(rng, 2.0)))
    return out[:count]


#: Each case: mode and a function of (rng, count) giving per-element parameters.
CASES = {
    "darboux": lambda rng, n: {},
    "darboux-delta": lambda rng, n: {"delta": rng.normal(size=n)},
    "darboux-long": lambda rng, n: {"delta": rng.normal(size=n), "long_way": rng.random(n) < 0.5},
    "darboux-lam": lambda rng, n: {"lam": 3.0 + rng.random(n), "branch": rng.choice([-1, 1], n)},
    "darboux-pitch": lambda rng, n: {"pitch_start": rng.normal(size=n)},
    "darboux-pitch-end": lambda rng, n: {"pitch_end": rng.normal(size=n)},
    "cubic": lambda rng, n: {},
    "cubic-ab": lambda rng, n: {"a": 0.3 * rng.normal(size=n), "b": 0.3 * rng.normal(size=n)},
    "cubic-m": lambda rng, n: {"m": 1.0 + rng.random((n, 4))},
    "cubic-given": lambda rng, n: {"m": 1.0 + rng.random((n, 4)), "frame": "given"},
    "cubic-alpha": lambda rng, n: {
        "m": 1.0 + rng.random((n, 4)),
        "alpha": 0.01 * rng.normal(size=(n, 6)),
    },
    "screw": lambda rng, n: {},
}


def alone(start, end, mode, params, i):
    """Element ``i`` built on its own (with warnings recorded)."""
    own = {
        key: (value if isinstance(value, str) else np.asarray(value)[i])
        for key, value in params.items()
    }
    if "long_way" in own:
        own["long_way"] = bool(own["long_way"])
    if "branch" in own:
        own["branch"] = int(own["branch"])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", A2bWarning)
        try:
            motion = a2b.motion(start[i], end[i], mode, **own)
        except A2bError as e:
            return None, e, []
    return motion, None, [str(w.message) for w in caught]


def buildable(rng, mode, make, count):
    """Pairs and parameters where every element builds alone (the rest are left out)."""
    candidates = pairs(rng, 3 * count)
    start = np.stack([a for a, _ in candidates])
    end = np.stack([b for _, b in candidates])
    params = make(rng, len(candidates))
    keep = [i for i in range(len(candidates)) if alone(start, end, mode, params, i)[0] is not None]
    keep = keep[:count]
    assert len(keep) == count, "too few buildable cases"
    params = {k: v if isinstance(v, str) else np.asarray(v)[keep] for k, v in params.items()}
    return start[keep], end[keep], params


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("shape", [(), (6,), (2, 3, 2)])
def test_every_element_of_a_batch_is_the_motion_alone(rng, case, shape):
    mode = case.split("-")[0]
    count = int(np.prod(shape))
    start, end, params = buildable(rng, mode, CASES[case], max(count, 1))
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always", A2bWarning)
        batch = a2b.motion(
            start.reshape(shape + (4, 4)),
            end.reshape(shape + (4, 4)),
            mode,
            **{
                k: v if isinstance(v, str) else v.reshape(shape + v.shape[1:])
                for k, v in params.items()
            },
        )
    assert batch.shape == shape
    mats = batch.matrices(TS).reshape((-1, len(TS), 4, 4))
    quat, trans = batch.quat_trans(TS)
    study = batch.study(TS).reshape(-1, len(TS), 8)
    choices = batch.choices if shape else [batch.choices]
    flat_choices = np.array(choices, dtype=object).reshape(-1).tolist() if shape else choices
    for i in range(count):
        single, error, _ = alone(start, end, mode, params, i)
        assert error is None
        expected = single.matrices(TS)
        scale = np.abs(expected).max()
        np.testing.assert_allclose(mats[i], expected, rtol=0, atol=RTOL * 8 * scale)
        q, t = single.quat_trans(TS)
        np.testing.assert_allclose(quat.reshape(-1, len(TS), 4)[i], q, rtol=0, atol=4 * RTOL)
        np.testing.assert_allclose(
            trans.reshape(-1, len(TS), 3)[i], t, rtol=0, atol=8 * RTOL * scale
        )
        np.testing.assert_allclose(study[i], single.study(TS), rtol=0, atol=8 * RTOL * scale)
        assert list(flat_choices[i]) == single.choices
        if shape:
            element = batch[np.unravel_index(i, shape)]
            assert element.shape == ()
            assert element.describe() == single.describe()
    if not shape:
        assert batch.describe() == alone(start, end, mode, params, 0)[0].describe()


def test_the_batch_table_is_bit_for_bit_the_single_table(rng):
    """Where the arithmetic is the same, so are the bits: the coefficient tables."""
    for case, make in CASES.items():
        mode = case.split("-")[0]
        start, end, params = buildable(rng, mode, make, 5)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", A2bWarning)
            batch = a2b.motion(start, end, mode, **params)
            for i in range(5):
                single = alone(start, end, mode, params, i)[0]
                np.testing.assert_array_equal(batch.table[i], single.table, err_msg=case)


def test_an_error_names_the_element_and_is_the_error_alone(rng):
    start = np.stack([random_pose(rng) for _ in range(4)])
    end = start.copy()
    end[2] = pose_about_axis(1.0, [0, 0, 1], [0, 0, 0], 0.0) @ start[2]
    # a pure translation cannot take a phase κ; here elements 0, 1 and 3 are B = A
    with pytest.raises(ParameterError, match=r"^motion 0: the phase κ is undefined") as info:
        a2b.motion(start, end, "darboux", kappa=0.3)
    assert info.value.index == 0
    with pytest.raises(ParameterError) as single:
        a2b.motion(start[0], end[0], "darboux", kappa=0.3)
    assert str(single.value) == info.value.reason


def test_an_error_names_a_multi_index(rng):
    start = np.broadcast_to(np.eye(4), (2, 3, 4, 4)).copy()
    end = start.copy()
    end[..., 2, 3] = 1.0
    a = np.zeros((2, 3))
    b = np.zeros((2, 3))
    b[1, 2] = -1.5  # ψB = −0.5: passes through infinity
    with pytest.raises(SingularMotionError, match=r"^motion \(1, 2\): the cubic motion passes"):
        a2b.motion(start, end, "cubic", a=a, b=b)


def test_warnings_come_per_element_with_the_index(rng):
    """A motion close to p(t) = 0 warns alone; in a batch only that element warns, and says so."""
    a = np.eye(4)
    b = pose_about_axis(2e-4, [0, 0, 1], [0, 0, 0], 0.0)  # the long way passes near p = 0
    start = np.stack([a, a, a])
    end = np.stack([random_pose(rng), b, random_pose(rng)])
    with warnings.catch_warnings(record=True) as alone_caught:
        warnings.simplefilter("always", A2bWarning)
        a2b.motion(a, b, "darboux", long_way=True)
    assert len(alone_caught) == 1
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", A2bWarning)
        batch = a2b.motion(start, end, "darboux", long_way=np.array([False, True, False]))
    messages = [str(w.message) for w in caught]
    assert messages == [f"motion 1: {alone_caught[0].message}"]
    assert batch.warnings[1] == [str(alone_caught[0].message)]
    assert batch.warnings[0] == batch.warnings[2] == []


def test_parameters_broadcast_against_the_poses(rng):
    start, end = random_pose(rng), random_pose(rng)
    deltas = np.linspace(-1, 1, 5)
    batch = a2b.motion(start, end, "darboux", delta=deltas)
    assert batch.shape == (5,)
    for i, delta in enumerate(deltas):
        np.testing.assert_allclose(
            batch.matrices(TS)[i],
            a2b.motion(start, end, "darboux", delta=delta).matrices(TS),
            rtol=0,
            atol=1e-14,
        )
    with pytest.raises(ParameterError, match="leading shapes do not broadcast"):
        a2b.motion(np.stack([start] * 3), end, "darboux", delta=deltas)


def test_a_count_of_samples_is_evenly_spaced(rng):
    motion = a2b.motion(random_pose(rng), random_pose(rng), "screw")
    np.testing.assert_array_equal(motion.matrices(5), motion.matrices(np.linspace(0, 1, 5)))
    assert a2b.interpolate(np.eye(4), np.eye(4), 3).shape == (3, 4, 4)
    with pytest.raises(ParameterError, match="at least 2"):
        motion.matrices(1)


def test_interpolate_broadcasts(rng):
    start = np.stack([random_pose(rng) for _ in range(3)])
    out = a2b.interpolate(start, random_pose(rng), 7, mode="cubic")
    assert out.shape == (3, 7, 4, 4)


class Block:
    """A block of jobs as the readers make it."""

    def __init__(self, start, end, names, modes, samples, parameters):
        self.start, self.end = start, end
        self.names, self.modes, self.samples, self.parameters = names, modes, samples, parameters


def test_jobs_of_mixed_kinds_come_out_in_order_as_alone(rng):
    n = 9
    start = np.stack([random_pose(rng) for _ in range(n)])
    end = np.stack([random_pose(rng) for _ in range(n)])
    modes = ["darboux", "cubic", "darboux", "screw", "cubic", None, "darboux", "screw", None]
    params = [
        {},
        {"a": 0.2},
        {"delta": 0.5},
        {},
        {"m": [1, 2, 3, 4], "frame": "given"},
        {},
        {},
        {},
        {},
    ]
    counts = [3, 5, None, 5, 5, 2, 3, 70, 4]
    block = Block(
        start, end, [None, "b", None, "d", "e", None, "g", "h", None], modes, counts, params
    )
    pieces = list(sample([block], mode="cubic", samples=4, rows=64))
    names = [name for p in pieces for name in p.job]
    expected_names = ["job0", "b", "job2", "d", "e", "job5", "g", "h", "job8"]
    expected_counts = [3, 5, 4, 5, 5, 2, 3, 70, 4]
    assert names == [m for m, c in zip(expected_names, expected_counts) for _ in range(c)]
    assert max(len(p.t) for p in pieces) <= 64
    rows = np.concatenate([p.trans for p in pieces])
    ref = np.concatenate(
        [
            a2b.motion(start[i], end[i], modes[i] or "cubic", **params[i]).quat_trans(
                np.linspace(0, 1, expected_counts[i])
            )[1]
            for i in range(n)
        ]
    )
    np.testing.assert_allclose(rows, ref, rtol=0, atol=1e-14)


def test_a_failing_job_comes_after_the_jobs_before_it(rng):
    n = 5
    start = np.stack([np.eye(4)] * n)
    end = np.stack([random_pose(rng) for _ in range(n)])
    params = [{}, {"b": 0.1}, {"b": -3.0}, {}, {"b": 0.1}]
    block = Block(start, end, list("vwxyz"), ["cubic"] * n, [3] * n, params)
    seen = []
    with pytest.raises(SingularMotionError, match=r"^job x: the cubic motion passes through"):
        for piece in sample([block]):
            seen += piece.job.names
    assert seen == ["v", "w"]


@pytest.mark.parametrize(
    "mode, parameters, message",
    [
        ("darboux", {"long_way": "no"}, "long_way must be True or False"),
        ("darboux", {"long_way": 0}, "long_way must be True or False"),
        ("darboux", {"long_way": np.array([1.0])}, "long_way must be True or False"),
        ("darboux", {"delta": "1"}, "delta must be a number"),
        ("darboux", {"delta": True}, "delta must be a number"),
        ("darboux", {"lam": 2.0, "branch": True}, "branch must be a number"),
        ("darboux", {"lam": 2.0, "branch": float("nan")}, "branch must be finite"),
        ("darboux", {"lam": 2.0, "branch": 0.5}, "branch must be +1 or -1"),
        ("darboux", {"kappa": [[1.0], ["x"]]}, "kappa must be a number"),
        ("cubic", {"m": "1,0,0,0"}, "m must be a number"),
        ("cubic", {"a": "0.5"}, "a must be a number"),
        ("cubic", {"alpha": [True] * 6}, "alpha must be a number"),
        ("screw", {"delta": 1.0}, "delta"),
    ],
)
def test_library_arguments_of_the_wrong_type_name_the_argument(rng, mode, parameters, message):
    a, b = random_pose(rng), random_pose(rng)
    with pytest.raises(A2bError, match=re.escape(message)):
        a2b.motion(a, b, mode, **parameters)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda a, b: a2b.motion(a, b).matrices("0.5"), "ts must be a number"),
        (lambda a, b: a2b.motion(a, b).matrices([True, False]), "ts must be a number"),
        (lambda a, b: a2b.interpolate(a, b, [[0.0], [0.5, 1.0]]), "ts must be a number"),
        (lambda a, b: a2b.motion("pose A", b), "a pose matrix must be a number"),
        (lambda a, b: a2b.bezier([a, b], 5, weights="1,2"), "weights must be a number"),
        (lambda a, b: a2b.bezier([a, b], 5, weights=[True, True]), "weights must be a number"),
    ],
)
def test_samples_poses_and_weights_of_the_wrong_type(rng, call, message):
    with pytest.raises(A2bError, match=re.escape(message)):
        call(random_pose(rng), random_pose(rng))


@pytest.mark.parametrize("parameter", ["delta", "lam", "pitch_start", "pitch_end"])
def test_a_parameter_that_swamps_the_poses_is_refused_at_the_ends(rng, parameter):
    """With δ = 1e16 the t = 1 sample was not B (tz 0.0 instead of 0.5), with no warning."""
    a, b = random_pose(rng), random_pose(rng)
    value = 1e16
    with pytest.raises(ParameterError, match="does not reach its end poses") as caught:
        a2b.motion(a, b, "darboux", **{parameter: value})
    assert "tolerance 1e-09" in str(caught.value)
    fine = a2b.motion(a, b, "darboux", delta=0.5).describe()[parameter]  # a valid value
    batch = np.array([fine, value, fine])
    with pytest.raises(ParameterError, match=r"^motion 1: the Darboux motion does not reach"):
        a2b.motion(a, b, "darboux", **{parameter: batch})


@pytest.mark.parametrize("turn", ["random", "tiny", "near_pi", "pi", "none"])
def test_default_motions_reach_their_ends_far_within_the_tolerance(rng, turn):
    """Why only motions with a parameter given are checked at their ends (docs/math.md):
    without one, every mode reproduces A and B to a few units of rounding, for any turn and
    for translations of 1e-9 to 1e9 at either end."""
    from a2b.motions.base import END_TOL, end_residuals
    from a2b.poses import matrices_from_quat_trans, quaternions_from_axis_angle
    from a2b.study import quat_mul

    n = 2000
    qa = rng.normal(size=(n, 4))
    qa /= np.linalg.norm(qa, axis=1, keepdims=True)
    angle = {"random": rng.uniform(0, np.pi, n), "tiny": 10.0 ** rng.uniform(-12, -4, n),
             "near_pi": np.pi - 10.0 ** rng.uniform(-12, -2, n), "pi": np.full(n, np.pi),
             "none": np.zeros(n)}[turn]  # fmt: skip
    qb = quat_mul(quaternions_from_axis_angle(rng.normal(size=(n, 3)), angle), qa)
    scale_a = 10.0 ** rng.uniform(-9, 9, (n, 1))
    scale_b = np.where(rng.random((n, 1)) < 0.5, scale_a, 10.0 ** rng.uniform(-9, 9, (n, 1)))
    ta, tb = rng.normal(size=(n, 3)) * scale_a, rng.normal(size=(n, 3)) * scale_b
    a, b = matrices_from_quat_trans(qa, ta), matrices_from_quat_trans(qb, tb)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", A2bWarning)  # near-translations warn for the cubic
        for mode, frame in [("screw", {}), ("darboux", {}), ("cubic", {}),
                            ("cubic", {"frame": "given"})]:  # fmt: skip
            assert end_residuals(a2b.motion(a, b, mode, **frame)).max() < 1e-14 < END_TOL / 1e4


def test_every_mode_reaches_its_end_poses_to_the_tolerance(rng):
    from a2b.motions.base import END_TOL

    for a, b in pairs(rng, 12):
        for mode in ("darboux", "cubic", "screw"):
            ends = a2b.motion(a, b, mode).matrices(np.array([0.0, 1.0]))
            scale = max(1.0, np.linalg.norm(a[:3, 3]), np.linalg.norm(b[:3, 3]))
            assert np.abs(ends[0] - a).max() <= END_TOL * scale
            assert np.abs(ends[1] - b).max() <= END_TOL * scale


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
@pytest.mark.parametrize("count", [2, 7, 1000, 5000])
def test_every_sample_of_a_batch_is_bit_for_bit_the_sample_alone(rng, mode, count):
    """Quaternions, matrices and Study parameters of a batch of any size (below and above the
    build's chunk of pairs) are those of each pair built alone, to the last bit: no result may
    depend on an element's place in the batch or on the memory layout of its arrays."""
    start = np.stack([random_pose(rng, 2.0) for _ in range(count)])
    end = np.stack([random_pose(rng, 2.0) for _ in range(count)])
    batch = a2b.motion(start, end, mode)
    quat, trans = batch.quat_trans(TS)
    mats, study = batch.matrices(TS), batch.study(TS)
    picked = {0, 1, count - 1, count // 2} | set(rng.choice(count, min(count, 40), replace=False))
    picked |= {i for i in (4095, 4096) if i < count}  # both sides of a chunk boundary
    for i in sorted(picked):
        single = a2b.motion(start[i], end[i], mode)
        q, t = single.quat_trans(TS)
        assert np.array_equal(quat[i], q), (mode, i)
        assert np.array_equal(trans[i], t), (mode, i)
        assert np.array_equal(mats[i], single.matrices(TS)), (mode, i)
        assert np.array_equal(study[i], single.study(TS)), (mode, i)


def _same_bits(x, y) -> bool:
    x, y = np.asarray(x), np.asarray(y)
    return x.shape == y.shape and x.tobytes() == y.tobytes()


def test_a_frame_made_lazily_is_bit_for_bit_the_frame_made_at_once(rng):
    from a2b.frames import screw_frame

    generic = pairs(rng, 40)[len(special_pairs(rng)) :]
    for chosen in (generic, pairs(rng, 40)):  # every pair rotates; the rare cases mixed in
        a, b = (np.array([pair[k] for pair in chosen]) for k in (0, 1))
        eager, lazy = screw_frame(a, b), screw_frame(a, b, axes=False)
        # only where every pair rotates, none by π, are the axes left for later
        assert ("screws" in lazy.__dict__) == (chosen is not generic)
        for name in ("axis_direction", "d", "t_disp", "t_perp", "axis_point", "p_end", "r"):
            assert _same_bits(getattr(eager, name), getattr(lazy, name)), name
        for i in (0, 7, len(chosen) - 1):  # an element of either is the pair alone
            alone = screw_frame(a[i], b[i], axes=False)
            for name in ("axis_direction", "d", "t_disp", "axis_point"):
                assert _same_bits(getattr(lazy[i], name), getattr(alone, name)), name
                assert _same_bits(getattr(eager[i], name), getattr(alone, name)), name


def test_a_darboux_motion_is_built_without_the_axes_and_describes_them(rng):
    a, b = random_pose(rng), random_pose(rng)
    motion = a2b.motion(a, b, "darboux")
    assert "screws" not in motion.frame.__dict__
    described = motion.describe()
    assert "screws" in motion.frame.__dict__
    assert described["d"] == float(a2b.motion(a, b, "screw").frame.d)
    assert "screws" in a2b.motion(a, b, "darboux", delta=0.3).frame.__dict__  # to solve δ


def test_a_displacement_beyond_float64_is_refused_however_the_frame_is_made():
    from a2b.frames import screw_frame

    far = np.eye(4)
    far[:3, 3] = [1.7e308, -1.7e308, 0.0]
    near = np.eye(4)
    near[:3, 3] = [-1.7e308, 1.7e308, 0.0]
    for axes in (True, False):
        with pytest.raises(ParameterError, match="overflows float64"):
            screw_frame(far, near, axes=axes)


def test_samples_at_t_0_and_1_repeated_are_each_the_end_poses(rng):
    a, b = random_pose(rng), random_pose(rng)
    ts = np.array([0.0, 0.0, 0.3, 1.0, 0.7, 1.0])
    for mode in ("darboux", "cubic", "screw"):
        out = a2b.interpolate(a, b, ts, mode)
        assert all(_same_bits(out[i], a) for i in (0, 1))
        assert all(_same_bits(out[i], b) for i in (3, 5))
        batch = a2b.interpolate(np.array([a, b]), np.array([b, a]), ts, mode)
        assert _same_bits(batch[0], out)
