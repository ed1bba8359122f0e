"""Grid convergence over N >= 3 levels by least squares: observed order, extrapolated value and an uncertainty
band (Eça & Hoekstra, "A procedure for the estimation of the numerical uncertainty of CFD calculations based on
grid refinement studies", J. Comput. Phys. 262 (2014) 104-130; Roache 1998; ASME V&V 20-2009, Sec. 2.4).

The discretisation error of a quantity f on a grid of size h is modelled as

    f(h) = f0 + α (h/h1)^p,        h1 the finest size, f0 the estimate of the exact value,

fitted to *all* levels in the least-squares sense (scipy), unweighted and with weights w_i ∝ 1/h_i;
the fit with the smaller standard deviation σ is kept:

    σ = sqrt( n Σ w_i (f_i - f_fit(h_i))² / (n - k) ),   Σ w_i = 1,  k the number of fitted parameters
    (w_i = 1/n is the plain sample form; σ = 0 for an exact fit, n = k).

Error estimate ε and safety factor Fs (E&H), with the data range parameter Δ_f = (f_max - f_min)/(n - 1):

* monotone data (every successive difference of one sign) and 0.5 <= p < 2.1: ε = |α|, the fitted error
  at the finest level (branch ``"observed order"``), Fs = 1.25 when σ < Δ_f, else 3;
* monotone, 0 < p < 0.5 or p >= 2.1 (the observed order is not credible): ε from the fixed-order fits
  f0 + α h (δ_1), f0 + α h² (δ_2), f0 + α1 h + α2 h² (δ_12), whichever has the smallest σ (only fits that
  leave a degree of freedom), Fs = 3 (branch ``"fixed order 1"``, ``"fixed order 2"``, ``"fixed orders 1+2"``).
  For a true order below 0.5 these fits under-estimate the error and Fs = 3 is the only margin: a low observed
  order is a warning in itself;
* monotone with p <= 0 (the differences grow under refinement) or non-monotone (a sign change): no order is
  credible and no extrapolation is claimed (``extrapolated`` NaN); the band is U = 3 Δ_M with
  Δ_M = max |f_i - f_j| the data range (the bound Eça & Hoekstra apply to anomalous data, e.g. J. Mar. Sci.
  Technol. 13 (2008), appendix; branch ``"diverging"`` or ``"non-monotone"``).

The band of the finest level:

    U = Fs ε + σ + |f1 - f_fit(h1)|                      if σ < Δ_f
    U = 3 σ/Δ_f (ε + σ + |f1 - f_fit(h1)|)               otherwise.

With three levels the fit is exact (σ = 0, f_fit(h1) = f1): for 0.5 <= p < 2.1 this is Roache's GCI,
U = 1.25 |f1 - f2|/(r^p - 1) = GCI_fine |f1| (:func:`rods.compare.richardson`), also for a non-constant ratio.
Monotonicity is reported over all levels and over the three finest separately, naming each level where the
sequence turns (a local extremum, or a repeat).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["P_CREDIBLE", "GridConvergence", "credible_order", "estimate"]

P_CREDIBLE = (0.5, 2.1)  # observed orders taken at face value, Fs = 1.25 (E&H) [-]
FS_GOOD, FS_POOR = 1.25, 3.0  # safety factors (Roache; E&H) [-]
_P_SCAN = np.concatenate([np.linspace(-4.0, -0.02, 200), np.linspace(0.02, 8.0, 400)])  # p start values [-]
_FIXED = {"fixed order 1": (1.0,), "fixed order 2": (2.0,), "fixed orders 1+2": (1.0, 2.0)}


@dataclass(frozen=True)
class GridConvergence:
    """Least-squares grid convergence of one quantity; levels ordered coarse to fine (h decreasing)."""

    levels: tuple[str, ...]
    h: tuple[float, ...]  # element size of each level (any length unit, e.g. [m])
    f: tuple[float, ...]  # the quantity on each level (its own unit)
    order: float  # fitted observed order p [-]; NaN for non-monotone data
    extrapolated: float  # f0 of the branch's fit; NaN where no extrapolation is claimed
    alpha: float  # α of f0 + α (h/h1)^p (unit of f); NaN where no fit is used
    sigma: float  # standard deviation of the branch's fit (unit of f)
    weighted: bool  # the branch's fit used weights ∝ 1/h
    branch: str  # "observed order", "fixed order 1", "fixed order 2", "fixed orders 1+2", "diverging",
    #              "non-monotone" or "constant"
    order_used: float  # the exponent behind ε: p, 1, 2, 1.5 for δ_12 (a label), NaN without a fit [-]
    safety_factor: float  # Fs [-]
    error_estimate: float  # ε, the fitted error of the finest level (unit of f)
    uncertainty: float  # U, the band of the finest level: f1 ± U (unit of f)
    data_range: float  # Δ_f = (f_max - f_min)/(n - 1) (unit of f)
    differences: tuple[float, ...]  # f_{i+1} - f_i, coarse to fine
    ratios: tuple[float, ...]  # refinement ratios h_i/h_{i+1} [-]
    monotone: bool  # every successive difference of one (non-zero) sign
    monotone_last3: bool  # the same over the three finest levels
    nonmonotone_levels: tuple[str, ...]  # the levels where the sequence turns or repeats

    @property
    def finest(self) -> float:
        return self.f[-1]

    @property
    def relative_uncertainty(self) -> float:
        """U/|f1| [-]: the GCI of the finest level when three levels are monotone with 0.5 <= p < 2.1."""
        return self.uncertainty / abs(self.finest) if self.finest != 0 else math.nan

    @property
    def extrapolation_claimed(self) -> bool:
        return math.isfinite(self.extrapolated)

    def fitted(self, h: Any) -> NDArray[np.float64]:
        """The observed-order fit f0 + α (h/h1)^p at sizes h (NaN where the branch has no such fit)."""
        x = np.asarray(h, dtype=float) / self.h[-1]
        if self.branch != "observed order":
            return np.full_like(x, math.nan)
        return self.extrapolated + self.alpha * x**self.order

    def note(self) -> str:
        """One plain-language sentence on the estimate."""
        return _note(self)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready fields (tuples as lists; NaN stays NaN for :func:`rods.io.dumps` to null)."""
        d = {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items()}
        derived = {
            "relative_uncertainty": self.relative_uncertainty,
            "extrapolation_claimed": self.extrapolation_claimed,
        }
        return d | derived | {"note": self.note()}


