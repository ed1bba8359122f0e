"""Comparison-stage math (issue #5): Richardson/GCI on synthetic data, Hertz at own force, subsurface Hertz."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rods import compare, hertz
from rods.convergence import estimate


@pytest.mark.parametrize("p", [1.0, 1.5, 2.0])
def test_richardson_recovers_order_and_limit(p):
    f_exact, C, h = 3.7, 0.8, 0.1
    f = [f_exact + C * (h * 2**k) ** p for k in range(3)]  # fine, mid, coarse
    r = compare.richardson(*f, ratio=2.0)
    assert r.monotone
    assert r.order == pytest.approx(p, rel=1e-12)
    assert r.extrapolated == pytest.approx(f_exact, rel=1e-12)
    # GCI_fine = 1.25 |e21/f1| / (2^p - 1) and it bounds the true error of the fine level
    assert r.gci_fine == pytest.approx(1.25 * abs((f[0] - f[1]) / f[0]) / (2**p - 1), rel=1e-12)
    assert abs(f[0] - f_exact) <= r.error_band


def test_richardson_divergent_has_no_extrapolation():
    """Monotone but the differences grow (p < 0): the order is reported, nothing is extrapolated."""
    r = compare.richardson(1.0, 1.5, 1.75)  # e21 = -0.5, e32 = -0.25: p = -1
    assert r.monotone and r.order == pytest.approx(-1.0) and not r.asymptotic
    assert math.isnan(r.extrapolated) and math.isnan(r.gci_fine)


def test_richardson_non_monotone():
    r = compare.richardson(1.0, 1.2, 1.1)
    assert not r.monotone and math.isnan(r.order) and math.isnan(r.extrapolated)


def test_hertz_at_force_consistent():
    E_star, R_star, F = 112.25e9, 0.035, 5543.0
    H = hertz.at_force(F, E_star, R_star)
    assert H["contact_radius"] == pytest.approx((3 * F * R_star / (4 * E_star)) ** (1 / 3), rel=1e-12)
    assert H["contact_area"] == pytest.approx(math.pi * H["contact_radius"] ** 2)
    assert H["peak_pressure"] == pytest.approx(1.5 * F / H["contact_area"], rel=1e-12)
    assert compare.percent(1.1, 1.0) == pytest.approx(10.0)


def test_plateau_radius_error_against_hertz_at_the_same_force():
    """Radii that follow Hertz at every force have zero error; a 2% larger patch has +2% with no spread."""
    E_star, R_star = 112e9, 0.0175  # [Pa], [m]
    F = 5e3 * np.sin(np.linspace(0.0, np.pi, 401))  # [N]
    a = hertz.contact_radius(F, E_star, R_star)
    m, s = compare.plateau_radius_error(F, a, E_star, R_star)
    assert abs(m) < 1e-12 and s < 1e-12
    m, s = compare.plateau_radius_error(F, 1.02 * a, E_star, R_star)
    assert m == pytest.approx(0.02, rel=1e-9) and s < 1e-12
    off = np.where(F < 0.9 * F.max(), 1.5, 1.0)  # errors off the plateau do not count
    assert abs(compare.plateau_radius_error(F, off * a, E_star, R_star)[0]) < 1e-12


def test_an_order_outside_the_credible_range_gets_the_fixed_order_fits_and_no_claim():
    """Three levels that agree to 0.002% (a submodel's force: 25081.6, 24976.3, 24975.7 N coarse to fine, measured on
    30 mm rods) give p = 7.5, and a titanium Rod 2's peak pressure (1.6252, 1.6521, 1.6765 GPa) p = 0.14: neither is
    an order (rods.convergence.P_CREDIBLE). The extrapolation and the GCI are then the least-squares estimate's
    fixed-order fits with Fs = 3 (its extrapolation at p = 0.14 was 1.93 GPa, 15% past the finest level, GCI 45%),
    and they are not credible. A credible order keeps Roache's 1.25."""
    for f in ((24975.7, 24976.3, 25081.6), (1.6765, 1.6521, 1.6252)):
        r = compare.richardson(*f)
        assert r.monotone and r.asymptotic and not r.credible
        est = estimate((4.0, 2.0, 1.0), f[::-1])
        assert est.branch.startswith("fixed order") and est.safety_factor == 3.0
        assert r.extrapolated == est.extrapolated and r.gci_fine == pytest.approx(est.uncertainty / f[0], rel=1e-12)
    low = compare.richardson(1.6765, 1.6521, 1.6252)
    assert low.order < 0.5 and 1.6765 < low.extrapolated < 1.70 and low.gci_fine < 0.05
    g = [3.7 + 0.8 * (0.1 * 2**k) ** 1.5 for k in range(3)]
    assert compare.richardson(*g).credible


