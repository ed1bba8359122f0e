"""Closed-form Hertz contact of two elastic spheres (a flat tip is a sphere of infinite radius).

Used for the contact law of the analytical model (paper Eq. 8), the contact radius and peak pressure
(paper Eq. 10) and the elastic stress field that the FE results are checked against (paper Fig. 6,
ref. [26] = Fischer-Cripps, Introduction to Contact Mechanics, 2000).

Assumptions throughout (Johnson, Contact Mechanics 1985, §4.2): frictionless contact of linear
elastic, isotropic bodies, each treated as a half-space (a << R and a << rod diameter), quasi-static.
Sign convention: compressive stress is negative; force F and pressure p are positive magnitudes.
All quantities are SI: force [N], length [m], stress and modulus [Pa].
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "YIELD_FACTOR",
    "HertzContact",
    "YieldWarning",
    "ROD_END_CHI",
    "ROD_END_ALPHA",
    "ROD_END_NU",
    "ROD_END_S",
    "approach",
    "axis_stresses",
    "bar_rise",
    "check_yield",
    "check_yield_rods",
    "rods_by_strength",
    "contact_radius",
    "at_force",
    "contact_constants",
    "contact_stiffness",
    "effective_modulus",
    "effective_radius",
    "max_shear",
    "peak_pressure",
    "pressure",
    "rigid_impact_duration",
    "rod_end_compliance",
    "subsurface_stresses",
    "surface_hoop_stress",
    "surface_radial_stress",
    "tangent_stiffness",
    "yield_check",
]

YIELD_FACTOR = 1.1  # P < 1.1 S_y keeps the contact elastic (paper §2.3, Fischer-Cripps) [-]

# The rod-end correction χ(ν, b/R, a/b) [-] of the Hertz approach (rods.fe.end_compliance: a rod's end differs from
# the half-space by χ F/(E b), measured from the end of the 1D bar of the rod's mass); tabulated by
# `python benchmarks/rod_end_compliance.py` (results/rod-end-compliance.md), indexed [ν][b/R][a/b].
ROD_END_NU = (-0.9, -0.5, -0.25, 0.0, 0.15, 0.25, 0.3, 0.35, 0.4, 0.45, 0.49)  # [-]
ROD_END_S = (0.0, 0.25, 0.5, 0.75, 0.9, 1.0)  # b/R: flat to a hemisphere [-]
ROD_END_ALPHA = (0.025, 0.05, 0.1, 0.2, 0.4)  # a/b: the Hertz patch's radius over the rod's [-]
ROD_END_CHI: tuple[tuple[tuple[float, ...], ...], ...] = (  # [-] [ν][b/R][a/b]
    (  # ν = -0.90
        (-0.08263, -0.08274, -0.08293, -0.08362, -0.08637),  # b/R = 0
        (0.09653, 0.07467, 0.05211, 0.02795, -0.00143),  # b/R = 0.25
        (0.30115, 0.25628, 0.21035, 0.16043, 0.09928),  # b/R = 0.5
        (0.54505, 0.47719, 0.40611, 0.32715, 0.22753),  # b/R = 0.75
        (0.72393, 0.64185, 0.55503, 0.45643, 0.32915),  # b/R = 0.9
        (0.87152, 0.77987, 0.68215, 0.56981, 0.42106),  # b/R = 1
    ),
    (  # ν = -0.50
        (-0.45528, -0.45557, -0.45566, -0.45575, -0.45580),  # b/R = 0
        (-0.11991, -0.17502, -0.23112, -0.28801, -0.34635),  # b/R = 0.25
        (0.23228, 0.11913, 0.00614, -0.10996, -0.23161),  # b/R = 0.5
        (0.60146, 0.43168, 0.25892, 0.08011, -0.10934),  # b/R = 0.75
        (0.83412, 0.62964, 0.42054, 0.20196, -0.03019),  # b/R = 0.9
        (0.99714, 0.76961, 0.53601, 0.29117, 0.02942),  # b/R = 1
    ),
    (  # ν = -0.25
        (-0.59227, -0.59261, -0.59262, -0.59234, -0.59074),  # b/R = 0
        (-0.32043, -0.36653, -0.41342, -0.46024, -0.50597),  # b/R = 0.25
        (-0.04726, -0.14239, -0.23587, -0.33006, -0.42429),  # b/R = 0.5
        (0.22449, 0.08277, -0.05931, -0.20213, -0.34465),  # b/R = 0.75
        (0.38902, 0.21880, 0.04769, -0.12525, -0.29618),  # b/R = 0.9
        (0.50214, 0.31316, 0.12269, -0.06945, -0.25931),  # b/R = 1
    ),
    (  # ν = +0.00
        (-0.64607, -0.64641, -0.64637, -0.64584, -0.64315),  # b/R = 0
        (-0.48470, -0.51158, -0.53907, -0.56592, -0.59034),  # b/R = 0.25
        (-0.32922, -0.38564, -0.43953, -0.49258, -0.54281),  # b/R = 0.5
        (-0.18083, -0.26383, -0.34540, -0.42446, -0.49801),  # b/R = 0.75
        (-0.09157, -0.19090, -0.28858, -0.38350, -0.46952),  # b/R = 0.9
        (-0.02791, -0.13778, -0.24605, -0.35046, -0.44445),  # b/R = 1
    ),
    (  # ν = +0.15
        (-0.63746, -0.63778, -0.63772, -0.63711, -0.63409),  # b/R = 0
        (-0.54131, -0.55612, -0.57145, -0.58604, -0.59800),  # b/R = 0.25
        (-0.45048, -0.48256, -0.51199, -0.54033, -0.56561),  # b/R = 0.5
        (-0.36452, -0.41091, -0.45551, -0.49715, -0.53321),  # b/R = 0.75
        (-0.31061, -0.36591, -0.41907, -0.46886, -0.50999),  # b/R = 0.9
        (-0.26868, -0.32958, -0.38826, -0.44245, -0.48672),  # b/R = 1
    ),
    (  # ν = +0.25
        (-0.61451, -0.61482, -0.61475, -0.61412, -0.61101),  # b/R = 0
        (-0.55425, -0.56216, -0.57056, -0.57824, -0.58338),  # b/R = 0.25
        (-0.49719, -0.51534, -0.53097, -0.54557, -0.55750),  # b/R = 0.5
        (-0.44185, -0.46743, -0.49128, -0.51246, -0.52904),  # b/R = 0.75
        (-0.40421, -0.43454, -0.46283, -0.48816, -0.50643),  # b/R = 0.9
        (-0.37160, -0.40477, -0.43586, -0.46301, -0.48230),  # b/R = 1
    ),
    (  # ν = +0.30
        (-0.59786, -0.59816, -0.59808, -0.59745, -0.59435),  # b/R = 0
        (-0.55201, -0.55707, -0.56260, -0.56745, -0.56986),  # b/R = 0.25
        (-0.50791, -0.52029, -0.53025, -0.53929, -0.54597),  # b/R = 0.5
        (-0.46363, -0.48061, -0.49599, -0.50898, -0.51810),  # b/R = 0.75
        (-0.43143, -0.45147, -0.46965, -0.48525, -0.49492),  # b/R = 0.9
        (-0.40164, -0.42341, -0.44329, -0.45976, -0.46977),  # b/R = 1
    ),
    (  # ν = +0.35
        (-0.57774, -0.57803, -0.57795, -0.57733, -0.57426),  # b/R = 0
        (-0.54341, -0.54612, -0.54930, -0.55183, -0.55207),  # b/R = 0.25
        (-0.50918, -0.51680, -0.52214, -0.52669, -0.52926),  # b/R = 0.5
        (-0.47271, -0.48264, -0.49113, -0.49759, -0.50102),  # b/R = 0.75
        (-0.44398, -0.45559, -0.46556, -0.47347, -0.47672),  # b/R = 0.9
        (-0.41568, -0.42811, -0.43893, -0.44698, -0.45017),  # b/R = 1
    ),
    (  # ν = +0.40
        (-0.55415, -0.55443, -0.55436, -0.55374, -0.55074),  # b/R = 0
        (-0.52803, -0.52899, -0.53040, -0.53123, -0.52993),  # b/R = 0.25
        (-0.50026, -0.50428, -0.50620, -0.50749, -0.50724),  # b/R = 0.5
        (-0.46808, -0.47274, -0.47614, -0.47795, -0.47766),  # b/R = 0.75
        (-0.44068, -0.44600, -0.44996, -0.45245, -0.45166),  # b/R = 0.9
        (-0.41244, -0.41793, -0.42213, -0.42432, -0.42335),  # b/R = 1
    ),
    (  # ν = +0.45
        (-0.52707, -0.52735, -0.52728, -0.52670, -0.52378),  # b/R = 0
        (-0.50546, -0.50535, -0.50568, -0.50548, -0.50334),  # b/R = 0.25
        (-0.48037, -0.48216, -0.48202, -0.48143, -0.47976),  # b/R = 0.5
        (-0.44872, -0.45014, -0.45051, -0.44975, -0.44788),  # b/R = 0.75
        (-0.42039, -0.42184, -0.42227, -0.42186, -0.41962),  # b/R = 0.9
        (-0.39070, -0.39198, -0.39230, -0.39145, -0.38919),  # b/R = 1
    ),
    (  # ν = +0.49
        (-0.50293, -0.50318, -0.50314, -0.50258, -0.49973),  # b/R = 0
        (-0.48190, -0.48154, -0.48158, -0.48106, -0.47882),  # b/R = 0.25
        (-0.45603, -0.45720, -0.45649, -0.45548, -0.45376),  # b/R = 0.5
        (-0.42211, -0.42247, -0.42199, -0.42082, -0.41933),  # b/R = 0.75
        (-0.39133, -0.39149, -0.39104, -0.39030, -0.38887),  # b/R = 0.9
        (-0.35926, -0.35932, -0.35866, -0.35758, -0.35649),  # b/R = 1
    ),
)

FloatOrArray = float | NDArray[np.float64]


def _out(x: NDArray[np.float64]) -> FloatOrArray:
    """Return a Python float for 0-d results so scalar calls stay scalar."""
    return float(x) if np.ndim(x) == 0 else x


class _MaterialLike(Protocol):
    @property
    def youngs_modulus(self) -> float: ...  # [Pa]
    @property
    def poisson_ratio(self) -> float: ...  # [-]


class _RodLike(Protocol):
    @property
    def tip_radius(self) -> float: ...  # [m]; inf = flat
    @property
    def diameter(self) -> float: ...  # [m]
    @property
    def material(self) -> _MaterialLike: ...


# --------------------------------------------------------------------------------------------
# Effective properties and the force-approach law
# --------------------------------------------------------------------------------------------
def effective_modulus(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Contact modulus E* = [(1-ν1²)/E1 + (1-ν2²)/E2]^-1 [Pa] (paper Eq. 8; Johnson Eq. 4.14ff).

    Assumes linear elastic, isotropic bodies that behave as half-spaces near the contact.
    """
    if E1 <= 0 or E2 <= 0:
        raise ValueError(f"Young's moduli must be > 0 Pa, got E1={E1!r}, E2={E2!r}")
    return 1.0 / ((1 - nu1**2) / E1 + (1 - nu2**2) / E2)


