"""What an explicit run records: named histories at the output steps, the energy balance, the peak.

:class:`Recorder` is an observer of the loop (:mod:`rods.fe.observers`). At every step it keeps the
total contact force (the contact duration is judged on every step), tracks the state at the largest
force (the peak) and integrates the dissipated energy; at the output steps it records one row of named
columns (:data:`BASE_COLUMNS`, then the probes' velocity and strain, the 3D patch keys, then
:data:`ENERGY_COLUMNS`, in that order, which is the order of ``history.csv``).

Energy bookkeeping (all [J], full rods: x ``multiplicity`` for a symmetry model):

* kinetic ½ v_{n-½}·M v_{n+½} and strain ½ u_n·K u_n, the scheme's conserved discrete energy
  (:mod:`rods.fe.explicit`), K u_n recovered from the stepper's velocity increment;
* contact: the penalty energy E_c(u_n) (0 for the kinematic contact);
* dissipated: the kinematic contact's dissipation (:mod:`rods.fe.kinematic`) plus the damping's
  W_n = Σ ½Δt (v_{k+½}·f_d,k + v_{k+½}·f_d,k+1), f_d,k = C v_{k-½} (trapezoid rule in the
  force over each velocity interval);
* external work: Σ of the observers' ``external_work()`` (a driven cut);
* energy error: max_n |E_n + W_n - W_ext,n - E_0| / max(E_0, max |W_ext|).

MPI: every recorded scalar is the Allreduce of this rank's partial sums (one reduction per record).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from mpi4py import MPI

from rods import metrics
from rods.fe.backend import PETSC, Backend, product
from rods.fe.checkpoint import Appended
from rods.fe.explicit import CentralDifference

__all__ = ["BASE_COLUMNS", "ENERGY_COLUMNS", "Recorder", "balance_scale", "output_steps"]

BASE_COLUMNS = {"time": "s", "contact_force": "N", "contact_radius": "m", "contact_area": "m^2", "peak_pressure": "Pa"}
ENERGY_COLUMNS = {
    "kinetic_energy": "J",
    "strain_energy": "J",
    "contact_energy": "J",
    "dissipated_energy": "J",
    "external_work": "J",
    "momentum": "kg m/s",
}


def balance_scale(E0: float, external_work: np.ndarray | float) -> float:
    """The energy balance's scale [J]: the larger of the initial energy E0 and the largest |work put in| so far (a
    driven submodel's cut). One definition: the summary's ``energy_error`` and the guard's growth divide by it."""
    return max(float(E0), float(np.max(np.abs(external_work), initial=0.0)))


def output_steps(end_time: float, interval: float, dt: float, steps: int) -> np.ndarray:
    """The step nearest to each output time 0, interval, 2 interval, ... <= end_time (unique, <= steps)."""
    n_out = int(math.floor(end_time / interval * (1 + 1e-12))) + 1
    out = np.unique(np.rint(np.arange(n_out) * interval / dt).astype(np.int64))
    return out[out <= steps]