def test_sigma_r_is_judged_at_its_stored_fields_own_force():
    """stress_field_hertz: Hertz at the force of the step whose field was kept (below the run's peak by the
    throttle of rods.fe.submodel.PeakField), the peak force where a summary lacks it; the σ_r error of a profile that
    is Hertz's own at that force is zero, and it is not at the peak force."""
    from rods import compare, hertz

    E_star, R_star, nu = 114e9, 0.0175, 0.3
    summary = {
        "peak_contact_force": 5600.0,
        "stress_field_force": 5000.0,
        "hertz_at_own_force": {"E_star": E_star, "R_star": R_star},
    }
    H = compare.stress_field_hertz(summary)
    assert H["force"] == 5000.0 and H["contact_radius"] == hertz.at_force(5000.0, E_star, R_star)["contact_radius"]
    r = np.linspace(0.0, 2 * H["contact_radius"], 41)
    profile = {
        "r": r,
        "depth": np.zeros_like(r),
        "sigma_r": hertz.surface_radial_stress(r, H["contact_radius"], H["peak_pressure"], nu),
    }
    assert compare.sigma_r_error(profile, H, nu)["surface"] < 1e-12
    at_peak = hertz.at_force(5600.0, E_star, R_star)
    assert compare.sigma_r_error(profile, at_peak, nu)["surface"] > 1e-2
    del summary["stress_field_force"]
    assert compare.stress_field_hertz(summary)["force"] == 5600.0


def test_the_largest_shear_below_a_hertz_contact_is_hertz_s_own():
    """rods.compare.max_shear_error on a profile that is Hertz's own field near the axis: no error, τ_max = 0.31 p0 at
    0.48 a for ν = 0.3 (Johnson §4.2, within the sampling); a model 3% above reads +3%; two flat tips: NaN."""
    a, p0, nu = 1.1e-3, 2.2e9, 0.3  # [m, Pa, -]
    z = np.linspace(0.01, 3.0, 600) * a
    r = np.full_like(z, 1e-3 * a)
    σ_r, _, σ_z = hertz.subsurface_stresses(r, z, a, p0, nu)
    profile = {"r": r, "depth": z, "tau": 0.5 * np.abs(σ_z - σ_r)}
    H = {"contact_radius": a, "peak_pressure": p0}
    e = compare.max_shear_error(profile, H, nu)
    assert e["max_shear_error"] == pytest.approx(0.0, abs=1e-12)
    assert e["max_shear"] == pytest.approx(0.31 * p0, rel=0.01) and e["max_shear_depth"] == pytest.approx(
        0.48 * a, rel=0.02
    )
    τ_max, z_max = hertz.max_shear(a, p0, nu)
    assert e["max_shear_hertz"] == pytest.approx(τ_max, rel=1e-4)
    assert e["max_shear_depth"] == pytest.approx(z_max, abs=1e-3 * a)  # between the samples: the parabola's vertex
    coarse = {k: v[::40] for k, v in profile.items()}  # samples 0.2 a apart: the vertex still finds 0.48 a
    assert compare.max_shear_error(coarse, H, nu)["max_shear_depth"] == pytest.approx(z_max, abs=0.02 * a)
    e = compare.max_shear_error(profile | {"tau": 1.03 * profile["tau"]}, H, nu)
    assert e["max_shear_error"] == pytest.approx(0.03)
    flat = compare.max_shear_error(profile, {"contact_radius": math.nan, "peak_pressure": math.nan}, nu)
    assert all(math.isnan(v) for v in flat.values())
    full = {k: np.repeat(v, 4) for k, v in profile.items()}  # a full 3D model's layer: four points of one depth
    assert compare.max_shear_error(full, H, nu) == pytest.approx(compare.max_shear_error(profile, H, nu), rel=1e-12)
    shallow = {k: v[z < 0.3 * a] for k, v in profile.items()}  # the maximum past the profile's end: not bracketed
    assert all(math.isnan(v) for v in compare.max_shear_error(shallow, H, nu).values())