def credible_order(p: float) -> bool:
    """An observed order taken at face value: :data:`P_CREDIBLE` [0.5, 2.1) (E&H); NaN is not."""
    return P_CREDIBLE[0] <= p < P_CREDIBLE[1]


def _sigma(res: NDArray[np.float64], w: NDArray[np.float64], k: int) -> float:
    """σ = sqrt(n Σ w r²/(n - k)), Σ w = 1; 0 for an exact fit (n <= k)."""
    n = res.size
    return 0.0 if n <= k else float(math.sqrt(n * np.sum(w * res * res) / (n - k)))


def _linear(x: NDArray, g: NDArray, w: NDArray, exps: Sequence[float]) -> tuple[NDArray, NDArray]:
    """Weighted linear least squares of g = c0 + Σ c_j x^e_j: (coefficients, residuals)."""
    A = np.column_stack([np.ones_like(x), *(x**e for e in exps)])
    sw = np.sqrt(w)
    c = np.linalg.lstsq(A * sw[:, None], g * sw, rcond=None)[0]
    return c, g - A @ c


def _scan(x: NDArray, g: NDArray, w: NDArray) -> float:
    """The p of _P_SCAN with the smallest weighted SSR, (g0, α) solved in closed form for each p (Σ w = 1):
    α = cov_w(x^p, g)/var_w(x^p), SSR = var_w(g) - cov²/var."""
    X = x[None, :] ** _P_SCAN[:, None]
    Xc, gc = X - (X @ w)[:, None], g - w @ g
    var, cov = (Xc * Xc) @ w, Xc @ (w * gc)
    ssr = np.where(var > 0, w @ (gc * gc) - cov * cov / np.where(var > 0, var, 1.0), np.inf)
    return float(_P_SCAN[int(np.argmin(ssr))])


