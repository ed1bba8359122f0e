"""Hertz contact (rods/hertz.py): textbook identities and the paper's contact numbers."""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import quad

from rods import hertz
from rods.hertz import (
    HertzContact,
    YieldWarning,
    approach,
    axis_stresses,
    check_yield,
    contact_radius,
    contact_stiffness,
    effective_modulus,
    effective_radius,
    max_shear,
    peak_pressure,
    pressure,
    surface_hoop_stress,
    surface_radial_stress,
    yield_check,
)

# Paper Table 1: A2 steel, Rod 1 tip radius 35 mm, Rod 2 flat; Table 3: F = 5543 N.
E = 204.3e9  # [Pa]
NU = 0.3  # [-]
R1 = 0.035  # [m]
F_PAPER = 5543.0  # [N]


def _paper_contact() -> HertzContact:
    return HertzContact(F_PAPER, effective_modulus(E, NU, E, NU), effective_radius(R1, math.inf), NU)


# -- effective properties -----------------------------------------------------------------------
def test_effective_modulus_identical_materials():
    assert effective_modulus(E, NU, E, NU) == pytest.approx(E / (2 * (1 - NU**2)), rel=1e-14)


def test_effective_radius_flat_and_spheres():
    assert effective_radius(0.035, math.inf) == 0.035
    assert effective_radius(math.inf, 0.02) == 0.02
    assert effective_radius(0.02, 0.02) == pytest.approx(0.01, rel=1e-14)
    with pytest.raises(ValueError, match="flat"):
        effective_radius(math.inf, math.inf)
    with pytest.raises(ValueError):
        effective_radius(-1.0, 0.02)


# -- paper numbers ------------------------------------------------------------------------------
def test_paper_contact_radius_and_area():
    c = _paper_contact()
    assert c.a == pytest.approx(1.090e-3, rel=5e-3)  # Table 2, Spec. 1 Trial 3 (2.197 m/s)
    assert c.area * 1e6 == pytest.approx(3.73, rel=5e-3)  # Table 3, analytical [mm^2]
    assert c.p0 == pytest.approx(1.5 * F_PAPER / c.area, rel=1e-12)  # peak = 1.5 x mean


def test_from_rods_matches_direct():
    steel = SimpleNamespace(youngs_modulus=E, poisson_ratio=NU)
    soft = SimpleNamespace(youngs_modulus=E / 2, poisson_ratio=0.25)
    rod1 = SimpleNamespace(tip_radius=R1, material=steel)
    rod2 = SimpleNamespace(tip_radius=math.inf, material=soft)
    c1 = HertzContact.from_rods(rod1, rod2, F_PAPER)
    c2 = HertzContact.from_rods(rod1, rod2, F_PAPER, body=2)
    assert c1.nu == NU and c2.nu == 0.25
    assert c1.R_star == R1
    assert c1.E_star == pytest.approx(effective_modulus(E, NU, E / 2, 0.25), rel=1e-14)
    assert c1.a == c2.a
    with pytest.raises(ValueError):
        HertzContact.from_rods(rod1, rod2, F_PAPER, body=3)


def test_from_rods_with_scene_objects():
    from rods import scene

    m = scene.Material(density=7803.0, youngs_modulus=E, poisson_ratio=NU)
    rod1 = scene.Rod(length=0.25009, diameter=0.0127, tip_radius=R1, material=m)
    rod2 = scene.Rod(length=0.70099, diameter=0.0127, tip_radius=math.inf, material=m)
    assert HertzContact.from_rods(rod1, rod2, F_PAPER).a == pytest.approx(_paper_contact().a, rel=1e-14)


# -- force law consistency ----------------------------------------------------------------------
def test_approach_and_stiffness_consistency():
    c = _paper_contact()
    assert c.delta == pytest.approx(c.a**2 / c.R_star, rel=1e-12)
    K = contact_stiffness(c.E_star, c.R_star)
    assert K * c.delta**1.5 == pytest.approx(F_PAPER, rel=1e-12)
    assert K == pytest.approx(4 / 3 * c.E_star * math.sqrt(R1), rel=1e-14)


def test_pressure_integrates_to_force():
    c = _paper_contact()
    total, _ = quad(lambda r: float(pressure(r, c.a, c.p0)) * 2 * math.pi * r, 0.0, c.a, epsabs=0)
    assert total == pytest.approx(F_PAPER, rel=1e-8)
    assert pressure(0.0, c.a, c.p0) == c.p0
    assert pressure(1.5 * c.a, c.a, c.p0) == 0.0


