"""Fibers of a pose under the extended kinematic maps κ (section 3) and μ_[m] (eq. 15)."""

from __future__ import annotations

import numpy as np

from .errors import ParameterError
from .extended import (
    kernel_basis,
    matrices_from_model_points,
    mu_fiber_points,
    paper_basis_degenerate,
)
from .poses import check_matrices, matrices_from_study, study_from_matrices
from .study import kappa_fiber_direction, kappa_fiber_points


def fiber(
    pose, kind: str = "kappa", s=(0.0,), m=None, alphas=((0.0,) * 6,), basis: str = "auto"
) -> dict:
    """The fiber of ``pose`` under κ or μ_[m], as plain data (what ``--json`` prints).

    Parameters
    ----------
    pose : ndarray, shape (4, 4)
        Robotics layout.
    kind : {"kappa", "mu"}
    s : sequence of float
        κ: the points ``h + s ε p`` (docs/math.md, correction 1).
    m : sequence of 4 floats
        μ: the vector m of μ_[m].
    alphas : sequence of 6-tuples
        μ: the points ``(1, R) + Σ α_l f_l`` with translation block ``ψ t`` (eq. 15).
    basis : {"auto", "paper", "rref"}
        μ: the kernel basis of ``M_m``; ``auto`` is the paper's unless it degenerates.

    Returns
    -------
    dict
        ``map, pose, basis_name, basis, points, residuals`` and, for μ, ``m, alphas,
        paper_basis_degenerate``, and ``choices`` (the kernel basis chosen for the user).
        ``residuals[i]`` is ``max |map(point_i) − pose|``.
    """
    if kind not in ("kappa", "mu"):
        raise ParameterError(f"unknown map {kind!r}; expected 'kappa' or 'mu'")
    pose = check_matrices(pose)
    out = {"map": kind, "pose": pose.tolist(), "choices": []}
    if kind == "kappa":
        h = study_from_matrices(pose)
        points = kappa_fiber_points(h, np.asarray(s, dtype=float))
        back = matrices_from_study(points, through_kappa=True)
        out.update(
            basis_name="h, εp: the fiber is the line h ∨ εp without εp",
            basis=[h.tolist(), kappa_fiber_direction(h).tolist()],
            s=[float(v) for v in s],
        )
    else:
        if m is None:
            raise ParameterError("the μ_[m]-fiber needs m (4 numbers)")
        m = np.asarray(m, dtype=float)
        base, name = kernel_basis(m, basis)
        if basis == "auto" and name == "rref":
            out["choices"].append(
                "the paper's kernel basis (eq. 13) degenerates for this m (n0 = 0); used the RREF "
                "basis"
            )
        points = mu_fiber_points(
            pose, m, np.asarray(alphas, dtype=float).reshape(-1, 6), basis=name
        )
        back = matrices_from_model_points(points, m)
        out.update(
            m=m.tolist(),
            paper_basis_degenerate=bool(paper_basis_degenerate(m)),
            basis_name=name,
            basis=base.tolist(),
            alphas=[list(a) for a in alphas],
        )
    out["points"] = points.tolist()
    out["residuals"] = np.max(np.abs(back - pose), axis=(-2, -1)).tolist()
    return out
