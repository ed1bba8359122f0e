"""3D meshing (rods.fe.mesh3d): the extrusion layers along each rod are the layout's axial spacing
(rods.fe.layout.axial_spacing), on any cap, a deep cap's block of equal elements included."""

from __future__ import annotations

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rods.fe.layout import axial_spacing
from rods.fe.mesh3d import _layers
from rods.scene import load_scene

from ..conftest import PAPER


@settings(max_examples=60, deadline=None)
@given(
    tip_radius=st.floats(5e-3, 1.0),  # [m] from a hemisphere (0.5 d) up
    diameter=st.floats(5e-3, 30e-3),  # [m]
    h=st.floats(0.5e-3, 4e-3),  # [m]
    grading=st.floats(0.05, 1.0),
)
def test_extrusion_layers_are_the_layouts_spacing(tip_radius, diameter, h, grading):
    """Heights rise strictly to 1 (the rod's length), one layer per graded element, the first as thick as the
    layout's tip element. A deep cap's block of equal elements (ratio 1) divided by zero before (a 3D scene of the
    paper rods with rod1.tip_radius = 12.5 mm at 2 mm along: ZeroDivisionError; found by an options fuzz,
    2026-12-06)."""
    rod = load_scene(PAPER, [f"rod1.diameter={diameter}", f"rod2.diameter={diameter}",
                             f"rod1.tip_radius={max(tip_radius, 0.5 * diameter)}"]).rod1  # fmt: skip
    sp = axial_spacing(rod, h, grading)
    counts, z, blend = _layers(rod, h, grading)
    z = np.asarray(z)
    assert np.all(np.isfinite(z)) and np.all(np.diff(z) > 0) and z[-1] == 1.0
    assert counts == [1] * sp.n_graded + [sp.n_uniform] and len(z) == sp.n_graded + 1
    if sp.n_graded:
        assert z[0] * rod.length == pytest.approx(sp.h_tip if sp.ratio > 1.0 else sp.graded_length / sp.n_graded)
        assert z[-2] * rod.length == pytest.approx(sp.graded_length) and blend == sp.graded_length


def test_a_deep_cap_makes_a_block_of_equal_elements():
    """The case that failed: the paper rods (12.7 mm) with a 12.5 mm tip, 2 mm along, tip grading 0.75: the block
    clears the 1.73 mm cap with four equal elements (ratio 1)."""
    rod = load_scene(PAPER, ["rod1.tip_radius=0.0125"]).rod1
    sp = axial_spacing(rod, 2e-3, 0.75)
    assert sp.n_graded == 4 and sp.ratio == 1.0
    _, z, _ = _layers(rod, 2e-3, 0.75)
    assert np.allclose(np.diff(np.asarray(z[: sp.n_graded]) * rod.length), sp.graded_length / sp.n_graded)


@pytest.mark.parametrize("extra", [(), ("fe.tip_grading=1",)], ids=["graded", "ungraded"])
def test_the_tip_rim_cell_is_the_meshers_own(extra):
    """rods.fe.mesh3d.tip_rim_cell, which the plan's step reads (rods.cost._tip_step) without building a mesh, gives
    corners of the built 3D mesh to round-off: the first layer's outermost ring cell on the O-grid's diagonal, moved
    onto the cap by the tip mapping (Rod 2 curved, its apex at the origin)."""
    from mpi4py import MPI

    from rods.fe.mesh3d import build_mesh_3d, tip_rim_cell

    sc = load_scene(PAPER, ["fe.kind=3d", "fe.symmetry=quarter", "fe.axial_size=1e-3", "fe.radial_size=0.5e-3",
                            "rod1.tip_radius=inf", "rod2.tip_radius=0.02", "rod1.length=0.03", "rod2.length=0.04",
                            *extra])  # fmt: skip
    x = build_mesh_3d(sc, MPI.COMM_SELF).mesh.geometry.x
    cell, along_rim = tip_rim_cell(sc.rod2, sc["fe.radial_size"], sc["fe.axial_size"], sc.tip_grading)
    rho, depth = cell[0, :, 0], cell[0, :, 1]
    corners = np.stack([rho / np.sqrt(2), rho / np.sqrt(2), depth], axis=1)  # on the diagonal x = y
    found = np.linalg.norm(x[None, :, :] - corners[:, None, :], axis=2).min(axis=1)
    assert found.max() < 1e-9 * sc.rod2.diameter, found
    assert 0 < along_rim < sc.rod2.diameter