def test_vectorised_over_force():
    c = _paper_contact()
    F = np.array([0.0, 1000.0, F_PAPER])
    a = contact_radius(F, c.E_star, c.R_star)
    assert isinstance(a, np.ndarray) and a.shape == (3,)
    assert a[2] == pytest.approx(c.a, rel=1e-14)
    p0 = peak_pressure(F, a)
    assert p0[0] == 0.0  # no contact, no 0/0
    assert p0[2] == pytest.approx(c.p0, rel=1e-14)
    d = approach(F, c.E_star, c.R_star)
    np.testing.assert_allclose(d, a**2 / c.R_star, rtol=1e-12)
    assert isinstance(contact_radius(F_PAPER, c.E_star, c.R_star), float)
    with pytest.raises(ValueError):
        contact_radius(-1.0, c.E_star, c.R_star)


# -- stress field -------------------------------------------------------------------------------
@pytest.mark.parametrize("nu", [0.0, 0.25, 0.3, 0.45])
def test_surface_radial_stress_continuous_at_edge(nu):
    a, p0 = 1.2e-3, 2.0e9
    expected = (1 - 2 * nu) * p0 / 3
    inside = surface_radial_stress(a, a, p0, nu)
    r_out = a * (1 + 1e-13)
    assert r_out / a > 1.0  # really takes the outside branch
    outside = surface_radial_stress(r_out, a, p0, nu)
    assert inside == pytest.approx(expected, rel=1e-12, abs=1e-3)
    assert outside == pytest.approx(expected, rel=1e-12, abs=1e-3)
    assert surface_hoop_stress(a, a, p0, nu) == pytest.approx(-expected, rel=1e-12, abs=1e-3)


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.45])
def test_surface_stress_centre_limit_and_sum(nu):
    a, p0 = 1.0e-3, 1.0e9
    centre = -(1 + 2 * nu) / 2 * p0
    assert surface_radial_stress(0.0, a, p0, nu) == pytest.approx(centre, rel=1e-14)
    assert surface_hoop_stress(0.0, a, p0, nu) == pytest.approx(centre, rel=1e-14)
    # Limit is approached smoothly (no cancellation blow-up near r = 0).
    assert surface_radial_stress(1e-9 * a, a, p0, nu) == pytest.approx(centre, rel=1e-9)
    r = np.linspace(0, a, 201)
    total = surface_radial_stress(r, a, p0, nu) + surface_hoop_stress(r, a, p0, nu)
    np.testing.assert_allclose(total, -(1 + 2 * nu) * pressure(r, a, p0), rtol=1e-12, atol=1e-3)
    ro = np.linspace(1.01 * a, 5 * a, 50)
    np.testing.assert_allclose(surface_hoop_stress(ro, a, p0, nu), -surface_radial_stress(ro, a, p0, nu))


def test_axis_stresses_at_surface_and_depth():
    a, p0, nu = 1.0e-3, 1.0e9, 0.3
    sz, sr, st = axis_stresses(0.0, a, p0, nu)
    assert sz == -p0
    assert sr == pytest.approx(-(1 + 2 * nu) / 2 * p0, rel=1e-14)
    assert st == sr
    # z -> 0 meets the surface solution at r = 0.
    sz, sr, _ = axis_stresses(1e-9 * a, a, p0, nu)
    assert sz == pytest.approx(-float(pressure(0.0, a, p0)), rel=1e-12)
    assert sr == pytest.approx(surface_radial_stress(0.0, a, p0, nu), rel=1e-8)
    # Deep below, all stresses decay.
    sz, sr, _ = axis_stresses(np.array([10 * a, 100 * a]), a, p0, nu)
    assert abs(sz[1]) < abs(sz[0]) < 0.01 * p0
    assert np.all(np.abs(sr) < 0.01 * p0)
    with pytest.raises(ValueError):
        axis_stresses(-1e-6, a, p0, nu)


def test_max_shear_textbook_value():
    a, p0 = 1.0e-3, 2.0e9
    τ, z = max_shear(a, p0, 0.3)
    assert τ / p0 == pytest.approx(0.31, abs=0.005)
    assert z / a == pytest.approx(0.48, abs=0.01)
    # It is the maximum along the axis.
    zz = np.linspace(0, 3 * a, 3001)
    sz, sr, _ = axis_stresses(zz, a, p0, 0.3)
    assert np.max(np.abs(sz - sr) / 2) <= τ * (1 + 1e-9)


