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

Contact switching: the linear bound above holds for every fixed set of active contact pairs, but a
penalty spring that switches on and off between steps changes the scheme's conserved (shadow) energy
by a fraction of order (ω_c Δt)²/4, ω_c the frequency of an isolated contact pair
(:meth:`rods.fe.contact.PenaltyContact.pair_frequency`). Stiff penalties make the contact nodes rattle
and pump energy into the rods: measured on a 2 x 0.5 mm mesh at 200 x E*/h, ω_c Δt = 1.58 (0.8 of the
linear limit) grew the energy tenfold and 1.18 by 1.6%, while ω_c Δt <= 1 kept the energy error at or
below 1.5e-3 for penalties from 20 to 1000 x E*/h. The step is
therefore also limited to Δt <= :data:`SWITCHING` / ω_c (:func:`switching_step`); for penalties that
do not control the spectrum (ω_c Δt ~ 0.25-0.45 at the paper mesh) this limit is inactive.

Safe lower bound (Gershgorin): ω_max² <= max_i Σ_j |(K + K_c)_ij| / m_i, reported with the step as
``dt_gershgorin`` (a check on the Krylov-Schur value, never used to march).

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

__all__ = ["SWITCHING", "largest_eigenvalue", "power_iteration", "stable_step", "switching_step"]

SWITCHING = 1.0  # largest ω_c Δt of an isolated contact pair [-] (see the module docstring)


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


def switching_step(ω_contact: float) -> float:
    """Δt_switch = SWITCHING / ω_c [s]: the contact-switching limit (module docstring); inf without contact."""
    return SWITCHING / ω_contact if ω_contact > 0 else math.inf
