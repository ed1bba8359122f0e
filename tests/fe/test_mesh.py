"""Axisymmetric meshing (rods.fe.mesh): the built mesh is what its layout (rods.fe.layout) counts, cell by cell and
node by node; the graded tip block keeps its tip element on any cap and the built mesh has it where the contact is;
a graded mesh, a graded butterfly and a coarsened mesh are built as their layouts say."""

from __future__ import annotations

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from mpi4py import MPI

from rods.fe.layout import (
    GRADED_SHARE,
    GROWTH,
    axial_spacing,
    coarsening_start,
    element_sizes,
    face_count,
    graded_butterfly,
    mesh_counts,
    scene_columns,
)
from rods.fe.mesh import build_mesh
from rods.scene import load_scene

from ..conftest import PAPER


@settings(max_examples=80, deadline=None)
@given(
    tip_radius=st.floats(
        7.0e-3, 1.0
    ),  # [m] (butterfly caps from 7.4 mm down on these rods: the block starts at the rim)
    diameter=st.floats(5e-3, 30e-3),  # [m]
    h=st.floats(0.2e-3, 3e-3),  # [m]
    grading=st.floats(0.05, 0.99),
)
def test_graded_block_keeps_its_tip_element(tip_radius, diameter, h, grading):
    """The block's elements grow by at most GROWTH from exactly g h, none longer than h, filling its length, which
    clears the cap (2 cap + h on deep caps: there the block has more elements, not longer ones)."""
    rod = load_scene(PAPER, [f"rod1.diameter={diameter}", f"rod2.diameter={diameter}",
                             f"rod1.tip_radius={max(tip_radius, 0.5 * diameter)}"]).rod1  # fmt: skip
    sp = axial_spacing(rod, h, grading)
    q, n = sp.ratio, sp.n_graded
    sizes = sp.graded_length * ((q - 1.0) / (q**n - 1.0) if q > 1.0 else 1.0 / n) * q ** np.arange(n)
    assert sizes.sum() == pytest.approx(sp.graded_length, rel=1e-9)
    assert sizes[0] <= grading * h * (1 + 1e-9) and sp.h_tip == pytest.approx(grading * h)
    if q > 1.0:
        assert sizes[0] == pytest.approx(grading * h, rel=1e-9)
    assert 1.0 <= q <= GROWTH * (1 + 1e-12) and sizes[-1] <= h * (1 + 1e-9)
    assert sp.graded_length >= 2.0 * rod.cap_height  # clear of the cap


def axis_tip_element(overrides: list[str]) -> tuple[float, float]:
    """(first element along the axis from Rod 1's apex, the intended h_tip) [m] of the built mesh."""
    sc = load_scene(PAPER, ["simulation.end_time=1e-5", *overrides])
    rm = build_mesh(sc, MPI.COMM_SELF)
    x = rm.mesh.geometry.x
    z = np.unique(-x[(np.abs(x[:, 0]) < 1e-12) & (x[:, 1] <= 0.0), 1])  # Rod 1's axis nodes (and Rod 2's apex), depth
    h = sc["fe.axial_size"] if sc["fe.axial_size"] != "auto" else sc.axial_size
    return float(z[1] - z[0]), sc.tip_grading * h


@pytest.mark.parametrize(
    "overrides",
    [
        [],  # the paper's 35 mm tip: a shallow cap (0.58 mm)
        ["rod1.tip_radius=0.0075"],  # a 3.5 mm deep cap
        [
            "rod1.diameter=0.03",
            "rod2.diameter=0.03",
            "rod1.length=0.2",
            "rod2.length=0.3",
            "fe.axial_size=1.18e-3",
            "fe.radial_size=0.235e-3",
        ],  # a 3.4 mm cap on a thick rod, refined: was 1.076 mm for 0.484 mm wanted
    ],
    ids=["paper", "deep-cap", "thick-refined"],
)
def test_built_mesh_has_the_tip_element_on_the_axis(overrides):
    first, wanted = axis_tip_element(overrides)
    assert first == pytest.approx(wanted, rel=1e-6), (first, wanted)


