"""The cubic build of many pairs at once (a2b.motions.cubic.cubic_tables): chunks, parameters
and the orthogonality check, each element as it is alone."""

from __future__ import annotations

import numpy as np
import pytest

import a2b
from a2b.errors import A2bWarning, ParameterError
from a2b.motions._rational import CHUNK, FRAGILE_TOL
from a2b.motions.base import path_minimum
from a2b.motions.cubic import WEIGHT_RATIO, _bounded_away
from a2b.poses import quaternions_from_rotations

from .conftest import random_pose

#: Every kind of parameter of the cubic, per element (a, b within (−0.3, 0.3): no pole).
PARAMETERS = {
    "canonical": lambda rng, n: {},
    "canonical-ab-m": lambda rng, n: {
        "m": 1.0 + rng.random((n, 4)),
        "a": 0.6 * rng.random(n) - 0.3,
        "b": 0.6 * rng.random(n) - 0.3,
    },
    "given": lambda rng, n: {"frame": "given"},
    "given-ab-m": lambda rng, n: {
        "m": 1.0 + rng.random((n, 4)),
        "a": 0.6 * rng.random(n) - 0.3,
        "b": 0.6 * rng.random(n) - 0.3,
        "frame": "given",
    },
}


def own(params: dict, i: int) -> dict:
    return {k: v if isinstance(v, str) else v[i] for k, v in params.items()}


@pytest.mark.filterwarnings("ignore::a2b.errors.A2bWarning")  # a few random pairs pass near p = 0
@pytest.mark.parametrize("case", list(PARAMETERS))
def test_a_batch_over_chunks_is_its_elements_bit_for_bit(rng, case):
    """Across the boundaries of the build's chunks (and in the short last one), tables, ends,
    weights and samples of every element are those of the pair built alone."""
    count = 2 * CHUNK + 5
    start = np.stack([random_pose(rng, 2.0) for _ in range(count)])
    end = np.stack([random_pose(rng, 2.0) for _ in range(count)])
    params = PARAMETERS[case](rng, count)
    batch = a2b.motion(start, end, "cubic", **params)
    ts = np.array([0.0, 0.3, 1.0])
    samples = batch.matrices(ts)
    for i in (0, 1, CHUNK - 1, CHUNK, 2 * CHUNK - 1, 2 * CHUNK, count - 1):
        single = a2b.motion(start[i], end[i], "cubic", **own(params, i))
        assert np.array_equal(batch.table[i], single.table), i
        assert np.array_equal(batch.quat_ends[i], single.quat_ends), i
        assert np.array_equal(batch.weights[i], single.weights), i
        assert np.array_equal(samples[i], single.matrices(ts)), i


@pytest.mark.parametrize("frame", ["canonical", "given"])
def test_the_table_reproduces_the_construction(rng, frame):
    """Samples from the table are μ_m of the line between the fiber points: the rotation of
    ``p(t) = (1−t) wA pA + t wB pB`` and, in the given frame, the translation
    ``((1−t) ψA tA + t ψB tB) / ((1−t) ψA + t ψB)`` (docs/math.md)."""
    start = np.stack([random_pose(rng, 2.0) for _ in range(7)])
    end = np.stack([random_pose(rng, 2.0) for _ in range(7)])
    m = 1.0 + rng.random((7, 4))
    a, b = 0.2 * rng.random(7), -0.2 * rng.random(7)
    motion = a2b.motion(start, end, "cubic", m=m, a=a, b=b, frame=frame)
    ts = np.linspace(0.0, 1.0, 11)
    mats = motion.matrices(ts)
    w_a, w_b = motion.weights[:, 0, None, None], motion.weights[:, 1, None, None]
    p = (1 - ts)[:, None] * w_a * motion.frame.p_start[:, None] + ts[:, None] * w_b * (
        motion.frame.p_end[:, None]
    )
    p /= np.linalg.norm(p, axis=-1, keepdims=True)
    q = quaternions_from_rotations(mats[..., :3, :3])
    np.testing.assert_allclose(np.abs(np.sum(p * q, axis=-1)), 1.0, atol=1e-14)
    if frame == "given":
        psi_a, psi_b = (1 + a)[:, None, None], (1 + b)[:, None, None]
        u = (1 - ts)[:, None]
        line = (u * psi_a * start[:, None, :3, 3] + ts[:, None] * psi_b * end[:, None, :3, 3]) / (
            u * psi_a + ts[:, None] * psi_b
        )
        np.testing.assert_allclose(mats[..., :3, 3], line, atol=1e-13)


