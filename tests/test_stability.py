"""rods.stability: the step limits as closed forms, checked against the scheme they bound (central differences on a
damped oscillator, the damping at v_{n-½} as rods.fe.explicit applies it) and against their limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rods import stability


def _amplification(ω: float, ξ: float, dt: float) -> float:
    """Spectral radius of one step (u_n, v_{n-½}) -> (u_{n+1}, v_{n+½}) of u'' + 2 ξ ω u' + ω² u = 0 by central
    differences, v_{n+½} = v_{n-½} + Δt (-ω² u_n - 2 ξ ω v_{n-½}), u_{n+1} = u_n + Δt v_{n+½}."""
    d = 1.0 - 2.0 * ξ * ω * dt
    step = np.array([[1.0 - (ω * dt) ** 2, dt * d], [-dt * ω**2, d]])
    return float(np.abs(np.linalg.eigvals(step)).max())


@pytest.mark.parametrize("ξ", [0.0, 0.1, 0.5, 0.99])
def test_the_stable_step_is_the_schemes_limit(ξ):
    """Below Δt_crit = 2/ω (sqrt(1 + ξ²) - ξ) no mode grows, above it one does, at any damping ratio."""
    ω = 3.7e6  # [rad/s]
    dt = stability.stable_step(ω, ξ)
    assert _amplification(ω, ξ, 0.999 * dt) <= 1.0 + 1e-12
    assert _amplification(ω, ξ, 1.001 * dt) > 1.0 + 1e-4


def test_damping_factor_limits():
    """1 undamped; 1/(2ξ) for heavy damping; the stable step 2/ω undamped."""
    assert stability.damping_factor(0.0) == 1.0 and stability.stable_step(2.0) == 1.0
    assert stability.damping_factor(1e3) == pytest.approx(1 / 2e3, rel=1e-6)


def test_the_switching_limit_and_the_auto_step():
    """SWITCHING / ω_c, infinite without a contact spring; fe.dt = 'auto' takes the fraction of the stable step unless
    the switching limit is shorter."""
    assert stability.switching_step(0.0) == math.inf
    assert stability.switching_step(2e7) == pytest.approx(stability.SWITCHING / 2e7)
    assert stability.march_step(0.8, 1e-7, math.inf) == pytest.approx(0.8e-7)
    assert stability.march_step(0.8, 1e-7, 5e-8) == 5e-8
