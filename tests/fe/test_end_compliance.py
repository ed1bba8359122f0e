"""The rod-end correction χ(ν) of the Hertz approach (rods.fe.end_compliance) against its table and its
assumptions: independent of the load size for a << b, converged in the mesh."""

from __future__ import annotations

import pytest

from rods import hertz
from rods.fe.end_compliance import end_correction


@pytest.mark.parametrize("ν", [0.0, 0.3])
def test_table_reproduced_on_a_coarse_mesh(ν):
    """The committed table (n = 48) from a mesh half as fine: within 0.2% (measured: 0.10%)."""
    χ_table = hertz.ROD_END_CHI[hertz.ROD_END_NU.index(ν)]
    assert end_correction(ν, n=24) == pytest.approx(χ_table, rel=2e-3)


def test_correction_does_not_depend_on_the_patch_size():
    """χ is the far field's: a Hertz patch of 0.1 b and of 0.2 b give the same χ to 0.3%; the half-space part
    (∝ 1/a) changes by 2 x between them, so a wrong half-space term could not pass."""
    small, large = end_correction(0.3, a=0.1, n=24), end_correction(0.3, a=0.2, n=24)
    assert small == pytest.approx(large, rel=3e-3)
    assert -0.65 < small < -0.55  # the end is stiffer than the half-space by about 0.6 F/(E b)