# -- elastic limit ------------------------------------------------------------------------------
def test_yield_check_and_warning():
    S_y = 2.0e9  # [Pa]
    assert yield_check(2.1e9, S_y)
    assert not yield_check(2.3e9, S_y)
    assert yield_check(1e12, None)
    with pytest.warns(YieldWarning, match=r"1\.1 S_y") as rec:
        assert check_yield(2.3e9, S_y, where="Rod 1 tip") is False
    msg = str(rec[0].message)
    assert "2300.0 MPa" in msg and "2200.0 MPa" in msg and "1.045" in msg and "Rod 1 tip" in msg
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning would fail here
        assert check_yield(2.1e9, S_y) is True
        assert check_yield(1e12, None) is True
    assert issubclass(YieldWarning, UserWarning)
    assert hertz.YIELD_FACTOR == 1.1


def test_rod_end_compliance_scales_with_modulus_and_radius():
    """c = χ(ν, b/R, a/b)/(E b): the table's value at a node, halved by doubling E or all lengths (χ is
    dimensionless: the same b/R and a/b), and clamped outside the table's ν and a/b ranges."""
    from types import SimpleNamespace as NS

    def rod(E, ν, d, R=math.inf):
        return NS(diameter=d, tip_radius=R, material=NS(youngs_modulus=E, poisson_ratio=ν))

    i, j, k = hertz.ROD_END_NU.index(0.3), hertz.ROD_END_S.index(1.0), hertz.ROD_END_ALPHA.index(0.1)
    b = 0.00635  # [m]
    c = hertz.rod_end_compliance(rod(200e9, 0.3, 2 * b, b), 0.1 * b)
    assert c == pytest.approx(hertz.ROD_END_CHI[i][j][k] / (200e9 * b), rel=1e-12)
    assert hertz.rod_end_compliance(rod(400e9, 0.3, 2 * b, b), 0.1 * b) == pytest.approx(c / 2, rel=1e-12)
    assert hertz.rod_end_compliance(rod(200e9, 0.3, 4 * b, 2 * b), 0.2 * b) == pytest.approx(c / 2, rel=1e-12)
    flat = rod(200e9, 0.3, 2 * b)
    assert hertz.rod_end_compliance(flat, 0.1 * b) < 0
    assert hertz.rod_end_compliance(rod(200e9, 0.4999, 2 * b), 0.1 * b) == hertz.rod_end_compliance(
        rod(200e9, hertz.ROD_END_NU[-1], 2 * b), 0.1 * b
    )
    assert hertz.rod_end_compliance(flat, 1e-6 * b) == hertz.rod_end_compliance(flat, hertz.ROD_END_ALPHA[0] * b)


def test_rod_end_table_is_a_smooth_physical_surface():
    """The tabulated χ: a flat end is stiffer than the half-space (χ < 0) and does not depend on the patch's size
    (within 1% over a/b 0.025-0.4 for ν >= -0.5: the far field sees a point load); a cap is softer the deeper it
    is (χ rises with b/R at every ν and patch), and on a hemisphere χ rises as the patch shrinks for ν <= 0.35
    (the curved surface's ln(R/a), whose weight falls towards ν = 1/2: within 0.015 above)."""
    χ = np.asarray(hertz.ROD_END_CHI)
    assert χ.shape == (len(hertz.ROD_END_NU), len(hertz.ROD_END_S), len(hertz.ROD_END_ALPHA))
    flat = χ[:, 0, :]
    assert np.all(flat < 0)
    assert np.all(np.ptp(flat[1:], axis=1) < 0.01 * np.abs(flat[1:]).min(axis=1))  # ν >= -0.5
    assert np.all(np.diff(χ, axis=1) > 0)
    ν = np.asarray(hertz.ROD_END_NU)
    assert np.all(np.diff(χ[ν <= 0.35, -1, :], axis=1) < 0)
    assert np.all(np.ptp(χ[ν > 0.35, -1, :], axis=1) < 0.015)


