"""Explicit central-difference integration (Newmark β = 0, γ = ½) and its stable step.

Scheme, with lumped (diagonal) mass M, stiffness K, damping C = β_v K and contact force f_c(u):

    M a_n = f_c(u_n) - K u_n - C v_{n-½}
    v_{n+½} = v_{n-½} + Δt a_n        (first step: v_{½} = v_0 + ½Δt a_0)
    u_{n+1} = u_n + Δt v_{n+½}

Stability: Δt <= Δt_crit = 2/ω_max (sqrt(1 + ξ²) - ξ), ω_max² the largest eigenvalue of
M^-1 (K + K_c) with the contact stiffness K_c at full engagement (the penalty stiffens the system as
contact closes) and ξ the fraction of critical damping in that mode: C = β_v K with β_v = 2ξ/ω_max is
stiffness-proportional (Rayleigh) damping, ξ ω_i/ω_max of critical in mode i, shear modes as well as volumetric
ones (the key is ``fe.bulk_viscosity`` after the explicit codes' high-frequency damping, but unlike Abaqus's linear
bulk viscosity it acts on the whole strain rate, not its volumetric part alone). ω_max² is found
with SLEPc (Krylov-Schur, symmetric) on the scaled operator M^-½ (K + K_c) M^-½, which has the same
spectrum. The step needs ω_max to a fraction of a percent (it marches at ``fe.dt_fraction`` of the limit),
not to round-off: the Ritz pair (θ, y) is converged to a relative residual of :data:`EIGEN_TOL` and
θ + ‖A y - θ y‖ is used. θ <= λ_max, and some eigenvalue lies within ‖A y - θ y‖ of θ; that it is λ_max is
not proven, but the sum lay above λ_max in every case measured (below), by at most EIGEN_TOL, so the step
errs on the stable side by at most ½ EIGEN_TOL. A residual of 1e-8 took 4-10x the products for no useful
change in the step (3D coarse mesh, 132k DOFs: 401 products against 101, θ + ‖r‖ 2.8e-5 above the converged
λ_max; 983k DOFs: 801 against 81, 8.8e-5 above; the axisymmetric paper mesh: 41 either way; the 1D Laplacian
of tests/fe/test_explicit.py, whose top eigenvalues crowd: 9e-5 above, 601 products, where a residual of 1e-8
is not reached in 10,220). An unconverged solve raises; :func:`rods.fe.timestep.time_step` then marches at the
Gershgorin bound.
The element estimate h_min/c_d (c_d the dilatational wave speed) is reported alongside.

Contact switching: the linear bound above holds for every fixed set of active contact pairs, but a
penalty spring that switches on and off between steps changes the scheme's conserved (shadow) energy
by a fraction of order (ω_c Δt)²/4, ω_c the frequency of an isolated contact pair
(:meth:`rods.fe.contact.PenaltyContact.pair_frequency`). Stiff penalties make the contact nodes rattle
and pump energy into the rods: measured on a 2 x 0.5 mm mesh at 200 x E*/h, ω_c Δt = 1.58 (0.8 of the
linear limit) grew the energy tenfold and 1.18 by 1.6%, while ω_c Δt <= 1 kept the energy error at or
below 1.5e-3 for penalties from 20 to 1000 x E*/h. The step is
therefore also limited to Δt <= :data:`rods.stability.SWITCHING` / ω_c (:func:`switching_step`); for penalties that
do not control the spectrum (ω_c Δt ~ 0.25-0.45 at the paper mesh) this limit is inactive.

Gershgorin bound: ω_max² <= max_i Σ_j |(K + K_c)_ij| / m_i, an upper bound on ω_max² and so a safe lower
bound on the stable step, reported with the step as ``dt_gershgorin``: a check on the Krylov-Schur value, and the
step marched at where that solve does not converge (above).

Discrete energy: for the linear part the scheme conserves exactly
H_n = ½ v_{n-½}·M v_{n+½} + ½ u_n·K u_n, so the kinetic energy is reported as ½ v_{n-½}·M v_{n+½}
(the mid-step product, → ½ v·M v as Δt → 0). The contact adds E_c(u_n) (conserved to O(Δt²)).

The integrator is an object (:class:`CentralDifference`, after dolfiny's ``odeint.ODEInt2``): it holds
the state and advances it by :meth:`CentralDifference.step`; the caller owns the loop and what it
records (:mod:`rods.fe.recorder`, :mod:`rods.fe.observers`). One class for every array backend
(:mod:`rods.fe.backend`: PETSc Mat/Vec, NumPy/SciPy CSR, CuPy/cuSPARSE CSR).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from rods.fe.backend import PETSC, Backend
from rods.stability import SWITCHING, stable_step, switching_step  # the closed forms (no PETSc)

__all__ = [
    "EIGEN_TOL",
    "SWITCHING",
    "CentralDifference",
    "NotConverged",
    "largest_eigenvalue",
    "stable_step",
    "switching_step",
]

EIGEN_TOL = 1e-4  # relative residual of the ω_max² Ritz pair [-] (see the module docstring, "Stability")


class NotConverged(RuntimeError):
    """An eigenvalue iteration that did not converge: its test is on reduced quantities, so every rank raises it
    together (not any RuntimeError: PETSc's errors are RuntimeErrors too, and one raised on one rank only, caught
    as this, left that rank marching on while the others waited in SLEPc, a hang: an audit, 2026-12-07)."""


class _Shell:
    def __init__(self, apply: Callable[[np.ndarray, np.ndarray], None]):
        self.apply = apply

    def mult(self, mat, x, y):  # noqa: ARG002 (petsc4py shell signature)
        y.array[:] = 0.0
        self.apply(x.array_r, y.array)


def largest_eigenvalue(
    apply: Callable[[np.ndarray, np.ndarray], None],
    n_local: int,
    comm: MPI.Comm,
    tol: float = EIGEN_TOL,
    start: np.ndarray | None = None,
) -> float:
    """Upper estimate θ + ‖A y - θ y‖ of the largest eigenvalue of the symmetric operator y = A x (``apply(x, y)``
    adds A x to y): SLEPc's Krylov-Schur Ritz pair (θ, y), ‖y‖ = 1, converged to the relative residual ``tol``
    (:data:`EIGEN_TOL`), plus its residual norm, computed with one more product (module docstring, "Stability").
    ``start``: the owned start vector (default 1 + 0.1 sin i). The estimate depends on it at the level of the
    residual, so a result that must not depend on the rank count starts from a function of the node positions
    (:func:`rods.fe.timestep.start_vector`).

    :class:`NotConverged` if SLEPc does not converge (:func:`rods.fe.timestep.time_step` then marches at the Gershgorin
    bound, a true upper bound).
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
    x0.array[:] = 1.0 + 0.1 * np.sin(np.arange(n_local) + comm.rank * 7919.0) if start is None else start
    eps.setInitialSpace([x0])
    eps.solve()
    converged, its = eps.getConverged() >= 1, eps.getIterationNumber()
    if converged:
        θ = eps.getEigenvalue(0).real
        λ = θ + eps.computeError(0, SLEPc.EPS.ErrorType.ABSOLUTE)  # ‖A y - θ y‖: within it of an eigenvalue
    eps.destroy()
    A.destroy()
    if not converged:
        raise NotConverged(f"Krylov-Schur: largest eigenvalue not converged to {tol:g} in {its} restarts")
    return float(λ)