def effective_radius(r1: float, r2: float) -> float:
    """Relative radius R* = r1 r2/(r1 + r2) [m]; ``math.inf`` marks a flat tip (Johnson Eq. 4.14ff).

    The paper's Eq. 8 prints R* = sqrt(r1 r2/(r1 + r2)), a misprint: K = 4/3 E* sqrt(R*) already takes
    the root, and R* must be a length. The dimensionally consistent form 1/R* = 1/r1 + 1/r2 is used;
    the paper itself states R* = r1 for the flat Rod 2 (§2.3). Two flat tips have no Hertz contact
    (the contact is conformal, not a point), so that raises ValueError. Assumes convex tips, a << R*.
    """
    if not (r1 > 0 and r2 > 0):
        raise ValueError(f"tip radii must be > 0 m (inf = flat), got r1={r1!r}, r2={r2!r}")
    if math.isinf(r1) and math.isinf(r2):
        raise ValueError("both tips are flat: two flats have no Hertz (point) contact")
    if math.isinf(r2):
        return float(r1)
    if math.isinf(r1):
        return float(r2)
    return r1 * r2 / (r1 + r2)


def contact_stiffness(E_star: float, R_star: float) -> float:
    """Hertz stiffness K = 4/3 E* sqrt(R*) [N/m^1.5], so that F = K δ^{3/2} (paper Eq. 8).

    Assumes frictionless, elastic half-spaces and a << R*.
    """
    return 4.0 / 3.0 * E_star * math.sqrt(R_star)