@pytest.mark.parametrize("tip_radius", [0.01, 0.035])  # [m]: an arc 8.3% and 0.6% longer than the radius
def test_curved_face_nodes_are_spaced_as_the_flat_face_they_meet(tip_radius):
    """A curved tip's face is divided along its arc, so its nodes near the axis (where the peak pressure is) sit
    where the flat face's do: divided by the radius instead, a 10 mm tip's were 8% farther apart and the one-pass
    node-to-surface contact read the submodel's fine-level peak pressure 4.6% low (1.6% with the arc's count)."""
    sc = load_scene(PAPER, ["simulation.end_time=1e-5", f"rod1.tip_radius={tip_radius}", "fe.radial_size=0.25e-3"])
    x = build_mesh(sc, MPI.COMM_SELF).mesh.geometry.x
    r, z = x[:, 0], x[:, 1]
    on_cap = (r > 1e-12) & (np.abs(z + tip_radius - np.sqrt(np.maximum(tip_radius**2 - r**2, 0.0))) < 1e-12)
    on_face = (r > 1e-12) & (np.abs(z) < 1e-12)
    slave, master = np.sort(r[on_cap & (z < 0)]), np.sort(r[on_face])
    assert slave.size and master.size
    assert slave[0] == pytest.approx(master[0], rel=1e-2)  # the first ring off the axis (measured 0.6%, was 8.3%)
    assert np.diff(slave).max() <= 0.25e-3 * (1 + 1e-9)  # no face element longer than the size asked for


def test_a_graded_mesh_is_built_as_its_columns_say():
    """The built mesh's tip face: nodes hr apart out to the core's radius, then the columns' growing sizes to the
    rim (Rod 2's flat face, the paper rods at 0.1 m/s); the summary's sizes are the core's and the rim's."""
    sc = load_scene(PAPER, ["simulation.end_time=1e-5", "impact.speed=0.1"])
    rm = build_mesh(sc, MPI.COMM_SELF)
    assert rm.graded == (True, True)
    x = rm.mesh.geometry.x
    face = np.sort(x[(np.abs(x[:, 1]) < 1e-12) & (x[:, 0] > -1.0), 0])  # Rod 2's face (Rod 1's apex at r = 0 too)
    expected = np.concatenate([[0.0], np.cumsum(element_sizes(scene_columns(sc)[1]))])
    np.testing.assert_allclose(np.unique(face), expected, rtol=1e-8, atol=1e-15)  # gmsh's progression: 2e-9
    assert rm.h_radial == pytest.approx(sc["fe.radial_size"], rel=1e-9)
    assert rm.core_radius == pytest.approx(min(c[0].r_end for c in scene_columns(sc)), rel=1e-12)
    assert rm.h_rim == pytest.approx(max(element_sizes(c).max() for c in scene_columns(sc)), rel=1e-9)


def test_a_graded_butterfly_is_built_as_its_layout_says():
    """The paper rods with a hemispherical Rod 1 at 0.1 m/s (auto: graded, 52 elements across instead of 116): the
    built mesh has the counted cells and nodes, its tip face's nodes hr apart along the arc out to the core and the
    rim plane's as the body's columns say, and no cell angle under 40° (the uniform butterfly's: 46°)."""
    sc = load_scene(PAPER, ["rod1.tip_radius=0.00635", "impact.speed=0.1", "simulation.end_time=1e-5"])
    hr = sc["fe.radial_size"]
    gb = graded_butterfly(sc.rod1, hr, sc["fe.axial_size"], sc.graded_core, "auto")
    assert gb is not None and gb.n_core + gb.n_g + gb.m <= GRADED_SHARE * face_count(sc.rod1, hr)
    rm = build_mesh(sc, MPI.COMM_SELF)
    start = coarsening_start(sc)
    counts = [mesh_counts(r, hr, sc["fe.axial_size"], sc.tip_grading, sc.graded_core, "auto", None, (0, 0), start)
              for r in sc.rods]  # fmt: skip
    assert rm.mesh.topology.index_map(2).size_local == sum(c for c, _ in counts)
    assert rm.mesh.geometry.x.shape[0] == sum(n for _, n in counts)
    assert rm.graded == (True, True) and scene_columns(sc)[0] == gb.columns
    assert rm.core_radius == pytest.approx(min(gb.r_core, scene_columns(sc)[1][0].r_end), rel=1e-12)
    x = rm.mesh.geometry.x[:, :2]
    rt = sc.rod1.tip_radius
    on_cap = (x[:, 1] < 0) & (np.abs(np.hypot(x[:, 0], x[:, 1] + rt) - rt) < 1e-9)  # Rod 1's spherical face
    arc = np.sort(rt * np.arcsin(np.clip(x[on_cap, 0] / rt, 0, 1)))
    np.testing.assert_allclose(np.diff(arc)[: gb.n_core], hr, rtol=1e-6)
    rim = np.sort(x[np.abs(x[:, 1] + sc.rod1.cap_height) < 1e-12, 0])  # Rod 1's rim plane O-G-E
    np.testing.assert_allclose(rim, np.concatenate([[0.0], np.cumsum(element_sizes(gb.columns))]), atol=1e-12)
    cells = x[rm.mesh.geometry.dofmaps[0]][:, [0, 1, 3, 2]]  # counter-clockwise corners
    e = np.roll(cells, -1, axis=1) - cells
    a, b = -np.roll(e, 1, axis=1), e
    cos = (a * b).sum(2) / (np.linalg.norm(a, axis=2) * np.linalg.norm(b, axis=2))
    assert np.degrees(np.arccos(np.clip(cos, -1, 1))).min() > 40.0


