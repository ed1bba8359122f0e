"""The rod-end correction χ(ν, b/R, a/b) of the Hertz approach (rods.fe.end_compliance) against its table and
its assumptions: independent of the load size for a << b on a flat end, converged in the mesh, and its cap part
measured from the end of the bar of the rod's mass."""

from __future__ import annotations

import pytest

from rods import hertz
from rods.fe.end_compliance import end_correction


@pytest.mark.parametrize(("ν", "s"), [(0.0, 0.0), (0.3, 0.0), (0.3, 1.0)])
def test_table_reproduced_on_a_coarse_mesh(ν, s):
    """The committed table (refine = 2) from a mesh half as fine: within 0.3% (measured: 0.1% flat, 0.02% on a
    hemisphere at a = 0.05 b)."""
    χ_table = hertz.ROD_END_CHI[hertz.ROD_END_NU.index(ν)][hertz.ROD_END_S.index(s)][hertz.ROD_END_ALPHA.index(0.05)]
    assert end_correction(ν, s, 0.05, refine=1.0) == pytest.approx(χ_table, rel=3e-3)


def test_flat_correction_does_not_depend_on_the_patch_size():
    """χ of a flat end is the far field's: a Hertz patch of 0.1 b and of 0.2 b give the same χ to 0.3%; the
    half-space part (∝ 1/a) changes by 2 x between them, so a wrong half-space term could not pass."""
    small, large = end_correction(0.3, 0.0, 0.1, refine=1.0), end_correction(0.3, 0.0, 0.2, refine=1.0)
    assert small == pytest.approx(large, rel=3e-3)
    assert -0.65 < small < -0.55  # the end is stiffer than the half-space by about 0.6 F/(E b)


def test_a_hemisphere_is_softer_than_a_flat_end():
    """A hemispherical end (b/R = 1) is softer than a flat one by more than 0.1 F/(E b) (measured from its bar's
    end, b/3 in from the apex), and the table holds the solve's value."""
    flat, cap = end_correction(0.3, 0.0, 0.1, refine=1.0), end_correction(0.3, 1.0, 0.1, refine=1.0)
    assert cap > flat + 0.1
    χ = hertz.ROD_END_CHI[hertz.ROD_END_NU.index(0.3)][hertz.ROD_END_S.index(1.0)][hertz.ROD_END_ALPHA.index(0.1)]
    assert cap == pytest.approx(χ, rel=3e-3)