def _force(F: ArrayLike) -> NDArray[np.float64]:
    F = np.asarray(F, dtype=float)
    if np.any(F < 0):
        # The DDE model's force is negative (compressive); Hertz formulas take its magnitude.
        raise ValueError("contact force must be >= 0 N here; pass the magnitude |F|")
    return F


def contact_radius(F: ArrayLike, E_star: float, R_star: float) -> FloatOrArray:
    """Contact radius a = (3 F R*/(4 E*))^{1/3} [m] (paper Eq. 10; Johnson §4.2).

    Vectorised over F >= 0 [N]. Assumes frictionless, elastic half-spaces and a << R*.
    """
    return _out(np.cbrt(3.0 * _force(F) * R_star / (4.0 * E_star)))


def peak_pressure(F: ArrayLike, a: ArrayLike) -> FloatOrArray:
    """Peak (central) pressure p0 = 3F/(2π a²) [Pa] (paper Eq. 10, "P"; Johnson §4.2).

    It is 1.5 x the mean pressure F/(π a²). Returns 0 where a == 0 (no contact). Vectorised.
    Assumes the Hertz (elliptical) pressure distribution: frictionless, elastic half-spaces.
    """
    F = _force(F)
    a = np.asarray(a, dtype=float)
    F, a = np.broadcast_arrays(F, a)
    den = 2.0 * np.pi * a**2
    p0 = np.divide(3.0 * F, den, out=np.zeros_like(den), where=den > 0)
    return _out(p0)


def approach(F: ArrayLike, E_star: float, R_star: float) -> FloatOrArray:
    """Mutual approach δ = a²/R* = (F/K)^{2/3} [m] (paper Eq. 8 inverted; Johnson §4.2).

    Vectorised over F >= 0 [N]. Assumes frictionless, elastic half-spaces and a << R*.
    """
    K = contact_stiffness(E_star, R_star)
    return _out((_force(F) / K) ** (2.0 / 3.0))


RIGID_IMPACT_TIME = 2.9432  # t = this x δ_m/v for a Hertz impact of rigid masses (Johnson 1985, Eq. 11.24) [-]


