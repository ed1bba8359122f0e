"""Explicit central-difference integration (Newmark β = 0, γ = ½) and its stable step.

Scheme, with lumped (diagonal) mass M, stiffness K, damping C = β_v K and contact force f_c(u):

    M a_n = f_c(u_n) - K u_n - C v_{n-½}
    v_{n+½} = v_{n-½} + Δt a_n        (first step: v_{½} = v_0 + ½Δt a_0)
    u_{n+1} = u_n + Δt v_{n+½}

Stability: Δt <= Δt_crit = 2/ω_max (sqrt(1 + ξ²) - ξ), ω_max² the largest eigenvalue of
M^-1 (K + K_c) with the contact stiffness K_c at full engagement (the penalty stiffens the system as
contact closes) and ξ the bulk-viscosity fraction of critical damping in that mode. ω_max² is found
with SLEPc (Krylov-Schur, symmetric) on the scaled operator M^-½ (K + K_c) M^-½, which has the same
spectrum. The element estimate h_min/c_d (c_d the dilatational wave speed) is reported alongside.

Discrete energy: for the linear part the scheme conserves exactly
H_n = ½ v_{n-½}·M v_{n+½} + ½ u_n·K u_n, so the kinetic energy is reported as ½ v_{n-½}·M v_{n+½}
(the mid-step product, → ½ v·M v as Δt → 0). The contact adds E_c(u_n) (conserved to O(Δt²)).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

__all__ = ["largest_eigenvalue", "power_iteration", "stable_step"]


class _Shell:
    def __init__(self, apply: Callable[[np.ndarray, np.ndarray], None]):
        self.apply = apply

    def mult(self, mat, x, y):  # noqa: ARG002 (petsc4py shell signature)
        y.array[:] = 0.0
        self.apply(x.array_r, y.array)


def largest_eigenvalue(
    apply: Callable[[np.ndarray, np.ndarray], None], n_local: int, comm: MPI.Comm, tol: float = 1e-8
) -> float:
    """Largest eigenvalue of the symmetric operator y = A x (``apply(x, y)`` adds A x to y) by SLEPc.

    Falls back to 200 power iterations if SLEPc does not converge.
    """
    from slepc4py import SLEPc

    A = PETSc.Mat().createPython(((n_local, PETSc.DECIDE), (n_local, PETSc.DECIDE)), _Shell(apply), comm=comm)
    A.setUp()
    eps = SLEPc.EPS().create(comm)
    eps.setOperators(A)
    eps.setProblemType(SLEPc.EPS.ProblemType.HEP)
    eps.setWhichEigenpairs(SLEPc.EPS.Which.LARGEST_REAL)
    eps.setType(SLEPc.EPS.Type.KRYLOVSCHUR)
    eps.setDimensions(nev=1, ncv=40)
    eps.setTolerances(tol=tol, max_it=500)
    x0 = A.createVecRight()
    x0.array[:] = 1.0 + 0.1 * np.sin(np.arange(n_local) + comm.rank * 7919.0)  # deterministic start
    eps.setInitialSpace([x0])
    eps.solve()
    if eps.getConverged() >= 1:
        λ = eps.getEigenvalue(0).real
    else:
        λ = power_iteration(apply, n_local, comm, 200)
    eps.destroy()
    A.destroy()
    return float(λ)


def power_iteration(
    apply: Callable[[np.ndarray, np.ndarray], None], n_local: int, comm: MPI.Comm, its: int = 50
) -> float:
    """Rayleigh quotient after ``its`` power iterations (a lower bound of the largest eigenvalue)."""
    x = 1.0 + 0.1 * np.sin(np.arange(n_local) + comm.rank * 7919.0)
    y = np.zeros_like(x)
    λ = 0.0
    for _ in range(its):
        x /= math.sqrt(comm.allreduce(float(x @ x)))
        y[:] = 0.0
        apply(x, y)
        λ = comm.allreduce(float(x @ y))
        x, y = y, x
    return λ


def stable_step(ω_max: float, ξ: float = 0.0) -> float:
    """Δt_crit = 2/ω_max (sqrt(1 + ξ²) - ξ) [s] for central differences with damping ratio ξ at ω_max."""
    return 2.0 / ω_max * (math.sqrt(1.0 + ξ * ξ) - ξ)
