"""Run guards: stop an explicit run that has gone wrong, with a diagnosis, instead of writing garbage.

Checked at every recorded output step (cheap: the energies and the contact state are computed there
anyway) and, for non-finite values, on the velocity every ``FINITE_EVERY`` steps:

* a NaN/Inf in the state or the energies;
* energy growth: (E_kin + E_strain + E_contact + E_dissipated - W_external - E_0) / scale above ``growth_limit``,
  scale the larger of E_0 and the work put in so far (rods.fe.recorder.balance_scale: the summary's energy error
  divides by the same; a driven submodel's cut brings work in) (central differences conserve a modified energy
  exactly below the stable step, so growth means instability, not accumulated round-off);

The likely cause is named from the state: a step near or above the stable limit ("step too large"),
or a contact energy that dominates ("penalty too stiff"). Every ``INVERSION_EVERY`` steps the corner
Jacobians of the deformed cells are checked too ("mesh inverted"): displacements themselves are not
bounded, since they include the rods' rigid-body motion, which the small-strain model carries exactly.

:class:`RunGuard` applies these checks as an observer of the loop (:mod:`rods.fe.observers`), after
the recorder; :class:`CornerJacobians` counts the inverted cells.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from mpi4py import MPI

from rods import interrupt
from rods.fe.backend import PETSC

__all__ = [
    "DRIFT",
    "FINITE_EVERY",
    "INTERRUPT_EVERY",
    "INVERSION_EVERY",
    "CornerJacobians",
    "Guard",
    "InterruptCheck",
    "Interrupted",
    "RunGuard",
    "SimulationError",
]

FINITE_EVERY = 100  # steps between non-finite checks of the velocity [-]
# energy growth below which a guard's stop is the scheme's drift, not an instability (which grows by orders of
# magnitude): round-off ~1e-9, a penalty layer's wobble 3e-7 damped, 1.1e-6 to 7e-5 undamped (measured) [-]
DRIFT = 1e-4
INTERRUPT_EVERY = 10  # steps between collective checks of a stop request (one integer Allreduce) [-]
INVERSION_EVERY = 2000  # steps between inverted-cell checks (a few ms each at 50k DOFs: < 1% of the loop) [-]


class SimulationError(RuntimeError):
    """The run was stopped by a guard; ``partial`` holds the histories recorded so far (an FEResult)."""

    status = "failed"  # the partial summary's status

    def __init__(self, message: str, step: int, time: float, cause: str, partial: Any = None):
        super().__init__(message)
        self.step, self.time, self.cause, self.partial = step, time, cause, partial


class Interrupted(SimulationError):
    """The run was stopped on request (Ctrl-C, SIGTERM) by every rank at the same step; ``checkpointed``: a
    checkpoint of that step was written first (a run that can resume)."""

    status = "interrupted"
    checkpointed = False


@dataclass
class Guard:
    """The stability rules of the time loop (:class:`RunGuard` applies them): a run whose energy grows by more than
    ``growth_limit`` of the initial energy, whose state turns non-finite or whose elements invert stops with a
    :class:`SimulationError` naming the likely cause against the step's limits (the stable step, the
    contact-switching limit)."""

    dt: float  # [s]
    dt_critical: float  # [s]
    growth_limit: float = 0.05  # relative energy growth that stops the run (scene fe.energy_growth_limit) [-]
    dt_switching: float = math.inf  # [s] the contact-switching limit of the step (rods.fe.explicit.switching_step)

    def _drift(self, growth: float) -> str:
        """A growth below :data:`DRIFT` is the scheme's drift (round-off, a contact layer's O(Δt²) wobble), no
        instability: the limit is set below what a stable run does."""
        return (
            f"drift, not an instability: a growth of {growth:.2g} is what stable runs do (round-off; a penalty "
            "layer's wobble, 1.1e-6 to 7e-5 undamped); raise fe.energy_growth_limit, or damp the contact "
            "(fe.contact_damping)"
        )

    def _cause(self, contact_share: float) -> str:
        """Step (at the stable limit), penalty (contact energy dominates, or the step sits at the contact's
        switching limit: a stiff layer rattles), else an instability below both limits."""
        if self.dt > 0.99 * self.dt_critical:
            return f"step too large: dt = {self.dt:.4g} s is at the stable limit {self.dt_critical:.4g} s"
        if contact_share > 0.5:
            return "penalty too stiff: the contact energy dominates; lower fe.penalty or fe.dt_fraction"
        if self.dt > 0.99 * self.dt_switching:
            return (
                f"penalty too stiff: dt = {self.dt:.4g} s is at the contact-switching limit {self.dt_switching:.4g} s "
                "(a rattling contact pumps energy); lower fe.penalty"
            )
        return (
            "instability below the stable and switching limits (energy grows without a dominant contact energy: "
            "mesh quality, bulk viscosity or an estimate of the limit too high); lower fe.dt_fraction"
        )

    def check(self, step: int, t: float, energies: tuple[float, ...], E0: float, scale: float | None = None) -> None:
        """Raise SimulationError if the recorded state at ``step`` is not physical.

        ``energies`` = (kinetic, strain, contact, dissipated less the work put in) [J]; the growth is the balance's
        excess over ``E0`` relative to ``scale`` (rods.fe.recorder.balance_scale, as the summary's energy error;
        default ``E0``)."""
        Ek, Es, Ec, W = energies
        total = Ek + Es + Ec + W
        share = abs(Ec) / max(abs(total), 1e-300)
        if not all(math.isfinite(x) for x in energies):
            cause = self._cause(share)
            raise SimulationError(
                f"non-finite state at step {step} (t = {t:.6g} s); likely cause: {cause}", step, t, cause
            )
        scale = E0 if scale is None else scale
        growth = (total - E0) / scale if scale > 0 else 0.0
        if growth > self.growth_limit:
            cause = self._cause(share) if growth > DRIFT else self._drift(growth)
            raise SimulationError(
                f"energy grew by {growth:.3g} x {'E0' if scale == E0 else 'the work put in'} (limit "
                f"{self.growth_limit:g}) at step {step} "
                f"(t = {t:.6g} s); likely cause: {cause}",
                step,
                t,
                cause,
            )

    def check_inverted(self, step: int, t: float, n_cells: int) -> None:
        """Raise if ``n_cells`` elements are inverted in the deformed configuration."""
        if n_cells > 0:
            cause = "mesh inverted: the deformation is too large for small-strain elements (impact too violent)"
            raise SimulationError(
                f"{n_cells} inverted cell(s) at step {step} (t = {t:.6g} s); likely cause: {cause}", step, t, cause
            )

    def check_finite(self, step: int, t: float, finite: bool) -> None:
        if not finite:
            cause = self._cause(0.0)
            raise SimulationError(
                f"non-finite velocity at step {step} (t = {t:.6g} s); likely cause: {cause}", step, t, cause
            )


class RunGuard:
    """Observer: :class:`Guard` on the recorder's energies at its output steps, a non-finite velocity
    every ``FINITE_EVERY`` steps and inverted cells (``inverted(u)``, collective count on this rank)
    every ``INVERSION_EVERY`` steps; raises :class:`SimulationError`. It reads the state where it lives
    (``dot``, ``inverted`` take the stepper's arrays: a device's too)."""

    def __init__(self, guard: Guard, recorder, inverted, comm: MPI.Comm, dot=None):
        self.guard, self.recorder, self.inverted, self.comm = guard, recorder, inverted, comm
        # v·v as a float where the state lives (rods.fe.backend.Backend.dot: on a device one reduction there, not
        # the whole state copied to the host); default: the host's
        self.dot = dot if dot is not None else PETSC.dot

    def after_step(self, step: int, t: float, state) -> None:
        if self.recorder.last is not None:
            self.guard.check(step, t, self.recorder.last, self.recorder.E0, self.recorder.energy_scale)
        if step % FINITE_EVERY == 0:
            # NaN/Inf anywhere poisons the dot product; inverted cells are counted every INVERSION_EVERY
            n_inv = self.inverted(state.u) if step % INVERSION_EVERY == 0 else 0
            health = np.array([float(np.isfinite(self.dot(state.v, state.v))), -float(n_inv)])
            if self.comm.size > 1:
                self.comm.Allreduce(MPI.IN_PLACE, health, op=MPI.MIN)
            self.guard.check_finite(step, t, bool(health[0]))
            self.guard.check_inverted(step, t, int(-health[1]))


class InterruptCheck:
    """Observer: every ``every`` steps, the stop request of any rank (:mod:`rods.interrupt`, MAX over the
    ranks) stops all ranks together with :class:`Interrupted`, after ``on_stop(step, t)`` (a checkpoint).
    Signals are requests only while the loop runs (armed at the first step, disarmed by ``finish``)."""

    def __init__(self, comm: MPI.Comm, every: int = INTERRUPT_EVERY, on_stop: Any = None):
        self.comm, self.every, self._ctx = comm, every, None
        self._signum = np.zeros(1, dtype=np.int64)  # the stop request's buffer (Allreduce, MAX over the ranks)
        self.on_stop = on_stop  # on_stop(step, t), collective, before the stop (a restartable checkpoint)

    def after_step(self, step: int, t: float, state) -> None:  # noqa: ARG002
        if self._ctx is None:
            self._ctx = interrupt.armed()
            self._ctx.__enter__()
        if step % self.every == 0:
            # serial: the request itself (no reduction); under MPI one integer Allreduce (not the pickled allreduce)
            if self.comm.size == 1:
                signum = interrupt.requested()
            else:
                self._signum[0] = interrupt.requested()
                self.comm.Allreduce(MPI.IN_PLACE, self._signum, op=MPI.MAX)
                signum = int(self._signum[0])
            if signum:
                interrupt.reset()
                if self.on_stop is not None:
                    self.on_stop(step, t)
                cause = f"interrupted by signal {signum}"
                stop = Interrupted(f"run interrupted at step {step} (t = {t:.6g} s)", step, t, cause)
                stop.checkpointed = self.on_stop is not None
                raise stop

    def finish(self) -> None:
        if self._ctx is not None:
            self._ctx.__exit__(None, None, None)
            self._ctx = None


class CornerJacobians:
    """Counts this rank's cells with a corner whose deformed Jacobian changed sign (an inverted element;
    P1 cells, corner Jacobians from the edges to the corner's tensor-product neighbours).

    :meth:`use` moves the count to a serial device backend: there the cells, the reference coordinates and
    signs are copied once and a count is a few kernels and one scalar back, where the host copies the
    state back and evaluates every cell there (2.44M hexahedra at the paper's 3D mesh: seconds a count)."""

    def __init__(self, V, n_local: int, n_owned_cells: int):
        import dolfinx

        self.cells = V.dofmap.list  # (n_cells, corners) node indices, tensor-product vertex order
        nc = self.cells.shape[1]
        self.dim = int(round(np.log2(nc)))
        self.nbr = np.array([[k ^ (1 << d) for d in range(self.dim)] for k in range(nc)])  # (corners, dim)
        self.X = V.tabulate_dof_coordinates()[:, : self.dim]
        self.uf = dolfinx.fem.Function(V)
        self.n_local, self.n_owned_cells, self.bs = n_local, n_owned_cells, V.dofmap.index_map_bs
        self.sign = np.sign(self._dets(np, self.X, self.cells, self.nbr))
        self._device = None  # (xp, cells, nbr, X, sign) on a serial device backend (use)
        self._to_host = np.asarray  # a state array to the host (use)

    def use(self, backend) -> None:
        """Count on ``backend``'s arrays from now on where it is a device (serial: every node is owned, so no
        ghost update is needed); on the host nothing changes."""
        self._to_host = backend.to_host
        if backend.on_device and self.n_local == self.X.shape[0] * self.bs:
            put = backend.asarray
            self._device = (backend.xp, put(self.cells), put(self.nbr), put(self.X), put(self.sign))

    @staticmethod
    def _dets(xp, x, cells, nbr):
        e = x[cells[:, nbr]] - x[cells][:, :, None, :]  # (cells, corners, dim, dim) edge vectors
        if x.shape[1] == 2:
            return e[..., 0, 0] * e[..., 1, 1] - e[..., 0, 1] * e[..., 1, 0]
        return xp.einsum("...i,...i->...", e[..., 0, :], xp.cross(e[..., 1, :], e[..., 2, :]))

    def count(self, u_owned) -> int:
        """Inverted owned cells at the displacement ``u_owned`` (owned array; collective scatter; an array of
        the device of :meth:`use` is counted there)."""
        if self._device is not None and not isinstance(u_owned, np.ndarray):
            (xp, cells, nbr, X, sign), u = self._device, u_owned
        else:
            xp, cells, nbr, X, sign = np, self.cells, self.nbr, self.X, self.sign
            self.uf.x.array[: self.n_local] = self._to_host(u_owned)
            self.uf.x.scatter_forward()
            u = self.uf.x.array
        bad = (self._dets(xp, X + u.reshape(-1, self.bs)[:, : self.dim], cells, nbr) * sign <= 0).any(axis=1)
        return int(xp.count_nonzero(bad[: self.n_owned_cells]))