def rigid_impact_duration(m: float, v: float, E_star: float, R_star: float) -> float:
    """Duration [s] of Hertz's impact of two rigid bodies of reduced mass ``m`` [kg] closing at ``v`` [m/s]:
    t = 2.94 δ_m/v with the largest approach δ_m = (15 m v²/(16 E* R*^½))^(2/5) (Johnson 1985, §11.4, Eqs.
    11.23-11.24; the contact force F = K δ^{3/2} of paper Eq. 8 on the masses, their waves neglected). The
    quasi-static limit of a rod impact: a contact slow against the rods' transits lasts it (two stubby rods drawn
    at random: 132.0 and 151.2 µs against the analytical model's 132.4 and 151.0 µs)."""
    return RIGID_IMPACT_TIME * rigid_approach(m, v, E_star, R_star) / v


def rigid_approach(m: float, v: float, E_star: float, R_star: float) -> float:
    """δ_m = (15 m v²/(16 E* R*^½))^(2/5) [m]: the largest approach of Hertz's impact of rigid bodies of reduced
    mass ``m`` [kg] at ``v`` [m/s] (Johnson 1985, §11.4: their kinetic energy stored as the contact's,
    8/15 K δ^(5/2))."""
    return (15.0 * m * v**2 / (16.0 * E_star * math.sqrt(R_star))) ** 0.4


def rigid_impact_force(m: float, v: float, E_star: float, R_star: float) -> float:
    """Largest force [N] of Hertz's impact of two rigid bodies of reduced mass ``m`` [kg] closing at ``v`` [m/s]:
    F_m = K δ_m^{3/2}, δ_m as in :func:`rigid_impact_duration` (Johnson 1985, §11.4). The rods' elasticity (their
    waves, a series compliance) lowers it, nearly: the quasi-static bound of a slow contact on stubby rods (the
    paper's rods cut to 30 mm, a hemispherical tip, 0.1 m/s: 60.5 N at the rods' masses, caps counted; the FE's
    60.7 N, its contact stiffened a little by the rods' end term), far above the impedance bound on slender ones."""
    return contact_stiffness(E_star, R_star) * rigid_approach(m, v, E_star, R_star) ** 1.5


def tangent_stiffness(F: ArrayLike, E_star: float, R_star: float) -> FloatOrArray:
    """dF/dδ = (3/2) K^{2/3} F^{1/3} = 2 E* a [N/m]: the contact's tangent stiffness at the force F >= 0 [N]
    (paper Eq. 8 differentiated). Vectorised. Assumes frictionless, elastic half-spaces and a << R*."""
    K = contact_stiffness(E_star, R_star)
    return _out(1.5 * K ** (2.0 / 3.0) * np.cbrt(_force(F)))


def _rise_time(u: float) -> float:
    """τ(u) = ∫_0^u 2w/(1 - w³) dw [-]: the time of :func:`bar_rise`'s y' = 1 - y^(3/2) to reach y = u²."""
    return (
        -2.0 / 3.0 * math.log1p(-u)
        + math.log(1.0 + u + u * u) / 3.0
        - 2.0 / math.sqrt(3.0) * (math.atan((2.0 * u + 1.0) / math.sqrt(3.0)) - math.pi / 6.0)
    )


def bar_rise(τ: float) -> tuple[float, float]:
    """A Hertz contact of two long bars before a reflection returns, at τ = t s1/δ_P [-]: (F/P, S) [-, -].

    Rod 1 at s1 onto Rod 2 at rest: until a reflection comes back, each end moves as a bar's, so the approach obeys
    δ' = s1 - F (1/Z1 + 1/Z2) with F = K δ^(3/2) (paper Eq. 8; Z = ρ c A). With the impedance bound
    P = s1 Z1 Z2/(Z1 + Z2) and δ_P = (P/K)^(2/3), y = δ/δ_P obeys y' = 1 - y^(3/2), y(0) = 0, whose time to
    reach y = u² is τ(u) = -2/3 ln(1 - u) + 1/3 ln(1 + u + u²) - 2/√3 (atan((2u + 1)/√3) - π/6) (u = √y;
    partial fractions of 2u/(1 - u³)). F/P = y^(3/2); S = ∂ln F/∂ln K at a fixed time t (τ ∝ K^(2/3)) =
    τ (1 - y^(3/2))/y: how much the force at t rests on the contact stiffness: 0 once it is impedance-bound (F = P
    whatever K), 1 while the bars have barely moved (F = K (s1 t)^(3/2)). Past τ ≈ 22.8, y is 1 to round-off: (1, 0)."""
    if τ <= 0.0:
        return 0.0, 1.0
    from scipy.optimize import brentq  # lazy: a scene validates without scipy's optimisers loaded

    top = 1.0 - 1e-15  # [-] u below 1 by about round-off: τ(top) ≈ 22.8
    if τ >= _rise_time(top):
        return 1.0, 0.0
    u = brentq(lambda u: _rise_time(u) - τ, 0.0, top, xtol=1e-15, rtol=1e-14)
    y = u * u
    return y**1.5, τ * (1.0 - y**1.5) / y