def _power_fit(x: NDArray, g: NDArray, w: NDArray) -> tuple[float, float, float]:
    """(g0, α, p) minimising Σ w (g - g0 - α x^p)²: a scan over p (g0, α linear for fixed p) started from the
    best, then Gauss-Newton (scipy least_squares) over all three."""
    p_start = _scan(x, g, w)
    (g0, a), r0 = _linear(x, g, w, (p_start,))
    sw = np.sqrt(w)

    def res(v: NDArray) -> NDArray:
        return sw * (g - v[0] - v[1] * x ** v[2])

    def jac(v: NDArray) -> NDArray:  # d res/d (g0, α, p), exact: a difference quotient cost 3x the fit
        xp = x ** v[2]
        return -sw[:, None] * np.column_stack((np.ones_like(x), xp, v[1] * xp * np.log(x)))

    from scipy.optimize import least_squares  # here: scipy.optimize costs every entry point ~1 s at start

    lo, hi = _P_SCAN[0] - 1.0, _P_SCAN[-1] + 1.0
    sol = least_squares(
        res,
        [g0, a, p_start],
        jac=jac,
        bounds=([-np.inf, -np.inf, lo], [np.inf, np.inf, hi]),
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
        max_nfev=2000,
    )
    best = sol.x if np.sum(sol.fun**2) <= np.sum(w * r0 * r0) else np.array([g0, a, p_start])
    return float(best[0]), float(best[1]), float(best[2])


def _weights(x: NDArray) -> dict[bool, NDArray]:
    """Unweighted (False) and 1/h-weighted (True), each summing to 1."""
    return {False: np.full_like(x, 1.0 / x.size), True: (1.0 / x) / np.sum(1.0 / x)}


def _fit_observed(x: NDArray, g: NDArray) -> dict[str, Any]:
    """The observed-order fit, unweighted or weighted, whichever has the smaller σ (ties: unweighted)."""
    best: dict[str, Any] = {}
    for weighted, w in _weights(x).items():
        g0, a, p = _power_fit(x, g, w)
        s = _sigma(g - g0 - a * x**p, w, 3)
        if not best or s < best["sigma"]:
            best = {"g0": g0, "alpha": a, "p": p, "sigma": s, "weighted": weighted, "fit1": g0 + a}
    return best


def _fit_fixed(x: NDArray, g: NDArray) -> dict[str, Any]:
    """δ_1, δ_2, δ_12, weighted or not, with the smallest σ among the fits that leave a degree
    of freedom (δ_12 needs four levels)."""
    best: dict[str, Any] = {}
    for name, exps in _FIXED.items():
        if x.size <= len(exps) + 1:
            continue
        for weighted, w in _weights(x).items():
            c, r = _linear(x, g, w, exps)
            s = _sigma(r, w, len(exps) + 1)
            if not best or s < best["sigma"]:
                p = exps[0] if len(exps) == 1 else 1.5
                best = {"name": name, "g0": c[0], "fit1": float(np.sum(c)), "sigma": s, "weighted": weighted, "p": p}
    return best


def _monotonicity(levels: tuple[str, ...], d: NDArray) -> tuple[bool, bool, tuple[str, ...]]:
    """(all monotone, three finest monotone, the levels where the sequence turns or repeats): level j turns
    when the differences on its two sides, f_j - f_{j-1} and f_{j+1} - f_j, are not of one non-zero sign."""
    turns = tuple(levels[j] for j in range(1, d.size) if d[j - 1] * d[j] <= 0)
    return bool(np.all(d * d[0] > 0)), bool(d[-1] * d[-2] > 0), turns


