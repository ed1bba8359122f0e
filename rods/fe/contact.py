"""Two-body node-to-surface penalty contact between the rod tips (paper Sec. 2.2: "penalty algorithm").

Slaves are the nodes of the Rod-1 tip face, the master is the Rod-2 tip face, interpolated linearly
in r between its nodes. With u_z the axial displacements, the gap of slave s is

    g_s = z_m(r_s) - z_s = [Σ_j W_sj (Z_j + u_z,j)] - (Z_s + u_z,s)       [m]

(Z: reference axial coordinates, W: linear interpolation weights of the master nodes at r_s). The
initial gap g_s(0) carries the tip profiles (the 35 mm cap against the flat), so contact grows from the
axis outwards as in Hertz theory. Assumptions: small displacements — the interpolation weights are
taken at the reference radii (radial motion of the faces ~µm against 0.25 mm elements) and the
contact normal is the axis; frictionless.

Pressure (penalty law) p_s = ε_pen <-g_s>, ε_pen = fe.penalty x E*/h_n [Pa/m], with E* the contact
modulus (paper Eq. 8) and h_n the element size normal to the face: fe.penalty = 1 gives a contact
layer as stiff as one element of the softer rod. Nodal force F_s = p_s a_s, a_s the row-sum tributary
area ∫ N_s 2πr ds over the Rod-1 tip; the reaction W_sj F_s goes to the master nodes, so the
pair forces cancel exactly (momentum is conserved to round-off). The force derives from the penalty
energy E_c = ½ Σ ε_pen a_s <-g_s>², so it is conservative.

MPI: the tip arrays are small (tens of nodes); every rank holds all of them, in r order, and the owned
axial displacements are summed into them with one Allreduce per step; every rank then evaluates the
identical contact law and adds the forces of the nodes it owns.
"""

from __future__ import annotations

from dataclasses import dataclass

import dolfinx
import numpy as np
from mpi4py import MPI

__all__ = ["PenaltyContact", "TipNodes", "tip_nodes"]


@dataclass
class TipNodes:
    """Nodes of one tip face, identical on every rank, sorted by r."""

    r: np.ndarray  # reference radius [m]
    z: np.ndarray  # reference axial coordinate [m]
    area: np.ndarray  # row-sum tributary area ∫ N 2πr ds [m^2]
    local: np.ndarray  # owned-array index of the u_z entry of the nodes this rank owns
    pos: np.ndarray  # their positions in the sorted arrays


def tip_nodes(V: dolfinx.fem.FunctionSpace, facets: np.ndarray, area_vec: np.ndarray, axial: int) -> TipNodes:
    """Collect the nodes of the tip facets ``facets``; ``area_vec`` is the owned, assembled a_i vector."""
    msh = V.mesh
    comm = msh.comm
    imap = V.dofmap.index_map
    bs = V.dofmap.index_map_bs
    nodes = dolfinx.fem.locate_dofs_topological(V, msh.topology.dim - 1, facets)
    nodes = nodes[nodes < imap.size_local]
    x = V.tabulate_dof_coordinates()[nodes]
    gidx = imap.local_to_global(nodes.astype(np.int32))
    local = nodes * bs + axial
    rows = np.column_stack([gidx.astype(float), x[:, 0], x[:, 1], area_vec[local]])
    allrows = np.vstack(comm.allgather(rows))
    order = np.lexsort((allrows[:, 0], allrows[:, 1]))  # by r, ties by global index
    allrows = allrows[order]
    rank_of = np.concatenate([np.full(len(rr), i) for i, rr in enumerate(comm.allgather(rows))])[order]
    mine = np.flatnonzero(rank_of == comm.rank)
    # map my sorted positions back to my local entries (same global index)
    g_local = {int(g): loc for g, loc in zip(gidx, local, strict=True)}
    my_local = np.array([g_local[int(allrows[p, 0])] for p in mine], dtype=np.int64)
    return TipNodes(allrows[:, 1].copy(), allrows[:, 2].copy(), allrows[:, 3].copy(), my_local, mine)


