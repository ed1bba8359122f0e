"""Two-body node-to-surface penalty contact between the rod tips (paper Sec. 2.2: "penalty algorithm"); the
default contact law is the penalty-free kinematic one (:mod:`rods.fe.kinematic`), which shares this pairing.

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
layer as stiff as one plane-strain element of each rod in series (E* = [(1 - ν1²)/E1 + (1 - ν2²)/E2]^-1; on two
equal steel rods 0.55 E/h, about 0.41 of one element's constrained modulus (λ + 2μ)/h). The factor moves the
answer (``benchmarks/contact_study.py``, ``results/contact-study.md``): a soft layer adds its compliance to the
Hertz contact and stretches the low-force tail of the release, a stiff one rattles and sharpens the wave fronts the
strain gauges see (RMS > 10 µε). Stiff penalties also limit the step (:func:`rods.fe.explicit.switching_step`).
Nodal force F_s = p_s a_s, a_s the row-sum tributary
area ∫ N_s 2πr ds over the Rod-1 tip; the reaction W_sj F_s goes to the master nodes, so the
pair forces cancel exactly (momentum is conserved to round-off). The force derives from the penalty
energy E_c = ½ Σ ε_pen a_s <-g_s>², so it is conservative.

Contact damping (``fe.contact_damping`` ζ, penalty law only): a stiff penalty layer makes the contact nodes
rattle at the pair frequency ω_s (:meth:`PenaltyContact.pair_frequency`), and the raw force peak is a rattle
spike (paper scene, 1 to 8 x E*/h undamped: raw peaks +0.17% to +2.2% against the analytical model while the
2 µs-smoothed peaks agree to 0.05%). Explicit codes damp the pair along the normal (LS-DYNA's VDC, Abaqus's
contact damping); here each pair gets the viscous force c_s (-ġ_s), c_s = 2 ζ sqrt(k_s m_s) with the pair's
reduced mass m_s = 1/(1/m_slave + Σ_j W_sj²/m_j), ġ_s the half-step rate (g_n - g_{n-1})/Δt (explicit, as
the central-difference velocity), and the total kept compressive: F_s = <k_s <-g_s> + c_s (-ġ_s)> while
g_s < 0. With the rate at the half step the damped pair is stable for ω_s Δt <= 2 (sqrt(1 + ζ²) - ζ), above
the switching limit ω_s Δt <= 1 for every allowed ζ <= 0.5. The damping's work over each step (trapezoid,
as the kinematic contact's) is counted as ``dissipated_energy``, so the energy balance stays closed.

Array backends (:mod:`rods.fe.backend`): the per-step law (gaps, forces, scatter) is written once against
the backend's array namespace; serial, the gaps are one sparse product g = g0 + B u with the gap operator B
(:meth:`PenaltyContact.gap_matrix`: -1 at the slave, W_sj at its master nodes), on a device one kernel
instead of the gather's and the interpolation's dozen; a device backend holds the pairing and the tip entries on
the device and copies back the total force and energy (and, damped, the damping's work) in one copy per
step, and the tip arrays (gap, pressure, forces) only when they are read.

MPI: the tip arrays are small (tens of nodes); every rank holds all of them, in r order, and the owned
axial displacements are summed into them with one Allreduce per step; every rank then evaluates the
identical contact law and adds the forces of the nodes it owns.

3D (the same class, the same law): slaves are the nodes of Rod 1's cap, the master is Rod 2's tip face,
a quadrilateral surface interpolated bilinearly, z_m(x, y) = Σ_j W_sj (Z_j + u_z,j) over the 4 nodes of
the face quadrilateral that contains the slave's (x, y). The pairing (:func:`bilinear_pairing`) is a
geometric search — a k-d tree of the face quadrilaterals' centroids and an inverse bilinear map —
run identically on every rank over the allgathered face (nodes and quadrilaterals), so the cap and the
face may sit on different ranks. It is computed once, at the reference (placed) positions, and kept
fixed: the same small-displacement assumption as in the axisymmetric case (lateral motion of the cap
~µm against 0.25 mm elements), which keeps the contact force conservative and momentum exact. The
contact normal is z (Rod 2's face). With a symmetry model (half, quarter) the force, energy and area
are reported for the full rods (x ``multiplicity``). Contact radius in 3D: r = sqrt(A/π) of the active
nodal area A (the paper's definition, Sec. 3), plus the patch's force-weighted centroid and its largest
node distance from the centroid (:meth:`PenaltyContact.patch`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import dolfinx
import numpy as np
import scipy.sparse
from mpi4py import MPI

from rods.fe.backend import PETSC, Backend, product

__all__ = ["PATCH_KEYS", "PenaltyContact", "TipNodes", "bilinear_pairing", "edge_radius", "face_quads", "tip_nodes"]

# 3D-only history/summary keys of the contact patch [m] (see PenaltyContact.patch)
PATCH_KEYS = ("contact_centroid_x", "contact_centroid_y", "contact_radius_max")


@dataclass
class TipNodes:
    """Nodes of one tip face, identical on every rank, sorted by r (3D: by r, x, y)."""

    r: np.ndarray  # reference radius [m]
    z: np.ndarray  # reference axial coordinate [m]
    area: np.ndarray  # row-sum tributary area ∫ N 2πr ds [m^2] (3D: ∫ N ds)
    local: np.ndarray  # owned-array index of the u_z entry of the nodes this rank owns
    pos: np.ndarray  # their positions in the sorted arrays
    xy: np.ndarray | None = None  # 3D: reference (x, y) [m], shape (n, 2)
    gid: np.ndarray | None = None  # global node (block) indices, for face_quads


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
    three_d = msh.geometry.dim == 3
    if three_d:  # columns: gid, r, z, area, x, y
        rows = np.column_stack([gidx.astype(float), np.hypot(x[:, 0], x[:, 1]), x[:, 2], area_vec[local], x[:, :2]])
    else:
        rows = np.column_stack([gidx.astype(float), x[:, 0], x[:, 1], area_vec[local]])
    allrows = np.vstack(comm.allgather(rows))
    if three_d:  # by r, x, y: independent of the partition
        order = np.lexsort((allrows[:, 0], allrows[:, 5], allrows[:, 4], allrows[:, 1]))
    else:
        order = np.lexsort((allrows[:, 0], allrows[:, 1]))  # by r, ties by global index
    allrows = allrows[order]
    rank_of = np.concatenate([np.full(len(rr), i) for i, rr in enumerate(comm.allgather(rows))])[order]
    mine = np.flatnonzero(rank_of == comm.rank)
    # map my sorted positions back to my local entries (same global index)
    g_local = {int(g): loc for g, loc in zip(gidx, local, strict=True)}
    my_local = np.array([g_local[int(allrows[p, 0])] for p in mine], dtype=np.int64)
    xy = allrows[:, 4:6].copy() if three_d else None
    gid = allrows[:, 0].astype(np.int64)
    return TipNodes(allrows[:, 1].copy(), allrows[:, 2].copy(), allrows[:, 3].copy(), my_local, mine, xy, gid)


def face_quads(V: dolfinx.fem.FunctionSpace, facets: np.ndarray, face: TipNodes) -> np.ndarray:
    """Quadrilaterals of the (hexahedral, P1) face ``facets`` as positions in ``face``'s sorted arrays,
    (n_q, 4) in counter-clockwise order in the x-y plane, sorted; identical on every rank (allgather)."""
    msh = V.mesh
    tdim = msh.topology.dim
    msh.topology.create_connectivity(tdim - 1, tdim)
    msh.topology.create_connectivity(tdim, tdim - 1)
    f2c, c2f = msh.topology.connectivity(tdim - 1, tdim), msh.topology.connectivity(tdim, tdim - 1)
    layout = V.dofmap.dof_layout
    imap = V.dofmap.index_map
    quads = []
    for f in facets:
        c = f2c.links(f)[0]
        lf = int(np.flatnonzero(c2f.links(c) == f)[0])
        dofs = V.dofmap.cell_dofs(c)[layout.entity_closure_dofs(tdim - 1, lf)]
        quads.append(imap.local_to_global(dofs.astype(np.int32)))
    allq = np.vstack([q for q in msh.comm.allgather(np.array(quads, dtype=np.int64).reshape(-1, 4)) if q.size])
    pos_of = {int(g): i for i, g in enumerate(face.gid)}
    q = np.vectorize(pos_of.__getitem__, otypes=[np.int64])(allq)
    xy = face.xy[q]  # (n_q, 4, 2)
    angle = np.arctan2(*(xy - xy.mean(axis=1, keepdims=True)).transpose(2, 0, 1)[::-1])
    q = np.take_along_axis(q, np.argsort(angle, axis=1), axis=1)
    q = _start_at_min(q)
    return np.unique(q, axis=0)


def _start_at_min(q: np.ndarray) -> np.ndarray:
    """Rotate each cyclic row to start at its smallest entry (a canonical form for np.unique)."""
    k = np.argmin(q, axis=1)
    idx = (k[:, None] + np.arange(q.shape[1])[None, :]) % q.shape[1]
    return np.take_along_axis(q, idx, axis=1)


def _bilinear(ξ: np.ndarray, η: np.ndarray) -> np.ndarray:
    """Q1 shape functions of the unit square at (ξ, η), nodes in cyclic order (0,0), (1,0), (1,1), (0,1)."""
    return np.stack([(1 - ξ) * (1 - η), ξ * (1 - η), ξ * η, (1 - ξ) * η], axis=-1)


def bilinear_pairing(
    xy_s: np.ndarray, xy_m: np.ndarray, quads: np.ndarray, k: int = 8, tol: float = 1e-9
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pair slaves at ``xy_s`` (n_s, 2) with the master quadrilaterals ``quads`` (positions in ``xy_m``).

    Geometric search: the ``k`` quadrilaterals with the nearest centroids (k-d tree) are tried in order
    of distance; the first whose inverse bilinear map (Newton, 12 iterations) gives (ξ, η) in
    [-tol, 1 + tol]² is taken. Returns (J, W, inside): master positions (n_s, 4), bilinear weights
    (n_s, 4; rows sum to 1) and whether the slave lies over the face (else W = 0, no contact).
    """
    from scipy.spatial import cKDTree

    n = len(xy_s)
    J, W = np.zeros((n, 4), dtype=np.int64), np.zeros((n, 4))
    inside = np.zeros(n, dtype=bool)
    if n == 0 or len(quads) == 0:
        return J, W, inside
    X = xy_m[quads]  # (n_q, 4, 2)
    k = min(k, len(quads))
    _, cand = cKDTree(X.mean(axis=1)).query(xy_s, k=k)
    cand = cand.reshape(n, k)
    for c in range(k):
        todo = np.flatnonzero(~inside)
        if todo.size == 0:
            break
        Xq = X[cand[todo, c]]  # (m, 4, 2)
        p = xy_s[todo]
        ξ, η = np.full(todo.size, 0.5), np.full(todo.size, 0.5)
        for _ in range(12):
            N = _bilinear(ξ, η)
            r = np.einsum("mi,mij->mj", N, Xq) - p
            dξ = np.stack([-(1 - η), 1 - η, η, -η], axis=-1)
            dη = np.stack([-(1 - ξ), -ξ, ξ, 1 - ξ], axis=-1)
            Jac = np.stack([np.einsum("mi,mij->mj", dξ, Xq), np.einsum("mi,mij->mj", dη, Xq)], axis=-1)
            step = np.linalg.solve(Jac, r[..., None])[..., 0]
            ξ, η = ξ - step[:, 0], η - step[:, 1]
        ok = (ξ >= -tol) & (ξ <= 1 + tol) & (η >= -tol) & (η <= 1 + tol)
        hit = todo[ok]
        inside[hit] = True
        J[hit] = quads[cand[hit, c]]
        W[hit] = _bilinear(np.clip(ξ[ok], 0.0, 1.0), np.clip(η[ok], 0.0, 1.0))
    return J, W, inside