def rod_end_compliance(rod: _RodLike, a: float) -> float:
    """The rod-end correction χ(ν, b/R, a/b)/(E b) [m/N] of one body's Hertz approach at a Hertz radius ``a`` [m]:
    the approach of the contact centre relative to the end of the rod's 1D bar (rods.scene.Rod.bar_offset) differs
    from the half-space's, because the bar's strain already carries the far field (a flat end: stiffer, χ < 0) and
    a deep cap is slenderer than a half-space beside the patch (softer: χ rises towards 0 with b/R).
    The approach of the bar ends is δ = δ_Hertz(F) + Σ_i χ_i F/(E_i b_i).

    χ is interpolated (monotone cubic in ν, b/R and ln a/b) in :data:`ROD_END_CHI`: ν in [-0.9, 0.49], b/R in
    [0, 1] (the schema's range), a/b in [0.025, 0.4]; outside, the end value (a Poisson ratio below -0.9 or
    above 0.49 is no engineering metal; on a flat end χ varies by 0.7% over the whole a/b range, on a hemisphere
    by about 0.03 per halving of a, so a smaller patch's clamped value is a few hundredths off). The clamp's
    error in ν is a part of the whole term's effect, which is small there (measured on the paper scene, both
    rods at ν: the term moves the first contact by -0.027 µs at -0.95 and -1.02 µs at 0.4999, of which the
    table's slope over the last 0.01 in ν is 1.3%, and the peak force by 4e-9 and 4e-5): no warning. Above a/b =
    0.4 the 0.4 value is held: on a flat or shallow end (b/R <= 0.25) χ moved by at most 0.06 over the table's last
    doubling of a/b, on a hemisphere by up to 0.26, where a patch over 0.4 b lies far past yield for any metal; the
    patch-at-the-rim check (rods.checks.RIM_FRACTION) warns from 0.57 of the thinner rod's radius."""
    b = 0.5 * rod.diameter  # [m]
    s = 0.0 if math.isinf(rod.tip_radius) else b / rod.tip_radius
    return _end_chi(rod.material.poisson_ratio, s, a / b) / (rod.material.youngs_modulus * b)


def _end_chi(ν: float, s: float, α: float) -> float:
    """χ [-] interpolated in :data:`ROD_END_CHI` at Poisson ratio ν, b/R = s and a/b = α, each clamped to its axis."""
    from scipy.interpolate import RegularGridInterpolator

    axes = (ROD_END_NU, ROD_END_S, np.log(ROD_END_ALPHA))
    point = [min(max(x, axis[0]), axis[-1]) for x, axis in zip((ν, s, math.log(α)), axes, strict=True)]
    return float(RegularGridInterpolator(axes, np.asarray(ROD_END_CHI), method="pchip")(point)[0])


# --------------------------------------------------------------------------------------------
# One contact state
# --------------------------------------------------------------------------------------------


def contact_constants(rod1: _RodLike, rod2: _RodLike) -> tuple[float, float]:
    """(E*, R*) of two rods' tips [Pa, m] (paper Eq. 8): the one definition every model uses.

    R* is ``math.inf`` when both tips are flat (no Hertz point contact; :func:`at_force` then gives NaN)."""
    m1, m2 = rod1.material, rod2.material
    E_star = effective_modulus(m1.youngs_modulus, m1.poisson_ratio, m2.youngs_modulus, m2.poisson_ratio)
    flat = math.isinf(rod1.tip_radius) and math.isinf(rod2.tip_radius)
    return E_star, (math.inf if flat else effective_radius(rod1.tip_radius, rod2.tip_radius))


def at_force(F: float, E_star: float, R_star: float) -> dict[str, float]:
    """Hertz at a model's own force F [N] (paper Eq. 10): contact radius a [m], area π a² [m^2], peak
    pressure p0 [Pa], so that a model's contact size is judged against the contact law, not against a
    different force. NaN for two flat tips (R* = inf)."""
    if math.isinf(R_star):
        return {"force": F, "contact_radius": math.nan, "contact_area": math.nan, "peak_pressure": math.nan}
    a = float(contact_radius(F, E_star, R_star))
    return {
        "force": F,
        "contact_radius": a,
        "contact_area": math.pi * a * a,
        "peak_pressure": float(peak_pressure(F, a)),
    }


@dataclass(frozen=True)
class HertzContact:
    """Hertz contact at one force level (paper Eqs. 8 and 10; Johnson §4.2).

    ``nu`` is the Poisson ratio of the body whose stresses are evaluated (the stress field depends on
    it, the contact size does not). Assumes frictionless, elastic half-spaces and a << R*.
    """

    F: float  # contact force magnitude [N]
    E_star: float  # contact modulus [Pa]
    R_star: float  # relative radius [m]
    nu: float = 0.3  # Poisson ratio of the evaluated body [-]

    def __post_init__(self) -> None:
        if self.F < 0:
            raise ValueError(f"contact force must be >= 0 N, got {self.F!r}")

    @classmethod
    def from_rods(cls, rod1: _RodLike, rod2: _RodLike, F: float, body: int = 1) -> HertzContact:
        """Contact of two rods' tips at force F [N]; stresses are for rod ``body`` (1 or 2)."""
        if body not in (1, 2):
            raise ValueError(f"body must be 1 or 2, got {body!r}")
        E_star, R_star = contact_constants(rod1, rod2)
        nu = (rod1.material if body == 1 else rod2.material).poisson_ratio
        return cls(F=float(F), E_star=E_star, R_star=R_star, nu=nu)

    @property
    def K(self) -> float:
        """Hertz stiffness [N/m^1.5] (paper Eq. 8)."""
        return contact_stiffness(self.E_star, self.R_star)

    @property
    def a(self) -> float:
        """Contact radius [m] (paper Eq. 10)."""
        return float(contact_radius(self.F, self.E_star, self.R_star))

    @property
    def p0(self) -> float:
        """Peak pressure [Pa] (paper Eq. 10)."""
        return float(peak_pressure(self.F, self.a))

    @property
    def delta(self) -> float:
        """Mutual approach δ = a²/R* [m]."""
        return float(approach(self.F, self.E_star, self.R_star))

    @property
    def area(self) -> float:
        """Contact area π a² [m^2] (paper Table 3)."""
        return math.pi * self.a**2


