"""Velocities and accelerations of a moving body, from the derivatives of its pose matrices.

Every function here takes a *derivative stack*: the robotics matrices ``M = [R | t]`` of
samples and their derivatives in one parameter, shape ``(..., r + 1, N, 4, 4)`` with
``stack[..., 0, :, :, :] = M``, ``stack[..., 1, :, :, :] = M'`` and so on. The parameter is
whatever the stack was differentiated by: the motion's ``t`` (:meth:`Motion.derivatives`) or
time (:mod:`a2b.timelaw`). Nothing here knows how the motion was built.

Twists are ``(vx, vy, vz, wx, wy, wz)``, linear part first as in ``geometry_msgs/Twist``:

``world``
    ``v`` is the velocity of the body point ``x`` (given in the moving frame; its origin by
    default), ``w`` the angular velocity, both in fixed-frame coordinates.
``body``
    The same two vectors in moving-frame coordinates (``v = Rᵀ ẋ``, ``w = Rᵀ ω``): for the
    origin, the body twist ``M⁻¹ Ṁ``, and the twist of ``nav_msgs/Odometry`` in its child frame.
``spatial``
    The spatial twist ``Ṁ M⁻¹``: ``w = ω`` and ``v = ṫ − ω × t``, the velocity of the body
    point that passes through the fixed origin. It has no body point.

The angular velocity is ``ω = vee(Ṙ Rᵀ)``; the angular acceleration is ``α = ω̇ =
vee(skew(R̈ Rᵀ))`` (``Ṙ Ṙᵀ`` is symmetric, so ``d/dt(Ṙ Rᵀ)`` is the skew part of ``R̈ Rᵀ``).
"""

from __future__ import annotations

import numpy as np

from .errors import ParameterError
from .study import dots

__all__ = ["FRAMES", "accelerations", "path_rates", "point_derivatives", "twists"]

FRAMES = ("world", "body", "spatial")


def check_point(point) -> np.ndarray:
    """A body point ``(x, y, z)`` in the moving frame (``None``: its origin)."""
    if point is None:
        return np.zeros(3)
    arr = np.asarray(point, dtype=float)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ParameterError(f"a point is three finite numbers x, y, z; got {point!r}")
    return arr


def _check_frame(frame: str, point) -> None:
    if frame not in FRAMES:
        raise ParameterError(f"frame must be one of {', '.join(FRAMES)}, got {frame!r}")
    if frame == "spatial" and point is not None:
        raise ParameterError("the spatial twist belongs to no body point; give no point")


def point_derivatives(stack: np.ndarray, point=None) -> np.ndarray:
    """The body point and its derivatives ``(..., r + 1, N, 3)``: ``R^(k) x + t^(k)``, each
    row of ``R^(k) x`` summed in one order (:func:`a2b.study.dots`), whatever the layout."""
    x = check_point(point)
    return dots(stack[..., :3, :3], x) + stack[..., :3, 3]


def _vee(skew: np.ndarray) -> np.ndarray:
    """The vector of the skew part of ``(..., 3, 3)`` matrices."""
    return 0.5 * np.stack(
        [
            skew[..., 2, 1] - skew[..., 1, 2],
            skew[..., 0, 2] - skew[..., 2, 0],
            skew[..., 1, 0] - skew[..., 0, 1],
        ],
        axis=-1,
    )


def _angular(stack: np.ndarray, order: int) -> np.ndarray:
    """``ω`` (order 1) or ``α`` (order 2) in fixed-frame coordinates, ``(..., N, 3)``."""
    rot = stack[..., 0, :, :3, :3]
    rate = stack[..., order, :, :3, :3]
    # Ṙ Rᵀ entry by entry (rows of Ṙ against rows of R), each summed in one order by dots:
    # a stacked ``@`` sums in an order that depends on the layout in older numpy
    product = dots(rate[..., :, None, :], rot[..., None, :, :])
    return _vee(product)


