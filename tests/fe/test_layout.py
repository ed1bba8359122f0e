"""Laying out the axisymmetric mesh (rods.fe.layout), before anything is built: a radially graded rod keeps the
patch's size in its core and grows smoothly to the bar's size outside it, a near-hemispherical (butterfly) cap too;
"auto" grades where that halves the elements across; the coarsening merges threes up to the bar's size, and only
where it can help."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from rods.fe.layout import (
    GRADED_SHARE,
    GROWTH,
    altitudes,
    arc_to,
    axial_spacing,
    bar_size,
    butterfly,
    butterfly_counts,
    coarsening,
    coarsening_start,
    element_sizes,
    face_areas,
    face_count,
    graded_butterfly,
    radial_columns,
    row_volumes,
    scene_columns,
)
from rods.scene import BAR_ELEMENTS, load_scene

from ..conftest import PAPER


def _progression_sizes(first: float, n: int, q: float) -> np.ndarray:
    return first * q ** np.arange(n)


@settings(max_examples=200, deadline=None)
@given(
    diameter=st.floats(3e-3, 40e-3),  # [m]
    tip_radius=st.one_of(st.just(float("inf")), st.floats(0.03, 1.0)),  # [m] flat or a shallow-to-deep cap
    hr=st.floats(5e-6, 1e-3),  # [m]
    h_over_hr=st.floats(1.0, 40.0),
    core_over_hr=st.floats(1.0, 200.0),
)
@example(diameter=0.004, tip_radius=float("inf"), hr=1.2e-05, h_over_hr=2.0, core_over_hr=163.5)  # a 2.67 hr band
def test_graded_columns_keep_the_core_and_grow_smoothly(diameter, tip_radius, hr, h_over_hr, core_over_hr):
    """Graded: the columns fill the radius exactly; the core's elements are hr long along the tip face (the uniform
    face's spacing, where the patch and the stable step's smallest element are); outside it no element is shorter
    than hr or longer than the bar's size min(h, R/BAR_ELEMENTS), and neighbours differ by at most GROWTH, across the
    columns' joins too. A core past the rim or leaving a band no such elements fill (under hr, 1.2-2 hr, 2.64-3 hr),
    or a bar size below 2 hr, stay one uniform column (as a butterfly cap does; the caps drawn here are shallower)."""
    R = diameter / 2
    sc = load_scene(PAPER, [f"rod1.diameter={diameter}", f"rod2.diameter={diameter}", "rod1.length=1",
                            "rod2.length=1", f"rod1.tip_radius={max(min(tip_radius, 1.0), 3 * R)}"])  # fmt: skip
    rod = sc.rod2 if np.isinf(tip_radius) else sc.rod1  # the paper's Rod 2 is flat
    h, core = h_over_hr * hr, core_over_hr * hr
    columns = radial_columns(rod, hr, h, core, "graded")
    assert columns[-1].r_end == pytest.approx(R, rel=1e-12)
    sizes = element_sizes(columns)
    assert sizes.sum() == pytest.approx(R, rel=1e-9)
    if len(columns) == 1:
        assert columns == radial_columns(rod, hr, h, core, "uniform") and columns[0].n == face_count(rod, hr)
        rt, n = rod.tip_radius, np.ceil(arc_to(rod, core) / hr - 1e-9)  # the core rounded up to whole elements
        band = (R - (n * hr if np.isinf(rt) else rt * np.sin(min(n * hr / rt, np.arcsin(R / rt))))) / hr  # [hr]
        gaps = ((-np.inf, 1.0), (GROWTH, 2.0), (GROWTH + GROWTH**2, 3.0))  # no hr q^k, q <= GROWTH, fills these
        assert min(h, R / BAR_ELEMENTS) < 2 * hr or any(lo - 1e-9 < band < hi + 1e-9 for lo, hi in gaps), band
        return
    n_core = columns[0].n
    arc = rod.tip_radius * np.arcsin(columns[0].r_end / rod.tip_radius) if np.isfinite(rod.tip_radius) else None
    assert (arc if arc is not None else columns[0].r_end) == pytest.approx(n_core * hr, rel=1e-9)
    assert columns[0].r_end >= core * (1 - 1e-9)  # the core holds what it was asked to
    outside = sizes[n_core:]
    assert outside.min() >= hr * (1 - 1e-9) and outside.max() <= min(h, R / BAR_ELEMENTS) * (1 + 1e-9)
    steps = sizes[1:] / sizes[:-1]
    arc_over_r = n_core * hr / columns[0].r_end  # a curved core's elements are hr along the face, less across (r)
    assert steps.max() <= GROWTH * arc_over_r * (1 + 1e-9) and steps.min() >= 1 - 1e-9  # never shrinking outward
    assert sizes.size < face_count(rod, hr)  # and fewer than the uniform face's


def test_auto_grades_where_it_halves_the_elements_across():
    """fe.radial_grading "auto": the paper scene (19 of 24 across graded) and the verification matrix stay uniform;
    the paper rods at 0.1 m/s (a_P = 0.39 mm) are graded on both rods, with under half the uniform count; "uniform"
    and "graded" force either."""
    paper = load_scene(PAPER, [])
    assert all(len(c) == 1 for c in scene_columns(paper))
    assert all(len(c) == 2 for c in scene_columns(paper.with_overrides("fe.radial_grading='graded'")))
    slow = load_scene(PAPER, ["impact.speed=0.1"])
    for rod, columns in zip(slow.rods, scene_columns(slow), strict=True):
        assert len(columns) > 1 and sum(c.n for c in columns) <= 0.5 * face_count(rod, slow["fe.radial_size"])
    assert all(len(c) == 1 for c in scene_columns(slow.with_overrides("fe.radial_grading='uniform'")))


@settings(max_examples=200, deadline=None)
@given(
    diameter=st.floats(3e-3, 40e-3),  # [m]
    bulge=st.floats(0.0, 0.99),  # tip radius from R (a hemisphere) towards the butterfly's limit R / sin 70°
    hr=st.floats(5e-6, 1e-3),  # [m]
    h_over_hr=st.floats(1.0, 40.0),
    core_over_hr=st.floats(1.0, 200.0),
)
def test_a_graded_butterfly_keeps_the_core_and_grows_smoothly(diameter, bulge, hr, h_over_hr, core_over_hr):
    """A butterfly cap graded (rods.fe.mesh.graded_butterfly): the arc from the apex holds n_core elements of hr
    (at least the core asked for), then grows by at most GROWTH to P, filling the arc A-P exactly; across the bands
    the elements grow from hr at the face to fill their thickness; along P-E on; no element above the bar's size
    (or the last before P, where that is larger), none below hr; the body's columns fill the radius, neighbours within
    GROWTH across every join (the core's edge, G), and fewer than the uniform butterfly's. None: uniform (a bar size
    under 2 hr, or an arc or band too short for the growth)."""
    R = diameter / 2
    rt = R * (1 + 1e-12) / (1.0 - bulge * (1.0 - np.sin(np.radians(70.0))))  # R <= rt < R / sin 70°
    sc = load_scene(PAPER, [f"rod1.diameter={diameter}", f"rod2.diameter={diameter}", "rod1.length=1",
                            "rod2.length=1", f"rod1.tip_radius={rt}"])  # fmt: skip
    rod = sc.rod1
    b = butterfly(rod)
    assert b is not None
    h, core, H = h_over_hr * hr, core_over_hr * hr, bar_size(rod, h_over_hr * hr)
    gb = graded_butterfly(rod, hr, h, core, "graded")
    n_a, _, m_uniform = butterfly_counts(b, hr)
    if gb is None:
        assert radial_columns(rod, hr, h, core, "graded") == radial_columns(rod, hr, h, core, "uniform")
        return  # (the property: what is graded is smooth; graded_butterfly refuses the layouts it cannot make so)
    arc_ap, arc_pe = b.arcs
    assert gb.n_core * hr >= arc_to(rod, core) * (1 - 1e-9)
    along = np.concatenate([np.full(gb.n_core, hr), _progression_sizes(hr, gb.n_g, gb.q_g)])
    across = _progression_sizes(hr, gb.m, gb.q_m)
    q = gb.q_b  # P-E as gmsh divides it: n_b elements growing by q_b filling the arc
    on = _progression_sizes(arc_pe / gb.n_b if q == 1 else arc_pe * (q - 1) / (q**gb.n_b - 1), gb.n_b, q)
    assert along.sum() == pytest.approx(arc_ap, rel=1e-9) and across.sum() == pytest.approx(b.t, rel=1e-9)
    for sizes in (along, across):
        assert sizes.min() >= hr * (1 - 1e-9) and sizes.max() <= H * (1 + 1e-9)
        assert (sizes[1:] / sizes[:-1]).max() <= GROWTH * (1 + 1e-9)
    assert on.max() <= max(H, along[-1]) * (1 + 1e-9) and 1 <= q <= GROWTH * (1 + 1e-9)
    assert 1 / GROWTH <= on[0] / along[-1] * (1 + 1e-9) and on[0] / along[-1] <= GROWTH * (1 + 1e-9)  # at P
    body = element_sizes(gb.columns)
    assert gb.columns[-1].r_end == R and body.sum() == pytest.approx(R, rel=1e-9)
    ratios = body[1:] / body[:-1]
    assert max(ratios.max(), 1 / ratios.min()) <= GROWTH * (1 + 1e-9)  # the band's shrink to the rim included
    assert body[-1] == pytest.approx(hr, rel=1e-9) and len(body) < n_a + m_uniform
    auto = graded_butterfly(rod, hr, h, core, "auto")
    assert (auto is not None) == (len(body) <= GRADED_SHARE * (n_a + m_uniform))


@settings(max_examples=80, deadline=None)
@given(
    diameter=st.floats(5e-3, 30e-3),  # [m]
    tip_radius=st.one_of(st.just(np.inf), st.floats(5e-3, 1.0)),  # [m]
    hr=st.floats(0.02e-3, 0.5e-3),  # [m]
    h_over_hr=st.floats(1.0, 40.0),
    grading=st.sampled_from(["uniform", "auto", "graded"]),
)
def test_coarsening_merges_threes_up_to_the_bar_size(diameter, tip_radius, hr, h_over_hr, grading):
    """rods.fe.mesh.coarsening on any columns: each layer's nodes are the last one's (a group of three merges, one
    passes through), no merged element wider than the bar's size H (so at least BAR_ELEMENTS across where the
    columns are no wider), merging until no three fit H; a layer's cells are 4 per merge and 1 per pass."""
    from rods.scene import Material, Rod

    steel = Material(density=7800.0, youngs_modulus=200e9, poisson_ratio=0.3)
    rod = Rod(length=1.0, diameter=diameter, tip_radius=max(tip_radius, diameter / 2 * 1.0001), material=steel)
    h = hr * h_over_hr
    columns = radial_columns(rod, hr, h, 3 * hr, grading)
    sp = axial_spacing(rod, h, 1.0)
    co = coarsening(rod, columns, h, sp, 2 * diameter)
    H = bar_size(rod, h)
    widths = np.diff(np.concatenate([[0.0], np.cumsum(element_sizes(columns))]))
    if co is None:
        triples = widths[:-2] + widths[1:-1] + widths[2:]
        assert widths.size < 3 or triples.min() > H * (1 + 1e-6)
        return
    assert co.radii[0][-1] == rod.diameter / 2 and co.z >= 2 * diameter * (1 - 1e-12)
    for k, groups in enumerate(co.layers):
        below, above = np.array(co.radii[k]), np.array(co.radii[k + 1])
        assert sum(groups) == below.size - 1 and len(groups) == above.size - 1 and 3 in groups
        np.testing.assert_array_equal(above, below[np.concatenate([[0], np.cumsum(groups)])])
        merged = np.diff(above)[np.array(groups) == 3]
        assert merged.max() <= H * (1 + 1e-6)
    last, i = np.diff(co.radii[-1]), 0
    while i + 3 <= last.size:  # the greedy scan that stopped finds no three to merge
        assert last[i : i + 3].sum() > H * (1 + 1e-6)
        i += 1
    assert co.cells == sum(4 * g.count(3) + g.count(1) for g in co.layers) and co.n_far == last.size
    assert co.n_far >= BAR_ELEMENTS or last.max() > H * (1 + 1e-6)  # all within H: at least R / H across