def estimate(h: Sequence[float], f: Sequence[float], levels: Sequence[str] | None = None) -> GridConvergence:
    """Least-squares observed order, extrapolated value and band U of f over n >= 3 levels of sizes h (any
    order; distinct, > 0), after Eça & Hoekstra (2014) as set out in the module docstring."""
    hs, fs = np.asarray(h, dtype=float), np.asarray(f, dtype=float)
    names = tuple(levels) if levels is not None else tuple(f"h={v:g}" for v in hs)
    if not (hs.size == fs.size == len(names) and hs.size >= 3):
        raise ValueError(f"need >= 3 levels with one h and one f each, got {hs.size}, {fs.size}, {len(names)}")
    if np.any(hs <= 0) or np.unique(hs).size != hs.size or not np.all(np.isfinite(fs)):
        raise ValueError("sizes h must be distinct and > 0, values f finite")
    order = np.argsort(-hs)  # coarse to fine
    hs, fs, names = hs[order], fs[order], tuple(names[i] for i in order)
    d = np.diff(fs)
    monotone, last3, turns = _monotonicity(names, d)
    common = {
        "levels": names,
        "h": tuple(hs.tolist()),
        "f": tuple(fs.tolist()),
        "differences": tuple(d.tolist()),
        "ratios": tuple((hs[:-1] / hs[1:]).tolist()),
        "monotone": monotone,
        "monotone_last3": last3,
        "nonmonotone_levels": turns,
        "data_range": float((fs.max() - fs.min()) / (fs.size - 1)),
    }
    if np.all(d == 0):
        return GridConvergence(
            order=math.nan,
            extrapolated=float(fs[-1]),
            alpha=0.0,
            sigma=0.0,
            weighted=False,
            branch="constant",
            order_used=math.nan,
            safety_factor=FS_GOOD,
            error_estimate=0.0,
            uncertainty=0.0,
            **common,
        )
    return _branch(hs, fs, common)


def _branch(hs: NDArray, fs: NDArray, common: dict[str, Any]) -> GridConvergence:
    """Pick E&H's error estimate for monotone or anomalous data and form the band U."""
    scale = float(np.max(np.abs(fs - fs[-1])))  # the fits run on g = (f - f1)/scale, x = h/h1, O(1) both
    x, g = hs / hs[-1], (fs - fs[-1]) / scale
    obs = _fit_observed(x, g)
    p = obs["p"]
    anomalous = not common["monotone"] or p <= 0
    if anomalous:
        return GridConvergence(
            order=p if common["monotone"] else math.nan,
            extrapolated=math.nan,
            alpha=math.nan,
            sigma=math.nan,
            weighted=False,
            branch="non-monotone" if not common["monotone"] else "diverging",
            order_used=math.nan,
            safety_factor=FS_POOR,
            error_estimate=math.nan,
            uncertainty=FS_POOR * float(np.ptp(fs)),
            **common,
        )
    credible = credible_order(p)
    fit = obs if credible else _fit_fixed(x, g)
    if not fit:  # three levels and a non-credible order: no fixed-order fit leaves a degree of freedom
        fit = obs
    branch = "observed order" if fit is obs else fit["name"]
    sigma, eps = fit["sigma"] * scale, abs(fit["fit1"] - fit["g0"]) * scale
    off = abs(fit["fit1"]) * scale  # |f1 - f_fit(h1)|: g1 = 0
    dr = common["data_range"]
    good = sigma < dr
    fs_ = FS_GOOD if (branch == "observed order" and credible and good) else FS_POOR
    U = fs_ * eps + sigma + off if good else FS_POOR * sigma / dr * (eps + sigma + off)
    return GridConvergence(
        order=p,
        extrapolated=float(fs[-1] + fit["g0"] * scale),
        alpha=obs["alpha"] * scale if fit is obs else math.nan,
        sigma=sigma,
        weighted=fit["weighted"],
        branch=branch,
        order_used=fit["p"],
        safety_factor=fs_,
        error_estimate=eps,
        uncertainty=float(U),
        **common,
    )


def _note(gc: GridConvergence) -> str:
    turns = ", ".join(gc.nonmonotone_levels)
    if gc.branch == "constant":
        return "the value is the same on every level"
    if gc.branch == "non-monotone":
        tail = "the three finest are monotone" if gc.monotone_last3 else "the three finest are not monotone either"
        return f"non-monotone at {turns} ({tail}): no order and no extrapolation; band 3 x data range"
    if gc.branch == "diverging":
        return f"monotone but the differences grow under refinement (p = {gc.order:.2f}): no extrapolation"
    how = (
        f"observed order p = {gc.order:.2f}"
        if gc.branch == "observed order"
        else f"observed order p = {gc.order:.2f} outside {P_CREDIBLE[0]}-{P_CREDIBLE[1]}: {gc.branch} fit used"
    )
    fit = "fit exact (3 levels)" if gc.sigma == 0 else f"fit σ = {gc.sigma:.3g}"
    return f"monotone; {how}; {fit}; Fs = {gc.safety_factor:g}"
