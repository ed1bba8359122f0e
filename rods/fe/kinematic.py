"""Penalty-free explicit contact: forward-increment Lagrange multipliers (kinematic predictor-corrector).

Carpenter, Taylor & Katona (1991), "Lagrange constraints for transient finite element surface contact",
IJNME 32:103-128; Abaqus/Explicit's kinematic contact. The same pairing, gaps and tip arrays as the
penalty contact (:mod:`rods.fe.contact`: slave s, master interpolation W_s, gap g_s = g0_s + b_s·u with
b_s = W_s on the master's axial entries and -1 on the slave's); only the force law differs.

At step n the stepper forms the contact-free velocity v*_{n+½} (:class:`rods.fe.explicit.CentralDifference`),
so the predicted gaps at t_{n+1} are g* = g_n + Δt B v*. The contact impulses P_s = h Δt F_s >= 0 (h = ½ on
the first half step, else 1) are the solution of the linear complementarity problem

    g_{n+1} = g* + Δt D P >= 0,   P >= 0,   P_s g_{n+1,s} = 0,     D = B M^-1 Bᵀ  [1/kg]

(D: the Delassus operator of the lumped mass M, sparse, symmetric positive definite), and the corrected
velocity is v_{n+½} = v* + M^-1 Bᵀ P: every closed pair sits at exactly zero gap at t_{n+1}. The LCP is
solved by a primal active set (start from the predicted penetrations, drop negative impulses, add
penetrating pairs; exact for the final set), factorising the dense active block D_AA once per change of
the active set and reusing it while the set is unchanged (the set changes a few hundred times per impact).

Assumptions: frictionless, normal along the axis, small displacements (the pairing is fixed at the
reference configuration), as for the penalty law. No spring, so no contact stiffness enters the spectrum:
the step is the bulk limit of K alone and there is no switching limit (:func:`pair_frequency` is 0).
Costs per step: a gather of the tip velocities beside the displacements' (under MPI both in one Allreduce) and,
while in contact, a triangular solve of the active block (~|A|² flops, |A| <= tens of nodes).

Energy: a pair that closes at a nonzero relative velocity loses that velocity (a perfectly plastic
node-on-surface impact), so the contact dissipates. From the scheme's discrete energy identity
E_{n+1} - E_n = ½ (u_{n+1} - u_n)·(f_n + f_{n+1}) (:mod:`rods.fe.explicit`), with f = Bᵀ F the contact
dissipation is accumulated as D_c += -½ (F_{n-1} + F_n)·(g_n - g_{n-1}) [J] (F_0 at weight ½: the first
step is a half step) and reported in the
``dissipated_energy`` column, so the energy balance stays closed. Stored contact energy: 0.

Array backends: the gaps and the predicted rates are formed on the backend's arrays and come to the host
in one copy per step (on a device the step's only synchronisation); the LCP is solved there (tens of
entries), and the host keeps what the recorder reads (gaps, pressures, forces), so reading them costs no
further copy. The forces go back through :meth:`PenaltyContact.add_force` only while a pair is closed: in
the steps before and after contact (most of a run) the step adds nothing, which on a device saves the
dozen small kernels of the upload, the master reaction and the scatter.

Overlap (serial, undamped, the backend's ``overlap``: on a device by default): the predicted rates need the
step's matrix product only on the tip rows, B v* = B v_{n-½} + h (B A) u_n with A = -Δt M^-1 K, so they are
formed *before* the product from B A (n_s rows, built once by :meth:`KinematicContact.predict_with`), and
their copy to the host (:meth:`rods.fe.backend.Backend.to_host_async`) is waited for *after* the product is
queued: the host solves the LCP while the device multiplies, instead of after it. Same impulses to
round-off (the two sums round differently; ``tests/fe/test_backend.py`` runs it on the NumPy backend).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.linalg import lapack

from rods.fe.backend import product
from rods.fe.contact import PenaltyContact, _interp, _transpose

__all__ = ["KinematicContact", "solve_lcp"]

MAX_SWEEPS = 100  # active-set changes per step before giving up (a set of n pairs needs <= ~n)


def solve_lcp(D, g: np.ndarray, candidates: np.ndarray, cache: dict | None = None) -> np.ndarray:
    """x >= 0 with y = g + D x >= 0 and x·y = 0 (D symmetric positive definite, sparse or dense).

    Primal active set over the ``candidates`` (boolean; the others stay at x = 0): A = {g < 0}, solve
    D_AA x_A = -g_A, drop the pairs with x < 0, add the candidates with y < 0, repeat. ``cache`` keeps the
    Cholesky factor of the last active block (key: the active set). Raises RuntimeError if it cycles."""
    x = np.zeros(g.size)
    A = candidates & (g < 0.0)
    tol = 1e-12 * max(float(np.abs(g).max(initial=0.0)), 1e-300)
    for _ in range(MAX_SWEEPS):
        if not A.any():
            return x
        idx = np.flatnonzero(A)
        key = idx.tobytes()
        if cache is not None and cache.get("key") == key:
            factor = cache["factor"]
        else:
            block = D[idx][:, idx]
            factor = _cholesky(block.toarray() if sp.issparse(block) else np.asarray(block, dtype=float))
            if cache is not None:
                cache.update(key=key, factor=factor)
        x[:] = 0.0
        x[idx] = lapack.dpotrs(factor, -g[idx], lower=False)[0]
        negative = x < 0.0
        if negative.any():
            A &= ~negative
            continue
        y = g + product(D, x)
        add = candidates & ~A & (y < -tol)
        if not add.any():
            return x
        A |= add
    raise RuntimeError("kinematic contact: the active-set LCP did not settle")


def _cholesky(block: np.ndarray) -> np.ndarray:
    """The upper Cholesky factor of the SPD ``block`` (LAPACK potrf, as scipy.linalg.cho_factor computes it; the
    LCP's active block, once per change of the active set). Called directly: SciPy's wrappers' checks cost more than
    the solve on a block of tens of pairs, every step in contact. LinAlgError if the block is not positive definite."""
    factor, info = lapack.dpotrf(block, lower=False, clean=False)
    if info != 0:
        raise np.linalg.LinAlgError(
            f"kinematic contact: the Delassus block is not positive definite (potrf info {info})"
        )
    return factor


class KinematicContact(PenaltyContact):
    """Kinematic (forward-increment Lagrange multiplier) contact; see the module docstring.

    Same arguments as :class:`PenaltyContact` less the penalty, plus ``inv_mass``: the owned inverse lumped
    mass [1/kg] (the stepper's), from which the Delassus operator D = B M^-1 Bᵀ is built once."""

    predictive = True
    stiffens = False  # no springs: ω_max is the rods' own (rods.fe.timestep solves it once)

    def __init__(
        self, slave, master, comm, inv_mass: np.ndarray, pairing=None, multiplicity=1, mirrored=(False, False)
    ):
        super().__init__(slave, master, 0.0, comm, pairing, multiplicity, mirrored)
        ims, imm = (a.copy() for a in self.gather(inv_mass))
        rows = np.flatnonzero(self.inside)
        nw = self.J.shape[1]
        B = sp.coo_matrix(
            (
                np.concatenate([-np.ones(rows.size), self.W[rows].ravel()]),
                (np.concatenate([rows, np.repeat(rows, nw)]), np.concatenate([rows, self.ns + self.J[rows].ravel()])),
            ),
            shape=(self.ns, self.ns + self.nm),
        ).tocsr()
        self.delassus = (B @ sp.diags(np.concatenate([ims, imm])) @ B.T).tocsr()  # D [1/kg]
        self._cache: dict = {}
        self._BA = None  # B A on the backend when the rates are predicted before the product (Overlap)
        self._pending = None  # the wait for the predicted gaps and rates on their way into self._buffer
        self._buffer = None  # host array the predicted gaps and rates are copied into (Overlap)
        self._pair_buf = np.zeros(2 * (self.ns + self.nm))  # under MPI: u_n's and v*'s tip entries, one gather
        self._u = None  # under MPI: u_n, whose gaps correct() gathers with the rates

    def predict_with(self, op) -> None:
        """Predict the rates before the step's product from now on (module docstring, "Overlap"): ``op`` the
        stepper's scaled operator A = -Δt M^-1 K on a serial array backend (``op.rows(R)`` = R A as a CSR matrix
        of the backend)."""
        self._BA = op.rows(self.gap_rows(self._d, op.shape[1]))  # [n_s x n]: the product's tip rows
        self._buffer = self.backend.host_buffer(2 * self.ns)

    def predict(self, v, u, h: float) -> None:
        """Form g_n and the rates of v* = v_{n-½} + h A u_n (``v``, ``u`` before the product) and start their
        copy to the host; :meth:`correct` waits for it."""
        xp = self.backend.xp
        rate = self.normal_rates(v) + h * (self._BA @ u)  # [m/s]
        self._pending = self.backend.to_host_async(xp.concatenate((self._g, rate)), self._buffer)

    def use(self, backend) -> None:
        """As :meth:`PenaltyContact.use` (the state starts at rest: no forces, no dissipation yet; pressure
        p_s = F_s / a_s with its 1/a_s)."""
        super().use(backend)
        self.dissipated = 0.0  # contact dissipation D_c, full rods [J]
        self._F_prev = np.zeros(self.ns)  # h F_{n-1} [N]
        self._g_prev: np.ndarray | None = None  # g_{n-1} [m]
        self._inv_area_host = backend.to_host(self._inv_area)  # 1/a_s [1/m^2]
        self._no_force = (self._Fs, self._Fm)  # zeros on the backend, never written: the open steps' forces
        self._closed = False  # a pair carries force this step (add_force adds it)

    def evaluate(self, u) -> None:
        """Gaps at u_n on the backend (they come to the host with the rates in :meth:`correct`). Under MPI the
        gather is left to :meth:`correct`: u_n stays as it is until the next step's drift, so one Allreduce there
        gathers it with the rates' v* (two a step before; the sums are the same, each entry from its one owner)."""
        if self.serial:
            self._g, self._host = self.gaps(u), None
        else:
            self._u, self._host = u, None

    def correct(self, v, dt: float, h: float, dt_inv_mass) -> None:
        """v += M^-1 Bᵀ P so that no pair penetrates at t_{n+1} (``v``: v*_{n+½} on the backend; ``h``: ½
        on the first half step, else 1; ``dt_inv_mass``: the stepper's Δt M^-1)."""
        xp, ns = self.backend.xp, self.ns
        if self._pending is not None:  # predicted before the product (Overlap): wait for its copy now
            self._pending()
            self._pending = None
            g_rate = self._buffer.copy()  # the buffer is the next step's
        elif not self.serial:  # the gaps at u_n and the rates of v* from one gather (:meth:`evaluate`)
            self._g, rate = self._gaps_and_rates(self._u, v)
            g_rate = np.concatenate((self._g, rate))
        else:
            rate = self.normal_rates(v)  # d g/dt [m/s]
            g_rate = self.backend.to_host(xp.concatenate((self._g, rate)))  # the step's one copy to the host
        g, rate = g_rate[:ns], g_rate[ns:]
        g_pred = g + dt * rate
        if (self.inside & (g_pred < 0.0)).any():
            P = solve_lcp(self.delassus, g_pred / dt, self.inside, self._cache)  # impulses [N s]
        else:
            P = np.zeros(ns)
        F = P / (h * dt)  # [N]
        self._closed = bool(F.any())
        self._host = (g, F * self._inv_area_host, F)  # gap [m], pressure [Pa], forces [N]: read on the host
        if self._closed:
            self._Fs = self.backend.asarray(F) if xp is not np else F
            self._Fm = _transpose(xp, self._d.J, self._d.W, self._Fs, self.nm, self._d.WT)
            self._p = self._Fs * self._inv_area
        else:
            self._Fs, self._Fm = self._no_force
            self._p = self._Fs
        self.force = self.multiplicity * float(F.sum())
        if self._g_prev is not None:  # the work of the contact forces over [t_{n-1}, t_n], trapezoid
            self.dissipated -= 0.5 * self.multiplicity * float((self._F_prev + F) @ (g - self._g_prev))
        # the half step's identity is E_1 - E_0 = ½ (u_1 - u_0)·(f_1 + ½ f_0): its force enters at weight h
        self._F_prev, self._g_prev = h * F, g
        if self._closed:  # h Δt M^-1 formed only then: a full-length product each step costs about an axpy
            self.add_force(v, dt_inv_mass if h == 1.0 else h * dt_inv_mass)

    def _gaps_and_rates(self, u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(g_s at ``u``, B ``v``) under MPI, host arrays: :meth:`gaps` and :meth:`normal_rates` from one Allreduce
        of both arrays' axial tip entries (:meth:`gather`'s, side by side)."""
        d, ns, n = self._host_arrays, self.ns, self.ns + self.nm
        b = self._gather_into(d, self._pair_buf, (u, v))
        g = d.g0 + (_interp(d.J, d.W, b[ns:n]) - b[:ns])
        return g, _interp(d.J, d.W, b[n + ns :]) - b[n : n + ns]

    def add_force(self, y, scale=None) -> None:
        """As :meth:`PenaltyContact.add_force`, nothing while every pair is open (the forces are zero)."""
        if self._closed:
            super().add_force(y, scale)

    def slave_forces(self, u) -> np.ndarray:  # noqa: ARG002
        """The slave forces F_s [N] of the last step (not a function of u: they are constraint forces)."""
        return self._on_host()[2]

    def pair_frequency(self, inv_mass: np.ndarray) -> float:  # noqa: ARG002
        """0: no contact spring, no switching limit (module docstring)."""
        return 0.0

    def apply_stiffness(self, x, y) -> None:  # noqa: ARG002
        """No contact stiffness enters the spectrum."""

    def add_abs_row_sums(self, y) -> None:  # noqa: ARG002
        """No contact stiffness enters the Gershgorin bound."""

    def state(self) -> dict[str, np.ndarray]:
        """What a restart needs: the previous forces and gaps and the dissipation so far."""
        g_prev = self._g_prev if self._g_prev is not None else np.full(self.ns, np.nan)
        return {
            "contact_F_prev": self._F_prev,
            "contact_g_prev": g_prev,
            "contact_dissipated": np.array(self.dissipated),
        }

    def restore(self, state: dict[str, np.ndarray]) -> None:
        self._F_prev = np.asarray(state["contact_F_prev"], float).copy()
        g_prev = np.asarray(state["contact_g_prev"], float)
        self._g_prev = None if np.isnan(g_prev).any() else g_prev.copy()
        self.dissipated = float(state["contact_dissipated"])
