"""Least-squares grid convergence (Eça & Hoekstra 2014): closed-form data f = f0 + α h^p recovered, the
three-level case is Roache's Richardson/GCI, anomalous data are flagged and not extrapolated."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rods.compare import richardson
from rods.convergence import FS_POOR, estimate
from rods.io import dumps

H5 = np.array([0.25, 0.125, 0.0625, 0.03125, 0.015625])  # halving sizes [mm]


def power(h, f0=3.0, alpha=0.7, p=1.4):
    return f0 + alpha * np.asarray(h, dtype=float) ** p


@pytest.mark.parametrize("p", [0.6, 1.0, 1.4, 2.0])
@pytest.mark.parametrize("n", [4, 5])
def test_exact_power_law_recovered(p, n):
    h = H5[:n]
    gc = estimate(h, power(h, p=p))
    assert gc.branch == "observed order" and gc.monotone and gc.monotone_last3
    assert gc.order == pytest.approx(p, abs=1e-6)
    assert gc.extrapolated == pytest.approx(3.0, abs=1e-9)
    # exact fit: σ = 0, the band is Fs |f1 - f0| with Fs = 1.25
    assert gc.sigma < 1e-10 and gc.safety_factor == 1.25
    assert gc.uncertainty == pytest.approx(1.25 * 0.7 * h[-1] ** p, rel=1e-6)


@pytest.mark.parametrize("seed", range(5))
def test_noisy_power_law_within_tolerance(seed):
    """Noise of 2% of the finest level's error: p within 0.1, f0 within that error's tenth, and the band
    covers the true error of the finest level."""
    rng = np.random.default_rng(seed)
    e1 = 0.7 * H5[-1] ** 1.4
    f = power(H5) + 0.02 * e1 * rng.standard_normal(H5.size)
    gc = estimate(H5, f)
    assert gc.order == pytest.approx(1.4, abs=0.1)
    assert gc.extrapolated == pytest.approx(3.0, abs=0.1 * e1)
    assert gc.sigma > 0 and gc.uncertainty >= abs(f[-1] - 3.0)


@pytest.mark.parametrize(("p", "ratio"), [(0.58, 2.0), (1.0, 2.0), (1.6, 2.0), (2.0, 1.5), (0.9, 3.0)])
def test_three_levels_are_richardson_and_gci(p, ratio):
    h = np.array([ratio**2, ratio, 1.0]) * 0.1
    f = power(h, f0=-2.0, alpha=5.0, p=p)
    gc = estimate(h, f)
    rr = richardson(f[2], f[1], f[0], ratio)
    assert gc.order == pytest.approx(rr.order, rel=1e-8)
    assert gc.extrapolated == pytest.approx(rr.extrapolated, rel=1e-10)
    assert gc.uncertainty == pytest.approx(rr.error_band, rel=1e-8)
    assert gc.relative_uncertainty == pytest.approx(rr.gci_fine, rel=1e-8)


def test_the_fit_on_three_levels_of_a_recorded_submodel_force_is_the_three_level_formula():
    """Three submodel forces of a record (mid, fine, extra-fine of an earlier table3.json, copied here): the
    least-squares fit over exactly three levels is rods.compare.richardson's closed form, the same p and GCI band."""
    F = [5506.595833695046, 5564.020088901916, 5602.548979507645]  # mid, fine, extra-fine [N]
    gc = estimate([0.125e-3, 0.0625e-3, 0.03125e-3], F)
    rr = richardson(F[2], F[1], F[0], 2.0)
    assert gc.order == pytest.approx(rr.order, rel=1e-8) and gc.uncertainty == pytest.approx(rr.error_band, rel=1e-8)


def test_non_monotone_flagged_and_not_extrapolated():
    """The coarse-level turn of the record's contact radius (mid above coarse and fine): named, the three
    finest still monotone; no order, no extrapolation, the band is 3 x the data range."""
    a = [1.1106526, 1.1324246, 1.1233499, 1.1012662]  # [mm]
    gc = estimate([0.25, 0.125, 0.0625, 0.03125], a, ["coarse", "mid", "fine", "extra-fine"])
    assert not gc.monotone and gc.monotone_last3 and gc.nonmonotone_levels == ("mid",)
    assert gc.branch == "non-monotone" and not gc.extrapolation_claimed and math.isnan(gc.order)
    assert gc.uncertainty == pytest.approx(FS_POOR * (max(a) - min(a)))
    assert "non-monotone at mid" in gc.note()


