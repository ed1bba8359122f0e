"""The paper's analytical model (Section 2.1): 1D bar waves in both rods + quasi-static Hertz contact.

Wave form used here
-------------------
Each rod i carries d'Alembert waves (paper Eq. 1). Take x_i from the impacted tip into the rod and
let ``a_i(t)`` be the particle velocity of the wave *leaving* the tip (positive away from the
contact, relative to the rod's initial motion); the wave arriving at the tip is the same wave back
from the free far end, ``a_i(t - T_i)`` with ``T_i = 2 L_i / c_i`` (free end, paper Eqs. 2 and 4).
Hooke's law at the tip (Eqs. 3 and 5) with impedance ``Z_i = ρ_i c_i A_i`` gives

    a_i(t) = a_i(t - T_i) + P(t) / Z_i,        P = K δ^{3/2} for δ > 0, else 0   (Hertz, Eq. 8)

and the compression rate (Eq. 6) is minus the sum of the two tip velocities away from contact,

    δ'(t) = s1 - 2 a_1(t - T_1) - 2 a_2(t - T_2) - P(t) (1/Z_1 + 1/Z_2).

With ``a_i(t) = Σ_k P(t - k T_i) / Z_i`` this is one scalar delay differential equation with the
discrete delays k T_i; the paper's f_i', g_i' are a_i and the returning wave.

Contact law: the paper's (``analytical.contact = "hertz"``, :data:`PAPER_LAW`) is Hertz's half-space approach.
The default, ``"hertz-rod"``, adds the rods' end correction, a linear term: δ = (P/K)^{2/3} + c P with
c = Σ_i χ_i/(E_i b_i) (:func:`rods.hertz.rod_end_compliance`, χ_i < 0 on the paper's rods): the bars already
carry the far field that the half-space approach counts, and a deep cap is softer than a half-space. χ_i depends
on ν_i, the cap's depth b_i/R_i and weakly on the patch a/b_i, taken at the scene's impedance-bound patch a_P
(rods.scene.Scene.impedance_patch_radius, which bounds the first contact's). It also counts the caps' shape in
the bars: each is the uniform bar of its rod's mass (rods.scene.Rod.bar_length: a curved tip's cap holds less than
the cylinder of its height, so the bar ends ΔL_i short of the apex, 0.29 mm on the paper's 35 mm tip, 2.1 mm on a
hemisphere of the paper's rods), where the paper's bars are L_i from the apex, and a station x from the apex sits at
x - ΔL_i along its bar (:attr:`WaveModel.caps`). The state is then the Hertz part δ_H = (P/K)^{2/3}, and
δ_H' = δ' / (1 + (3/2) c K sqrt(δ_H)). Where the patch grows as wide as the rods the correction would
reverse the approach (:meth:`WaveModel.rod_end_term_problem`); such a run falls back to the paper's law and
says so in its warnings (status "warnings"). The paper's reproduction (Table 2) uses the paper's law. It is the paper's
system (2)-(7) with two misprints corrected: Eq. 8's R* is r1 r2/(r1 + r2) (the paper prints its
square root), and Eq. 5's last factor is dδ/dt, not δ (F' = (3/2) K sqrt(δ) dδ/dt). P is the
magnitude of the compressive force (the paper's F = -P).

Numerics
--------
Method of steps: each call of an embedded Runge-Kutta pair (DOP853, tolerance ``rtol``) spans at
most min T_i, so every delayed value lies in already computed segments and is read from their
dense output. Integration restarts at every contact release/engagement (terminal events on δ = 0)
and at the breakpoints those create, t_e + k T_i, where the delayed force has kinks. The contact
may release and engage again (several impacts). The impulse I = ∫P dt is integrated alongside δ,
so the rigid-body velocities after the last separation follow exactly: V2 = I/m2, V1 = s1 - I/m1.
"""

from __future__ import annotations

import bisect
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rods import cost, hertz, metrics
from rods.scene import SCHEMA, Rod, Scene, impedance_force

__all__ = [
    "PAPER_LAW", "AnalyticalResult", "WaveModel", "contact_compliance", "force_trace", "rod_end_term", "simulate",
]  # fmt: skip