def test_orthogonality_names_the_first_element_and_the_start_before_the_end(rng):
    """m orthogonal to B's quaternion in element 1 and to A's in element 3: the start pose is
    checked first over the whole batch, as one element alone would be."""
    start = np.stack([random_pose(rng) for _ in range(5)])
    end = np.stack([random_pose(rng) for _ in range(5)])
    m = 1.0 + rng.random((5, 4))
    q_end = quaternions_from_rotations(end[1, :3, :3])
    q_start = quaternions_from_rotations(start[3, :3, :3])
    m[1] = [-q_end[1], q_end[0], -q_end[3], q_end[2]]  # m·pB = 0
    m[3] = [-q_start[1], q_start[0], -q_start[3], q_start[2]]  # m·pA = 0
    with pytest.raises(ParameterError, match=r"^motion 3: m = .* start pose \(m·p = "):
        a2b.motion(start, end, "cubic", m=m, frame="given")
    with pytest.raises(ParameterError, match=r"^motion 1: m = .* end pose \(m·p = .*1e-12·\|m\|"):
        a2b.motion(start[:3], end[:3], "cubic", m=m[:3], frame="given")
    with pytest.raises(ParameterError, match=r"^m = .* of the end pose \(m·p = "):
        a2b.motion(start[1], end[1], "cubic", m=m[1], frame="given")


def test_with_x0_constant_one_both_denominators_are_the_same(rng):
    """a = b = 0 in the canonical frame: Δ · x0 is Δ to the bit, so that sampling divides by
    one denominator; with a ≠ b the translation has its own."""
    start = np.stack([random_pose(rng, 2.0) for _ in range(50)])
    end = np.stack([random_pose(rng, 2.0) for _ in range(50)])
    table = a2b.motion(start, end, "cubic").table
    assert np.array_equal(table[..., 12], table[..., 13])
    table = a2b.motion(start, end, "cubic", a=0.1, b=0.2).table
    assert not np.array_equal(table[..., 1:3, 12], table[..., 1:3, 13])


def test_weights_within_the_ratio_keep_p_away_from_the_origin(rng):
    """Where ``wA wB c ≥ 0`` and the weights are within WEIGHT_RATIO of each other,
    ``|p(t)|² / max|p|²`` on [0, 1] is at least ``q² / (1 + q²) > 2 FRAGILE_TOL``: the bound
    by which the build skips the singularity checks (docs/math.md)."""
    count = 20000
    quats = rng.normal(size=(count, 2, 4))
    quats /= np.linalg.norm(quats, axis=-1, keepdims=True)
    c = np.sum(quats[:, 0] * quats[:, 1], axis=-1)
    quats[:, 1] *= np.where(c < 0, -1.0, 1.0)[:, None]  # the short way, as screw_frame
    c = np.abs(c)
    q = WEIGHT_RATIO + (1.0 - WEIGHT_RATIO) * rng.random(count) ** 4  # many near the edge
    q[:100] = WEIGHT_RATIO
    scale = 10.0 ** rng.uniform(-3, 3, count) * np.where(rng.random(count) < 0.5, -1.0, 1.0)
    weights = np.stack([scale, scale * q])
    swap = rng.random(count) < 0.5
    weights[:, swap] = weights[::-1, swap]
    assert _bounded_away(weights, c)
    ends = quats * np.moveaxis(weights, 0, -1)[..., None]
    _, ratio = path_minimum(ends, 0.0, 1.0)
    bound = q**2 / (1 + q**2)
    assert np.all(ratio >= bound * (1 - 1e-12))
    assert ratio.min() > 2 * FRAGILE_TOL
    # one pair outside: weights further apart, or of opposite signs with c > 0
    weights[1, 7] = weights[0, 7] * 0.14
    assert not _bounded_away(weights, c)
    weights[1, 7] = -weights[0, 7]
    assert not _bounded_away(weights, c)


@pytest.mark.filterwarnings("ignore::a2b.errors.A2bWarning")
def test_a_batch_with_one_unbounded_pair_is_checked_as_each_pair_alone(rng):
    """The default motions are bounded and skip the singularity checks on [0, 1]; one pair of
    weights far apart in a batch brings the checks back for the whole batch, and its warning
    (p(t) close to 0) names that element as it is named alone."""
    start = np.stack([random_pose(rng, 2.0) for _ in range(6)])
    end = np.stack([random_pose(rng, 2.0) for _ in range(6)])
    default = a2b.motion(start, end, "cubic")
    assert default._bounded
    assert not np.any(default._rotation_is_fragile(0.0, 1.0))
    _, ratio = path_minimum(default.quat_ends, 0.0, 1.0)
    assert ratio.min() >= 0.5 * (1 - 1e-12)  # equal weights: as a Darboux motion's
    # m nearly orthogonal to pB in element 4: wB ≪ wA, p(t) passes close to 0 near t = 1
    m = np.tile([1.0, 0.0, 0.0, 0.0], (6, 1))
    quats = quaternions_from_rotations(np.stack([start[4], end[4]])[:, :3, :3])
    p_b = quats[1] * np.sign(np.dot(quats[0], quats[1]))
    m[4] = quats[0] - (np.dot(quats[0], p_b) - 1e-5) * p_b
    with pytest.warns(A2bWarning, match=r"^motion 4: the cubic motion passes close to p"):
        batch = a2b.motion(start, end, "cubic", m=m, frame="given")
    assert not batch._bounded
    with pytest.warns(A2bWarning, match=r"^the cubic motion passes close to p"):
        alone = a2b.motion(start[4], end[4], "cubic", m=m[4], frame="given")
    assert batch.warnings[4] == alone.warnings
    ts = np.linspace(0.0, 1.0, 7)
    assert np.array_equal(batch.matrices(ts)[4], alone.matrices(ts))
