"""Uncertainty propagation: linear outputs reproduce the input uncertainty exactly."""

from __future__ import annotations

import pytest

from rods.uncertainty import propagate


def test_linear_quantities_carry_the_input_uncertainty(scene_with):
    s = scene_with()
    bands = propagate(s, lambda sc: {"speed": sc.speed, "E": sc.rod1.material.youngs_modulus, "two": 2 * sc.speed})
    assert bands["speed"].uncertainty == pytest.approx(0.02, rel=1e-9)
    assert bands["two"].uncertainty == pytest.approx(0.04, rel=1e-9)
    assert bands["E"].uncertainty == pytest.approx(0.01 * 204.3e9, rel=1e-9)
    assert bands["speed"].low == pytest.approx(s.speed - 0.02)


def test_hertz_radius_band(scene_with):
    """a ∝ (F R*/E*)^{1/3} and F ∝ s1 roughly: a ±0.02 m/s scatter moves the radius by about 0.3%."""
    from rods import hertz

    s = scene_with()

    def q(sc):
        F = sc.speed * sc.rod1.impedance / 2  # stiff-contact force
        Es = hertz.effective_modulus(sc.rod1.material.youngs_modulus, 0.3, sc.rod2.material.youngs_modulus, 0.3)
        return {"a": hertz.contact_radius(F, Es, sc.rod1.tip_radius)}

    b = propagate(s, q, {"impact.speed": ("abs", 0.02)})
    assert b["a"].uncertainty / b["a"].nominal == pytest.approx(0.02 / 2.197 / 3, rel=1e-3)