PAPER_LAW = "analytical.contact=hertz"  # the paper's half-space Hertz (Eq. 8), as a scene override
END_TERM_LIMIT = 0.25  # smallest dδ/dδ_H at which the rod-end term is still a correction [-]
# samples of the force trace (:func:`force_trace`) over the contact's span, first touch to last release. Its duration
# against a 0.2 ns grid's (measured): paper scene (2 ns apart) +0.001 ns, on the 0.25 µs output grid +36 ns (the 1e-3
# threshold is crossed 0.15 µs after first touch); 1 m and 1.5 m rods 5 mm thick (crossed at 44 ns, 5 ns apart)
# +0.05 ns, at 20 000 samples +1.3 ns; the trace and its checks take 8 ms [-]
TRACE_SAMPLES = 100_000


class _History:
    """Dense output of y = (δ, I) over all accepted steps, evaluated without scipy's per-call overhead.

    Stores DOP853's 7th-order interpolants (Hairer, Norsett & Wanner, II.6) step by step; the scalar
    path serves the delayed terms of the right-hand side, the vectorised path the output grid.
    """

    def __init__(self) -> None:
        self.t_lo: list[float] = []
        self.h: list[float] = []
        self.y0: list[NDArray[np.float64]] = []
        self.F: list[NDArray[np.float64]] = []  # (7, 2) per step, reversed for Horner
        self.d0: list[float] = []  # δ components as plain floats for the scalar path
        self.dF: list[tuple[float, ...]] = []
        self._stacked: tuple[NDArray[np.float64], ...] | None = None

    def append(self, sol: Any) -> None:
        for ip in sol.interpolants:
            F = np.asarray(ip.F)[::-1]
            self.t_lo.append(float(ip.t_old))
            self.h.append(float(ip.h))
            self.y0.append(np.asarray(ip.y_old, float))
            self.F.append(F)
            self.d0.append(float(ip.y_old[0]))
            self.dF.append(tuple(float(f) for f in F[:, 0]))

    @property
    def t_end(self) -> float:
        return self.t_lo[-1] + self.h[-1] if self.t_lo else 0.0

    def delta(self, τ: float) -> float:
        """δ(τ) for one time inside the stored range (scalar fast path)."""
        j = bisect.bisect_right(self.t_lo, τ) - 1
        x = (τ - self.t_lo[j]) / self.h[j]
        y, xm = 0.0, 1.0 - x
        for i, f in enumerate(self.dF[j]):
            y = (y + f) * (x if i % 2 == 0 else xm)
        return y + self.d0[j]

    def _arrays(self) -> tuple[NDArray[np.float64], ...]:
        """(t_lo, h, F, y0) as arrays, stacked once per stored length (not per call: the peak search calls
        the vectorised path hundreds of times on thousands of steps)."""
        if self._stacked is None or self._stacked[0].size != len(self.t_lo):
            self._stacked = (np.asarray(self.t_lo), np.asarray(self.h), np.stack(self.F), np.stack(self.y0))
        return self._stacked

    def __call__(self, t: NDArray[np.float64], comp: int) -> NDArray[np.float64]:
        """Component ``comp`` of y at the times ``t`` (clipped to the stored range)."""
        lo, h, F_all, y0 = self._arrays()
        tt = np.clip(t, lo[0], self.t_end)
        j = np.clip(np.searchsorted(lo, tt, side="right") - 1, 0, lo.size - 1)
        x = (tt - lo[j]) / h[j]
        F = F_all[j, :, comp]  # (n, 7)
        y = np.zeros_like(tt)
        for i in range(F.shape[1]):
            y = (y + F[:, i]) * (x if i % 2 == 0 else 1.0 - x)
        return y + y0[j, comp]


