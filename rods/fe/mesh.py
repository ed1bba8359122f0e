"""Structured (r, z) quadrilateral mesh of both rods for the axisymmetric global model (paper Sec. 2.2), built.

Layout (x = r >= 0, y = z along the common axis; SI units, metres):

* Rod 2 occupies ``z >= 0``: its tip apex sits at the origin, the far end is the plane ``z = L2``.
* Rod 1 occupies ``z <= 0``: its cap apex touches Rod 2 at the origin at t = 0, the far end is
  ``z = -L1`` (lengths measured along the axis from the apex).
* A curved tip of radius r_k is the spherical cap ``z = ±(r_k - sqrt(r_k² - r²))`` (height
  :attr:`rods.scene.Rod.cap_height` at r = d/2); a flat tip is the plane ``z = 0``.

What goes where, and how many, is :mod:`rods.fe.layout` (counted there, before anything is built, by the same rules):
the tip's block or butterfly, the columns across (uniform or graded), the spacing along (a graded tip block) and the
3:1 layers that coarsen the columns away from the tips. This module draws that layout in gmsh on rank 0 only
(transfinite + recombine: structured quadrilaterals) and distributes it with :func:`dolfinx.io.gmsh.model_to_mesh`.
The two rods are separate gmsh surfaces with their own points: they share no nodes and interact only through
contact.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import dolfinx
import dolfinx.io.gmsh
import numpy as np
from mpi4py import MPI

from rods.fe.layout import (
    Butterfly,
    Coarsening,
    Column,
    GradedButterfly,
    RodLayout,
    arc_to,
    axial_blocks,
    butterfly_counts,
    butterfly_tip_element,
    cap_depth,
    element_sizes,
    rod_layouts,
)
from rods.scene import Rod, Scene

__all__ = ["TAGS", "RodsMesh", "build_mesh", "cell_sizes", "gmsh_to_dolfinx"]

# Physical-group tags: cells by rod, facets by role.
TAGS = {
    "rod1": 1,
    "rod2": 2,
    "rod1_tip": 11,
    "rod2_tip": 12,
    "rod1_end": 21,
    "rod2_end": 22,
    "axis": 31,
    "rod1_outer": 41,
    "rod2_outer": 42,
}

# a 3:1 template's inner nodes m1, m2 this many side elements' widths below its top (at most half way) [-]: its
# slanted sides then meet the columns' at 45°; half way up, a 1 mm layer over 0.024 mm elements had 2.8° corners.
# Either way the step stays the tip's (paper rods at 0.1 and 2.197 m/s, a hemispherical tip at 0.1: Δt_crit within
# 3e-6 of the uncoarsened mesh's at 0.5, 1, 2 and 100, 2026-12-06)
SLANT = 1.0  # [-]


@dataclass
class RodsMesh:
    """The two rods' axisymmetric mesh (r, z; :func:`build_mesh`): the DOLFINx mesh with its cell tags (rod 1, rod 2)
    and facet tags (the tip faces, the far ends), and the element counts and sizes the plan and the summary report."""

    mesh: dolfinx.mesh.Mesh
    cell_tags: dolfinx.mesh.MeshTags
    facet_tags: dolfinx.mesh.MeshTags
    n_radial: int  # elements across the radius (the thicker rod's where they differ) [-]
    n_axial: tuple[int, int]  # elements along rod 1, rod 2 [-]
    h_radial: float  # element size along the tip faces in the patch's core (radial; on a curved face along its arc) [m]
    h_tip: float  # axial size of the element at the tips (normal to the contact face) [m]
    h_axial: float  # nominal axial element size [m]
    graded: tuple[bool, bool]  # rod 1, rod 2 graded across (fe.radial_grading) [-]
    core_radius: float  # radius out to which the tip faces have h_radial [m] (inf: the whole face)
    h_rim: float  # the largest element size across, at the rims of graded rods [m] (0: uniform)
    coarsened: tuple[Coarsening | None, Coarsening | None]  # rod 1, rod 2 (fe.radial_coarsening; None: none)


def _butterfly_cap(geo, b: Butterfly, s: float, hr: float, gb: GradedButterfly | None) -> dict[str, Any]:
    """Mesh a cap laid out as ``b`` (:func:`butterfly`; side ``s`` = -1: rod 1, +1: rod 2) in three blocks, or in
    five graded as ``gb`` (:class:`GradedButterfly`: the band along A-P and the core split at K, K', K''); returns the
    tip and axis curves, the rim line O-G-E (the body's bottom, one entry per column), its points and counts."""
    import gmsh

    pts = dict(b.points)
    if gb is None:
        n_a, n_b, m = butterfly_counts(b, hr)
    else:
        n_a, n_b, m = gb.n_core + gb.n_g, gb.n_b, gb.m
        rt, t = pts["Oc"][1], b.t
        th = gb.n_core * hr / rt  # K: the core's edge on the arc
        K = (rt * math.sin(th), rt * (1.0 - math.cos(th)))
        pts |= {"K": K, "K'": (K[0] * (1.0 - t / rt), K[1] + t * (rt - K[1]) / rt), "K''": (gb.r_core, pts["O"][1])}
    p = {k: geo.addPoint(r, s * z, 0.0) for k, (r, z) in pts.items()}
    c, loops, rim, corners, tip = _butterfly_blocks(geo, p, (n_a, n_b, m), gb)

    def tag(name: str) -> int:
        return -c[name[1:]][0] if name.startswith("-") else c[name][0]

    surfaces = [geo.addPlaneSurface([geo.addCurveLoop([tag(x) for x in loop])]) for loop in loops]
    geo.synchronize()
    for curve, n, q in c.values():
        gmsh.model.geo.mesh.setTransfiniteCurve(curve, n + 1, "Progression", q)
    for surf in surfaces:
        gmsh.model.geo.mesh.setTransfiniteSurface(surf)
        gmsh.model.geo.mesh.setRecombine(2, surf)
    return {
        "surfaces": surfaces,
        "tip": [tag(x) for x in tip],
        "axis": [tag("AD"), tag("DO")],
        "rim": [[tag(x) for x in column] for column in rim],
        "corners": [p[x] for x in corners],
        "n_cross": n_a + m,
        "h_tip": butterfly_tip_element(b, hr, gb),  # the element normal to the contact face at the apex [m]
        "h_face": max(length / n for length, n in zip(b.arcs, (n_a, n_b), strict=True)) if gb is None else hr,
    }


def _butterfly_blocks(geo, p: dict[str, int], counts: tuple[int, int, int], gb: GradedButterfly | None):
    """The butterfly's curves between its points ``p`` (gmsh tags), each as (tag, elements, progression along it),
    and its blocks as curve loops (a leading "-" reverses a curve), with the rim's columns, its corner points and
    the tip's curves from the apex out: three blocks of ``counts`` = (n_a, n_b, m), or five graded as ``gb``."""
    n_a, n_b, m = counts
    q_m, q_b = (1.0, 1.0) if gb is None else (gb.q_m, gb.q_b)
    arc, line = (lambda a, z: geo.addCircleArc(p[a], p["Oc"], p[z])), (lambda a, z: geo.addLine(p[a], p[z]))
    c = {
        "PE": (arc("P", "E"), n_b, q_b),
        "AD": (line("A", "D"), m, q_m),  # across the bands: from hr at the face inward
        "PC": (line("P", "C"), m, q_m),
        "EG": (line("E", "G"), m, q_m),
        "CG": (line("C", "G"), n_b, q_b),
        "DO": (line("D", "O"), n_b, q_b),
    }
    if gb is None:
        c |= {"AP": (arc("A", "P"), n_a, 1.0), "DC": (line("D", "C"), n_a, 1.0), "OG": (line("O", "G"), n_a, 1.0)}
        loops = [["AP", "PC", "-DC", "-AD"], ["PE", "EG", "-CG", "-PC"], ["DC", "CG", "-OG", "-DO"]]
        return c, loops, [["OG", "-EG"]], ["O", "E"], ["AP", "PE"]
    c |= {
        "AK": (arc("A", "K"), gb.n_core, 1.0),
        "KP": (arc("K", "P"), gb.n_g, gb.q_g),
        "KK'": (line("K", "K'"), m, q_m),
        "DK'": (line("D", "K'"), gb.n_core, 1.0),
        "K'C": (line("K'", "C"), gb.n_g, gb.q_g),
        "K'K''": (line("K'", "K''"), n_b, q_b),
        "OK''": (line("O", "K''"), gb.n_core, 1.0),
        "K''G": (line("K''", "G"), gb.n_g, gb.q_g),
    }
    loops = [
        ["AK", "KK'", "-DK'", "-AD"],  # the band over the core
        ["KP", "PC", "-K'C", "-KK'"],  # the band, graded along
        ["PE", "EG", "-CG", "-PC"],  # the band to the rim
        ["DK'", "K'K''", "-OK''", "-DO"],  # the core under the core
        ["K'C", "CG", "-K''G", "-K'K''"],  # the core, graded along
    ]
    return c, loops, [["OK''"], ["K''G"], ["-EG"]], ["O", "K''", "G", "E"], ["AK", "KP", "PE"]


def _flat_block_cap(geo, rod: Rod, s: float, columns: tuple[Column, ...]) -> dict[str, Any]:  # rank 0 only
    """The tip face of a flat or flatter curved tip: the first block's bottom, from the apex to the rim, one curve
    per column (:func:`radial_columns`), each split point on the face at its column's radius."""
    import gmsh

    R, rt = rod.diameter / 2, rod.tip_radius
    centre = None if math.isinf(rt) else geo.addPoint(0.0, s * rt, 0.0)
    points = [geo.addPoint(0.0, 0.0, 0.0)]
    tips = []
    for c in columns:
        r = R if c is columns[-1] else c.r_end  # the rim exactly, whatever a column's round-off
        points.append(geo.addPoint(r, s * (rod.cap_height if r == R else float(cap_depth(r, rt))), 0.0))
        a, b = points[-2], points[-1]
        tips.append(geo.addLine(a, b) if centre is None else geo.addCircleArc(a, centre, b))
    geo.synchronize()
    for tag, c in zip(tips, columns, strict=True):
        gmsh.model.geo.mesh.setTransfiniteCurve(tag, c.n + 1, "Progression", c.ratio)
    return {
        "surfaces": [],
        "tip": tips,
        "axis": [],
        "rim": [[t] for t in tips],
        "corners": points,
        "h_face": arc_to(rod, columns[0].r_end) / columns[0].n,
    }  # the core's (the whole face's when uniform)


def _column_block(
    geo,
    lower: list[list[int]],
    corners: list[int],
    columns,
    z_end: float,
    n: int,
    ratio: float,
    split: Sequence[float] | None = None,
):
    """One axial block of a rod, from the station below (``lower``: each column's bottom curves; ``corners``: the
    points where the columns meet it, axis to rim) to ``z_end`` [m], ``n`` elements along by ``ratio``; returns its
    surfaces, the axis and outer lines and the new station (tops, corners). ``split``: the new station's node radii
    [m], one line per element, where a coarsening's first layer starts (:attr:`Coarsening.radii`' first station,
    whose nodes :func:`_coarsening_layers` builds on)."""
    import gmsh

    radii = [0.0, *(c.r_end for c in columns)]
    upper = [geo.addPoint(r, z_end, 0.0) for r in radii]
    verticals = [geo.addLine(a, b) for a, b in zip(corners, upper, strict=True)]  # oriented away from the tip
    if split is not None:  # each column's top as its elements' lines, the nodes between its ends at split's radii
        first = np.concatenate(([0], np.cumsum([c.n for c in columns])))  # each column's first node in split
        nodes, tops = [upper[0]], []
        for j in range(len(columns)):
            inner = split[first[j] + 1 : first[j + 1]]
            column = [nodes[-1], *(geo.addPoint(r, z_end, 0.0) for r in inner), upper[j + 1]]
            tops.append([geo.addLine(a, b) for a, b in zip(column[:-1], column[1:], strict=True)])
            nodes += column[1:]
    else:
        tops = [[geo.addLine(a, b)] for a, b in zip(upper[:-1], upper[1:], strict=True)]
    surfaces = [
        geo.addPlaneSurface(
            [geo.addCurveLoop([*bottom, verticals[j + 1], *(-t for t in tops[j][::-1]), -verticals[j]])]
        )
        for j, bottom in enumerate(lower)
    ]
    geo.synchronize()
    for c in verticals:
        gmsh.model.geo.mesh.setTransfiniteCurve(c, n + 1, "Progression", ratio)
    for j, (surf, col) in enumerate(zip(surfaces, columns, strict=True)):
        for t in tops[j]:
            gmsh.model.geo.mesh.setTransfiniteCurve(
                t, col.n + 1 if split is None else 2, "Progression", col.ratio if split is None else 1.0
            )
        if len(lower[j]) == 1 and split is None:
            gmsh.model.geo.mesh.setTransfiniteSurface(surf)
        else:  # a butterfly's rim line O-G-E or a split top is several curves: name the corners
            gmsh.model.geo.mesh.setTransfiniteSurface(
                surf, "Left", [corners[j], corners[j + 1], upper[j + 1], upper[j]]
            )
        gmsh.model.geo.mesh.setRecombine(2, surf)
    if split is not None:
        return surfaces, verticals[0], verticals[-1], [[t] for top in tops for t in top], nodes
    return surfaces, verticals[0], verticals[-1], tops, upper


def _coarsening_layers(geo, lower: list[list[int]], corners: list[int], co: Coarsening, z0: float, dz: float):
    """The layers of a coarsening ``co`` (:class:`Coarsening`) from the split station ``lower``/``corners`` (one line
    and point per element) at ``z0``, each ``dz`` long [m] (signed: away from the tip): a group of three elements
    below meets one above in the 3:1 template of four quadrilaterals (nodes b0..b3 below, t0, t1 above, m1, m2 over
    b1, b2 a side element's width below the top, :data:`SLANT`: b0 b1 m1 t0, b1 b2 m2 m1, b2 b3 t1 m2, m1 m2 t1
    t0), a group of one passes through as one quadrilateral; every side between groups one line, so neighbours
    conform. Returns the surfaces, the axis and outer lines and the station above the last layer (one line and point
    per element)."""
    import gmsh

    surfaces, axis, outer, lines = [], [], [], []
    for k, groups in enumerate(co.layers):
        below, z1, zm = co.radii[k], z0 + (k + 1) * dz, z0 + (k + 0.5) * dz
        top = [geo.addPoint(r, z1, 0.0) for r in co.radii[k + 1]]
        starts = np.concatenate(([0], np.cumsum(groups)))  # each group's first element below
        side = [geo.addLine(corners[i], t) for i, t in zip(starts, top, strict=True)]  # oriented away from the tip
        roof = [geo.addLine(a, b) for a, b in zip(top[:-1], top[1:], strict=True)]
        loops = []
        for j, (i, g) in enumerate(zip(starts[:-1], groups, strict=True)):
            if g == 1:
                loops.append([lower[i][0], side[j + 1], -roof[j], -side[j]])
                continue
            m1, m2 = (geo.addPoint(below[i + q], z1 - math.copysign(min(abs(zm - z1), SLANT * w), dz), 0.0)
                      for q, w in ((1, below[i + 1] - below[i]), (2, below[i + 3] - below[i + 2])))  # fmt: skip
            b1m1, b2m2 = geo.addLine(corners[i + 1], m1), geo.addLine(corners[i + 2], m2)
            m1m2, m1t0, m2t1 = geo.addLine(m1, m2), geo.addLine(m1, top[j]), geo.addLine(m2, top[j + 1])
            lines += [b1m1, b2m2, m1m2, m1t0, m2t1]
            loops += [
                [lower[i][0], b1m1, m1t0, -side[j]],
                [lower[i + 1][0], b2m2, -m1m2, -b1m1],
                [lower[i + 2][0], side[j + 1], -m2t1, -b2m2],
                [m1m2, m2t1, -roof[j], -m1t0],
            ]
        surfaces += [geo.addPlaneSurface([geo.addCurveLoop(loop)]) for loop in loops]
        lines += side + roof
        axis.append(side[0])
        outer.append(side[-1])
        lower, corners = [[r] for r in roof], top
    geo.synchronize()
    for c in lines:
        gmsh.model.geo.mesh.setTransfiniteCurve(c, 2)
    for surf in surfaces:
        gmsh.model.geo.mesh.setTransfiniteSurface(surf)
        gmsh.model.geo.mesh.setRecombine(2, surf)
    return surfaces, axis, outer, lower, corners


def _rod_body(geo, cap: dict[str, Any], layout: RodLayout, s: float):
    """A rod's body from its ``cap`` to its far end, on the side ``s`` (-1: z < 0, rod 1; +1: rod 2): its axial blocks
    (:func:`rods.fe.layout.axial_blocks`: a graded submodel's core, the tip's graded block, then the uniform block),
    the uniform block in three where it coarsens (to the first layer, split per element, the layers, the rest on the
    layers' last elements). Returns its surfaces, axis and outer lines and the far end's station."""
    columns, co = layout.columns, layout.coarsened
    blocks = axial_blocks(layout.rod, layout.spacing, co)
    lower, corners, surfaces, axis, outer = cap["rim"], cap["corners"], [], [], []
    for i, (z_end, n, ratio, split) in enumerate(blocks):
        if co is not None and i == len(blocks) - 1:  # the layers, then the rest on their last elements
            surfs, a, o, lower, corners = _coarsening_layers(geo, lower, corners, co, s * co.z, s * co.dz)
            surfaces, axis, outer = surfaces + surfs, axis + a, outer + o
            columns = tuple(Column(r, 1) for r in co.radii[-1][1:])
        surfs, a, o, lower, corners = _column_block(geo, lower, corners, columns, s * z_end, n, ratio, split)
        surfaces, axis, outer = surfaces + surfs, axis + [a], outer + [o]
    return surfaces, axis, outer, lower


def _build_gmsh_model(scene: Scene):  # rank 0 only
    import gmsh

    hr = scene["fe.radial_size"]
    geo = gmsh.model.geo
    surfaces, tips, ends, axes, outers = {}, {}, {}, {}, {}
    info = {}
    for k, (layout, s) in enumerate(zip(rod_layouts(scene), (-1.0, 1.0), strict=True), start=1):
        rod, b, columns = layout.rod, layout.butterfly, layout.columns
        if b:
            cap = _butterfly_cap(geo, b, s, hr, layout.graded)
        else:
            cap = _flat_block_cap(geo, rod, s, columns)
        surfs, axis_curves, outer_curves, lower = _rod_body(geo, cap, layout, s)
        surfaces[k] = list(cap["surfaces"]) + surfs
        tips[k], ends[k], axes[k], outers[k] = (
            cap["tip"],
            [c[0] for c in lower],
            cap["axis"] + axis_curves,
            outer_curves,
        )
        sp = layout.spacing
        info[k] = (sum(c.n for c in columns), sp, cap.get("h_tip", sp.h_tip), cap["h_face"], columns, layout.coarsened)
    geo.synchronize()
    for k in (1, 2):
        gmsh.model.addPhysicalGroup(2, surfaces[k], TAGS[f"rod{k}"], name=f"rod{k}")
        gmsh.model.addPhysicalGroup(1, tips[k], TAGS[f"rod{k}_tip"], name=f"rod{k}_tip")
        gmsh.model.addPhysicalGroup(1, ends[k], TAGS[f"rod{k}_end"], name=f"rod{k}_end")
        gmsh.model.addPhysicalGroup(1, outers[k], TAGS[f"rod{k}_outer"], name=f"rod{k}_outer")
    gmsh.model.addPhysicalGroup(1, axes[1] + axes[2], TAGS["axis"], name="axis")
    gmsh.model.mesh.generate(2)
    return info


def start_gmsh() -> None:
    """``gmsh.initialize`` keeping this process's SIGINT and SIGTERM handlers (rods.interrupt's): gmsh sets SIGTERM's
    C-level handler back to the default, so a SIGTERM during the set-up (a SLURM time limit in a 3D mesh's
    generation) killed the rank, exit 15, no line, the folder's lock left (an audit, 2026-12-07; Python's record of
    the handler stayed, so reinstalling it restores the C-level one). Not interruptible: gmsh's own SIGINT handler
    would leave the mesh half-built without telling Python. A SIGTERM within gmsh.initialize itself (~2 ms, gmsh's
    handler in place) ends the rank with 15 (blocking the signal in the main thread does not hold it back: the
    process's other threads take it), so the entry points start gmsh on rank 0 before their handlers go in
    (workflows/_cli.py ``_start_gmsh``); a start here afresh keeps that window."""
    import signal
    import threading

    import gmsh

    keep = threading.current_thread() is threading.main_thread()  # only the main thread may set handlers
    handlers = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)} if keep else {}
    gmsh.initialize(interruptible=False)
    for s, handler in handlers.items():
        if handler is not None:  # None: set from outside Python, nothing to put back
            signal.signal(s, handler)