class PenaltyContact:
    """Node-to-surface penalty contact (see module docstring); all arrays in SI units."""

    def __init__(self, slave: TipNodes, master: TipNodes, ε_pen: float, comm: MPI.Comm):
        self.slave, self.master, self.ε, self.comm = slave, master, ε_pen, comm
        rm = master.r
        j = np.clip(np.searchsorted(rm, slave.r, side="right") - 1, 0, max(len(rm) - 2, 0))
        t = (slave.r - rm[j]) / np.where(rm[j + 1] > rm[j], rm[j + 1] - rm[j], 1.0)
        self.inside = (t >= -1e-12) & (t <= 1 + 1e-12)  # slaves over the master face
        t = np.clip(t, 0.0, 1.0)
        self.j0, self.j1 = j, j + 1
        self.w0, self.w1 = 1.0 - t, t
        self.g0 = self.w0 * master.z[j] + self.w1 * master.z[j + 1] - slave.z  # initial gap [m]
        self.k = np.where(self.inside, ε_pen * slave.area, 0.0)  # nodal penalty stiffness [N/m]
        self.ns, self.nm = len(slave.r), len(master.r)
        self._buf = np.zeros(self.ns + self.nm)
        self.serial = comm.size == 1
        # state of the last evaluation
        self.gap = self.g0.copy()
        self.pressure = np.zeros(self.ns)  # [Pa]
        self.force = 0.0  # total compressive contact force [N]
        self.energy = 0.0  # penalty energy [J]
        self._Fs, self._Fm = np.zeros(self.ns), np.zeros(self.nm)

    def gather(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Axial entries of the owned array ``x`` at all slave and master nodes (every rank)."""
        b = self._buf
        if self.serial:
            b[self.slave.pos] = x[self.slave.local]
            b[self.ns + self.master.pos] = x[self.master.local]
        else:
            b[:] = 0.0
            b[self.slave.pos] = x[self.slave.local]
            b[self.ns + self.master.pos] = x[self.master.local]
            self.comm.Allreduce(MPI.IN_PLACE, b, op=MPI.SUM)
        return b[: self.ns], b[self.ns :]

    def _scatter(self, f: np.ndarray, fs: np.ndarray, fm: np.ndarray) -> None:  # fs, fm: all tip nodes
        """f[owned slave/master axial entries] += fs, fm (forces as arrays over all tip nodes)."""
        f[self.slave.local] += fs[self.slave.pos]
        f[self.master.local] += fm[self.master.pos]

    def evaluate(self, u: np.ndarray) -> None:
        """Contact state at displacement ``u`` (owned array): gaps, pressures, nodal forces, energy."""
        us, um = self.gather(u)
        g = self.g0 + self.w0 * um[self.j0] + self.w1 * um[self.j1] - us
        pen = np.maximum(-g, 0.0) * self.inside  # penetration [m]
        F = self.k * pen  # compressive nodal forces on the slaves [N]
        self._Fs = F
        self._Fm = np.bincount(self.j0, self.w0 * F, self.nm) + np.bincount(self.j1, self.w1 * F, self.nm)
        self.gap = g
        self.pressure = self.ε * pen
        self.force = float(F.sum())
        self.energy = 0.5 * float(np.dot(self.k, pen * pen))

    def add_force(self, y: np.ndarray, scale: np.ndarray | None = None) -> None:
        """y += scale ⊙ f_c for the owned tip entries: f_c = -F on the slaves (pushed along -z),
        +Wᵀ F on the master nodes (the reaction). ``scale`` (e.g. Δt M^-1) defaults to 1."""
        ls, lm = self.slave.local, self.master.local
        fs, fm = -self._Fs[self.slave.pos], self._Fm[self.master.pos]
        if scale is not None:
            fs, fm = fs * scale[ls], fm * scale[lm]
        y[ls] += fs
        y[lm] += fm

    def add_internal(self, u: np.ndarray, f: np.ndarray) -> None:
        """Evaluate at ``u`` and subtract the contact force from ``f`` (internal forces K u - f_c)."""
        self.evaluate(u)
        self._sub(f)

    def _sub(self, f: np.ndarray) -> None:
        f[self.slave.local] += self._Fs[self.slave.pos]
        f[self.master.local] -= self._Fm[self.master.pos]

    def apply_stiffness(self, x: np.ndarray, y: np.ndarray) -> None:
        """y += K_c x with every potential contact pair active (full engagement): K_c = Σ k_s b_s b_sᵀ."""
        xs, xm = self.gather(x)
        t = self.k * (self.w0 * xm[self.j0] + self.w1 * xm[self.j1] - xs)
        ym = np.bincount(self.j0, self.w0 * t, self.nm) + np.bincount(self.j1, self.w1 * t, self.nm)
        self._scatter(y, -t, ym)

    def radius(self) -> float:
        """Contact radius [m]: the gap's zero crossing beyond the outermost active slave (linear)."""
        act = np.flatnonzero(self.pressure > 0)
        if act.size == 0:
            return 0.0
        k = act[-1]
        r, g = self.slave.r, self.gap
        if k + 1 < self.ns and g[k + 1] > g[k]:
            return float(r[k] + (r[k + 1] - r[k]) * (-g[k]) / (g[k + 1] - g[k]))
        return float(r[k])

    def active_area(self) -> float:
        """Sum of the tributary areas of the active slaves [m^2] (a node-based area, as FE codes report)."""
        return float(self.slave.area[self.pressure > 0].sum())