def _to_body(stack: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Fixed-frame vectors ``(..., N, 3)`` in the moving frame: ``Rᵀ v``."""
    rot = stack[..., 0, :, :3, :3]
    # (Rᵀ v)_j = Σ_i R_ij v_i: each column of R against v, summed in one order
    return dots(np.swapaxes(rot, -1, -2), vectors[..., None, :])


def twists(stack: np.ndarray, frame: str = "world", point=None) -> np.ndarray:
    """Twists ``(..., N, 6)``, ``(v, w)``, in ``frame`` (see the module) from a stack of order
    at least 1."""
    _check_frame(frame, point)
    omega = _angular(stack, 1)
    if frame == "spatial":
        trans = stack[..., 0, :, :3, 3]
        linear = stack[..., 1, :, :3, 3] - np.cross(omega, trans)
        return np.concatenate([linear, omega], axis=-1)
    linear = point_derivatives(stack[..., :2, :, :, :], point)[..., 1, :, :]
    if frame == "body":
        linear, omega = _to_body(stack, linear), _to_body(stack, omega)
    return np.concatenate([linear, omega], axis=-1)


def accelerations(stack: np.ndarray, frame: str = "world", point=None) -> np.ndarray:
    """The derivatives of :func:`twists` in the same frame, ``(..., N, 6)``, from a stack of
    order at least 2.

    ``world``: ``(ẍ, α)``. ``body``: ``d/dt (Rᵀ ẋ) = Ṙᵀ ẋ + Rᵀ ẍ`` and ``Rᵀ α`` (``Ṙᵀ ω = 0``).
    ``spatial``: ``(ẗ − α × t − ω × ṫ, α)``.
    """
    _check_frame(frame, point)
    alpha = _angular(stack, 2)
    if frame == "spatial":
        omega = _angular(stack, 1)
        trans, rate, accel = (stack[..., k, :, :3, 3] for k in range(3))
        linear = accel - np.cross(alpha, trans) - np.cross(omega, rate)
        return np.concatenate([linear, alpha], axis=-1)
    moving = point_derivatives(stack[..., :3, :, :, :], point)
    if frame == "world":
        return np.concatenate([moving[..., 2, :, :], alpha], axis=-1)
    rate_rot = stack[..., 1, :, :3, :3]
    linear = (moving[..., 1, :, None, :] @ rate_rot)[..., 0, :] + _to_body(
        stack, moving[..., 2, :, :]
    )
    return np.concatenate([linear, _to_body(stack, alpha)], axis=-1)


def path_rates(stack: np.ndarray, point=None) -> dict:
    """The rates a time law limits, ``(..., N)`` each, from a stack of order 3 in time.

    ``speed`` ``|ẋ|`` of the body point; ``accel`` and ``jerk`` along its path, ``s̈`` and
    ``s⃛`` of its arc length ``s`` (``s̈ = ẋ·ẍ / |ẋ|``, ``s⃛ = (|ẍ|² + ẋ·x⃛ − s̈²) / |ẋ|``; where
    the point stands still, ``|ẍ|`` and ``|x⃛|``); ``total_accel`` ``|ẍ|``, the centripetal
    part included; ``angular_speed`` ``|ω|`` and ``angular_accel`` ``|α|``.
    """
    moving = point_derivatives(stack, point)
    rate, accel, jerk = (moving[..., k, :, :] for k in (1, 2, 3))
    speed = np.linalg.norm(rate, axis=-1)
    total = np.linalg.norm(accel, axis=-1)
    still = speed <= 1e-300
    safe = np.where(still, 1.0, speed)
    along = np.where(still, total, dots(rate, accel) / safe)
    third = (total**2 + dots(rate, jerk) - along**2) / safe
    third = np.where(still, np.linalg.norm(jerk, axis=-1), third)
    return {
        "speed": speed,
        "accel": along,
        "jerk": third,
        "total_accel": total,
        "angular_speed": np.linalg.norm(_angular(stack, 1), axis=-1),
        "angular_accel": np.linalg.norm(_angular(stack, 2), axis=-1),
    }


def reparametrise(stack: np.ndarray, rates: np.ndarray) -> np.ndarray:
    """A stack in ``t`` as a stack in ``τ``, given ``t(τ)``'s derivatives ``rates``
    ``(..., N, r)`` (``ṫ, ẗ, t⃛``; Faà di Bruno up to order 3)."""
    order = min(stack.shape[-4] - 1, rates.shape[-1])
    r = [np.moveaxis(rates, -1, 0)[k][..., None, None] for k in range(order)]
    d = [stack[..., k, :, :, :] for k in range(order + 1)]
    out = [d[0]]
    if order >= 1:
        out.append(d[1] * r[0])
    if order >= 2:
        out.append(d[2] * r[0] ** 2 + d[1] * r[1])
    if order >= 3:
        out.append(d[3] * r[0] ** 3 + 3.0 * d[2] * r[0] * r[1] + d[1] * r[2])
    return np.stack(out, axis=-4)


class Kinematic:
    """Velocities for a motion class that provides ``derivatives(ts, order)``."""

    def derivatives(self, ts, order: int = 1, point=None) -> np.ndarray:  # pragma: no cover
        raise NotImplementedError

    def twists(self, ts, frame: str = "world", point=None) -> np.ndarray:
        """Velocities per unit of ``t`` at ``ts``: ``(v, w)`` in ``frame``, shape ``(..., N, 6)``.

        ``frame`` is ``world`` (the velocity of the body ``point``, the moving frame's origin
        by default, and the angular velocity, in fixed coordinates), ``body`` (the same in the
        moving frame) or ``spatial`` (the spatial twist); see :mod:`a2b.kinematics`. The
        values are exact derivatives of the motion's rational (screw: trigonometric) formulas.
        Divide by the duration for velocities in time, or use :func:`a2b.timing`.
        """
        _check_frame(frame, point)
        return twists(self.derivatives(ts, 1), frame, point)

    def accelerations(self, ts, frame: str = "world", point=None) -> np.ndarray:
        """The derivatives in ``t`` of :meth:`twists`, shape ``(..., N, 6)``."""
        _check_frame(frame, point)
        return accelerations(self.derivatives(ts, 2), frame, point)

    def point_speeds(self, ts, point=None) -> np.ndarray:
        """``|dx/dt|`` of the body point ``point`` (the origin by default), ``(..., N)``."""
        path = self.derivatives(ts, 1, point=check_point(point))
        return np.linalg.norm(path[..., 1, :, :], axis=-1)