def _interp(J, W, zm):
    """Σ_j W_sj zm_j at every slave (columns summed in order: the 2-node case is w0 z0 + w1 z1)."""
    out = W[:, 0] * zm[J[:, 0]]
    for c in range(1, J.shape[1]):
        out = out + W[:, c] * zm[J[:, c]]
    return out


def _transpose(xp, J, W, t, n_master: int, WT=None):
    """Wᵀ t: the slave values ``t`` distributed to the ``n_master`` master nodes (``xp``: numpy or cupy).
    ``WT``: Wᵀ as a sparse matrix of ``xp``'s namespace (:func:`transpose_matrix`), used where given (every
    backend's step arrays): on the host one product instead of a bincount per face corner (an audit of the loop's
    overhead, 2026-12-07: ~8 µs a closed step); on a device CuPy's bincount waits for the device (it reads max(J)
    and checks J >= 0 on the host), which inside a step waits for the step's matrix product and undoes the
    kinematic contact's overlap."""
    if WT is not None:
        return WT @ t
    out = xp.bincount(J[:, 0], weights=W[:, 0] * t, minlength=n_master)
    for c in range(1, J.shape[1]):
        out = out + xp.bincount(J[:, c], weights=W[:, c] * t, minlength=n_master)
    return out


def transpose_matrix(J: np.ndarray, W: np.ndarray, n_master: int) -> scipy.sparse.csr_matrix:
    """Wᵀ as a host CSR matrix [n_master x n_slave]: (Wᵀ t)_m = Σ_(s,c: J_sc = m) W_sc t_s, the sum of
    :func:`_transpose` (repeated masters of one slave summed)."""
    ns, nw = J.shape
    cols = np.repeat(np.arange(ns), nw)
    return scipy.sparse.csr_matrix((W.ravel(), (J.ravel(), cols)), shape=(n_master, ns))