def test_no_coarsening_where_it_cannot_help():
    """No layers on a rod shorter than the start and a row past the layers (a submodel's region, rods cut to
    fe.submodel_length), nor on the 3D model (an O-grid); a long submodel cut moves the start past its band."""
    from rods.fe.submodel import submodel_scene

    sc = load_scene(PAPER, [])
    sub = submodel_scene(sc, 0.125e-3, None)
    start = coarsening_start(sub)
    for rod, columns in zip(sub.rods, scene_columns(sub), strict=True):
        assert (
            coarsening(rod, columns, sub.bar_axial_size, axial_spacing(rod, sub["fe.axial_size"], 1.0), start) is None
        )
    assert coarsening_start(sc.with_overrides("fe.kind='3d'")) == np.inf
    assert coarsening_start(sc.with_overrides("fe.radial_coarsening='none'")) == np.inf
    assert coarsening_start(sc.with_overrides("fe.submodel_length=0.05")) == pytest.approx(0.05 + 3 * 1e-3)


def test_altitudes_are_a_cells_thickness_across_its_thinnest_direction():
    """rods.fe.layout.altitudes: a rectangle's shorter side; a parallelogram sheared by θ, its height b cos θ where
    that is below its width a; the corners in tip_row's order (face side 0-1, the side below it 2-3)."""
    a, b, θ = 2e-3, 0.5e-3, np.radians(40.0)  # [m], [m], [rad]
    rectangle = np.array([[[0, 0], [a, 0], [0, b], [a, b]]], dtype=float)
    shear = np.array([b * np.sin(θ), b * np.cos(θ)])  # the side 0-2 leans by θ from the normal of 0-1
    parallelogram = np.array([[[0, 0], [a, 0], shear, [a + shear[0], shear[1]]]])
    assert altitudes(rectangle)[0] == pytest.approx(b, rel=1e-12)
    assert altitudes(parallelogram)[0] == pytest.approx(b * np.cos(θ), rel=1e-12)
    assert altitudes(rectangle[:, :, ::-1])[0] == pytest.approx(b, rel=1e-12)  # r and z swapped