@pytest.mark.parametrize(
    "overrides",
    [
        [],  # the paper scene: 24 across merge into 8 (one layer)
        ["impact.speed=0.1"],  # graded columns (a 19-element core growing out): two layers, a few passing through
        ["rod1.tip_radius=0.00635", "impact.speed=0.1"],  # a graded butterfly's three columns: three layers
        ["impact.speed=0.5", "rod2.tip_radius=0.02"],  # two curved tips, uniform columns
    ],
)
def test_a_coarsened_mesh_is_built_as_counted(overrides):
    """fe.radial_coarsening "auto" (the default): the built mesh has the cells and nodes mesh_counts counts (what the
    plan's cost says), its layers start past 2 diameters from the tips, its far ends are the layers' last elements,
    no cell angle is under 40° (the 3:1 templates' slanted sides at 45° to the columns', rods.fe.mesh.SLANT; a graded
    butterfly's own cells from 43.7°), and "none" keeps the columns the rod's whole length."""
    sc = load_scene(PAPER, [*overrides, "simulation.end_time=1e-5"])
    hr, start = sc["fe.radial_size"], coarsening_start(sc)
    assert start == pytest.approx(2 * 12.7e-3)
    rm = build_mesh(sc, MPI.COMM_SELF)
    counts = [mesh_counts(r, hr, sc["fe.axial_size"], sc.tip_grading, sc.graded_core, sc["fe.radial_grading"],
                          sc.bar_axial_size, sc.axial_core, start) for r in sc.rods]  # fmt: skip
    assert rm.mesh.topology.index_map(2).size_local == sum(c for c, _ in counts)
    assert rm.mesh.geometry.x.shape[0] == sum(n for _, n in counts)
    assert all(co is not None and co.z >= start for co in rm.coarsened)
    x = rm.mesh.geometry.x[:, :2]
    for k, co in enumerate(rm.coarsened):
        far = np.sort(x[np.isclose(np.abs(x[:, 1]), sc.rods[k].length, rtol=0, atol=1e-12), 0])
        np.testing.assert_allclose(far, co.radii[-1], atol=1e-12)
    cells = x[rm.mesh.geometry.dofmaps[0]][:, [0, 1, 3, 2]]  # counter-clockwise corners
    e = np.roll(cells, -1, axis=1) - cells
    a, b = -np.roll(e, 1, axis=1), e
    cos = (a * b).sum(2) / (np.linalg.norm(a, axis=2) * np.linalg.norm(b, axis=2))
    assert np.degrees(np.arccos(np.clip(cos, -1, 1))).min() > 40.0
    none = build_mesh(sc.with_overrides("fe.radial_coarsening='none'"), MPI.COMM_SELF)
    assert none.coarsened == (None, None) and none.mesh.topology.index_map(2).size_local > 1.5 * sum(
        c for c, _ in counts
    )


@pytest.mark.parametrize(
    "overrides, submodel",
    [
        ((), False),  # the paper's 35 mm tip, graded along
        (("rod1.tip_radius=0.008", "fe.radial_grading='graded'"), False),  # a deep cap over graded columns
        (("rod1.diameter=0.03", "rod1.tip_radius=0.05"), False),  # a thick rod's cap, 2.4 mm deep
        (("rod1.tip_radius=inf", "rod2.tip_radius=0.02"), False),  # Rod 2's tip curved, Rod 1's flat
        (("fe.tip_grading=1", "fe.radial_size=0.2e-3"), False),  # no graded block: the first is the coarsening's
        (("fe.radial_grading='graded'",), True),  # a graded submodel: its core block first
    ],
    ids=["paper", "graded-8mm", "thick-rod", "rod2-tip", "ungraded-coarsened", "graded-submodel"],
)
def test_the_tip_row_is_the_meshers_own(overrides, submodel):
    """rods.fe.layout.tip_row, which the plan's step estimate reads (rods.cost._tip_step) without building a mesh, gives
    the corners of the built mesh's cells on each one-block tip face, to round-off: a face's nodes on its arc, the
    first block's end station, the transfinite surface's first row between them."""
    from rods.fe.layout import rod_layouts, tip_row
    from rods.fe.submodel import submodel_scene

    sc = load_scene(PAPER, ["simulation.end_time=1e-5", *overrides])
    if submodel:
        sc = submodel_scene(sc, 0.25e-3, end_time=1e-5)
    msh = build_mesh(sc, MPI.COMM_SELF).mesh
    x = msh.geometry.x[:, :2]
    for sign, layout in zip((-1.0, 1.0), rod_layouts(sc), strict=True):
        if np.isinf(layout.rod.tip_radius):
            continue
        row = tip_row(layout) * np.array([1.0, sign])  # Rod 1 lies at z < 0
        found = np.linalg.norm(x[None, :, :] - row.reshape(-1, 1, 2), axis=2).min(axis=1)
        assert found.max() < 1e-9 * layout.rod.diameter, found.max()