# --------------------------------------------------------------------------------------------
# Pressure and stresses (Johnson §3.9, Eqs. 3.39-3.45)
# --------------------------------------------------------------------------------------------
def pressure(r: ArrayLike, a: float, p0: float) -> FloatOrArray:
    """Hertz pressure p(r) = p0 sqrt(1 - r²/a²) for r <= a, 0 outside [Pa] (Johnson 1985, §3.4 and §4.2).

    r [m] is the radial distance from the contact centre; vectorised. Assumes frictionless,
    elastic half-spaces.
    """
    s = np.abs(np.asarray(r, dtype=float)) / a
    return _out(p0 * np.sqrt(np.clip(1.0 - s**2, 0.0, None)))


def _edge_term(s: NDArray[np.float64]) -> NDArray[np.float64]:
    """(1/s²)[1 - (1 - s²)^{3/2}] for 0 <= s <= 1, with its limit 3/2 at s = 0.

    Written with expm1/log1p because the bracket cancels catastrophically for small s.
    """
    x = s**2
    safe = np.where(x > 0, x, 1.0)
    with np.errstate(divide="ignore"):  # log1p(-1) = -inf at the edge gives the exact value 1
        val = -np.expm1(1.5 * np.log1p(-np.minimum(safe, 1.0))) / safe
    return np.where(x > 0, val, 1.5)