def test_face_areas_and_row_volumes_are_the_closed_forms_of_a_flat_face():
    """rods.fe.layout.face_areas and row_volumes, the switching estimate's areas and lumped masses (over 2π, 2π ρ):
    on a flat face of n elements Δ wide over a row t thick, ∫ N_i r ds = Δ²/6 at the axis, Δ r_i inside and
    Δ (3 r_n - Δ)/6 at the rim; ∫ N_i r dA = t/2 of each (the bilinear shape's mean over the row's depth); they sum
    to R²/2 and t R²/4, the face's and the half row's ∫ r."""
    n, Δ, t = 5, 0.4e-3, 0.1e-3  # [-], [m], [m]
    r = Δ * np.arange(n + 1)
    cells = np.stack([np.stack([r[:-1], 0 * r[:-1]], 1), np.stack([r[1:], 0 * r[1:]], 1),
                      np.stack([r[:-1], t + 0 * r[:-1]], 1), np.stack([r[1:], t + 0 * r[1:]], 1)], axis=1)  # fmt: skip
    area, volume = face_areas(r, r), row_volumes(cells)
    assert area[0] == pytest.approx(Δ**2 / 6, rel=1e-12) and area[-1] == pytest.approx(Δ * (3 * r[-1] - Δ) / 6)
    assert area[1:-1] == pytest.approx(Δ * r[1:-1], rel=1e-12)
    assert volume == pytest.approx(area * t / 2, rel=1e-12)
    assert area.sum() == pytest.approx(r[-1] ** 2 / 2) and volume.sum() == pytest.approx(t * r[-1] ** 2 / 4)


@pytest.mark.parametrize("h", [1e-7, 1e-6])
def test_a_tiny_axial_size_is_counted_without_overflow(h):
    """An in-range 0.1 µm axial size at tip grading 0.05 (the paper's 35 mm cap, 0.58 mm deep, in a graded block of
    ~1.2 mm): the block's count was searched one n at a time from its first guess and overflowed GROWTH^n on the way
    (OverflowError, exit 1, before the plan could refuse the mesh's memory). Now the count starts where elements of
    h can fill the block: every element at most h, the tip element g h, the block's length its own."""
    rod = load_scene(PAPER).rod1
    sp = axial_spacing(rod, h, 0.05)
    sizes = sp.h_tip * sp.ratio ** np.arange(sp.n_graded)  # [m]
    assert sp.h_tip == pytest.approx(0.05 * h, rel=1e-12)
    assert sizes.max() <= h * (1 + 1e-9) and sizes.sum() == pytest.approx(sp.graded_length, rel=1e-9)
    assert sp.n_graded >= sp.graded_length / h