class CentralDifference:
    """The scheme of the module docstring as an object: state (u_n, v_{n+½}), :meth:`step` advances it.

    ``A`` is a freshly assembled K (a PETSc Mat, any layout; a SciPy matrix for the array backends), or a
    callable that assembles it (called after the state arrays are allocated, the allocation order the loop
    was measured with); it is scaled to -Δt M^-1 K, so the constrained rows with zero inverse mass vanish
    (PETSc: in place). ``mass``/``inv_mass``: the owned lumped mass [kg] and its inverse [1/kg] (0 on
    constrained entries), host arrays; ``v0`` the initial velocity [m/s]; ``β`` the damping C = β K [s];
    ``contact`` an object with ``evaluate(u)`` and ``add_force(y, scale)``
    (:class:`rods.fe.contact.PenaltyContact`, on the same backend) or None; ``backend`` where the state
    lives and how A acts (:mod:`rods.fe.backend`; default the PETSc path).

    Per step: one matrix product, the contact impulse Δt M^-1 f_c on the tip entries and the drift
    u += Δt v, written once against the backend's array namespace and operator (``mult``, ``mult_add``,
    ``axpy``). Undamped, the product is the multiply-add v += A u_n. Damped, the damping's A v_{n-½} is not
    a second product: K is linear and u_n = u_{n-1} + Δt v_{n-½}, so A v_{n-½} = (A u_n - A u_{n-1})/Δt from
    the product q_n = A u_n and the last step's q_{n-1} (one vector kept; the first step, which has no
    q_{-1}, multiplies v_0, and a restore multiplies u_n once). The difference rounds to ~ε |A u|/Δt, ε
    n |A v| over n steps (~1e-11 of the damping force after 1e5 steps), and the energy record uses the
    damping force the step applied, so the balance is unaffected. A damped step costs one product instead
    of two: the step time of the matrix-bound loop nearly halves. The drift is deferred
    to the start of the next step, so that after :meth:`step` the state is (u_n, v_{n+½}): observers see
    u_n and may prescribe entries of v_{n+½} (a driven cut) before u_{n+1} = u_n + Δt v_{n+½} is formed.

    With ``keep=True`` a step also keeps what an energy record needs: ``v_prev`` = v_{n-½} and
    ``increment`` = -Δt M^-1 K u_n, recovered from the scheme's own velocity increment (no second
    multiply), so that ½ u_n·K u_n = -½ (M/Δt) u_n·increment. ``damping_power`` = v_{n-½}·C v_{n-½}
    [W] at every damped step (the dissipation's trapezoid rule needs it before v is overwritten), a scalar of the
    backend (on a device it stays there: the step does not wait for it).
    """

    def __init__(
        self,
        A: PETSc.Mat | Callable[[], PETSc.Mat],
        mass: np.ndarray,
        inv_mass: np.ndarray,
        dt: float,
        v0: np.ndarray,
        β: float = 0.0,
        contact=None,
        backend: Backend = PETSC,
    ):
        xp, n = backend.xp, mass.size
        self.backend = backend
        self.u, self.v, self._z, self.y, self._q, self._q_prev = (xp.zeros(n) for _ in range(6))
        self.dt_inv_mass = backend.asarray(dt * inv_mass)  # Δt M^-1 [s/kg]
        self.mass_dt = backend.asarray(mass / dt)  # M/Δt [kg/s]
        self.dt, self.β, self.contact, self.damped = dt, β, contact, β > 0
        self.mass = backend.asarray(mass)  # [kg]
        self.v[:] = backend.asarray(v0)
        arrays = (self.u, self.v, self._z, self.y, self._q, self._q_prev)
        self._neg_dt_inv_mass = -self.dt_inv_mass  # -Δt M^-1: the operator's scale, and the energy record's
        self.op = backend.operator(A, self._neg_dt_inv_mass, arrays)
        # the kinematic contact's rates before the product (rods.fe.kinematic, "Overlap"): serial CSR, undamped
        self.overlap = bool(
            backend.overlap and contact is not None and contact.predictive and contact.serial and not self.damped
        )
        if self.overlap:
            contact.predict_with(self.op)
        self.n = 0  # index of the state's u_n
        self.pending = False  # the drift u_{n+1} = u_n + Δt v_{n+½} is due at the next step
        self.v_prev = None  # v_{n-½} (backend array) when kept
        self.increment = None  # -Δt M^-1 K u_n (backend array) when kept
        self.damping_power = 0.0  # v_{n-½}·C v_{n-½} [W]

    def step(self, keep: bool = False) -> None:
        """Advance (u_{n-1}, v_{n-½}) to (u_n, v_{n+½}): drift, contact at u_n, velocity update."""
        u, v, y, dt_inv_mass, β, op = self.u, self.v, self.y, self.dt_inv_mass, self.β, self.op
        if self.pending:
            op.axpy(u, self.dt, v)  # u_n = u_{n-1} + Δt v_{n-½}
            self.n += 1
        c = self.contact
        if c is not None:
            c.evaluate(u)  # contact at u_n
            if self.overlap:  # its rates at v* = v_{n-½} + h A u_n, on their way to the host during the product
                c.predict(v, u, 0.5 if self.n == 0 else 1.0)
        if keep:
            self.v_prev = v.copy()
        if self.damped:  # q = A u_n; y = A v_{n-½} = -Δt M^-1 K v: f_d,n = C v_{n-½} (class docstring)
            self._q, self._q_prev = self._q_prev, self._q
            q = self._q
            op.mult(u, q)
            if self.n == 0:
                op.mult(v, y)  # no A u_{-1}: the first step's one extra product
            else:
                self.backend.xp.subtract(q, self._q_prev, out=y)
                y *= 1.0 / self.dt
            self.damping_power = -β * self.backend.sum_product(self.mass_dt * v, y)  # a backend scalar
        if self.n == 0:  # half step: v_{½} = v_0 + ½ Δt a_0
            z = self._z
            if self.damped:
                z[:] = q
                z += β * y
            else:
                op.mult(u, z)
            z *= 0.5
            if c is not None and not c.predictive:
                c.add_force(z, 0.5 * dt_inv_mass)
            v += z
            if c is not None and c.predictive:
                c.correct(v, self.dt, 0.5, dt_inv_mass)
        else:  # v_{n+½} = v_{n-½} + Δt M^-1 (f_c - K u_n - C v_{n-½})
            if self.damped:
                v += q
                op.axpy(v, β, y)
            else:
                op.mult_add(u, v)
            if c is not None:
                if c.predictive:  # kinematic: the impulse that closes the predicted gaps
                    c.correct(v, self.dt, 1.0, dt_inv_mass)
                else:
                    c.add_force(v, dt_inv_mass)
        if keep:
            self.increment = self._stiffness_increment()
        self.pending = True

    def _stiffness_increment(self):
        """-Δt M^-1 K u_n: damped, the step's own product q_n; undamped, the velocity increment less its
        contact part (x2 on the half step)."""
        if self.damped:
            return self._q.copy()
        h = 0.5 if self.n == 0 else 1.0
        dv = self.v - self.v_prev
        if self.contact is not None:
            # -Δt M^-1 kept from the set-up (-h Δt M^-1 on the half step only): not a full-length product per record
            self.contact.add_force(dv, self._neg_dt_inv_mass if self.n else -h * self.dt_inv_mass)
        if self.n == 0:
            dv *= 2.0
        return dv

    def state(self, step: int | None = None) -> dict[str, np.ndarray | int]:  # noqa: ARG002
        """What a restart needs (this rank's owned arrays, on the host): u_n, v_{n+½}, n."""
        return {"u": self.backend.to_host(self.u), "v": self.backend.to_host(self.v), "step": self.n}

    def restore(self, state: dict[str, np.ndarray]) -> None:
        """Resume from :meth:`state` (after a step: the drift is due)."""
        self.u[:], self.v[:] = self.backend.asarray(state["u"]), self.backend.asarray(state["v"])
        self.n, self.pending = int(state["step"]), True
        if self.damped:  # q_n = A u_n, the product the next step's damping differences against
            self.op.mult(self.u, self._q)

    def destroy(self) -> None:
        self.op.destroy()