def test_subsurface_hertz_reduces_to_surface_and_axis():
    a, p0, nu = 1.1e-3, 2.2e9, 0.3
    r = np.linspace(0.02, 2.5, 40) * a
    σ_r, σ_θ, σ_z = hertz.subsurface_stresses(r, np.zeros_like(r), a, p0, nu)
    assert np.allclose(σ_r, hertz.surface_radial_stress(r, a, p0, nu), rtol=1e-9, atol=1e-6 * p0)
    assert np.allclose(σ_θ, hertz.surface_hoop_stress(r, a, p0, nu), rtol=1e-9, atol=1e-6 * p0)
    assert np.allclose(σ_z, -hertz.pressure(r, a, p0), atol=1e-6 * p0)
    z = np.array([0.2, 0.5, 1.0, 2.0]) * a
    sz, sr, _ = hertz.axis_stresses(z, a, p0, nu)
    σ_r, _, σ_z = hertz.subsurface_stresses(1e-3 * a, z, a, p0, nu)
    assert np.allclose(σ_z, sz, rtol=1e-5)
    assert np.allclose(σ_r, sr, rtol=1e-2, atol=1e-3 * p0)  # a²/r² (1 - q³) cancels near the axis


@pytest.mark.parametrize("τ", [0.05, 0.76, 1.5, 2.25, 6.3])
def test_bar_rise_solves_the_bars_approach(τ):
    """bar_rise's closed form against y' = 1 - y^(3/2), y(0) = 0 integrated numerically (the bars' approach
    δ' = s1 - F (1/Z1 + 1/Z2), F = K δ^(3/2), scaled by δ_P and δ_P/s1), and its S = ∂ln F/∂ln K against a central
    difference in K at a fixed time (τ ∝ K^(2/3))."""
    from scipy.integrate import solve_ivp

    y = solve_ivp(lambda s, y: [1.0 - y[0] ** 1.5], (0.0, τ), [0.0], rtol=1e-12, atol=1e-14).y[0, -1]
    force, S = hertz.bar_rise(τ)
    assert force == pytest.approx(y**1.5, rel=1e-8)
    ε = 1e-5  # [-] relative change of K
    up, down = (hertz.bar_rise(τ * (1 + e) ** (2 / 3))[0] for e in (ε, -ε))
    assert S == pytest.approx((math.log(up) - math.log(down)) / (math.log1p(ε) - math.log1p(-ε)), rel=1e-5)


def test_bar_rise_limits():
    """Early the bars have barely moved: F = K (s1 t)^(3/2), F/P = τ^(3/2), S = 1; late the force is the impedance
    bound P whatever K (S = 0); monotone between."""
    force, S = hertz.bar_rise(1e-4)
    assert force == pytest.approx(1e-6, rel=1e-3) and S == pytest.approx(1.0, abs=1e-3)
    assert hertz.bar_rise(0.0) == (0.0, 1.0) and hertz.bar_rise(40.0) == (1.0, 0.0)
    rises = [hertz.bar_rise(t) for t in np.linspace(0.1, 20.0, 60)]
    assert all(a[0] < b[0] and a[1] > b[1] for a, b in zip(rises, rises[1:], strict=False))


def test_tangent_stiffness_is_the_derivative_of_the_force_approach_law():
    """dF/dδ of F = K δ^{3/2} by central differences, and Johnson's 2 E* a, at the paper's constants."""
    E_star, R_star = 112e9, 0.0175  # [Pa], [m]
    F = np.array([10.0, 5.5e3])  # [N]
    δ = hertz.approach(F, E_star, R_star)
    K, e = hertz.contact_stiffness(E_star, R_star), 1e-6
    fd = K * ((δ * (1 + e)) ** 1.5 - (δ * (1 - e)) ** 1.5) / (2 * e * δ)
    k = hertz.tangent_stiffness(F, E_star, R_star)
    np.testing.assert_allclose(k, fd, rtol=1e-8)
    np.testing.assert_allclose(k, 2 * E_star * hertz.contact_radius(F, E_star, R_star), rtol=1e-12)


@pytest.mark.parametrize(("m", "v"), [(0.18, 2.197), (1e-3, 0.05), (20.0, 10.0)])  # [kg], [m/s]
def test_rigid_impact_duration_is_the_hertz_oscillators_half_period(m, v):
    """Johnson's t = 2.94 δ_m/v against the integrated rigid-body impact m δ'' = -K δ^{3/2}, δ(0) = 0, δ'(0) = v
    (paper Eq. 8's force on two masses): the time δ returns to 0, to 1e-4."""
    from scipy.integrate import solve_ivp

    from rods.hertz import contact_stiffness, rigid_impact_duration

    E_star, R_star = 110e9, 0.035  # [Pa], [m] the paper's steel on a flat, its 35 mm tip
    K = contact_stiffness(E_star, R_star)

    def rhs(_, y):
        return [y[1], -K * max(y[0], 0.0) ** 1.5 / m]

    def released(_, y):
        return y[0]

    released.terminal, released.direction = True, -1
    t = rigid_impact_duration(m, v, E_star, R_star)
    sol = solve_ivp(rhs, (0.0, 3 * t), [0.0, v], events=released, rtol=1e-11, atol=1e-18, max_step=t / 200)
    assert sol.t_events[0][0] == pytest.approx(t, rel=1e-4)