def gmsh_to_dolfinx(build: Callable[[], Any], comm: MPI.Comm, gdim: int) -> tuple[Any, Any]:
    """Run ``build()`` (which fills the current gmsh model) on rank 0 only, broadcast what it returns,
    and distribute the mesh with dolfinx.io.gmsh.model_to_mesh; returns (MeshData, build's result)."""
    import gmsh

    info = None
    started = False
    if comm.rank == 0:
        if not gmsh.isInitialized():
            start_gmsh()
            started = True
        terminal = gmsh.option.getNumber("General.Terminal")  # a caller's own gmsh session gets its setting back
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("rods")
        info = build()
    info = comm.bcast(info, root=0)
    try:
        data = dolfinx.io.gmsh.model_to_mesh(gmsh.model if comm.rank == 0 else None, comm, 0, gdim=gdim)
    finally:
        if comm.rank == 0:
            gmsh.model.remove()
            if started:
                gmsh.finalize()
            else:
                gmsh.option.setNumber("General.Terminal", terminal)
    return data, info


def build_mesh(scene: Scene, comm: MPI.Comm = MPI.COMM_WORLD) -> RodsMesh:
    """Mesh both rods (gmsh on rank 0) and distribute; see the module docstring for the layout."""
    data, info = gmsh_to_dolfinx(lambda: _build_gmsh_model(scene), comm, gdim=2)
    msh = data.mesh
    msh.topology.create_connectivity(msh.topology.dim - 1, msh.topology.dim)
    sp1, sp2 = info[1][1], info[2][1]
    graded = tuple(len(info[k][4]) > 1 for k in (1, 2))
    return RodsMesh(
        mesh=msh,
        cell_tags=data.cell_tags,
        facet_tags=data.facet_tags,
        n_radial=max(info[1][0], info[2][0]),
        n_axial=(sp1.n, sp2.n),
        h_radial=max(info[1][3], info[2][3]),  # the larger node spacing along the two tip faces' cores
        h_tip=min(info[1][2], info[2][2]),
        h_axial=scene["fe.axial_size"],
        graded=graded,  # type: ignore[arg-type]
        core_radius=min((info[k][4][0].r_end for k in (1, 2) if graded[k - 1]), default=math.inf),
        h_rim=max((float(element_sizes(info[k][4]).max()) for k in (1, 2) if graded[k - 1]), default=0.0),
        coarsened=(info[1][5], info[2][5]),
    )


def cell_sizes(msh: dolfinx.mesh.Mesh) -> tuple[float, float]:
    """Smallest radial and axial cell extents [m] over all ranks (bounding boxes of the cells)."""
    x = msh.geometry.x[:, :2][msh.geometry.dofmaps[0]]  # (cells, nodes, 2)
    ext = x.max(axis=1) - x.min(axis=1)
    n = msh.topology.index_map(msh.topology.dim).size_local
    local = ext[:n].min(axis=0) if n else np.array([np.inf, np.inf])
    return tuple(float(msh.comm.allreduce(v, op=MPI.MIN)) for v in local)