@dataclass
class WaveModel:
    """Two free rods, Rod 1 moving at ``speed`` onto Rod 2 at rest, Hertz contact between the tips."""

    rod1: Rod
    rod2: Rod
    speed: float  # s1 [m/s]
    rtol: float = 1e-10
    compliance: float = 0.0  # c [m/N]: linear term of the approach (rod-end correction; 0: paper Eq. 8)
    # the bars of the rods' mass, a curved tip's cap counted (rods.scene.Rod.bar_length; the "hertz-rod" law's),
    # or the paper's bars of the rods' length L from the apex (False)
    caps: bool = False
    E_star: float = field(init=False)  # [Pa]
    R_star: float = field(init=False)  # [m]
    K: float = field(init=False)  # Hertz stiffness [N/m^1.5]

    @property
    def rods(self) -> tuple[Rod, Rod]:
        return self.rod1, self.rod2

    def __post_init__(self) -> None:
        self.E_star, self.R_star = hertz.contact_constants(self.rod1, self.rod2)
        self.K = hertz.contact_stiffness(self.E_star, self.R_star)
        self.Z = (self.rod1.impedance, self.rod2.impedance)  # [N s/m]
        self.c = (self.rod1.material.wave_speed, self.rod2.material.wave_speed)  # [m/s]
        self.offset = tuple(r.bar_offset if self.caps else 0.0 for r in self.rods)  # [m] apex to the bar's end
        self.L = tuple(r.length - d for r, d in zip(self.rods, self.offset, strict=True))  # [m] the bars
        self.T = tuple(2 * L / c for L, c in zip(self.L, self.c, strict=True))  # [s]
        self.mass = tuple(r.material.density * r.area * L for r, L in zip(self.rods, self.L, strict=True))  # [kg]
        self._history = _History()
        self.contacts: list[list[float]] = []  # [start, end] of each contact episode [s]
        # scale of δ: the quasi-static Hertz compression under the stiff-contact force s1 Z1 Z2/(Z1+Z2)
        P_stiff = impedance_force(self.speed, self.rod1, self.rod2)  # [N]
        self.delta_scale = float(hertz.approach(P_stiff, self.E_star, self.R_star))  # [m]
        self.steps = 0
        self.end_term_broke = False  # run stopped where the rod-end term reverses the approach

    # ---- history -------------------------------------------------------------------------
    def force(self, t: ArrayLike) -> NDArray[np.float64]:
        """Contact force magnitude P(t) = K <δ_H>^{3/2} [N] from the stored dense output (0 for t < 0)."""
        return self.K * np.maximum(self._hertz_approach(t), 0.0) ** 1.5

    def compression(self, t: ArrayLike) -> NDArray[np.float64]:
        """δ(t) = δ_H + c P [m]; negative values are the gap between the tips in free flight (0 for t < 0)."""
        δ_H = self._hertz_approach(t)
        return δ_H + self.compliance * self.K * np.maximum(δ_H, 0.0) ** 1.5

    def contact_energy(self, t: ArrayLike) -> NDArray[np.float64]:
        """Energy stored in the contact, ∫P dδ = (2/5) K δ_H^{5/2} + c P²/2 [J] (0 when apart)."""
        δ_H = np.maximum(self._hertz_approach(t), 0.0)
        P = self.K * δ_H**1.5
        return 0.4 * self.K * δ_H**2.5 + 0.5 * self.compliance * P**2

    def _hertz_approach(self, t: ArrayLike) -> NDArray[np.float64]:
        """The state δ_H(t) [m] (δ itself for the paper's law; 0 for t < 0)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        δ = self._history(t, 0)
        δ[t < 0] = 0.0
        return δ

    def impulse(self, t: ArrayLike) -> NDArray[np.float64]:
        """I(t) = ∫_0^t P dt [N s] (its final value beyond the integrated range)."""
        return self._history(np.atleast_1d(np.asarray(t, dtype=float)), 1)

    def _delayed_force(self, t: float) -> float:
        """Σ_i (2/Z_i) Σ_{k>=1} P(t - k T_i): the returning waves' share of δ' (scalar, for the RHS).

        Only the delays that land inside a contact episode [a, b] carry force, k from ceil((t - b)/T) to
        floor((t - a)/T): the work per call is the episodes' reflections, not all t/T of them (walking every k made
        the run's time grow as end_time², 12x the cost estimate at 0.1 s on the paper rods)."""
        total = 0.0
        for Z, T in zip(self.Z, self.T, strict=True):
            for k in self._delays(t, T):
                δ = self._history.delta(t - k * T)
                if δ > 0:
                    total += 2.0 / Z * self.K * δ**1.5
        return total

    def _delays(self, t: float, T: float) -> list[int]:
        """The k >= 1 with 0 < t - k T inside a stored contact episode [a, b] (ascending episodes, the open one
        last): per episode the k from (t - b)/T to (t - a)/T, widened by one each way and tested on τ = t - k T
        itself, so that rounding at a bound agrees with the test a <= τ <= b."""
        ks: list[int] = []
        for a, b in self.contacts:
            if a > t - T * (1 - 1e-12):
                break
            k_lo = 1 if b >= t - T else max(1, math.floor((t - b) / T))
            for k in range(k_lo, math.floor((t - a) / T) + 2):
                τ = t - k * T
                if 0.0 < τ and a <= τ <= b:
                    ks.append(k)
        return ks

    def wave(self, rod: int, t: ArrayLike) -> NDArray[np.float64]:
        """Outgoing wave a_i(t) = Σ_{k>=0} P(t - k T_i)/Z_i [m/s] of rod ``rod`` (1 or 2), vectorised.

        Per episode [a, b) and delay k only the times with t - k T inside it are evaluated (a slice of the sorted
        times), so the work is the samples in contact times their reflections, not all samples times t/T."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        Z, T = self.Z[rod - 1], self.T[rod - 1]
        order = np.argsort(t, kind="stable")
        ts = t[order]
        out = np.zeros_like(ts)
        bounds = self._episode_bounds()
        if ts.size == 0 or ts[-1] <= 0.0:
            return out
        for a, b in bounds.reshape(-1, 2):
            k_hi = math.floor((ts[-1] - a) / T)
            for k in range(0, k_hi + 1):
                # τ = t - k T in [a, b) and τ > 0: t in [a + k T, b + k T), a slice of the sorted times
                i0 = int(np.searchsorted(ts, max(a + k * T, 0.0), side="right" if a <= 0.0 else "left"))
                i1 = int(np.searchsorted(ts, b + k * T, side="left"))
                if i1 > i0:
                    out[i0:i1] += self.force(ts[i0:i1] - k * T)
        result = np.empty_like(out)
        result[order] = out
        return result / Z

    def _episode_bounds(self) -> NDArray[np.float64]:
        """a0, b0, a1, b1, ... [s] of the contact episodes, ascending; an
        episode still open at the stored end runs on beyond it, where the dense output holds its last value."""
        bounds = np.asarray(self.contacts, dtype=float).ravel()
        if bounds.size and bounds[-1] >= self._history.t_end:
            bounds[-1] = math.inf
        return bounds

    # ---- integration ---------------------------------------------------------------------
    def _rhs(self, t: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
        """d/dt (δ_H, impulse) [m/s, N]: the compression rate (paper Eq. 6 with Eq. 5) under Hertz (Eq. 8) or the
        rod-end law, and the contact force."""
        root = math.sqrt(max(y[0], 0.0))
        P = self.K * root**3
        # dδ/dδ_H, 1 for the paper's law; floored for the integrator's trial stages only (checked after)
        stiffening = max(self.stiffening(y[0]), 0.1)
        Zs = 1.0 / self.Z[0] + 1.0 / self.Z[1]
        return np.array([(self.speed - self._delayed_force(t) - P * Zs) / stiffening, P])

    def _events(self) -> tuple[Callable, Callable]:
        """(release, end_term_breaks): the terminal events of one integration leg (solve_ivp's protocol)."""

        def release(t: float, y: NDArray[np.float64]) -> float:
            return y[0]

        def end_term_breaks(t: float, y: NDArray[np.float64]) -> float:
            """Zero where the rod-end term stops being a correction (:meth:`rod_end_term_problem`): stopping there
            spares the stiff, floored integration beyond (it ran for hours on 20 µm rods)."""
            return self.stiffening(y[0]) - END_TERM_LIMIT

        release.terminal = end_term_breaks.terminal = True  # type: ignore[attr-defined]
        end_term_breaks.direction = -1.0  # type: ignore[attr-defined]
        return release, end_term_breaks

    def _add_breaks(self, breaks: list[float], te: float, end_time: float) -> None:
        """Insert the delay breaks te + k T_i (k >= 1) before ``end_time`` into the sorted ``breaks`` [s]: the
        delayed force is not smooth there, so each integration leg ends at one."""
        for T in self.T:
            tb = te + T
            while tb < end_time:
                bisect.insort(breaks, tb)
                tb += T

    def run(self, end_time: float) -> WaveModel:
        """Integrate from first touch (t = 0, δ = 0, δ' = s1) to ``end_time``."""
        from scipy.integrate import solve_ivp  # here: scipy.integrate costs every entry point ~0.6 s at start

        Tmin = min(self.T)
        # absolute tolerances of δ [m] and of the impulse I [N s] at 1e-2 rtol of their scales: δ_P and K δ_P^(3/2) Tmin
        # (the impulse's had K δ_P Tmin, 1/sqrt(δ_P) = 171x looser on the paper scene and not in N s: a referee's read)
        scale = self.delta_scale
        atol = np.array([self.rtol * 1e-2 * scale, self.rtol * 1e-2 * self.K * scale**1.5 * Tmin])
        breaks: list[float] = []
        release, end_term_breaks = self._events()
        t, y, touching = 0.0, np.zeros(2), True
        self.contacts.append([0.0, math.inf])
        self._add_breaks(breaks, 0.0, end_time)
        while t < end_time * (1 - 1e-14):
            nb = bisect.bisect_right(breaks, t * (1 + 1e-14) + 1e-18)
            t_stop = min(end_time, t + Tmin, breaks[nb] if nb < len(breaks) else math.inf)
            release.direction = -1.0 if touching else 1.0  # type: ignore[attr-defined]
            r = solve_ivp(
                self._rhs, (t, t_stop), y, method="DOP853", rtol=self.rtol, atol=atol, dense_output=True,
                events=(release, end_term_breaks),
            )  # fmt: skip
            if r.status < 0:
                raise RuntimeError(f"DDE integration failed at t = {t:.6e} s: {r.message}")
            self.steps += r.t.size - 1
            self._history.append(r.sol)
            t, y = float(r.t[-1]), r.y[:, -1].copy()
            if r.t_events[1].size:  # the caller re-solves with the paper's law (simulate)
                self.end_term_broke = True
                return self
            if r.status == 1:  # δ crossed zero: contact released or engaged again
                y[0] = 0.0
                if touching:
                    self.contacts[-1][1] = t
                else:
                    self.contacts.append([t, math.inf])
                touching = not touching
                self._add_breaks(breaks, t, end_time)
            elif touching:
                self.contacts[-1][1] = t  # provisional end, so delayed lookups see the open episode
        return self

    def stiffening(self, δ_H: float) -> float:
        """dδ/dδ_H = 1 + (3/2) c K sqrt(δ_H) [-] of the contact law (1 for the paper's, c = 0)."""
        return 1.0 + 1.5 * self.compliance * self.K * math.sqrt(max(δ_H, 0.0))

    def rod_end_term_problem(self) -> str | None:
        """Why the rod-end term is not a correction on this run (None: it is). It must stay one:
        dδ/dδ_H = 1 + (3/2) c K sqrt(δ_H) >= 0.25 at the largest approach (about a <= 0.57 b for equal steel rods
        with flat ends: a flat end's χ is constant to 0.7% for Hertz radii a from 0.025 b to 0.4 b,
        rods.fe.end_compliance; beyond, the patch covers the rod's end and neither Hertz nor the correction holds).
        A deep cap's χ is larger (less negative; positive on caps of ν < -0.5), so its term reverses later or never."""
        if self.compliance == 0.0 or not self._history.t_lo:
            return None
        δ_H = max(float(np.max(self._history(np.asarray(self._history.t_lo), 0))), 0.0)
        if not self.end_term_broke and self.stiffening(δ_H) >= END_TERM_LIMIT:
            return None
        P = self.K * δ_H**1.5
        a = float(hertz.contact_radius(P, self.E_star, self.R_star))
        where = "where the rod-end law stopped, before the run's peak" if self.end_term_broke else "at its peak"
        return (
            f"analytical.contact: the Hertz radius {a * 1e3:.3g} mm at P = {P:.4g} N ({where}) is not small "
            f"against the rods' radii ({self.rod1.diameter * 500:.3g}, "
            f"{self.rod2.diameter * 500:.3g} mm): the rod-end term would reverse the approach, so this run uses the "
            "paper's half-space law ('hertz'); neither holds there"
        )

    # ---- kinematics (paper Eq. 9, generalised to any station) ---------------------------
    def station(self, rod: int, x: float, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Axial velocity [m/s] (impact direction positive) and axial strain [-] (compression < 0)
        at distance ``x`` from the apex of rod ``rod`` (x - ΔL along its bar, rods.scene.Rod.bar_offset); Eq. 9 is
        the case rod = 2, x = L2/2."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        c, T = self.c[rod - 1], self.T[rod - 1]
        x = x - self.offset[rod - 1]  # [m] along the bar (a station is never in the cap)
        out = self.wave(rod, t - x / c)  # leaving the tip
        back = self.wave(rod, t + x / c - T)  # returning from the free end
        v_rel = out + back  # away from the contact
        ε = (back - out) / c
        v = v_rel if rod == 2 else self.speed - v_rel
        return v, ε

    def rigid_velocities(self) -> tuple[float, float]:
        """Mean (rigid-body) velocities of Rod 1 and Rod 2 after the last separation [m/s]."""
        I = float(self.impulse(self._history.t_end)[0])
        return self.speed - I / self.mass[0], I / self.mass[1]

    def peak(self) -> tuple[float, float]:
        """(time, value) of the largest contact force, refined on the dense output."""
        from scipy.optimize import minimize_scalar

        h = self._history
        # the stored step ends plus midpoints bracket the maximum; refine inside the best step
        tt = np.sort(np.concatenate([h.t_lo, np.asarray(h.t_lo) + 0.5 * np.asarray(h.h), [h.t_end]]))
        P = self.force(tt)
        i = int(np.argmax(P))
        lo, hi = tt[max(i - 1, 0)], tt[min(i + 1, tt.size - 1)]
        r = minimize_scalar(
            lambda s: -float(self.force(s)[0]), bounds=(lo, hi), method="bounded", options={"xatol": 1e-15}
        )
        return max((float(r.x), -float(r.fun)), (float(tt[i]), float(P[i])), key=lambda c: c[1])


@dataclass
class AnalyticalResult:
    """The analytical model's run (:func:`simulate`): the wave model it integrated, the histories at the output
    interval with their units, the summary (summary.json's keys) and the force on a fine grid for the checks."""

    model: WaveModel
    history: dict[str, NDArray[np.float64]]
    units: dict[str, str]
    summary: dict[str, Any]
    # time [s] and contact_force [N] on the fine grid of :func:`force_trace`: what the force checks read
    force_trace: dict[str, NDArray[np.float64]] = field(default_factory=dict)


def contact_compliance(scene: Scene) -> float:
    """The linear term c [m/N] of the contact law ``analytical.contact``: 0 for the paper's half-space Hertz,
    the two rods' end corrections for "hertz-rod" (module docstring)."""
    if scene["analytical.contact"] == "hertz":
        return 0.0
    return rod_end_term(scene)


def rod_end_term(scene: Scene) -> float:
    """c = Σ_i χ_i/(E_i b_i) [m/N]: the two rods' end corrections at the scene's impedance-bound patch (module
    docstring), the "hertz-rod" law's linear term, which the paper's law leaves out."""
    return sum(hertz.rod_end_compliance(rod, scene.impedance_patch_radius) for rod in scene.rods)


def _histories(scene: Scene, model: WaveModel) -> tuple[dict[str, NDArray[np.float64]], dict[str, str]]:
    """The histories on the scene's output grid (contact force, compression, Hertz radius and pressure at that
    force, each station's velocity and strain) and their units."""
    t = np.arange(0.0, scene.end_time * (1 + 1e-12), scene.output_interval)
    P = model.force(t)
    a = hertz.contact_radius(P, model.E_star, model.R_star)
    hist: dict[str, NDArray[np.float64]] = {
        "time": t,
        "contact_force": P,
        "compression": model.compression(t),
        "contact_radius": a,
        "peak_pressure": hertz.peak_pressure(P, a),
    }
    units = {"time": "s", "contact_force": "N", "compression": "m", "contact_radius": "m", "peak_pressure": "Pa"}
    for s in scene.stations:
        v, ε = model.station(s.rod, s.position, t)
        hist[f"{s.name}_velocity"], hist[f"{s.name}_strain"] = v, ε
        units[f"{s.name}_velocity"], units[f"{s.name}_strain"] = "m/s", "-"
    return hist, units


def force_trace(scene: Scene, model: WaveModel) -> dict[str, NDArray[np.float64]]:
    """Time [s] and contact force [N] on a uniform grid from first touch to one sample past the last release (the
    force is 0 beyond: the solver's release events, ``model.contacts``), spaced the output interval or the span over
    :data:`TRACE_SAMPLES`, the finer. The contact duration's threshold definition (rods.metrics) and the force checks
    (rods.checks.apply's ``force``) read this, not the output grid, whose spacing moved them: the paper scene's
    duration was 202.85 µs at a 0.25 µs output interval, 244.96 µs at 50 µs, with a bogus 0 µs rise."""
    span = min(model.contacts[-1][1], scene.end_time)  # [s] the last release (end_time while still in contact)
    h = min(scene.output_interval, span / TRACE_SAMPLES)  # [s] the largest spacing
    stop = min(scene.end_time, span + h)  # [s]
    t = np.linspace(0.0, stop, int(math.ceil(stop / h * (1 - 1e-12))) + 1)
    return {"time": t, "contact_force": model.force(t)}


def simulate(scene: Scene, rtol: float | None = None) -> AnalyticalResult:
    """Run the analytical model on a scene; histories on the scene's output grid plus summary.json keys (the contact
    duration from :func:`force_trace`, the peak from the dense output: neither depends on the output interval).
    ``rtol``: the solver's tolerance instead of the scene's analytical.rtol, held to that key's range (SceneError:
    0 or 1 failed deep in the solver)."""
    t0 = time.perf_counter()
    if rtol is not None:
        SCHEMA["analytical.rtol"][2]("analytical.rtol", rtol)
    rtol = scene["analytical.rtol"] if rtol is None else rtol

    def solve(c: float, caps: bool) -> WaveModel:
        return WaveModel(scene.rod1, scene.rod2, scene.speed, rtol=rtol, compliance=c, caps=caps).run(scene.end_time)

    c, law, law_warnings = contact_compliance(scene), scene["analytical.contact"], []
    model = solve(c, caps=law == "hertz-rod")
    if (problem := model.rod_end_term_problem()) is not None:
        # a patch as wide as the rods: the correction's range ends; the paper's law keeps the run (with a warning)
        c, law, law_warnings = 0.0, "hertz", [problem]
        model = solve(c, caps=False)
    wall = time.perf_counter() - t0
    hist, units = _histories(scene, model)
    trace = force_trace(scene, model)
    t_peak, P_peak = model.peak()
    a_peak = float(hertz.contact_radius(P_peak, model.E_star, model.R_star))
    p0 = float(hertz.peak_pressure(P_peak, a_peak))
    hertz.check_yield_rods(P_peak, a_peak, p0, scene.rods)
    V1, V2 = model.rigid_velocities()
    v_mid, ε_mid = hist["rod2_mid_velocity"], hist["rod2_mid_strain"]
    floor, gap = metrics.plateau_bounds(scene)  # [m/s], [s]: the FE models' own (one definition)
    gap_of_episodes = metrics.min_gap(scene)  # [s]
    summary: dict[str, Any] = {
        "model": "analytical",
        **scene.identity,
        "impact_speed": scene.speed,
        "peak_contact_force": P_peak,
        "peak_force_time": t_peak,
        "contact_radius": a_peak,
        "contact_area": math.pi * a_peak**2,
        "peak_contact_pressure": p0,
        "contact_duration": metrics.contact_duration(trace["time"], trace["contact_force"], gap_of_episodes),
        # the episodes by the contact duration's own definition (rods.metrics: gaps under min_gap do not end one), as
        # the FE recorder writes them: a sub-µs release the solver's events hold would end the first contact early
        "contact_episodes": [
            list(e) for e in metrics.contact_episodes(trace["time"], trace["contact_force"], gap_of_episodes)
        ],
        "midpoint_peak_speed": metrics.midpoint_peak_speed(hist["time"], v_mid, floor=floor, gap=gap),
        "midpoint_peak_strain": float(ε_mid.min()),
        "rigid_velocity_rod1": V1,
        "rigid_velocity_rod2": V2,
        "max_compression": float(model.compression(t_peak)[0]),
        "hertz": {"E_star": model.E_star, "R_star": model.R_star, "K": model.K},
        "contact_law": law,
        "round_trip_times": list(model.T),  # [s] each bar's 2 L/c at the law it ran (its first reflection's return)
        "contact_law_warnings": law_warnings,
        "contact_compliance": c,
        "rtol": model.rtol,
        "steps": model.steps,
        "wall_time": wall,
        "peak_memory": cost.peak_memory(),  # [B] this process's peak RSS, beside the plan's memory (rods.cost)
    }
    return AnalyticalResult(model, hist, units, summary, trace)