def edge_radius(r: np.ndarray, gap: np.ndarray, closed: np.ndarray) -> float:
    """Contact radius [m] from the nodal gaps [m] at radii ``r`` (sorted) and the ``closed`` (force-carrying) pairs:
    at zero gap under the kinematic law, penetrating under the penalty law; only the open gaps beyond them enter.

    Near the edge of a smooth frictionless contact the separation grows as (r - a)^{3/2} (the pressure vanishes
    as (a - r)^{1/2}; Johnson, Contact Mechanics, Sec. 4.2), so g^{2/3} is extrapolated linearly to zero from two
    open nodes beyond the outermost closed slave r_k. The two are r_{k+2}, r_{k+3}, not the first open node: the
    P1 surface between r_k (closed) and r_{k+1} is straight, so g_{k+1} is under-resolved (paper scene,
    0.125 mm submodel at its peak: 0.094 µm against Hertz's 0.243 µm), which put the edge up to 3% out as it
    passed between nodes; on the exact Hertz profile either pair is within 0.6% for a > 4 h. The result is kept
    within [r_{k-1}, r_{k+1}], not [r_k, r_{k+1}]: the discrete contact closes a node that lies just beyond the
    edge with a vanishing force (paper scene, 0.058 mm submodel at its peak: the outermost closed node 0.2 h beyond
    Hertz's edge, carrying 1% of p0; clipped at it, the radius read +1.05%, extrapolated +0.08%). Falls back to
    r_{k+1}, r_{k+2}, then to r_k, where there are not enough open nodes with growing gaps. The penalty law once
    took the linear zero crossing of the gap between r_k and r_{k+1}: the same under-resolved straight segment, so its
    radius jumped as the edge passed between nodes (aluminium rods at 5 m/s, penalty law, the fine submodel level's
    phase members at 0.061 to 0.064 mm: areas -3.14% to +1.66% from Hertz at their own force, each "ok"; with this,
    +0.01% to +0.36%)."""
    act = np.flatnonzero(closed)
    if act.size == 0:
        return 0.0
    k = act[-1]
    for j in (2, 1):
        i = k + j
        if i + 1 < r.size and 0.0 < gap[i] < gap[i + 1]:
            s1, s2 = gap[i] ** (2.0 / 3.0), gap[i + 1] ** (2.0 / 3.0)
            a = r[i] - s1 * (r[i + 1] - r[i]) / (s2 - s1)
            return float(min(max(a, r[max(k - 1, 0)]), r[k + 1]))  # (np.clip on a scalar: ~7 µs, every record)
    return float(r[k])