def test_oscillation_names_every_turn():
    f = [1.0, 2.0, 1.5, 1.7, 1.65]
    gc = estimate(H5, f, list("abcde"))
    assert gc.nonmonotone_levels == ("b", "c", "d") and not gc.monotone_last3
    assert richardson(f[4], f[3], f[2]).monotone is False  # the three-level formula agrees


def test_growing_differences_are_not_extrapolated():
    """Monotone but diverging (p < 0): like rods.compare.richardson, no extrapolation."""
    h = H5[:4]
    f = power(h, p=-0.8)
    gc = estimate(h, f)
    assert gc.monotone and gc.branch == "diverging" and gc.order < 0 and not gc.extrapolation_claimed
    assert not richardson(f[3], f[2], f[1]).asymptotic


@pytest.mark.parametrize("p", [3.0, 0.3])
def test_order_out_of_range_falls_back_to_fixed_orders(p):
    """p outside 0.5-2.1: the order is still reported, but a fixed-order fit gives the error estimate, Fs = 3."""
    gc = estimate(H5, power(H5, p=p))
    assert gc.order == pytest.approx(p, abs=1e-4)
    assert gc.branch in ("fixed order 1", "fixed order 2", "fixed orders 1+2") and gc.safety_factor == FS_POOR
    assert gc.extrapolation_claimed and gc.order_used in (1.0, 2.0, 1.5)


def test_high_order_band_covers_the_error():
    """p = 3 (above 2.1): the fixed-order (p <= 2) fit with Fs = 3 covers the true error of the finest level."""
    gc = estimate(H5, power(H5, p=3.0))
    assert gc.uncertainty >= abs(power(H5[-1:], p=3.0)[0] - 3.0)


def test_non_uniform_ratios():
    h = np.array([1.0, 0.7, 0.4, 0.25, 0.1])
    gc = estimate(h, power(h, p=1.2))
    assert gc.order == pytest.approx(1.2, abs=1e-6) and gc.extrapolated == pytest.approx(3.0, abs=1e-9)
    assert gc.ratios == pytest.approx((1 / 0.7, 0.7 / 0.4, 0.4 / 0.25, 2.5))
    three = estimate(h[[0, 2, 4]], power(h[[0, 2, 4]], p=1.2))  # ratios 2.5 and 4: still exact
    assert three.extrapolated == pytest.approx(3.0, abs=1e-9)
    assert three.uncertainty == pytest.approx(1.25 * 0.7 * 0.1**1.2, rel=1e-6)


def test_order_of_input_does_not_matter_and_json():
    h = H5[:4]
    f = power(h)
    a, b = estimate(h, f, list("abcd")), estimate(h[::-1], f[::-1], list("dcba"))
    assert a == b and a.levels == ("a", "b", "c", "d")
    d = json.loads(dumps(estimate(h, [1.0, 2.0, 1.5, 1.7]).as_dict()))
    assert d["extrapolated"] is None and d["branch"] == "non-monotone" and d["note"]


@pytest.mark.parametrize(
    ("h", "f"), [([1.0, 0.5], [1.0, 2.0]), ([1.0, 1.0, 0.5], [1, 2, 3]), ([1.0, 0.5, 0.0], [1, 2, 3])]
)
def test_bad_input(h, f):
    with pytest.raises(ValueError):
        estimate(h, f)


def test_the_band_of_a_noisy_five_level_fit_holds_each_of_its_terms():
    """Eça & Hoekstra's U = Fs ε + σ + |f1 - f_fit(h1)| on five noisy levels, with σ = sqrt(n Σ w r² / (n - 3)) of
    the fit's own weights (1/h or uniform): a mutation dropping the last term (21% of U here) or the degrees of
    freedom n/(n - 3) passed the exact power laws the other tests fit (a mutation audit, 2026-12-07)."""
    h = np.array([1.0, 0.5, 0.25, 0.125, 0.0625])
    f = 2.0 + 0.3 * h**1.5 + np.array([0.001, -0.001, 0.001, -0.002, 0.004])  # the finest level off its fit
    gc = estimate(h, f)
    assert gc.branch == "observed order" and gc.sigma < gc.data_range  # the "good fit" branch
    r = f - gc.fitted(h)
    x = h / h[-1]
    w = (1 / x) / np.sum(1 / x) if gc.weighted else np.full(h.size, 1 / h.size)
    assert gc.sigma == pytest.approx(math.sqrt(h.size * np.sum(w * r * r) / (h.size - 3)), rel=1e-9)
    off = abs(f[-1] - gc.fitted(h[-1:])[0])
    assert off > 0.15 * gc.uncertainty  # the term is there to be lost
    assert gc.uncertainty == pytest.approx(gc.safety_factor * gc.error_estimate + gc.sigma + off, rel=1e-9)
