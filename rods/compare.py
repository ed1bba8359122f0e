"""Comparison-stage math: Hertz at a model's own force, Richardson/GCI, the σ_r error against Hertz.

* :func:`richardson`: observed order, extrapolated value and grid-convergence index over three
  levels of constant refinement ratio (Roache 1998; ASME V&V 20-2009, Sec. 2.4):

      p = ln((f3 - f2)/(f2 - f1)) / ln r,   f_ext = f1 + (f1 - f2)/(r^p - 1),
      GCI_fine = F_s |(f1 - f2)/f1| / (r^p - 1),  F_s = 1.25

  with f1 the finest level. Monotone convergence ((f3 - f2)/(f2 - f1) > 0) is required for p.
  :func:`richardson_levels` picks the three finest levels of a study (constant ratio required).
* :func:`sigma_r_error`: the σ_r error of a model against Hertz at its own force (paper Fig. 6), with its
  band (away from the contact edge) and normalisation defined once.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from rods import hertz
from rods.convergence import FS_GOOD, credible_order, estimate

__all__ = [
    "SIGMA_EDGE_BAND",
    "Richardson",
    "cell",
    "difference",
    "max_shear_error",
    "measured",
    "percent",
    "plateau_radius_error",
    "richardson",
    "richardson_levels",
    "sigma_r_error",
    "stress_field_hertz",
]

SAFETY_FACTOR = FS_GOOD  # GCI factor of safety for three-grid studies at a credible order (Roache) [-]


def percent(x: float | None, ref: float | None) -> float:
    """Relative difference 100 (x - ref)/ref [%]; NaN where either is None (a quantity a run could not measure:
    a contact not ended, a midpoint without plateaus, written as null)."""
    return math.nan if x is None or ref is None else 100.0 * (x - ref) / ref


def difference(x: float | None, ref: float | None) -> float:
    """x - ref; NaN where either is None (as :func:`percent`)."""
    return math.nan if x is None or ref is None else x - ref


def measured(x: Any) -> bool:
    """A value a run measured: neither None (JSON null) nor NaN/inf (a quantity it could not measure)."""
    return x is not None and math.isfinite(x)


def cell(x: Any, spec: str, unit: str = "", scale: float = 1.0, missing: str = "–") -> str:
    """A table cell: ``x * scale`` formatted by ``spec`` plus ``unit``; ``missing`` where the value is not
    :func:`measured`."""
    return format(x * scale, spec) + unit if measured(x) else missing


@dataclass(frozen=True)
class Richardson:
    """Three-level Richardson extrapolation; f1 finest. ``order`` is NaN for non-monotone data; for
    monotone data whose differences grow under refinement (p <= 0: not in the asymptotic range) the order is
    kept but there is no extrapolation or GCI (NaN). An order outside rods.convergence.P_CREDIBLE is not taken
    at face value (as in rods.convergence.estimate): the extrapolation and GCI are the fixed-order fits' with the
    safety factor 3, and it is not :attr:`credible`, so no comparison rests on its extrapolation."""

    f1: float
    f2: float
    f3: float
    ratio: float  # refinement ratio r = h2/h1 = h3/h2 [-]
    order: float  # observed order p [-]
    extrapolated: float  # f_ext
    gci_fine: float  # GCI of the finest level, a fraction of |f1| [-]
    monotone: bool

    @property
    def asymptotic(self) -> bool:
        """Monotone and converging (p > 0): the extrapolation and the GCI apply."""
        return self.monotone and self.order > 0

    @property
    def credible(self) -> bool:
        """Monotone with an order in rods.convergence.P_CREDIBLE (0.5 <= p < 2.1): the extrapolation can be
        compared with a reference (a force's p = 6.3 over three levels that agree to 0.002% is not an order)."""
        return self.monotone and credible_order(self.order)

    @property
    def error_band(self) -> float:
        """Absolute uncertainty GCI_fine |f1| (same unit as f)."""
        return self.gci_fine * abs(self.f1)


def richardson(f_fine: float, f_mid: float, f_coarse: float, ratio: float = 2.0) -> Richardson:
    """Observed order, extrapolated value and GCI_fine (Roache; ASME V&V 20) from three levels. At an order outside
    rods.convergence.P_CREDIBLE the observed order's extrapolation is no estimate (p = 0.13 put a pressure 15% past
    its finest level): the extrapolation and the band are then the fixed-order fits' of rods.convergence.estimate
    (orders 1 or 2, whichever fits closer; safety factor 3), the same three levels' estimate as convergence.md's."""
    f1, f2, f3 = float(f_fine), float(f_mid), float(f_coarse)
    e21, e32 = f1 - f2, f2 - f3
    monotone = e21 != 0 and e32 / e21 > 0
    if not monotone:
        return Richardson(f1, f2, f3, ratio, math.nan, math.nan, math.nan, False)
    p = math.log(e32 / e21) / math.log(ratio)
    if p <= 0:  # the differences grow as h shrinks: extrapolating would move away from the data
        return Richardson(f1, f2, f3, ratio, p, math.nan, math.nan, True)
    if not credible_order(p):  # not taken at face value: Eça & Hoekstra's fixed-order fits, Fs = 3 (one definition)
        est = estimate((ratio**2, ratio, 1.0), (f3, f2, f1))
        return Richardson(f1, f2, f3, ratio, p, est.extrapolated, est.uncertainty / abs(f1), True)
    denom = ratio**p - 1.0
    return Richardson(f1, f2, f3, ratio, p, f1 + e21 / denom, SAFETY_FACTOR * abs(e21 / f1) / denom, True)


PLATEAU = 0.95  # samples with F >= PLATEAU x F_max form the force plateau [-]


def plateau_radius_error(
    force: np.ndarray, radius: np.ndarray, E_star: float, R_star: float, fraction: float = PLATEAU
) -> tuple[float, float]:
    """Mean and standard deviation of a(t)/a_H(F(t)) - 1 [-] over the force plateau F >= ``fraction`` F_max:
    the contact radius against Hertz (a = (3FR*/4E*)^(1/3), Johnson 1985 §4.2) at the *same* force, sample by sample.

    At one instant the FE radius jumps as the patch edge passes a node; averaging over the plateau (hundreds
    of samples, the edge moving across a fraction of an element) gives a steadier measure of the
    discretisation error, one Richardson extrapolation can use."""
    F, a = np.asarray(force, float), np.asarray(radius, float)
    m = F >= fraction * F.max()
    e = a[m] / hertz.contact_radius(F[m], E_star, R_star) - 1.0
    return float(e.mean()), float(e.std())


def richardson_levels(sizes: Mapping[str, float]) -> tuple[tuple[str, str, str], float] | None:
    """The three finest of ``sizes`` (level -> element size [m]) ordered coarse to fine, and their refinement
    ratio r = h3/h2 = h2/h1; None when fewer than three levels were run or the ratio is not constant (to
    1e-9), which Richardson's three-level formulas assume."""
    if len(sizes) < 3:
        return None
    coarse, mid, fine = sorted(sizes, key=lambda lv: -sizes[lv])[-3:]
    ratio = sizes[mid] / sizes[fine]
    if not math.isclose(sizes[coarse] / sizes[mid], ratio, rel_tol=1e-9) or ratio <= 1.0:
        return None
    return (coarse, mid, fine), ratio


SIGMA_EDGE_BAND = 0.2  # σ_r is compared away from the contact edge: |r - a| > SIGMA_EDGE_BAND a [-]


def stress_field_hertz(summary: Mapping[str, Any]) -> dict[str, float]:
    """Hertz (:func:`rods.hertz.at_force`, E* and R* of the summary's ``hertz_at_own_force``) at the force of a
    submodel's stored stress field, ``stress_field_force``: the largest force at a step the field was kept
    (rods.fe.submodel.PeakField), up to 8e-4 below the run's peak force on twelve probe submodels (2026-12-07); the
    peak force in a summary written before that key. σ_r is compared at the field's own force (:func:`sigma_r_error`,
    Fig. 6)."""
    H = summary["hertz_at_own_force"]
    if "stress_field_force" not in summary:
        return dict(H) | {"force": summary["peak_contact_force"]}
    F = summary["stress_field_force"]  # [N]
    return hertz.at_force(F, H["E_star"], H["R_star"]) | {"force": F}


def sigma_r_error(profile: Mapping[str, Any], hertz_at_force: Mapping[str, float], nu: float) -> dict[str, float]:
    """σ_r error of a model against Hertz at its own force (paper Fig. 6): max |σ_FE - σ_H| / |σ_H(0)| over
    the sample points (``profile``: r, depth [m], sigma_r [Pa], the Gauss points nearest the surface) with
    |r - a| > SIGMA_EDGE_BAND a, where the closed form's kink at the edge is unresolvable at any mesh size.
    σ_H: at the surface (Johnson Eq. 3.41) and at the sample depth (Eq. 3.44); the normalisation
    |σ_r,H(0)| = (1 + 2ν)/2 p0 is the surface value on the axis. ``hertz_at_force``: contact_radius a [m]
    and peak_pressure p0 [Pa] (:func:`rods.hertz.at_force`). Returns fractions and the median sample depth."""
    r, z, σ = (np.asarray(profile[k], dtype=float) for k in ("r", "depth", "sigma_r"))
    a, p0 = hertz_at_force["contact_radius"], hertz_at_force["peak_pressure"]
    away = np.abs(r - a) > SIGMA_EDGE_BAND * a
    if not away.any() or not math.isfinite(a):
        return {"surface": math.nan, "depth": math.nan, "gauss_depth": math.nan}
    ref = (1.0 + 2.0 * nu) / 2.0 * p0  # |σ_r(0)| at the surface [Pa]
    σ_s = hertz.surface_radial_stress(r, a, p0, nu)
    σ_d = hertz.subsurface_stresses(r, np.maximum(z, 0.0), a, p0, nu)[0]
    return {
        "surface": float(np.max(np.abs(σ - σ_s)[away]) / ref),
        "depth": float(np.max(np.abs(σ - σ_d)[away]) / ref),
        "gauss_depth": float(np.median(z)),
    }


def max_shear_error(profile: Mapping[str, Any], hertz_at_force: Mapping[str, float], nu: float) -> dict[str, float]:
    """The largest shear below the contact against Hertz at the model's own force: ``profile`` is a submodel's axis
    profile (rods.fe.submodel.axis_gauss_stress: depth, r [m], sigma_r, sigma_z, tau [Pa] at the Gauss points nearest
    the axis), Hertz's τ = |σ_z - σ_r|/2 taken at the same points (Johnson Eq. 3.44, whose axis limit gives
    τ_max ≈ 0.31 p0 at 0.48 a for ν = 0.3, the site of first yield). Returns the model's largest τ [Pa] and its depth
    [m], Hertz's over the same points and its depth, and their relative difference (a fraction); the points of one
    depth averaged first; NaN without a Hertz contact (two flat tips), without points, or where either maximum lies
    at an end of the profile (not bracketed: not a maximum)."""
    a, p0 = hertz_at_force["contact_radius"], hertz_at_force["peak_pressure"]
    r, z, τ = (np.asarray(profile[k], dtype=float) for k in ("r", "depth", "tau"))
    keys = ("max_shear", "max_shear_depth", "max_shear_hertz", "max_shear_depth_hertz", "max_shear_error")
    if not (math.isfinite(a) and τ.size):
        return dict.fromkeys(keys, math.nan)
    σ_r, _, σ_z = hertz.subsurface_stresses(r, np.maximum(z, 0.0), a, p0, nu)
    τ_h = 0.5 * np.abs(σ_z - σ_r)
    # one value a depth: a 3D model's layer holds 1, 2 or 4 points (quarter, half, full), equal neighbours in depth
    z, layer = np.unique(np.round(z, 12), return_inverse=True)
    count = np.bincount(layer)
    τ, τ_h = np.bincount(layer, τ) / count, np.bincount(layer, τ_h) / count
    i, j = int(np.argmax(τ)), int(np.argmax(τ_h))
    if not (0 < i < len(z) - 1 and 0 < j < len(z) - 1):  # a maximum at an end of the profile is not bracketed
        return dict.fromkeys(keys, math.nan)
    return {
        "max_shear": float(τ[i]),
        "max_shear_depth": _vertex(z, τ, i),
        "max_shear_hertz": float(τ_h[j]),
        "max_shear_depth_hertz": _vertex(z, τ_h, j),
        "max_shear_error": float(τ[i] / τ_h[j] - 1.0),
    }


def _vertex(z: np.ndarray, f: np.ndarray, i: int) -> float:
    """The depth [m] of the largest ``f`` between samples: the vertex of the parabola through sample ``i`` (the
    largest) and its neighbours, ``z[i]`` at an end. The Gauss points lie ~h/2 apart in depth, so the sampled
    maximum alone moves in half-element jumps (a model's depth read 0.6 h to 1.0 h off Hertz's over four levels).
    ``z`` distinct, increasing."""
    if not 0 < i < len(z) - 1:
        return float(z[i])
    (z0, z1, z2), (f0, f1, f2) = z[i - 1 : i + 2], f[i - 1 : i + 2]
    num = (z1 - z0) ** 2 * (f1 - f2) - (z1 - z2) ** 2 * (f1 - f0)
    den = (z1 - z0) * (f1 - f2) - (z1 - z2) * (f1 - f0)
    return float(z1 - 0.5 * num / den) if den != 0 else float(z1)