@dataclass
class _Arrays:
    """What a step reads, in one array namespace: pairing (J, W, inside), initial gap g0 [m], nodal
    penalty stiffness k [N/m], the owned tip entries (local) and their sorted positions (pos), a buffer;
    serial, the gap operator B as a CSR matrix of that namespace (made at the first product, for the
    owned array's length), with the backend that holds them; Wᵀ as a CSR matrix (WT, :func:`_transpose`)."""

    J: Any
    W: Any
    inside: Any
    g0: Any
    k: Any
    slave_local: Any
    slave_pos: Any
    master_local: Any
    master_pos: Any
    buf: Any
    backend: Backend
    B: Any = None
    WT: Any = None


class PenaltyContact:
    """Node-to-surface penalty contact (see module docstring); all arrays in SI units.

    ``pairing`` = (J, W, inside): master positions and interpolation weights per slave (3D:
    :func:`bilinear_pairing`); default: linear in r between neighbouring master nodes (axisymmetric).
    ``multiplicity`` (1, 2, 4) scales the reported force, energy and area to the full rods;
    ``mirrored`` = (about x = 0, about y = 0) says which symmetry planes bound the model (patch centroid).

    The set-up methods (:meth:`pair_frequency`, :meth:`add_abs_row_sums`) work on host arrays,
    :meth:`apply_stiffness` on either; the per-step ones (:meth:`evaluate`, :meth:`add_force`) on the
    arrays of the backend chosen by :meth:`use` (:mod:`rods.fe.backend`; the host by default). The
    evaluated state (``gap``, ``pressure``, the slave forces) is read on the host, copied once per
    evaluation when first asked for.
    """

    predictive = False  # the force follows from u_n alone (see rods.fe.kinematic for the other kind)
    stiffens = True  # its springs enter the spectrum (apply_stiffness): the step's limit is found with them

    def __init__(
        self,
        slave: TipNodes,
        master: TipNodes,
        ε_pen: float,
        comm: MPI.Comm,
        pairing: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
        multiplicity: int = 1,
        mirrored: tuple[bool, bool] = (False, False),
    ):
        self.slave, self.master, self.ε, self.comm = slave, master, ε_pen, comm
        self.multiplicity, self.mirrored = multiplicity, mirrored
        if pairing is None:
            rm = master.r
            j = np.clip(np.searchsorted(rm, slave.r, side="right") - 1, 0, max(len(rm) - 2, 0))
            t = (slave.r - rm[j]) / np.where(rm[j + 1] > rm[j], rm[j + 1] - rm[j], 1.0)
            inside = (t >= -1e-12) & (t <= 1 + 1e-12)  # slaves over the master face
            t = np.clip(t, 0.0, 1.0)
            pairing = (np.column_stack([j, j + 1]), np.column_stack([1.0 - t, t]), inside)
        self.J, self.W, self.inside = pairing  # (n_s, n_w) master positions, weights; (n_s,) bool
        self.three_d = slave.xy is not None
        self.patch_keys = PATCH_KEYS if self.three_d else ()
        self.g0 = _interp(self.J, self.W, master.z) - slave.z  # initial gap [m]
        self.k = np.where(self.inside, ε_pen * slave.area, 0.0)  # nodal penalty stiffness [N/m]
        self.ns, self.nm = len(slave.r), len(master.r)
        self.serial = comm.size == 1
        self._host_arrays = self._arrays(PETSC)
        self.ζ, self._c_dt = 0.0, np.zeros(self.ns)  # contact damping: fraction of critical, c_s/Δt [N/m]
        self.use(PETSC)
        self.force = 0.0  # total compressive contact force [N]
        self.energy = 0.0  # penalty energy [J]

    def _arrays(self, backend: Backend) -> _Arrays:
        s, m, put = self.slave, self.master, backend.asarray
        WT = backend.csr(transpose_matrix(self.J, self.W, self.nm))  # the master reaction: one sparse product
        return _Arrays(
            *(put(a) for a in (self.J, self.W, self.inside, self.g0, self.k, s.local, s.pos, m.local, m.pos)),
            backend.xp.zeros(self.ns + self.nm),
            backend,
            WT=WT,
        )

    def use(self, backend: Backend) -> None:
        """Evaluate on ``backend``'s arrays from now on (copied there once; the state starts at rest)."""
        self.backend = backend
        self._d = self._host_arrays if backend.xp is np else self._arrays(backend)
        xp = backend.xp
        self._g, self._p = self._d.g0.copy(), xp.zeros(self.ns)  # gap [m], pressure [Pa]
        self._Fs, self._Fm = xp.zeros(self.ns), xp.zeros(self.nm)  # slave, master nodal forces [N]
        self._host: tuple[np.ndarray, ...] | None = None
        a = self.slave.area
        self._inv_area = backend.asarray(np.where(a > 0, 1.0 / np.where(a > 0, a, 1.0), 0.0))  # 1/a_s [1/m^2]
        # contact damping: c_s/Δt, the last gaps and damping forces, the damping's work so far
        self._cd = backend.asarray(self._c_dt)
        self._g_prev, self._Fd_prev = self._d.g0.copy(), xp.zeros(self.ns)
        self.dissipated = 0.0  # [J], full rods

    def set_damping(self, ζ: float, inv_mass: np.ndarray, dt: float) -> None:
        """Contact damping ζ (fraction of critical of each isolated pair, module docstring) at the step ``dt``
        [s]; ``inv_mass`` the owned inverse lumped mass [1/kg]. Collective (a gather); kept by :meth:`use`."""
        inv_m = self._pair_inverse_mass(inv_mass)
        m = np.where(inv_m > 0, 1.0 / np.where(inv_m > 0, inv_m, 1.0), 0.0)  # m_s [kg]
        self.ζ, self._c_dt = float(ζ), 2.0 * ζ * np.sqrt(self.k * m) / dt
        self._cd = self.backend.asarray(self._c_dt)

    def _on_host(self) -> tuple[np.ndarray, ...]:
        """(gap, pressure, slave forces) of the last evaluation as host arrays."""
        if self._host is None:
            self._host = tuple(self.backend.to_host(a) for a in (self._g, self._p, self._Fs))
        return self._host

    @property
    def gap(self) -> np.ndarray:
        """Gap g_s at every slave [m] (last evaluation)."""
        return self._on_host()[0]

    @property
    def pressure(self) -> np.ndarray:
        """Penalty pressure p_s = ε <-g_s> at every slave [Pa] (last evaluation)."""
        return self._on_host()[1]

    def gather(self, x):
        """Axial entries of the owned array ``x`` (host or the evaluation backend's) at all slave and master
        nodes (every rank)."""
        d = self._host_arrays if isinstance(x, np.ndarray) else self._d
        b = self._gather_into(d, d.buf, (x,))
        return b[: self.ns], b[self.ns :]

    def _gather_into(self, d: _Arrays, b, xs):
        """``b`` holding, side by side, each owned array of ``xs``'s axial entries at all slave and master nodes
        (ns + nm each); under MPI (the PETSc path, host arrays) summed over the ranks in one Allreduce, each entry
        from its one owner."""
        n = self.ns + self.nm
        if not self.serial:
            b[:] = 0.0
        for k, x in enumerate(xs):
            part = b[k * n : (k + 1) * n]
            part[d.slave_pos] = x[d.slave_local]
            part[self.ns + d.master_pos] = x[d.master_local]
        if not self.serial:
            self.comm.Allreduce(MPI.IN_PLACE, b, op=MPI.SUM)
        return b

    def _scatter(self, f, fs, fm) -> None:  # fs, fm: all tip nodes
        """f[owned slave/master axial entries] += fs, fm (values over all tip nodes; host arrays, or the
        arrays of the backend of :meth:`use`)."""
        d = self._host_arrays if isinstance(f, np.ndarray) else self._d
        f[d.slave_local] += fs[d.slave_pos]
        f[d.master_local] += fm[d.master_pos]

    def gap_matrix(self, n: int) -> scipy.sparse.csr_matrix:
        """B (n_s x n, serial): row s has -1 at the slave's axial entry and W_sj at its master nodes' axial
        entries of an owned array of length ``n``, so that g = g0 + B u and ġ = B v."""
        s, m = self.slave, self.master
        master_entry = np.empty(self.nm, dtype=np.int64)
        master_entry[m.pos] = m.local
        rows = np.concatenate([s.pos, np.repeat(np.arange(self.ns), self.J.shape[1])])
        cols = np.concatenate([s.local, master_entry[self.J].ravel()])
        vals = np.concatenate([-np.ones(self.ns), self.W.ravel()])
        return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(self.ns, n))

    def normal_rates(self, x):
        """B x: Σ_j W_sj x_z,j - x_z,s at every slave for the owned array ``x`` (host or backend arrays). Serial
        it is one sparse product (on a device one kernel, not the gather's and interpolation's dozen); under
        MPI the gather (an Allreduce) and the interpolation."""
        d = self._host_arrays if isinstance(x, np.ndarray) else self._d
        if not self.serial:
            xs, xm = self.gather(x)
            return _interp(d.J, d.W, xm) - xs
        return product(self.gap_rows(d, x.size), x)

    def gap_rows(self, d, n: int):
        """B of :meth:`gap_matrix` as a CSR matrix of ``d``'s backend (host or backend arrays, serial), built at
        the first use for owned arrays of length ``n``."""
        if d.B is None or d.B.shape[1] != n:
            d.B = d.backend.csr(self.gap_matrix(n))
        return d.B

    def gaps(self, u):
        """g_s = g0_s + Σ_j W_sj u_z,j - u_z,s [m] at the owned displacement ``u`` (host or backend arrays)."""
        d = self._host_arrays if isinstance(u, np.ndarray) else self._d
        return d.g0 + self.normal_rates(u)

    def evaluate(self, u) -> None:
        """Contact state at displacement ``u`` (owned array): gaps, pressures, nodal forces, energy."""
        d, xp = self._d, self.backend.xp
        g = self.gaps(u)
        pen = xp.maximum(-g, 0.0) * d.inside  # penetration [m]
        F = d.k * pen  # compressive nodal forces on the slaves [N]
        twice_energy = xp.dot(d.k, pen * pen)  # twice the penalty energy [J] (this part)
        work = []  # damped: the damping's work over the step [J]
        if self.ζ > 0.0:
            F, w = self._damp(F, pen, g)
            work = [w]
        sums = [F.sum(), twice_energy, *work]  # force [N], ...
        self._Fs = F
        self._Fm = _transpose(xp, d.J, d.W, F, self.nm, d.WT)
        self._g, self._host = g, None
        self._p = self.ε * pen if self.ζ == 0.0 else F * self._inv_area
        sums = self.multiplicity * self.backend.to_host(xp.stack(sums))  # the step's one copy to the host
        self.force, self.energy = float(sums[0]), 0.5 * float(sums[1])  # full rods [N], [J]
        if self.ζ > 0.0:
            self.dissipated -= 0.5 * float(sums[2])

    def _damp(self, F, pen, g):
        """The elastic forces ``F`` plus the pairs' viscous forces c_s (g_{n-1} - g_n)/Δt, kept compressive
        where the pair penetrates (module docstring), and the damping's work over the step (trapezoid in g:
        (Fd_{n-1} + Fd_n)·(g_n - g_{n-1}), a backend scalar; -½ of it adds to the dissipation)."""
        xp = self.backend.xp
        F = xp.where(pen > 0.0, xp.maximum(F + self._cd * (self._g_prev - g), 0.0), 0.0)
        Fd = F - self._d.k * pen  # the damping part, after the clip [N]
        work = xp.dot(self._Fd_prev + Fd, g - self._g_prev)
        self._g_prev, self._Fd_prev = g, Fd
        return F, work

    def state(self) -> dict[str, np.ndarray]:
        """What a restart needs (the damped law's memory: last gaps, damping forces, dissipation)."""
        to_host = self.backend.to_host
        return {
            "contact_g_prev": to_host(self._g_prev),
            "contact_Fd_prev": to_host(self._Fd_prev),
            "contact_dissipated": np.array(self.dissipated),
        }

    def restore(self, state: dict[str, np.ndarray]) -> None:
        put = self.backend.asarray
        self._g_prev = put(np.asarray(state["contact_g_prev"], float).copy())
        self._Fd_prev = put(np.asarray(state["contact_Fd_prev"], float).copy())
        self.dissipated = float(state["contact_dissipated"])

    def slave_forces(self, u: np.ndarray) -> np.ndarray:
        """Compressive slave forces F_s = k_s <-g_s(u)> [N] at the host displacement ``u`` (collective under
        MPI: a gather), without touching the evaluated state (field output between steps; the elastic part:
        a damped law adds its viscous forces only inside the time loop)."""
        pen = np.maximum(-self.gaps(u), 0.0) * self.inside  # [m]
        return self.k * pen

    def add_force(self, y, scale=None) -> None:
        """y += scale ⊙ f_c for the owned tip entries: f_c = -F on the slaves (pushed along -z),
        +Wᵀ F on the master nodes (the reaction). ``scale`` (e.g. Δt M^-1) defaults to 1."""
        d = self._d
        ls, lm = d.slave_local, d.master_local
        fs, fm = -self._Fs[d.slave_pos], self._Fm[d.master_pos]
        if scale is not None:
            fs, fm = fs * scale[ls], fm * scale[lm]
        y[ls] += fs
        y[lm] += fm

    def apply_stiffness(self, x, y) -> None:
        """y += K_c x with every potential contact pair active (full engagement): K_c = Σ k_s b_s b_sᵀ
        (``x``, ``y``: owned host arrays, or the arrays of the backend of :meth:`use`)."""
        d, xp = (self._host_arrays, np) if isinstance(x, np.ndarray) else (self._d, self.backend.xp)
        xs, xm = self.gather(x)
        t = d.k * (_interp(d.J, d.W, xm) - xs)
        self._scatter(y, -t, _transpose(xp, d.J, d.W, t, self.nm, d.WT))

    def pair_frequency(self, inv_mass: np.ndarray) -> float:
        """Largest angular frequency [rad/s] of an isolated contact pair: a slave and its master nodes
        joined by the penalty spring k_s, ω_s² = k_s (1/m_s + Σ_j W_sj²/m_j) (2-mass spring; W: weights).

        It sets the contact *switching* limit of the step (:func:`rods.fe.explicit.switching_step`);
        ``inv_mass`` is the owned inverse lumped mass array [1/kg]."""
        ω2 = self.k * self._pair_inverse_mass(inv_mass)
        return float(math.sqrt(ω2.max())) if ω2.size else 0.0

    def _pair_inverse_mass(self, inv_mass: np.ndarray) -> np.ndarray:
        """1/m_s = 1/m_slave + Σ_j W_sj²/m_j [1/kg] of every pair (its reduced mass along the normal), from the
        owned inverse lumped mass ``inv_mass`` (collective: a gather)."""
        ims, imm = self.gather(inv_mass)
        return ims + (self.W**2 * imm[self.J]).sum(axis=1)

    def add_abs_row_sums(self, y: np.ndarray) -> None:
        """y += Σ_j |K_c,ij| bound for the owned tip entries: K_c = Σ_s k_s b_s b_sᵀ with
        b_s = W_s (master) - e_s (slave), so row i is bounded by Σ_s k_s |b_s,i| ‖b_s‖₁ (Gershgorin)."""
        norm1 = 1.0 + np.abs(self.W).sum(axis=1)
        t = self.k * norm1
        self._scatter(y, t, _transpose(np, self.J, self.W, t, self.nm))

    def radius(self) -> float:
        """Contact radius [m] (:func:`edge_radius`, the same for both laws: the active slaves are those that
        carry a pressure, the edge is extrapolated from the open gaps beyond them).
        3D: r = sqrt(A/π) of the active nodal area A of the full rods (the paper's definition)."""
        if self.three_d:
            return math.sqrt(self.active_area() / math.pi)
        return edge_radius(self.slave.r, self.gap, self.pressure > 0)

    def active_area(self) -> float:
        """Sum of the tributary areas of the active slaves [m^2] (a node-based area, as FE codes report),
        full rods."""
        return self.multiplicity * float(self.slave.area[self.pressure > 0].sum())

    def patch(self) -> tuple[float, ...]:
        """3D contact patch (values for :data:`PATCH_KEYS`): force-weighted centroid (x_c, y_c) of the
        active slaves at their reference positions and their largest distance from it [m]; a
        coordinate normal to a symmetry plane is 0 by symmetry. () in the axisymmetric case."""
        if not self.three_d:
            return ()
        F = self._on_host()[2]
        act = F > 0
        if not act.any():
            return (0.0, 0.0, 0.0)
        xy = self.slave.xy[act]
        c = (F[act] @ xy) / F[act].sum()
        c[np.array(self.mirrored)] = 0.0
        return (float(c[0]), float(c[1]), float(np.hypot(*(xy - c).T).max()))