class Recorder:
    """Observer: named histories at ``record_steps``, energy bookkeeping and the peak (module docstring).

    ``contact``: a :class:`rods.fe.contact.PenaltyContact`; ``probes``: (P, names) with P the sparse
    (2 n_p, n_owned) probe map (rows 2i: value, 2i + 1: ∂/∂z at point i) and names the (velocity,
    strain) column pairs; ``mass_axial``: the lumped mass of the axial entries (0 elsewhere) [kg], whose
    product with v is the axial momentum; ``sources``: observers whose ``external_work()`` (this rank's
    accumulated work on the model [J]) enters the balance; ``backend``: where the stepper's state lives
    (:mod:`rods.fe.backend`; P and ``mass_axial`` are copied there once, the sums come back as scalars)."""

    def __init__(
        self,
        contact,
        probes: tuple[Any, Sequence[tuple[str, str]]],
        mass_axial: np.ndarray,
        record_steps: np.ndarray,
        steps: int,
        dt: float,
        comm: MPI.Comm,
        multiplicity: float = 1.0,
        sources: Sequence[Any] = (),
        backend: Backend = PETSC,
    ):
        self.contact, self.comm, self.dt, self.multiplicity = contact, comm, dt, float(multiplicity)
        P, self.probe_keys = probes
        self.backend = backend
        self.P, self.mass_axial = backend.csr(P), backend.asarray(mass_axial)
        self.sources = [s for s in sources if hasattr(s, "external_work")]
        self.is_out = np.zeros(steps + 1, dtype=bool)
        self.is_out[record_steps] = True
        self.units = dict(BASE_COLUMNS)
        for kv, ks in self.probe_keys:
            self.units[kv], self.units[ks] = "m/s", "-"
        self.units.update(dict.fromkeys(contact.patch_keys, "m"))
        self.units.update(ENERGY_COLUMNS)
        self.columns = {name: np.zeros(record_steps.size) for name in self.units}
        self.k = 0  # rows recorded
        self.force = np.zeros(steps + 1)  # total contact force at every step [N]
        self.peak: dict[str, Any] = {"F": -1.0}
        self.p_max_all = 0.0  # largest nodal pressure over the recorded steps [Pa]
        self.W_local, self.s_prev = 0.0, 0.0  # dissipated energy (this rank) [J]; v_{n-½}·f_d,n-1 [W]
        self.E0 = 0.0  # total energy of the first record [J]
        self.energy_scale = 0.0  # balance_scale so far [J]
        self.last: tuple[float, ...] | None = None  # (E_k, E_s, E_c, W - W_ext) of this step's record [J]
        self.wall_before, self.t_start = 0.0, time.perf_counter()

    # -- the loop ------------------------------------------------------------------------------
    def start(self) -> None:
        self.t_start = time.perf_counter()

    def wall(self) -> float:
        """Loop wall time so far [s] (this rank; restarts add the time before the checkpoint)."""
        return self.wall_before + time.perf_counter() - self.t_start

    def after_step(self, step: int, t: float, st: CentralDifference) -> None:
        c = self.contact
        F = c.force  # at u_n
        self.force[step] = F
        if F > self.peak["F"]:
            self.peak = {"F": F, "t": t, "a": c.radius(), "A_nodal": c.active_area(), "p": c.pressure.copy()}
            self.peak["patch"] = c.patch()
        if st.damped:
            if step > 0:
                self.W_local += 0.5 * self.dt * (self.s_prev + st.damping_power)
            self.s_prev = -st.β * self.backend.sum_product(st.mass_dt * st.v, st.y)  # v_{n+½}·f_d,n (backend scalar)
        self.last = None
        if self.is_out[step]:
            self._record(t, st)

    def _record(self, t: float, st: CentralDifference) -> None:
        c, n_p, be = self.contact, self.P.shape[0], self.backend
        xp, sp = be.xp, be.sum_product
        E_s = -0.5 * sp(st.mass_dt * st.u, st.increment)  # ½ u_n·K u_n
        E_k = 0.5 * sp(st.mass * st.v_prev, st.v)  # ½ v_{n-½}·M v_{n+½}
        W_dev = not isinstance(self.W_local, float)  # damped on a device: the sum is there (np.float64 is a float)
        sums = [E_k, E_s, sp(self.mass_axial, st.v)] + ([self.W_local] if W_dev else [])
        # P (v_{n-½} + v_{n+½}) as two products of the few probe rows: no full-length sum per record
        probed = (product(self.P, st.v_prev) + product(self.P, st.v), product(self.P, st.u))
        got = be.to_host(xp.concatenate((xp.stack(sums), *probed)))  # one copy
        k = len(sums)
        W_ext = sum(s.external_work() for s in self.sources) if self.sources else 0.0
        W_local = got[3] if W_dev else self.W_local
        loc = np.concatenate(([got[0], got[1], W_local, W_ext], got[k : k + n_p], got[k + n_p : k + 2 * n_p], [got[2]]))
        if self.comm.size > 1:
            self.comm.Allreduce(MPI.IN_PLACE, loc, op=MPI.SUM)
        pv, pu, p_z = loc[4 : 4 + n_p], loc[4 + n_p : 4 + 2 * n_p], loc[4 + 2 * n_p]
        E_k, E_s, W, W_ext = loc[:4] * self.multiplicity  # full rods
        pmax = float(c.pressure.max()) if c.ns else 0.0
        self.p_max_all = max(self.p_max_all, pmax)
        a = c.radius()
        row = {"time": t, "contact_force": c.force, "contact_radius": a, "contact_area": math.pi * a * a}
        row["peak_pressure"] = pmax
        for (kv, ks), v_i, ε_i in zip(self.probe_keys, 0.5 * pv[0::2], pu[1::2], strict=True):
            row[kv], row[ks] = v_i, ε_i  # axial velocity at t_n (mean of the half steps), ε_zz at t_n
        row.update(zip(c.patch_keys, c.patch(), strict=True))
        W = W + c.dissipated  # damping + contact dissipation (kinematic contact; 0 for the penalty)
        row.update(kinetic_energy=E_k, strain_energy=E_s, contact_energy=c.energy, dissipated_energy=W)
        row.update(external_work=W_ext, momentum=p_z * self.multiplicity)  # momentum at t_{n+½}
        k = self.k
        for name, x in row.items():
            self.columns[name][k] = x
        if k == 0:
            self.E0 = float(np.array([E_k, E_s, c.energy]).sum())
        self.energy_scale = balance_scale(max(self.E0, self.energy_scale), W_ext)
        self.k += 1
        self.last = (E_k, E_s, c.energy, W - W_ext)

    # -- checkpoints ---------------------------------------------------------------------------
    def state(self, step: int) -> dict[str, Any]:
        """What a restart needs after ``step`` (this rank): rows so far, accumulators, peak, wall time."""
        k = self.k
        out: dict[str, Any] = {f"hist_{name}": Appended(col[:k]) for name, col in self.columns.items()}
        out.update(k=k, force=Appended(self.force[: step + 1]), W_local=float(self.W_local), s_prev=float(self.s_prev))
        out.update(p_max_all=self.p_max_all, wall=self.wall())
        out.update({f"peak_{key}": np.asarray(val) for key, val in self.peak.items()})
        if hasattr(self.contact, "state"):  # a contact with memory (kinematic: F_{n-1}, g_{n-1}, dissipation)
            out.update(self.contact.state())
        return out

    def restore(self, state: dict[str, np.ndarray]) -> None:
        k = self.k = int(state["k"])
        for name, col in self.columns.items():
            col[:k] = state[f"hist_{name}"]
        force = state["force"]
        self.force[: force.size] = force
        self.W_local, self.s_prev = float(state["W_local"]), float(state["s_prev"])
        self.p_max_all, self.wall_before = float(state["p_max_all"]), float(state["wall"])
        self.peak = {key[5:]: (v if v.ndim else float(v)) for key, v in state.items() if key.startswith("peak_")}
        if hasattr(self.contact, "restore"):
            self.contact.restore(state)
        if k > 0:
            c = self.columns
            self.E0 = float(np.array([c["kinetic_energy"][0], c["strain_energy"][0], c["contact_energy"][0]]).sum())
            self.energy_scale = balance_scale(self.E0, c["external_work"][:k])

    # -- results -------------------------------------------------------------------------------
    def history(self, rows: int | None = None) -> dict[str, np.ndarray]:
        """The named columns (the first ``rows`` records; all by default)."""
        k = self.k if rows is None else rows
        return {name: col[:k] for name, col in self.columns.items()}

    def force_trace(self, steps: int) -> dict[str, np.ndarray]:
        """time [s] and contact_force [N] at each of the first ``steps`` steps (the checks' force, rods.checks)."""
        force = self.force[:steps]
        return {"time": np.arange(force.size) * self.dt, "contact_force": force}

    def summary(
        self, hist: dict[str, np.ndarray], steps: int, midpoint: str, arrival: float, gap: float, min_gap: float
    ) -> dict[str, Any]:
        """History-derived summary values: peak, contact times, energy error (``steps``: force samples;
        ``arrival`` [m/s]: the midpoint speed below which the wave has not arrived, ``gap`` [s]: the shortest dip
        between two plateaus, rods.metrics.plateaus; ``min_gap`` [s]: between two contact episodes,
        rods.metrics.min_gap)."""
        trace = self.force_trace(steps)
        t_steps, force = trace["time"], trace["contact_force"]
        E_total = hist["kinetic_energy"] + hist["strain_energy"] + hist["contact_energy"]
        E0 = E_total[0]
        W_ext = hist["external_work"]
        # E(t) + dissipated(t) - work in(t) = E0; relative to the largest of E0 and the work put in
        scale = balance_scale(E0, W_ext)
        energy_error = float(np.max(np.abs(E_total + hist["dissipated_energy"] - W_ext - E0)) / scale)
        peak = self.peak
        a_peak = peak.get("a", 0.0)
        return {
            "peak_contact_force": peak["F"],
            "peak_force_time": peak.get("t", 0.0),
            "contact_radius": a_peak,
            "contact_area": math.pi * a_peak**2,
            "contact_area_nodal": peak.get("A_nodal", 0.0),
            "peak_contact_pressure": max(self.p_max_all, float(np.max(peak.get("p", [0.0])))),
            "contact_duration": metrics.contact_duration(t_steps, force, min_gap),
            "contact_episodes": [list(e) for e in metrics.contact_episodes(t_steps, force, min_gap)],
            "midpoint_peak_speed": metrics.midpoint_peak_speed(
                hist["time"], hist[f"{midpoint}_velocity"], floor=arrival, gap=gap
            ),
            "midpoint_peak_strain": float(np.min(hist[f"{midpoint}_strain"])),
            "energy_error": energy_error,
            "initial_energy": float(E0),
        }