def test_subsurface_stresses_on_the_axis_are_the_axis_limit():
    """At r = 0 the closed form's a²/r² term is 0/0 (a NaN with a divide warning, and a σ_r error of a profile
    starting on the axis read NaN): there it takes Eq. 3.45's axis values, the limit r -> 0 of Eq. 3.44."""
    import warnings

    a, p0, nu = 1e-3, 1e9, 0.3  # [m], [Pa], [-]
    z = np.array([0.0, 0.1e-3, 0.48e-3, 1e-3, 3e-3])  # [m]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        on = hertz.subsurface_stresses(np.zeros_like(z), z, a, p0, nu)
    near = hertz.subsurface_stresses(np.full_like(z, 1e-3 * a), z, a, p0, nu)
    for got, lim in zip(on, near, strict=True):  # the form near the axis, where a²/r² (1 - q³) cancels (above)
        assert np.all(np.isfinite(got))
        assert np.allclose(got, lim, rtol=1e-2, atol=1e-3 * p0)
    σ_z, σ_r, _ = hertz.axis_stresses(z, a, p0, nu)
    assert np.array_equal(on[0], on[1]) and np.allclose(on[0], σ_r) and np.allclose(on[2], σ_z)


def test_a_patch_wider_than_the_face_is_judged_by_the_faces_mean_pressure(scene_with):
    """rods.hertz.bearing_pressure: where Hertz's patch is wider than the thinner rod's face, the face's mean P/(πR²)
    is a lower bound of the peak pressure, and the yield checks judge it (a 10 km tip at 100 m/s: Hertz's 1.8 MPa
    over a 0.26 m patch, the face's 2.0 GPa, no yield warning before: an audit, 2026-12-07); inside the face, p0."""
    import math as m

    from rods import checks
    from rods.hertz import FACE_PRESSURE, HERTZ_PRESSURE, at_force, bearing_pressure, contact_constants

    sc = scene_with("rod1.tip_radius=1e4", "rod1.material.yield_strength=1.5e9", "rod2.material.yield_strength=1.5e9")
    R = sc.rod1.diameter / 2  # [m]
    P = 2.5e5  # [N]
    at = at_force(P, *contact_constants(sc.rod1, sc.rod2))
    assert at["contact_radius"] > R and at["peak_pressure"] < 1e7  # Hertz's: a wide, gentle patch
    p, what = bearing_pressure(P, at["contact_radius"], at["peak_pressure"], sc.rods)
    assert p == pytest.approx(P / (m.pi * R**2)) and what == FACE_PRESSURE
    (w,) = checks.yield_warnings(sc, P)
    assert w.startswith("Mean pressure P/(πR²) on the thinner rod's face") and "a larger tip radius" not in w
    paper = scene_with()
    at = at_force(5e3, *contact_constants(paper.rod1, paper.rod2))
    assert bearing_pressure(5e3, at["contact_radius"], at["peak_pressure"], paper.rods) == (
        at["peak_pressure"],
        HERTZ_PRESSURE,
    )


def test_effective_modulus_of_unlike_materials_and_the_lame_parameters():
    """E* = 1/((1 - ν1²)/E1 + (1 - ν2²)/E2) with ν1 ≠ ν2 (a mutation putting ν1 in both terms passed this file), and
    Material.lame against its closed form (λ = E ν/((1 + ν)(1 - 2ν)), μ = E/(2(1 + ν))): an audit, 2026-12-07."""
    from rods.hertz import effective_modulus
    from rods.scene import Material

    E1, n1, E2, n2 = 204.3e9, 0.29, 114e9, 0.34  # [Pa], [-] steel onto titanium
    assert effective_modulus(E1, n1, E2, n2) == pytest.approx(1 / ((1 - n1**2) / E1 + (1 - n2**2) / E2), rel=1e-14)
    assert effective_modulus(E1, n1, E2, n2) == effective_modulus(E2, n2, E1, n1)
    lam, mu = Material(7803.0, E1, n1, None).lame
    assert lam == pytest.approx(E1 * n1 / ((1 + n1) * (1 - 2 * n1)), rel=1e-14) and mu == pytest.approx(E1 / 2.58)
