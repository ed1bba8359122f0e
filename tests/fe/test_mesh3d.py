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


def test_the_section_cell_area_is_the_meshers_on_average():
    """rods.fe.mesh3d.section_cell_area, which the 3D switching estimate reads (rods.cost._pair_frequency_3d): on the
    built flat tip face of a quarter model, the core's cells within its half-side s are its squares (s/m)² to
    round-off, and the cells at each radius average it within 20% (the ring is wider on the axes than on the diagonal,
    and the core's corners reach into its radii)."""
    import dolfinx
    from mpi4py import MPI

    from rods.fe.mesh3d import TAGS_3D, build_mesh_3d, section_cell_area, section_counts

    sc = load_scene(PAPER, ["fe.kind=3d", "fe.symmetry=quarter", "fe.axial_size=2e-3", "fe.radial_size=0.5e-3",
                            "rod1.tip_radius=inf", "rod2.tip_radius=0.02", "rod1.length=0.03",
                            "rod2.length=0.03"])  # fmt: skip
    rm = build_mesh_3d(sc, MPI.COMM_SELF)
    msh = rm.mesh
    facets = rm.facet_tags.find(TAGS_3D["rod1_tip"])
    quads = msh.geometry.x[dolfinx.mesh.entities_to_geometry(msh, 2, facets)][:, :, :2]  # (facets, 4, xy) [m]
    d1, d2 = quads[:, 3] - quads[:, 0], quads[:, 2] - quads[:, 1]  # the diagonals, whatever the corners' order
    area = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])  # [m^2]
    rho = np.linalg.norm(quads.mean(axis=1), axis=1)  # [m] each cell's centre
    R, h = sc.rod1.diameter / 2, sc["fe.radial_size"]
    s = section_counts(R, h)[2]
    inside = np.abs(quads).max(axis=(1, 2)) <= s * (1 + 1e-9)  # the core's cells
    core = inside & (rho < s)  # within its half-side (its corners reach s √2, where the ring's cells are too)
    assert core.sum() > 10 and area[core] == pytest.approx(section_cell_area(R, h, rho[core]), rel=1e-6)
    bins = np.linspace(0.0, R, 9)  # [m] measured 0.91-1.16 of it on 6 to 12.7 mm rods at 0.25 and 0.5 mm
    for lo, hi in zip(bins[:-1], bins[1:], strict=True):
        ring = (rho >= lo) & (rho < hi)
        assert area[ring].mean() == pytest.approx(section_cell_area(R, h, rho[ring]).mean(), rel=0.2)