@pytest.mark.parametrize(
    "overrides",
    [
        (),  # the paper's 35 mm tip onto a flat face
        ("rod1.diameter=0.0088", "rod1.tip_radius=0.022", "rod2.diameter=0.0039"),  # graded over a thin uniform face
        ("rod1.tip_radius=0.0064", "rod2.tip_radius=0.007"),  # two butterflies, uniform
        ("rod1.tip_radius=0.0066", "rod2.tip_radius=0.007", "fe.radial_grading='graded'"),  # graded butterflies
    ],
    ids=["paper", "graded-over-thin", "butterflies", "graded-butterflies"],
)
def test_the_tip_faces_are_the_meshers_own(overrides):
    """rods.fe.layout.tip_faces, which the plan's switching limit reads (rods.cost._switching_step) without building
    a mesh: each face's node radii are the built mesh's tip nodes', to round-off, and its h_tip the mesh's."""
    import dolfinx

    from rods.fe.layout import tip_faces
    from rods.fe.mesh import TAGS

    sc = load_scene(PAPER, ["simulation.end_time=1e-5", *overrides])
    rm = build_mesh(sc, MPI.COMM_SELF)
    msh = rm.mesh
    faces = tip_faces(sc)
    for k, face in enumerate(faces, start=1):
        facets = rm.facet_tags.find(TAGS[f"rod{k}_tip"])
        nodes = np.unique(dolfinx.mesh.entities_to_geometry(msh, msh.topology.dim - 1, facets))
        r = np.sort(msh.geometry.x[nodes, 0])
        assert r.shape == face.r.shape and np.abs(r - face.r).max() < 1e-8 * face.rod.diameter
    assert rm.h_tip == pytest.approx(min(f.h_tip for f in faces), rel=1e-9)


def _caught(sig: int) -> bool:
    """Whether this process has a handler installed for ``sig`` at the C level (/proc/self/status, SigCgt)."""
    for line in open("/proc/self/status"):
        if line.startswith("SigCgt:"):
            return bool(int(line.split()[1], 16) >> (sig - 1) & 1)
    pytest.skip("no /proc/self/status")


def test_gmsh_keeps_the_interrupt_handlers():
    """rods.fe.mesh.start_gmsh: gmsh.initialize reset SIGTERM's C-level handler to the default (SIGTERM in a mesh's
    generation killed the rank, exit 15, no line); the handlers set before it stay, Python's and the C level's."""
    import signal

    import gmsh

    from rods.fe.mesh import start_gmsh

    def handler(*_):
        pass

    before = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        start_gmsh()
        try:
            assert _caught(signal.SIGTERM) and _caught(signal.SIGINT)
            assert signal.getsignal(signal.SIGTERM) is handler and signal.getsignal(signal.SIGINT) is handler
        finally:
            gmsh.finalize()
    finally:
        for s, h in before.items():
            signal.signal(s, h)


def test_a_callers_gmsh_session_keeps_its_models_and_terminal(scene_with):
    """A notebook's own gmsh session, open when a model is meshed: still open after, its model still there, its
    General.Terminal setting back (the mesher had set it to 0 for good: a library audit, 2026-12-07)."""
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 1)
        gmsh.model.add("mine")
        build_mesh(scene_with("fe.axial_size=4e-3", "fe.radial_size=1e-3", "rod1.length=0.05"), MPI.COMM_SELF)
        assert gmsh.isInitialized() and "mine" in gmsh.model.list()
        assert gmsh.option.getNumber("General.Terminal") == 1
    finally:
        gmsh.finalize()


def test_pictures_set_no_global_where_a_display_is(monkeypatch):
    """rods.io.offscreen_pyvista: EGL is VTK's default only on a headless Linux machine; with a display (a desktop
    notebook) the environment is left as it was, and pyvista's global OFF_SCREEN is never set."""
    import os
    import sys

    from rods.io import offscreen_pyvista

    monkeypatch.delenv("VTK_DEFAULT_OPENGL_WINDOW", raising=False)
    monkeypatch.setenv("DISPLAY", ":0")
    pv = offscreen_pyvista()
    assert "VTK_DEFAULT_OPENGL_WINDOW" not in os.environ and pv.OFF_SCREEN is False
    monkeypatch.delenv("DISPLAY")
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    offscreen_pyvista()
    headless = sys.platform.startswith("linux")
    assert ("VTK_DEFAULT_OPENGL_WINDOW" in os.environ) is headless
