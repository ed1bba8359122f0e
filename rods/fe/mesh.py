"""Structured (r, z) quadrilateral mesh of both rods for the axisymmetric global model (paper Sec. 2.2).

Layout (x = r >= 0, y = z along the common axis; SI units, metres):

* Rod 2 occupies ``z >= 0``: its tip apex sits at the origin, the far end is the plane ``z = L2``.
* Rod 1 occupies ``z <= 0``: its cap apex touches Rod 2 at the origin at t = 0, the far end is
  ``z = -L1`` (lengths measured along the axis from the apex).
* A curved tip of radius r_k is the spherical cap ``z = ±(r_k - sqrt(r_k² - r²))`` (height
  :attr:`rods.scene.Rod.cap_height` at r = d/2); a flat tip is the plane ``z = 0``.
* The tip face is the bottom of the first block, from the apex to the rim; a near-hemispherical cap (rim angle
  asin(d/2r_k) above :data:`BUTTERFLY_ANGLE`) is instead three blocks of its own (:func:`butterfly`), since one
  block's corner at the rim would be a 180° angle whose element sets the stable step.

The mesh is built by gmsh on rank 0 only (transfinite + recombine: structured quadrilaterals) and
distributed with :func:`dolfinx.io.gmsh.model_to_mesh`. The two rods are separate gmsh surfaces
with their own points: they share no nodes and interact only through contact. An optional geometric
grading (``fe.tip_grading`` g < 1) inserts a graded block next to each tip whose first element is
``g x fe.axial_size`` long and grows by a constant ratio up to ``fe.axial_size``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import dolfinx
import dolfinx.io.gmsh
import numpy as np
from mpi4py import MPI

from rods.scene import Rod, Scene

__all__ = ["TAGS", "RodsMesh", "axial_spacing", "build_mesh", "element_count", "mesh_counts"]

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

GROWTH = 1.2  # target size ratio between neighbouring elements in a graded tip block [-]


@dataclass
class RodsMesh:
    mesh: dolfinx.mesh.Mesh
    cell_tags: dolfinx.mesh.MeshTags
    facet_tags: dolfinx.mesh.MeshTags
    n_radial: int  # elements across the radius [-]
    n_axial: tuple[int, int]  # elements along rod 1, rod 2 [-]
    h_radial: float  # element size along the tip faces (radial; on a curved face along its arc) [m]
    h_tip: float  # axial size of the element at the tips (normal to the contact face) [m]
    h_axial: float  # nominal axial element size [m]


@dataclass(frozen=True)
class AxialSpacing:
    """Graded block at the tip (``n_graded`` elements, ratio ``ratio``, length ``graded_length``)
    followed by ``n_uniform`` uniform elements."""

    n_graded: int
    ratio: float
    graded_length: float  # [m]
    n_uniform: int
    h_tip: float  # [m]


def element_count(length: float, h: float) -> int:
    """Elements of about size ``h`` [m] over ``length`` [m]: at least one, rounded up, with 1e-9 of slack so a
    length that is a whole number of sizes up to round-off gets no extra element."""
    return max(1, math.ceil(length / h - 1e-9))


def axial_spacing(rod: Rod, h: float, grading: float) -> AxialSpacing:
    """Element counts along one rod for nominal size ``h`` [m] and tip grading ``g`` (h_tip = g h)."""
    L = rod.length
    if grading >= 1.0:
        n = element_count(L, h)
        return AxialSpacing(0, 1.0, 0.0, n, L / n)
    n_g = max(1, math.ceil(math.log(1.0 / grading) / math.log(GROWTH)))
    q = (1.0 / grading) ** (1.0 / n_g)  # sizes g h q^k, k = 0..n_g-1; the last is h / q
    a = grading * h  # the tip element [m]
    length = a * (q**n_g - 1.0) / (q - 1.0)
    cap = rod.cap_height
    if length < 2.0 * cap:  # keep the block's flat side clear of the cap: a longer block, the same tip element
        length = 2.0 * cap + h
        n_g, q = _graded_counts(a, length, h, n_g)
    n_u = element_count(L - length, h)
    return AxialSpacing(n_g, q, length, n_u, a)


def _graded_counts(a: float, length: float, h: float, n0: int) -> tuple[int, float]:
    """(n, q): the fewest n >= ``n0`` elements growing by q <= GROWTH from ``a`` [m] that fill ``length`` [m],
    a (q^n - 1)/(q - 1) = length, with none longer than ``h`` [m] (a deep cap's long graded block keeps the
    tip element; stretching the block's elements instead made it 2.2x longer on a 30 mm rod, 35 mm tip)."""
    n = n0
    while True:
        if n * a >= length:  # uniform elements of length/n <= a fill it
            return n, 1.0
        lo, hi = 1.0, GROWTH
        if a * (hi**n - 1.0) / (hi - 1.0) >= length:
            for _ in range(200):  # bisection: the block's length grows with q
                q = 0.5 * (lo + hi)
                lo, hi = (q, hi) if a * (q**n - 1.0) / (q - 1.0) < length else (lo, q)
            if a * hi ** (n - 1) <= h:
                return n, hi
        n += 1


BUTTERFLY_ANGLE = math.radians(70.0)  # rim angle asin(R/r_k) above which a cap is meshed as a butterfly [rad]


@dataclass(frozen=True)
class Butterfly:
    """Layout of a near-hemispherical cap (:func:`butterfly`), in (r, depth from the apex) [m].

    The single transfinite block of a flatter cap has a corner where the arc meets the cylinder; its angle is
    90° + the rim angle asin(R/r_k), so a hemisphere's corner element degenerates (180°) and sets the stable
    step: 0.95 ns instead of 19 ns on the paper rods with a 6.35 mm tip (277 402 steps for the contact phase).
    The butterfly splits the cap into three blocks without such a corner: two bands of thickness ``t`` along
    the arc (apex A to P, P to the rim E) around a core (D, C, G, O) whose far side O-G lies in the rim plane.
    ``t`` and P make every block's edges about equally long: t = (cap + R - r_k φ)/2 (> 0 for every φ) and
    the arc A-P is R - t long, P-E cap - t."""

    t: float  # thickness of the bands along the arc [m]
    theta_p: float  # polar angle of P seen from the sphere's centre [rad]
    points: dict[str, tuple[float, float]]  # A, P, E, G, O, D, C and the centre Oc

    @property
    def arcs(self) -> tuple[float, float]:
        """Lengths of the arcs A-P and P-E [m]."""
        rt = self.points["Oc"][1]
        return rt * self.theta_p, rt * (math.asin(self.points["E"][0] / rt) - self.theta_p)


def butterfly(rod: Rod) -> Butterfly | None:
    """The butterfly layout of ``rod``'s cap, or None where one transfinite block serves (flat or flatter tips,
    rim angle up to :data:`BUTTERFLY_ANGLE`: the paper's 35 mm tip has 10.4°)."""
    rt, R = rod.tip_radius, rod.diameter / 2
    if math.isinf(rt) or R / rt <= math.sin(BUTTERFLY_ANGLE):
        return None
    phi, cap = math.asin(R / rt), rod.cap_height
    t = 0.5 * (cap + R - rt * phi)
    th = (R - t) / rt
    P = (rt * math.sin(th), rt * (1.0 - math.cos(th)))
    C = (P[0] * (1.0 - t / rt), P[1] + t * (rt - P[1]) / rt)  # P moved by t along the normal to the centre
    pts = {"A": (0.0, 0.0), "P": P, "E": (R, cap), "G": (R - t, cap), "O": (0.0, cap), "D": (0.0, t), "C": C}
    return Butterfly(t, th, {**pts, "Oc": (0.0, rt)})


def tip_arc_length(rod: Rod) -> float:
    """Length [m] of the tip face's profile from the apex to the rim: R flat, r_t asin(R/r_t) on a spherical cap."""
    R, rt = rod.diameter / 2, rod.tip_radius
    return R if math.isinf(rt) else rt * math.asin(min(1.0, R / rt))


def face_count(rod: Rod, hr: float) -> int:
    """Elements along a one-block tip face at size ``hr`` [m], counted on its arc, so that a curved face's nodes
    are as far apart as the flat face's it meets (divided by the radius, a 10 mm tip on 12.7 mm rods had them
    8% farther apart, and the one-pass node-to-surface contact lost 4.6% of the peak pressure at the axis)."""
    return element_count(tip_arc_length(rod), hr)


def butterfly_counts(b: Butterfly, hr: float) -> tuple[int, int, int]:
    """Elements (n_a, n_b, m) of a butterfly at size ``hr`` [m]: along the arcs A-P and P-E, across the bands."""
    n_a, n_b = (element_count(x, hr) for x in b.arcs)
    return n_a, n_b, element_count(b.t, hr)


def mesh_counts(rod: Rod, hr: float, h: float, grading: float) -> tuple[int, int]:
    """(cells, nodes) of one rod's mesh at radial size ``hr``, axial ``h`` [m] and tip grading (what the mesher
    makes). Nodes: a simply connected quadrilateral mesh has V = F + E_b/2 + 1 (Euler's V - E + F = 1 with
    4F = 2E - E_b), E_b its boundary edges: the tip, the axis, the outer surface and the far end; with a butterfly
    cap the tip's arcs A-P-E, the axis A-D-O and the shaft, the far end n_a + m wide."""
    sp = axial_spacing(rod, h, grading)
    n_z = sp.n_graded + sp.n_uniform
    b = butterfly(rod)
    if b is None:
        n = face_count(rod, hr)
        cells, half_boundary = n * n_z, n + n_z
    else:
        n_a, n_b, m = butterfly_counts(b, hr)
        cells, half_boundary = (n_a + n_b) * m + n_a * n_b + (n_a + m) * n_z, n_a + n_b + m + n_z
    return cells, cells + half_boundary + 1


def _butterfly_cap(geo, b: Butterfly, s: float, hr: float) -> dict[str, Any]:  # rank 0 only
    """Mesh a cap laid out as ``b`` (:func:`butterfly`; side ``s`` = -1: rod 1, +1: rod 2) in three blocks; returns
    the tip and axis curves, the rim line O-G-E (the next block's bottom), its end points and counts."""
    import gmsh

    p = {k: geo.addPoint(r, s * z, 0.0) for k, (r, z) in b.points.items()}
    n_a, n_b, m = butterfly_counts(b, hr)
    c = {
        "AP": (geo.addCircleArc(p["A"], p["Oc"], p["P"]), n_a),
        "PE": (geo.addCircleArc(p["P"], p["Oc"], p["E"]), n_b),
        "AD": (geo.addLine(p["A"], p["D"]), m),
        "PC": (geo.addLine(p["P"], p["C"]), m),
        "EG": (geo.addLine(p["E"], p["G"]), m),
        "DC": (geo.addLine(p["D"], p["C"]), n_a),
        "CG": (geo.addLine(p["C"], p["G"]), n_b),
        "DO": (geo.addLine(p["D"], p["O"]), n_b),
        "OG": (geo.addLine(p["O"], p["G"]), n_a),
    }
    T = {k: v[0] for k, v in c.items()}
    loops = (
        [T["AP"], T["PC"], -T["DC"], -T["AD"]],  # the band along the arc from the apex
        [T["PE"], T["EG"], -T["CG"], -T["PC"]],  # the band to the rim
        [T["DC"], T["CG"], -T["OG"], -T["DO"]],  # the core
    )
    surfaces = [geo.addPlaneSurface([geo.addCurveLoop(loop)]) for loop in loops]
    geo.synchronize()
    for tag, n in c.values():
        gmsh.model.geo.mesh.setTransfiniteCurve(tag, n + 1)
    for surf in surfaces:
        gmsh.model.geo.mesh.setTransfiniteSurface(surf)
        gmsh.model.geo.mesh.setRecombine(2, surf)
    return {
        "surfaces": surfaces,
        "tip": [T["AP"], T["PE"]],
        "axis": [T["AD"], T["DO"]],
        "rim": [T["OG"], -T["EG"]],  # O -> G -> E
        "corners": (p["O"], p["E"]),
        "n_cross": n_a + m,
        "h_tip": b.t / m,  # the element normal to the contact face at the apex [m]
        "h_face": max(length / n for length, n in zip(b.arcs, (n_a, n_b), strict=True)),  # along the face [m]
    }


def _flat_block_cap(geo, rod: Rod, s: float, hr: float) -> dict[str, Any]:  # rank 0 only
    """The tip face of a flat or flatter curved tip: the first block's bottom, from the apex to the rim."""
    R, cap = rod.diameter / 2, rod.cap_height
    p_apex, p_edge = geo.addPoint(0.0, 0.0, 0.0), geo.addPoint(R, s * cap, 0.0)
    if math.isinf(rod.tip_radius):
        tip = geo.addLine(p_apex, p_edge)
    else:
        tip = geo.addCircleArc(p_apex, geo.addPoint(0.0, s * rod.tip_radius, 0.0), p_edge)
    n_r = face_count(rod, hr)
    return {"surfaces": [], "tip": [tip], "axis": [], "rim": [tip], "corners": (p_apex, p_edge), "n_cross": n_r,
            "h_face": tip_arc_length(rod) / n_r}  # fmt: skip


def _build_gmsh_model(scene: Scene):  # rank 0 only
    import gmsh

    hr = scene["fe.radial_size"]
    h = scene["fe.axial_size"]
    g = scene.tip_grading
    geo = gmsh.model.geo
    surfaces, tips, ends, axes, outers = {}, {}, {}, {}, {}
    info = {}
    for k, (rod, s) in enumerate(((scene.rod1, -1.0), (scene.rod2, 1.0)), start=1):
        R = rod.diameter / 2
        sp = axial_spacing(rod, h, g)
        b = butterfly(rod)
        cap = _butterfly_cap(geo, b, s, hr) if b else _flat_block_cap(geo, rod, s, hr)
        n_r = cap["n_cross"]
        # axial stations: optional graded block, then the uniform block to the far end
        blocks = []
        if sp.n_graded:
            blocks.append((s * sp.graded_length, sp.n_graded, sp.ratio))
        blocks.append((s * rod.length, sp.n_uniform, 1.0))
        (lower_axis, lower_outer), lower = cap["corners"], cap["rim"]
        surfaces[k], axis_curves, outer_curves = list(cap["surfaces"]), list(cap["axis"]), []
        for z_end, n, ratio in blocks:
            pa = geo.addPoint(0.0, z_end, 0.0)
            po = geo.addPoint(R, z_end, 0.0)
            c_axis = geo.addLine(lower_axis, pa)  # oriented away from the tip
            c_outer = geo.addLine(lower_outer, po)
            c_top = geo.addLine(pa, po)
            surf = geo.addPlaneSurface([geo.addCurveLoop([*lower, c_outer, -c_top, -c_axis])])
            geo.synchronize()
            for c in (c_axis, c_outer):
                gmsh.model.geo.mesh.setTransfiniteCurve(c, n + 1, "Progression", ratio)
            gmsh.model.geo.mesh.setTransfiniteCurve(c_top, n_r + 1)
            if len(lower) == 1:
                gmsh.model.geo.mesh.setTransfiniteCurve(lower[0], n_r + 1)
                gmsh.model.geo.mesh.setTransfiniteSurface(surf)
            else:  # a butterfly's rim line O-G-E is two curves: name the corners, G is none
                gmsh.model.geo.mesh.setTransfiniteSurface(surf, "Left", [lower_axis, lower_outer, po, pa])
            gmsh.model.geo.mesh.setRecombine(2, surf)
            surfaces[k].append(surf)
            axis_curves.append(c_axis)
            outer_curves.append(c_outer)
            lower_axis, lower_outer, lower = pa, po, [c_top]
        tips[k], ends[k], axes[k], outers[k] = cap["tip"], lower, axis_curves, outer_curves
        info[k] = (n_r, sp, cap.get("h_tip", sp.h_tip), cap["h_face"])
    geo.synchronize()
    for k in (1, 2):
        gmsh.model.addPhysicalGroup(2, surfaces[k], TAGS[f"rod{k}"], name=f"rod{k}")
        gmsh.model.addPhysicalGroup(1, tips[k], TAGS[f"rod{k}_tip"], name=f"rod{k}_tip")
        gmsh.model.addPhysicalGroup(1, ends[k], TAGS[f"rod{k}_end"], name=f"rod{k}_end")
        gmsh.model.addPhysicalGroup(1, outers[k], TAGS[f"rod{k}_outer"], name=f"rod{k}_outer")
    gmsh.model.addPhysicalGroup(1, axes[1] + axes[2], TAGS["axis"], name="axis")
    gmsh.model.mesh.generate(2)
    return info


def gmsh_to_dolfinx(build: Callable[[], Any], comm: MPI.Comm, gdim: int) -> tuple[Any, Any]:
    """Run ``build()`` (which fills the current gmsh model) on rank 0 only, broadcast what it returns,
    and distribute the mesh with dolfinx.io.gmsh.model_to_mesh; returns (MeshData, build's result)."""
    import gmsh

    info = None
    started = False
    if comm.rank == 0:
        if not gmsh.isInitialized():
            gmsh.initialize(interruptible=False)
            started = True
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
    return data, info


def build_mesh(scene: Scene, comm: MPI.Comm = MPI.COMM_WORLD) -> RodsMesh:
    """Mesh both rods (gmsh on rank 0) and distribute; see the module docstring for the layout."""
    data, info = gmsh_to_dolfinx(lambda: _build_gmsh_model(scene), comm, gdim=2)
    msh = data.mesh
    msh.topology.create_connectivity(msh.topology.dim - 1, msh.topology.dim)
    n_r = info[1][0]
    sp1, sp2 = info[1][1], info[2][1]
    return RodsMesh(
        mesh=msh,
        cell_tags=data.cell_tags,
        facet_tags=data.facet_tags,
        n_radial=n_r,
        n_axial=(sp1.n_graded + sp1.n_uniform, sp2.n_graded + sp2.n_uniform),
        h_radial=max(info[1][3], info[2][3]),  # the larger node spacing along the two tip faces
        h_tip=min(info[1][2], info[2][2]),
        h_axial=scene["fe.axial_size"],
    )


def cell_sizes(msh: dolfinx.mesh.Mesh) -> tuple[float, float]:
    """Smallest radial and axial cell extents [m] over all ranks (bounding boxes of the cells)."""
    x = msh.geometry.x[:, :2][msh.geometry.dofmaps[0]]  # (cells, nodes, 2)
    ext = x.max(axis=1) - x.min(axis=1)
    n = msh.topology.index_map(msh.topology.dim).size_local
    local = ext[:n].min(axis=0) if n else np.array([np.inf, np.inf])
    return tuple(float(msh.comm.allreduce(v, op=MPI.MIN)) for v in local)
