"""Point probes as precomputed linear maps: value = row · (owned dof array), one dot product per step.

A probe at a point X (a surface station: vibrometer and strain gauges sit on r = d/2) evaluates
u_z(X) = Σ_j N_j(X) u_z,j and ε_zz(X) = ∂u_z/∂z(X) = Σ_j ∂N_j/∂z(X) u_z,j. The rank owning the cell
containing X computes the basis values (pull-back to the reference cell, Jacobian of the coordinate
map); every rank keeps the entries of the dofs it owns, and the partial dot products are summed
with one Allreduce.
"""

from __future__ import annotations

import basix
import dolfinx
import dolfinx.geometry
import numpy as np
import scipy.sparse
from mpi4py import MPI

__all__ = ["PointProbes", "station_points"]


REFERENCE_TOL = 1e-8  # a point is in a cell whose reference coordinates lie in [0, 1] this far [-]


def _holds(X: np.ndarray) -> bool:
    """Whether reference coordinates ``X`` lie in the unit cell (to :data:`REFERENCE_TOL`)."""
    return bool(np.all(X >= -REFERENCE_TOL) and np.all(X <= 1.0 + REFERENCE_TOL))


def _cell_rows(V: dolfinx.fem.FunctionSpace, cell: int, point: np.ndarray, axial: int) -> tuple[np.ndarray, ...]:
    """Global vector indices, basis values and ∂/∂z of the basis at ``point`` in local ``cell``, and the point's
    reference coordinates there."""
    msh = V.mesh
    gdim = msh.geometry.dim
    cmap = msh.geometry.cmaps[0]
    xc = msh.geometry.x[msh.geometry.dofmaps[0][cell], :gdim]
    X = cmap.pull_back(point[None, :gdim], xc)
    cel = basix.create_element(
        basix.ElementFamily.P,
        basix.CellType.quadrilateral if gdim == 2 else basix.CellType.hexahedron,
        cmap.degree,
        basix.LagrangeVariant(cmap.variant),
    )
    dφ = cel.tabulate(1, X)[1:, 0, :, 0]  # (tdim, n_geom)
    J = xc.T @ dφ.T  # J_ij = ∂x_i/∂X_j
    tab = V.element.basix_element.tabulate(1, X)[:, 0, :, 0]  # (1 + tdim, ndofs)
    N = tab[0]
    dN = np.linalg.solve(J.T, tab[1:])  # ∇_x N = J^-T ∇_X N
    dofs = V.dofmap.cell_dofs(cell)
    bs = V.dofmap.index_map_bs
    g = V.dofmap.index_map.local_to_global(dofs.astype(np.int32)) * bs + axial
    return g, N, dN[axial], X[0]


class PointProbes:
    """Axial velocity/displacement and axial strain at points as one sparse map ``P`` (owned entries):
    (P x)[2i] is the axial value of x at point i, (P x)[2i + 1] its ∂/∂z; callers sum P x over the ranks.

    A point on the boundary of several cells (a station on a node) takes the mean over the cells that hold it (its
    reference coordinates in [0, 1] to :data:`REFERENCE_TOL`; the bounding-box test alone can name a neighbour, whose
    values would be extrapolated), whichever rank owns each: the value is continuous, so the same in each, and ∂/∂z,
    constant along z in a Q1 cell and jumping at the node, becomes the mean of the cells' values (on these extruded
    meshes as many cells lie on either side, so the mean of the one-sided values). The first cell found on the
    lowest rank was taken before, which depended on the partition: 6.6% of the column's largest strain between 1 and
    2 ranks at a node on a rank boundary (a fuzz, 2026-12-07)."""

    def __init__(self, V: dolfinx.fem.FunctionSpace, points: np.ndarray, axial: int):
        msh = V.mesh
        comm = msh.comm
        tdim = msh.topology.dim
        n_owned_cells = msh.topology.index_map(tdim).size_local
        pts = np.zeros((len(points), 3))
        pts[:, : points.shape[1]] = points
        tree = dolfinx.geometry.bb_tree(msh, tdim)
        cand = dolfinx.geometry.compute_collisions_points(tree, pts)
        coll = dolfinx.geometry.compute_colliding_cells(msh, cand, pts)
        mine = [[c for c in coll.links(i) if c < n_owned_cells] for i in range(len(pts))]  # owned: each cell once
        found = {i: [_cell_rows(V, c, pts[i], axial) for c in cells] for i, cells in enumerate(mine) if cells}
        holding = {i: [r[:3] for r in rs if _holds(r[3])] for i, rs in found.items()}
        n_found, n_holding = (
            comm.allreduce(np.array([len(d.get(i, ())) for i in range(len(pts))], dtype=np.int64), op=MPI.SUM)
            for d in (found, holding)
        )  # every rank's cells of each point
        if (outside := np.flatnonzero(n_found == 0)).size:
            raise ValueError(f"probe point {points[outside[0]]} lies outside the mesh")
        # the cells that hold it; all the colliding ones where none does to the tolerance (decided on every rank alike)
        rows = {i: holding[i] if n_holding[i] else [r[:3] for r in rs] for i, rs in found.items()}
        counts = np.where(n_holding > 0, n_holding, n_found)
        allrows: dict[int, list] = {i: [] for i in range(len(pts))}
        for d in comm.allgather(rows):
            for i, cell_rows in d.items():
                allrows[i] += cell_rows
        bs = V.dofmap.index_map_bs
        lo = V.dofmap.index_map.local_range[0] * bs
        n_local = V.dofmap.index_map.size_local * bs
        data, ri, ci = [], [], []
        for i in range(len(pts)):
            for g, N, dNz in allrows[i]:  # the mean over the cells (duplicate entries add up in the CSR)
                keep = (g >= lo) & (g < lo + n_local)
                for row, w in ((2 * i, N), (2 * i + 1, dNz)):
                    data.append(w[keep] / counts[i])
                    ri.append(np.full(keep.sum(), row))
                    ci.append(g[keep] - lo)
        self.P = scipy.sparse.csr_matrix(
            (np.concatenate(data), (np.concatenate(ri), np.concatenate(ci))), shape=(2 * len(pts), n_local)
        )


def station_points(scene, rm, three_d: bool) -> tuple[np.ndarray, list[tuple[str, str]]]:
    """The probes' points [m] and their (velocity, strain) history keys: the scene's stations on the rod surface
    (r = d/2): Rod 2 at z = +x, Rod 1 at z = -x from the tip (3D: at x = +d/2, y = 0, Rod 1's placed with the
    rod by ``rm.placement``), then in 3D Rod 2's midpoint at x = ±R2 (a quarter model holds x >= 0 only: its -x
    side is the mirror image of its +x side)."""
    pts, keys = [], [(f"{s.name}_velocity", f"{s.name}_strain") for s in scene.stations]
    for s in scene.stations:
        rod = scene.rods[s.rod - 1]
        if not three_d:
            pts.append([rod.diameter / 2, s.position if s.rod == 2 else -s.position])
        elif s.rod == 2:
            pts.append([rod.diameter / 2, 0.0, s.position])
        else:
            pts.append(rm.placement.apply(np.array([[rod.diameter / 2, 0.0, -s.position]]))[0])
    if three_d:
        R2, z_mid = scene.rod2.diameter / 2, scene.rod2.length / 2
        for side, x_side in (("plus_x", R2), ("minus_x", -R2)):
            pts.append([abs(x_side) if rm.symmetry == "quarter" else x_side, 0.0, z_mid])
            keys.append((f"rod2_mid_velocity_{side}", f"rod2_mid_strain_{side}"))
    return np.array(pts, dtype=float), keys