def subsurface_stresses(
    r: ArrayLike, z: ArrayLike, a: float, p0: float, nu: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(σ_r, σ_θ, σ_z) [Pa] at radius r >= 0 and depth z >= 0 [m] below a Hertz pressure p0, radius a: the paper
    computed this closed form at the FE integration points (Fig. 6), which lie ~0.21 h below the surface. On the
    axis r = 0, where the form's a²/r² term is 0/0, its limit :func:`axis_stresses` (Eq. 3.45; a profile starting
    at r = 0 read NaN there, and its σ_r error with it).

    Johnson (Contact Mechanics, 1985) Eq. 3.44 (Huber 1904), u = ½[(r² + z² - a²) + sqrt((r² + z² - a²)² + 4 a² z²)]:

        σ_r/p0 = (1-2ν)/3 a²/r² [1 - (z/√u)³] + (z/√u)³ a² u/(u² + a² z²)
                 + (z/√u)[(1-ν) u/(a² + u) + (1+ν)(√u/a) arctan(a/√u) - 2]
        σ_θ/p0 = -(1-2ν)/3 a²/r² [1 - (z/√u)³] - (z/√u)[2ν + (1-ν) u/(a² + u) - (1+ν)(√u/a) arctan(a/√u)]
        σ_z/p0 = -(z/√u)³ a² u/(u² + a² z²)

    At z = 0 it reduces to :func:`surface_radial_stress` (z/√u -> sqrt(1 - r²/a²) inside,
    0 outside). Frictionless, elastic half-space. Vectorised.
    """
    r, z = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(z, dtype=float))
    axis = r == 0.0
    r = np.where(axis, a, r)  # any r > 0 there: its value is replaced below
    s = r * r + z * z - a * a
    u = 0.5 * (s + np.sqrt(s * s + 4.0 * a * a * z * z))
    inside = u <= 0.0  # z = 0, r <= a
    uu = np.where(inside, 1.0, u)
    q = np.where(inside, np.sqrt(np.clip(1.0 - r * r / (a * a), 0.0, None)), z / np.sqrt(uu))  # z/√u
    # a² u/(u² + a² z²) -> 1/(1 - r²/a²) inside on the surface; times q³ gives q
    frac = np.where(inside, 0.0, a * a * uu / (uu * uu + a * a * z * z))
    t3 = np.where(inside, q, q**3 * frac)
    su = np.sqrt(np.where(inside, 0.0, u))
    atan_term = np.where(su > 0, (su / a) * np.arctan(a / np.where(su > 0, su, 1.0)), 0.0)
    c = (1.0 - 2.0 * nu) / 3.0
    edge = c * a * a / (r * r) * (1.0 - q**3)
    g = np.where(inside, 0.0, u / (a * a + u))
    σ_r = edge + t3 + q * ((1.0 - nu) * g + (1.0 + nu) * atan_term - 2.0)
    σ_θ = -edge - q * (2.0 * nu + (1.0 - nu) * g - (1.0 + nu) * atan_term)
    σ_z = -t3
    if axis.any():
        az, ar, _ = axis_stresses(np.where(axis, z, 0.0), a, 1.0, nu)
        σ_r, σ_θ, σ_z = (np.where(axis, on_axis, σ) for on_axis, σ in ((ar, σ_r), (ar, σ_θ), (az, σ_z)))
    return p0 * σ_r, p0 * σ_θ, p0 * σ_z


def surface_radial_stress(r: ArrayLike, a: float, p0: float, nu: float) -> FloatOrArray:
    """Radial stress σ_r at the surface z = 0 [Pa] (Johnson Eq. 3.41a; Fischer-Cripps Eq. 6.2.1).

    Inside (r <= a): σ_r/p0 = (1-2ν)/3 (a²/r²)[1 - (1 - r²/a²)^{3/2}] - sqrt(1 - r²/a²),
    with σ_r(0) = -(1+2ν)/2 p0. Outside: σ_r/p0 = (1-2ν)/3 a²/r² (tensile, peak at the edge).
    Vectorised over r [m]. Assumes frictionless, elastic half-space.
    """
    s = np.abs(np.asarray(r, dtype=float)) / a
    c = (1.0 - 2.0 * nu) / 3.0
    si = np.minimum(s, 1.0)
    inside = c * _edge_term(si) - np.sqrt(1.0 - si**2)
    outside = c / np.where(s > 1.0, s, 1.0) ** 2
    return _out(p0 * np.where(s <= 1.0, inside, outside))


def surface_hoop_stress(r: ArrayLike, a: float, p0: float, nu: float) -> FloatOrArray:
    """Hoop stress σ_θ at the surface z = 0 [Pa] (Johnson Eq. 3.41b; Fischer-Cripps Eq. 6.2.1).

    Inside (r <= a): σ_θ/p0 = -(1-2ν)/3 (a²/r²)[1 - (1 - r²/a²)^{3/2}] - 2ν sqrt(1 - r²/a²), so
    σ_r + σ_θ = -(1+2ν) p(r); σ_θ(0) = σ_r(0). Outside: σ_θ = -σ_r (pure shear, σ_z = 0).
    Vectorised over r [m]. Assumes frictionless, elastic half-space.
    """
    s = np.abs(np.asarray(r, dtype=float)) / a
    c = (1.0 - 2.0 * nu) / 3.0
    si = np.minimum(s, 1.0)
    inside = -c * _edge_term(si) - 2.0 * nu * np.sqrt(1.0 - si**2)
    outside = -c / np.where(s > 1.0, s, 1.0) ** 2
    return _out(p0 * np.where(s <= 1.0, inside, outside))


def _axis(ζ: NDArray[np.float64], nu: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Dimensionless (σ_z/p0, σ_r/p0) on the axis at depth ζ = z/a >= 0 (Johnson Eq. 3.45)."""
    q = 1.0 / (1.0 + ζ**2)
    # arctan2(1, ζ) = arctan(1/ζ) for ζ > 0 and tends to π/2 at ζ = 0, so ζ·arctan -> 0 there.
    σ_r = -(1.0 + nu) * (1.0 - ζ * np.arctan2(1.0, ζ)) + 0.5 * q
    return -q, σ_r


def axis_stresses(z: ArrayLike, a: float, p0: float, nu: float) -> tuple[FloatOrArray, FloatOrArray, FloatOrArray]:
    """Principal stresses (σ_z, σ_r, σ_θ) on the axis r = 0 at depth z >= 0 [Pa] (Johnson Eq. 3.45).

    σ_z/p0 = -(1 + z²/a²)^{-1}; σ_r/p0 = σ_θ/p0 = -(1+ν)[1 - (z/a) arctan(a/z)] + ½(1 + z²/a²)^{-1},
    with σ_r(0) = -(1+2ν)/2 p0, matching the surface values. Vectorised over z [m].
    Assumes frictionless, elastic half-space.
    """
    ζ = np.asarray(z, dtype=float) / a
    if np.any(ζ < 0):
        raise ValueError("depth z must be >= 0 m (measured into the body)")
    sz, sr = _axis(ζ, nu)
    return _out(p0 * sz), _out(p0 * sr), _out(p0 * sr)


def max_shear(a: float, p0: float, nu: float) -> tuple[float, float]:
    """Largest principal shear τ = |σ_z - σ_r|/2 on the axis and its depth: (τ_max [Pa], z [m]).

    Found numerically on 0 <= z <= 3a (Johnson Eq. 3.45 and §4.2: τ_max ≈ 0.31 p0 at z ≈ 0.48 a for
    ν = 0.3). It is the subsurface maximum of the whole field, where first yield occurs.
    Assumes frictionless, elastic half-space.
    """

    from scipy.optimize import minimize_scalar  # here: scipy.optimize costs every entry point 0.7 s at start

    def neg_τ(ζ: float) -> float:
        sz, sr = _axis(np.asarray(ζ, dtype=float), nu)
        return -0.5 * abs(float(sz) - float(sr))

    res = minimize_scalar(neg_τ, bounds=(0.0, 3.0), method="bounded", options={"xatol": 1e-10})
    return -float(res.fun) * p0, float(res.x) * a


