"""Structured (r, z) quadrilateral mesh of both rods for the axisymmetric global model (paper Sec. 2.2).

Layout (x = r >= 0, y = z along the common axis; SI units, metres):

* Rod 2 occupies ``z >= 0``: its tip apex sits at the origin, the far end is the plane ``z = L2``.
* Rod 1 occupies ``z <= 0``: its cap apex touches Rod 2 at the origin at t = 0, the far end is
  ``z = -L1`` (lengths measured along the axis from the apex).
* A curved tip of radius r_k is the spherical cap ``z = ±(r_k - sqrt(r_k² - r²))`` (height
  :attr:`rods.scene.Rod.cap_height` at r = d/2); a flat tip is the plane ``z = 0``.

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

__all__ = ["TAGS", "RodsMesh", "axial_spacing", "build_mesh"]

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
    h_radial: float  # radial element size [m]
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


def axial_spacing(rod: Rod, h: float, grading: float) -> AxialSpacing:
    """Element counts along one rod for nominal size ``h`` [m] and tip grading ``g`` (h_tip = g h)."""
    L = rod.length
    if grading >= 1.0:
        n = max(1, math.ceil(L / h - 1e-9))
        return AxialSpacing(0, 1.0, 0.0, n, L / n)
    n_g = max(1, math.ceil(math.log(1.0 / grading) / math.log(GROWTH)))
    q = (1.0 / grading) ** (1.0 / n_g)  # sizes g h q^k, k = 0..n_g-1; the last is h / q
    length = grading * h * (q**n_g - 1.0) / (q - 1.0)
    cap = rod.cap_height
    if length < 2.0 * cap:  # keep the block's flat side clear of the cap
        length = 2.0 * cap + h
    n_u = max(1, math.ceil((L - length) / h - 1e-9))
    return AxialSpacing(n_g, q, length, n_u, grading * h)


def _build_gmsh_model(scene: Scene):  # rank 0 only
    import gmsh

    R, R2 = scene.rod1.diameter / 2, scene.rod2.diameter / 2  # [m]
    hr = scene["fe.radial_size"]
    h = scene["fe.axial_size"]
    g = scene.tip_grading
    geo = gmsh.model.geo
    surfaces, tips, ends, axes, outers = {}, {}, {}, {}, {}
    info = {}
    for k, (rod, s, Rk) in enumerate(((scene.rod1, -1.0, R), (scene.rod2, 1.0, R2)), start=1):
        n_r = max(1, math.ceil(Rk / hr - 1e-9))
        sp = axial_spacing(rod, h, g)
        cap = rod.cap_height
        p_apex = geo.addPoint(0.0, 0.0, 0.0)
        p_edge = geo.addPoint(Rk, s * cap, 0.0)
        if math.isinf(rod.tip_radius):
            tip = geo.addLine(p_apex, p_edge)
        else:
            centre = geo.addPoint(0.0, s * rod.tip_radius, 0.0)
            tip = geo.addCircleArc(p_apex, centre, p_edge)
        # axial stations: optional graded block, then the uniform block to the far end
        blocks = []
        if sp.n_graded:
            blocks.append((s * sp.graded_length, sp.n_graded, sp.ratio))
        blocks.append((s * rod.length, sp.n_uniform, 1.0))
        lower_axis, lower_outer, lower = p_apex, p_edge, tip
        axis_curves, outer_curves = [], []
        for z_end, n, ratio in blocks:
            pa = geo.addPoint(0.0, z_end, 0.0)
            po = geo.addPoint(Rk, z_end, 0.0)
            c_axis = geo.addLine(lower_axis, pa)  # oriented away from the tip
            c_outer = geo.addLine(lower_outer, po)
            c_top = geo.addLine(pa, po)
            loop = geo.addCurveLoop([lower, c_outer, -c_top, -c_axis])
            surf = geo.addPlaneSurface([loop])
            geo.synchronize()
            for c in (c_axis, c_outer):
                gmsh.model.geo.mesh.setTransfiniteCurve(c, n + 1, "Progression", ratio)
            for c in (lower, c_top):
                gmsh.model.geo.mesh.setTransfiniteCurve(c, n_r + 1)
            gmsh.model.geo.mesh.setTransfiniteSurface(surf)
            gmsh.model.geo.mesh.setRecombine(2, surf)
            surfaces.setdefault(k, []).append(surf)
            axis_curves.append(c_axis)
            outer_curves.append(c_outer)
            lower_axis, lower_outer, lower = pa, po, c_top
        tips[k], ends[k], axes[k], outers[k] = [tip], [lower], axis_curves, outer_curves
        info[k] = (n_r, sp)
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
        h_radial=scene.rod1.diameter / 2 / n_r,
        h_tip=min(sp1.h_tip, sp2.h_tip),
        h_axial=scene["fe.axial_size"],
    )


def cell_sizes(msh: dolfinx.mesh.Mesh) -> tuple[float, float]:
    """Smallest radial and axial cell extents [m] over all ranks (bounding boxes of the cells)."""
    x = msh.geometry.x[:, :2][msh.geometry.dofmaps[0]]  # (cells, nodes, 2)
    ext = x.max(axis=1) - x.min(axis=1)
    n = msh.topology.index_map(msh.topology.dim).size_local
    local = ext[:n].min(axis=0) if n else np.array([np.inf, np.inf])
    return tuple(float(msh.comm.allreduce(v, op=MPI.MIN)) for v in local)