# --------------------------------------------------------------------------------------------
# Elastic limit
# --------------------------------------------------------------------------------------------
class YieldWarning(UserWarning):
    """The peak contact pressure breaks the elastic criterion P < 1.1 S_y (paper §2.3)."""


def yield_check(p0: float, yield_strength: float | None) -> bool:
    """True if the contact stays elastic by the paper's criterion P < 1.1 S_y (paper §2.3, ref. [26]).

    P is the peak pressure of Eq. 10. (Fischer-Cripps states 1.1 Y for the *mean* pressure at first
    yield, i.e. p0 ≈ 1.6 Y, Johnson §6.2; applying it to p0 as the paper does is conservative.)
    ``yield_strength`` None means unknown: returns True.
    """
    if yield_strength is None:
        return True
    return p0 < YIELD_FACTOR * yield_strength


def rods_by_strength(rods: Sequence[Any]) -> dict[float | None, str]:
    """Rod 1 and Rod 2 (``rods``) grouped by yield strength [Pa] (None: unknown), each group named in words ("rod
    2", "rods 1 and 2"): a yield check says one line per distinct strength (two steel rods: one, not two)."""
    groups: dict[float | None, list[int]] = {}
    for n, rod in enumerate(rods, start=1):
        groups.setdefault(rod.material.yield_strength, []).append(n)
    return {S_y: f"rod {ns[0]}" if len(ns) == 1 else f"rods {' and '.join(map(str, ns))}" for S_y, ns in groups.items()}


# what the yield checks call the pressure they judge: Hertz's p0, or a patch wider than the face's mean pressure
HERTZ_PRESSURE = "Hertz peak pressure"
FACE_PRESSURE = "mean pressure P/(πR²) on the thinner rod's face (Hertz's patch is wider than the face)"


def bearing_pressure(force: float, a: float, p0: float, rods: Sequence[Any]) -> tuple[float, str]:
    """The pressure [Pa] the yield checks judge at ``force`` [N], and its name: Hertz's ``p0``, or where Hertz's patch
    (radius ``a`` [m]) is wider than the thinner rod's face (radius R) the face's mean P/(πR²), a lower bound of the
    peak where it is the larger (a 10 km tip at 100 m/s: Hertz's 1.8 MPa over a 0.26 m patch on a 6.35 mm rod,
    the face's 2.0 GPa, which no yield check had seen: an audit, 2026-12-07)."""
    R = min(rod.diameter for rod in rods) / 2  # [m]
    face = force / (math.pi * R**2)  # [Pa]
    return (face, FACE_PRESSURE) if a > R and face > p0 else (p0, HERTZ_PRESSURE)


def pressure_lowered_by(what: str, speed: str = "impact.speed") -> str:
    """What lowers the pressure ``what`` names (:func:`bearing_pressure`): a lower ``speed``, and for Hertz's p0 a
    larger tip radius too (the face's mean pressure of a patch wider than the face, the speed alone)."""
    return f"a lower {speed}" if what == FACE_PRESSURE else f"a lower {speed} or a larger tip radius"


def check_yield_rods(force: float, a: float, p0: float, rods: Sequence[Any]) -> None:
    """:func:`check_yield` of Rod 1 and Rod 2 (``rods``) at ``force`` [N], whose Hertz patch has radius ``a`` [m] and
    peak pressure ``p0`` [Pa]: judged at :func:`bearing_pressure` (Hertz's p0, or the face's mean pressure of a patch
    wider than the face), one warning per distinct yield strength, naming the rods it holds for
    (:func:`rods_by_strength`)."""
    p, what = bearing_pressure(force, a, p0, rods)
    for S_y, which in rods_by_strength(rods).items():
        check_yield(p, S_y, where=which, what=what)


def check_yield(p0: float, S_y: float | None, where: str = "", what: str = HERTZ_PRESSURE) -> bool:
    """:func:`yield_check`, warning with :class:`YieldWarning` when the criterion is violated.

    p0 and S_y in [Pa]; ``where`` names the contact in the message, ``what`` the pressure. Returns the check's result.
    """
    if yield_check(p0, S_y):
        return True
    assert S_y is not None
    limit = YIELD_FACTOR * S_y
    at = f" at {where}" if where else ""
    warnings.warn(
        f"{what[0].upper()}{what[1:]}{at} at the model's peak force, p0 = {p0 / 1e6:.1f} MPa, exceeds 1.1 S_y = "
        f"{limit / 1e6:.1f} MPa "
        f"(p0 / 1.1 S_y = {p0 / limit:.3f}); the elastic Hertz solution no longer holds (every model here is "
        f"elastic: {pressure_lowered_by(what)} keeps the contact elastic)",
        YieldWarning,
        stacklevel=2,
    )
    return False
