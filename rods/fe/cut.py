"""The cut band of a submodel (paper Sec. 2.2): recorded by the global run, read to drive the submodel.

Storage (global side, :class:`CutRecorder`): during the global run an observer copies the owned
entries of u_n and v_{n+1/2} of a *band* of nodes — every global cell whose nodes all lie within
±2 global axial elements of a cut plane (both rods) — at every global step up to ``record_until``
(the band is small: ~270 nodes on the paper mesh). Rank 0 gathers and writes ``cut.h5`` (h5py):

    /times (n_rec,) [s]            times t_n of the recorded steps
    /u, /v (n_rec, n_nodes, gdim)  u_n [m] and v_{n+1/2} [m/s] at the band nodes
    /nodes (n_nodes, gdim) [m]     band node coordinates
    /cells (n_cells, n_verts)      band cells (DOLFINx vertex order), indices into /nodes
    attrs: cell_type, gdim, kind, dt, every, halfwidth, cut_planes, scene_values (JSON),
           record_id (a fresh random id per recording: :func:`cut_identity`)

Driving (submodel side, :class:`CutDriver`): the band is rebuilt as a DOLFINx mesh on the submodel's
communicator and the stored P1 field is interpolated onto the submodel's cut-boundary nodes with
DOLFINx non-matching interpolation (``create_interpolation_data`` + ``interpolate_nonmatching`` on
the cut cells only). Interpolation is linear, so it is done once per band node (unit fields) to
build a sparse matrix W (owned cut nodes x band nodes); u_cut(t) = W U_band(t), applied to every record
once at the set-up (:func:`record_products`: the run interpolates the cut's own history in time, no band and no
sparse product per step). Works
for meshes that do not nest node for node, for any number of ranks (the cut nodes may be on any
rank), and for 2D (axisymmetric) and 3D (hexahedral) band cells alike. In 3D the submodel keeps the
global ``fe.symmetry`` (half/quarter: the band and the cut share the symmetry planes, whose normal
displacement is zero in both), and a submodel section finer than the global one puts circle nodes
outside the band's polygonal section (by its sagitta, 0.03 mm for 1 mm global cells): DOLFINx
extrapolates them linearly from the nearest band cell, bounded by :data:`MAX_EXTRAPOLATION`. In
time, U_band is interpolated linearly
between recorded steps: the central-difference displacement is itself piecewise linear in time
(u_{n+1} = u_n + Δt v_{n+1/2}), so this reproduces the global trajectory exactly at any submodel time when every
global step is recorded (the driver's and --record-cut's default); ``--record-every k`` > 1 interpolates across k
steps, an O((k Δt)² ü) error.

Prescription in the explicit scheme: after v_{n+1/2} is computed, its cut entries are overwritten by
(u_cut(t_{n+1}) - u_n)/Δt, so u_{n+1} = u_cut(t_{n+1}) exactly. Initial state = the global one
(u = 0, Rod 1 at s1, Rod 2 at rest), consistent with the recorded u_0 = 0. The overwrite is an impulse
R = M (v_prescribed - v_scheme) of the cut reaction; its work R · (v_{n-1/2} + v_{n+1/2})/2 is summed
(``CutDriver.work``) and enters the model's energy balance, so a driven submodel is guarded like a global
run (balance closes to O(Δt): ~1e-3 on the tests' meshes).
"""

from __future__ import annotations

import bisect
import json
import math
import time
import uuid
from pathlib import Path
from typing import Any

import basix.ufl
import dolfinx
import dolfinx.mesh
import numpy as np
import scipy.sparse
import ufl
from mpi4py import MPI

from rods.fe.model import ExplicitModel
from rods.io import cut_identity  # the record's id, defined where a stage reads it without DOLFINx
from rods.scene import BAND_ELEMENTS, Scene, SceneError, cut_records

__all__ = [
    "MAX_EXTRAPOLATION",
    "CutDriver",
    "CutRecorder",
    "band_adjacency",
    "band_space",
    "cut_identity",
    "cut_planes",
    "cut_space",
    "cut_weights",
    "node_colouring",
    "read_band",
    "read_cut",
    "record_products",
    "recorded_until",
]

INTERPOLATION_TOL = 1e-6  # [-] interpolate_nonmatching's Newton tolerance of the pull-back to reference coordinates
# most negative interpolation weight accepted [-]: a cut node at most ~this fraction of a band cell outside it
# (3D: a finer submodel's circle bulges past the band's polygonal section by its sagitta, 0.03 mm on 1 mm cells)
MAX_EXTRAPOLATION = 0.1


def cut_planes(scene: Scene) -> tuple[float, float]:
    """Axial coordinates of the cut planes [m]: Rod 1 at -L_s, Rod 2 at +L_s."""
    L_s = scene["fe.submodel_length"]
    return -L_s, L_s


def _dof_to_geometry(V: dolfinx.fem.FunctionSpace) -> np.ndarray:
    """Geometry node of every local P1 dof (degree-1 Lagrange on a degree-1 mesh: cell-local order agrees)."""
    msh = V.mesh
    gdm = msh.geometry.dofmaps[0]
    dm = V.dofmap.list
    if dm.shape != gdm.shape:
        raise ValueError("cut recording needs P1 fields on a linear (Q1/hex8) mesh")
    out = np.full(V.dofmap.index_map.size_local + V.dofmap.index_map.num_ghosts, -1, dtype=np.int64)
    out[dm.ravel()] = gdm.ravel()
    return out


# ----------------------------------------------------------------------------------------------
# storage (global run)
# ----------------------------------------------------------------------------------------------
class CutRecorder:
    """Observer of the global run (:mod:`rods.fe.observers`): records u_n, v_{n+1/2} of the cut band every
    ``every`` steps up to ``record_until`` [s]; :meth:`write` gathers to rank 0 and writes ``cut.h5``. Its record
    is in memory, which no checkpoint holds: a run with it is not resumable, and writes no checkpoint."""

    resumable = False

    def __init__(self, model: ExplicitModel, record_until: float | None = None, every: int = 1):
        sc, V = model.scene, model.V
        msh = V.mesh
        self.model, self.every = model, max(1, int(every))
        self.axial = model.axial
        gdim = msh.geometry.dim
        self.gdim = gdim
        self.halfwidth = BAND_ELEMENTS * sc["fe.axial_size"]  # [m]
        self.planes = cut_planes(sc)
        tol = 1e-9 * max(sc.rod1.length, sc.rod2.length)
        w = self.halfwidth + tol

        def in_band(z: np.ndarray) -> np.ndarray:
            return (np.abs(z - self.planes[0]) <= w) | (np.abs(z - self.planes[1]) <= w)

        imap = V.dofmap.index_map
        n_own = imap.size_local
        X = V.tabulate_dof_coordinates()[:n_own]
        band = np.flatnonzero(in_band(X[:, self.axial]))
        self.band = band
        self.idx = (band[:, None] * model.bs + np.arange(model.bs)[None, :]).ravel()  # owned entries
        gidx = msh.geometry.input_global_indices
        d2g = _dof_to_geometry(V)
        self.keys = np.asarray(gidx, dtype=np.int64)[d2g[band]]
        self.coords = X[band, :gdim]
        # band cells: owned cells all of whose nodes lie in the band
        n_cells = msh.topology.index_map(msh.topology.dim).size_local
        gdm = msh.geometry.dofmaps[0][:n_cells]
        zc = msh.geometry.x[gdm, self.axial]
        cells = np.flatnonzero(in_band(zc).all(axis=1))
        self.cell_keys = np.asarray(gidx, dtype=np.int64)[gdm[cells]]
        self.cell_type = msh.topology.cell_name()
        n_rec = cut_records(sc, model.dt, model.steps, record_until, self.every)
        self.last = (n_rec - 1) * self.every  # last recorded step
        self.times = np.arange(n_rec) * self.every * model.dt
        self.U = np.zeros((n_rec, self.idx.size))
        self.idx_step = model.backend.asarray(self.idx)  # the band's entries where the state lives
        self.Vv = np.zeros((n_rec, self.idx.size))
        self.n = 0

    def after_step(self, step: int, t: float, state) -> None:  # noqa: ARG002
        if step > self.last or step % self.every:
            return
        host, idx = self.model.backend.to_host, self.idx_step  # the band's entries only leave the device
        self.U[self.n] = host(state.u[idx])  # u_n
        self.Vv[self.n] = host(state.v[idx])  # v_{n+1/2}
        self.n += 1

    def write(self, path: str | Path) -> None:
        """Write ``path`` on rank 0 (HDF5; layout in the module docstring): the band's nodes and cells gathered, then
        u and v one at a time, each rank's part received and placed in turn, so rank 0 holds one ordered copy of one
        of them beside its own record and one part: 1.9 copies of the record at the peak, which the plan counts
        (rods.cost.CUT_RECORD_COPIES; gathering both whole, concatenating and reordering them held 3.8)."""
        comm, n, gd = self.model.comm, self.n, self.gdim
        meta = comm.gather((self.keys, self.coords, self.cell_keys), root=0)
        records = (("u", self.U), ("v", self.Vv))
        if comm.rank != 0:
            for tag, (_, record) in enumerate(records):
                comm.send(record[:n], dest=0, tag=tag)
            comm.barrier()
            return
        import h5py

        keys, coords, cells_local, places = _band_layout(meta)
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        # a dot name, as the result files' (rods.io): a later run into the folder sweeps one a kill left
        tmp = path.with_name(f".{path.name}.tmp")
        try:
            with h5py.File(tmp, "w") as f:
                f["times"] = self.times[:n]
                for tag, (name, record) in enumerate(records):  # one ordered copy at a time
                    f[name] = _ordered(record[:n], places, keys.size, gd, comm, tag)
                f["nodes"] = coords
                f["cells"] = cells_local.astype(np.int64)
                self._attributes(f)
        except BaseException:  # a full disk: no half-written record left beside the results
            tmp.unlink(missing_ok=True)
            raise
        tmp.replace(path)
        comm.barrier()

    def _attributes(self, f: Any) -> None:
        """The record's attributes (module docstring), on the open HDF5 file ``f``."""
        m = self.model
        f.attrs["cell_type"] = self.cell_type
        f.attrs["gdim"] = self.gdim
        f.attrs["kind"] = m.kind
        f.attrs["axial"] = self.axial
        f.attrs["dt"] = m.dt
        f.attrs["every"] = self.every
        f.attrs["halfwidth"] = self.halfwidth
        f.attrs["cut_planes"] = np.array(self.planes)
        f.attrs["scene_values"] = json.dumps(m.scene.as_dict())
        f.attrs["note"] = "u = u_n [m], v = v_{n+1/2} [m/s] at t_n = times; nodes [m]"
        f.attrs["record_id"] = uuid.uuid4().hex  # this recording's identity, wherever the file is copied


def _ordered(own: np.ndarray, places: list, n_keys: int, gd: int, comm: MPI.Comm, tag: int) -> np.ndarray:
    """Rank 0's record (n samples x band entries) in the band's key order: its own part ``own`` and each other
    rank's, received in turn (tag ``tag``) and placed (``places``: rank -> (key positions, its rows))."""
    n = own.shape[0]
    ordered = np.empty((n, n_keys, gd))
    for r, (to, rows) in enumerate(places):
        part = own if r == 0 else comm.recv(source=r, tag=tag)
        ordered[:, to] = part.reshape(n, -1, gd)[:, rows]
        del part
    return ordered


def _band_layout(
    meta: list[tuple[np.ndarray, np.ndarray, np.ndarray]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[tuple[np.ndarray, np.ndarray]]]:
    """The cut file's node order from every rank's (owned node keys, coordinates, band cells' node keys): the band
    cells' nodes by key (a recorded node of no band cell left out), their coordinates, the cells in that numbering,
    and per rank (its nodes' places in that order, which of its recorded nodes they are)."""
    keys = np.concatenate([m[0] for m in meta])
    cells = np.vstack([m[2] for m in meta if len(m[2])])
    used = np.unique(cells)
    first = np.full(used.size, -1)  # each used node's record in the concatenated order (owned nodes: one each)
    where = np.searchsorted(used, keys)
    hit = np.flatnonzero((where < used.size) & (used[np.minimum(where, used.size - 1)] == keys))
    first[where[hit]] = hit
    if np.any(first < 0):
        raise RuntimeError("cut band: a band cell node was not recorded")
    coords = np.vstack([m[1] for m in meta])[first]
    offsets = np.cumsum([0, *(len(m[0]) for m in meta)])
    places = []
    for r in range(len(meta)):
        mine = (first >= offsets[r]) & (first < offsets[r + 1])
        places.append((np.flatnonzero(mine), first[mine] - offsets[r]))
    return used, coords, np.searchsorted(used, cells), places


# ----------------------------------------------------------------------------------------------
# driving (submodel run)
# ----------------------------------------------------------------------------------------------
def recorded_until(path: str | Path) -> tuple[float, dict[str, Any]]:
    """(the last time [s] of a cut record, the recording global's scene values): the submodels it drives can run
    to that time, and only on that scene's bodies and impact."""
    import h5py

    with h5py.File(path, "r") as f:
        return float(f["times"][-1]), json.loads(f.attrs["scene_values"])


def read_cut(path: Path) -> dict[str, Any]:
    """A whole cut record (layout in the module docstring): its datasets and attributes in one dict."""
    import h5py

    with h5py.File(path, "r") as f:
        d = {k: f[k][()] for k in ("times", "u", "v", "nodes", "cells")}
        d.update({k: f.attrs[k] for k in f.attrs})
    return d


def read_band(path: Path, model: ExplicitModel) -> dict[str, Any]:
    """The cut record at ``path`` (:func:`read_cut`) as ``model`` (a submodel) reads it: in 3D its band's nodes
    mapped onto the model's sections (:func:`match_sections`)."""
    d = read_cut(path)
    if int(d["gdim"]) == 3:  # the two O-grids' rims at their own radii
        d["nodes"] = match_sections(d["nodes"], json.loads(d["scene_values"]), model)
    return d


def band_space(d: dict[str, Any], comm: MPI.Comm) -> tuple[dolfinx.fem.FunctionSpace, np.ndarray]:
    """The recorded band as a P1 space on ``comm`` (rank 0 holds the input) and the band node of each dof."""
    gdim = int(d["gdim"])
    el = basix.ufl.element("Lagrange", str(d["cell_type"]), 1, shape=(gdim,))
    root = comm.rank == 0
    cells = d["cells"] if root else np.empty((0, d["cells"].shape[1]), dtype=np.int64)
    x = d["nodes"] if root else np.empty((0, gdim))
    band = dolfinx.mesh.create_mesh(comm, cells, ufl.Mesh(el), x)
    Vb = dolfinx.fem.functionspace(band, ("Lagrange", 1))
    return Vb, np.asarray(band.geometry.input_global_indices, dtype=np.int64)[_dof_to_geometry(Vb)]


def cut_space(model: ExplicitModel) -> tuple[dolfinx.fem.FunctionSpace, np.ndarray, np.ndarray, np.ndarray]:
    """The submodel's cut: scalar P1 space V0, its owned cut dofs, the cells incident to the cut facets,
    and the model's (parent) node of each owned cut dof."""
    msh, rm, tags = model.V.mesh, model.rm, model.tags
    fdim, tdim = msh.topology.dim - 1, msh.topology.dim
    facets = np.concatenate([rm.facet_tags.find(tags["rod1_end"]), rm.facet_tags.find(tags["rod2_end"])])
    msh.topology.create_connectivity(fdim, tdim)
    cut_cells = dolfinx.mesh.compute_incident_entities(msh.topology, facets, fdim, tdim).astype(np.int32)
    V0, to_parent = model.V.sub(0).collapse()
    nodes0 = dolfinx.fem.locate_dofs_topological(V0, fdim, facets)
    nodes0 = nodes0[nodes0 < V0.dofmap.index_map.size_local]
    to_parent = np.asarray(to_parent[0] if isinstance(to_parent, list | tuple) else to_parent)
    return V0, nodes0, cut_cells, to_parent[nodes0] // model.bs  # parent dof of component 0 is node * bs


def band_adjacency(cells: np.ndarray, n_nodes: int) -> scipy.sparse.csr_matrix:
    """The band's node graph (input indices): A_jk = 1 where nodes j and k share a cell (the diagonal included)."""
    n_cells, per_cell = cells.shape
    C = scipy.sparse.csr_matrix(
        (np.ones(cells.size), (np.repeat(np.arange(n_cells), per_cell), cells.ravel())), shape=(n_cells, n_nodes)
    )
    A = (C.T @ C).tocsr()
    A.data[:] = 1.0
    return A


def node_colouring(A: scipy.sparse.csr_matrix, hops: int) -> np.ndarray:
    """Colours of the nodes of graph ``A`` (:func:`band_adjacency`) such that two nodes within ``hops`` steps
    differ (greedy, in index order: every rank computes the same from the same cells). A unit field on all
    nodes of one colour is then, within reach of any point, a unit field on one node: one solve or
    interpolation serves a whole colour instead of each node (structured hexahedra: 27 colours at one hop, 125
    at two)."""
    R = A
    for _ in range(hops - 1):
        R = R @ A
    R = R.tocsr()
    colour = np.full(A.shape[0], -1, dtype=np.int64)
    for j in range(A.shape[0]):
        taken = colour[R.indices[R.indptr[j] : R.indptr[j + 1]]]
        free = np.ones(taken.size + 1, dtype=bool)
        free[taken[(taken >= 0) & (taken <= taken.size)]] = False
        colour[j] = int(np.argmax(free))
    return colour


def record_products(A: scipy.sparse.spmatrix, U: np.ndarray) -> np.ndarray:
    """A U_k for every record k of a band history ``U`` (n_rec, n_nodes, gdim): ``A`` acting on the band nodes
    (n_rows x n_nodes, per component) gives (n_rec, n_rows, gdim); on the flattened records (n_rows x n_nodes gdim)
    (n_rec, n_rows). One sparse product over all records: a linear map commutes with the linear interpolation in
    time, so a run interpolates A U_k instead of applying A to the interpolated band every step."""
    n_rec, n_nodes, gdim = U.shape
    if A.shape[1] == n_nodes:
        AU = A @ U.transpose(1, 0, 2).reshape(n_nodes, n_rec * gdim)  # (n_rows, n_rec gdim)
        return np.ascontiguousarray(AU.reshape(A.shape[0], n_rec, gdim).transpose(1, 0, 2))
    return np.ascontiguousarray((A @ U.reshape(n_rec, n_nodes * gdim).T).T)


def match_sections(nodes: np.ndarray, recorded: dict[str, Any], model: ExplicitModel) -> np.ndarray:
    """A 3D band's nodes [m] (the recording global's, its scene values ``recorded``) with each rod's section scaled
    about the rod's axis from the global's rim radius onto ``model``'s (rods.fe.mesh3d.section_radius: each O-grid
    puts its rim where its polygon holds the rod's area, at a radius that depends on its size), so that the two
    meshes' sections coincide at the rim: a submodel coarser across than its global had rim nodes outside the band.
    Rod 1's axis is its placed one (rods.fe.mesh3d.Placement), Rod 2's the z axis; the band's Rod-1 nodes are those
    at z < 0 (its cut plane at z = -L_s)."""
    from rods.fe.mesh3d import section_radius

    sc = model.scene
    origin, e_z = np.zeros(3), np.array([0.0, 0.0, 1.0])
    c1, tip1 = model.rm.placement.apply(np.array([origin, e_z]))  # Rod 1's axis as the mesh placed it
    axes = ((c1, tip1 - c1), (origin, e_z))
    out = np.array(nodes, dtype=float, copy=True)
    for k, (rod, (c, a)) in enumerate(zip(sc.rods, axes, strict=True), start=1):
        R = rod.diameter / 2  # [m]
        ratio = section_radius(R, sc["fe.radial_size"]) / section_radius(R, recorded["fe"]["radial_size"])
        on = out[:, 2] < 0.0 if k == 1 else out[:, 2] >= 0.0
        rel = out[on] - c
        along = rel @ a
        out[on] = c + along[:, None] * a + ratio * (rel - along[:, None] * a)
    return out


def cut_weights(
    V0, nodes0, cut_cells, Vb, node_of_dof, cells: np.ndarray, n_nodes: int, tol: float
) -> scipy.sparse.csr_matrix:
    """W (owned cut dofs x band nodes): each band node's unit scalar field interpolated onto the cut cells
    (DOLFINx non-matching interpolation; linear). One colour of nodes (:func:`node_colouring`, one hop: no two
    share a cell) at a time: a cut point lies in one band cell, which holds at most one node of the colour, so
    the interpolated unit field there is that node's weight, and the field (index + 1) over it names the node.
    Two interpolations per colour instead of one per band node (the 3D coarse submodel's cut: minutes to
    seconds); the weights are the per-node ones to round-off (tests/fe/test_submodel.py).

    DOLFINx's point ownership takes a point within a squared distance of 10 machine epsilons of a cell, in the
    mesh's units, as inside it (and ``padding`` is absolute too): in metres 4.7e-8 m, 5% of a 1 µm cell of a scene
    scaled by 1e-3, whose cut points near a band cell's face were extrapolated from its neighbour (weights off by
    up to 5e-3, histories by 5e-6 against the same scene at full size: an audit). Both meshes are therefore
    scaled by a power of two to the band's size while the weights are computed (exact, and undone after), which
    makes both tolerances relative to the scene."""
    meshes = [V0.mesh] if V0.mesh is Vb.mesh else [V0.mesh, Vb.mesh]
    size = Vb.mesh.comm.allreduce(float(np.abs(Vb.mesh.geometry.x).max(initial=0.0)), op=MPI.MAX)  # [m]
    scale = 2.0 ** -math.floor(math.log2(size)) if size > 0.0 else 1.0  # [1/m] exact both ways
    scaled = []  # the meshes scaled so far: undone whatever stops the computation, even between the two
    try:
        for m in meshes:
            m.geometry.x[:] *= scale
            scaled.append(m)
        return _cut_weights(V0, nodes0, cut_cells, Vb, node_of_dof, cells, n_nodes, tol)
    finally:
        for m in scaled:
            m.geometry.x[:] /= scale


def _cut_weights(
    V0, nodes0, cut_cells, Vb, node_of_dof, cells: np.ndarray, n_nodes: int, tol: float
) -> scipy.sparse.csr_matrix:
    """:func:`cut_weights` on meshes in units of about the band's size (``padding``: a fraction of it)."""
    data = dolfinx.fem.create_interpolation_data(V0, Vb, cut_cells, padding=1e-10)
    fb, g = dolfinx.fem.Function(Vb), dolfinx.fem.Function(V0)
    own = np.arange(Vb.dofmap.index_map.size_local)
    colour = node_colouring(band_adjacency(cells, n_nodes), 1)
    rows, cols, vals = [], [], []

    def interpolated(values: np.ndarray) -> np.ndarray:
        fb.x.array[:] = 0.0
        fb.x.array[own] = values
        fb.x.scatter_forward()
        g.x.array[:] = 0.0
        g.interpolate_nonmatching(fb, cut_cells, data, tol=tol)
        return g.x.array[nodes0].copy()

    for κ in range(int(colour.max(initial=-1)) + 1):  # collective: every rank has every colour
        on = colour[node_of_dof[own]] == κ
        w = interpolated(on.astype(float))
        named = interpolated(np.where(on, node_of_dof[own] + 1.0, 0.0))
        nz = np.flatnonzero(np.abs(w) > 1e-14)
        j = np.rint(named[nz] / w[nz]).astype(np.int64) - 1
        if nz.size and (j.min() < 0 or j.max() >= n_nodes or np.any(colour[j] != κ)):
            raise RuntimeError("cut weights: a cut point sees two band nodes of one colour (band cells overlap?)")
        rows.append(nz)
        cols.append(j)
        vals.append(w[nz])
    return scipy.sparse.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(nodes0.size, n_nodes)
    )


class CutDriver:
    """Observer of the submodel run: prescribes u at the cut nodes from a global ``cut.h5``; its work on
    the submodel (``external_work()``) enters the energy balance."""

    reads_band = False  # a subclass that builds more record products keeps ``band_u`` after this set-up

    def __init__(self, model: ExplicitModel, cut_file: str | Path, tol: float = INTERPOLATION_TOL):
        comm = model.comm
        d = read_band(Path(cut_file), model)  # every rank reads (small, read-only)
        self.times, self.band_u = d["times"], d["u"]  # (n_rec,), (n_rec, n_nodes, gdim): the set-up's only
        self._times_list = self.times.tolist()  # the same floats, for bisect (CutDriver.at)
        # the last step may end past the record by less than one record spacing or one submodel step (a submodel
        # step longer than the global's: a kinematic submodel under a penalty global): CutDriver.at extrapolates
        spacing = self.times[-1] - self.times[-2] if self.times.size > 1 else 0.0
        if model.steps * model.dt > self.times[-1] + max(spacing, model.dt):
            raise SceneError(
                "simulation.end_time",
                model.scene.end_time,
                f"must be <= the recorded global time {self.times[-1]:g} s (global run's --record-until)",
            )
        Vb, node_of_dof = band_space(d, comm)
        V0, nodes0, cut_cells, self.cut_nodes = cut_space(model)
        bs = model.bs
        self.idx = self.cut_nodes[:, None] * bs + np.arange(bs)[None, :]  # (n_cut, bs) owned entries
        t0 = time.perf_counter()
        self.W = cut_weights(V0, nodes0, cut_cells, Vb, node_of_dof, d["cells"], d["nodes"].shape[0], tol)
        self.band = (Vb, node_of_dof, d["cells"], d["nodes"].shape[0])  # the band space for a traction operator
        self.cut_cells = cut_cells
        self.build_time = comm.allreduce(time.perf_counter() - t0, op=MPI.MAX)
        # partition of unity: each cut node must be covered by the band (row sums 1). DOLFINx assigns a point
        # outside every cell but inside a candidate's bounding box to the closest cell and extrapolates (row sums
        # stay 1): bound how far, through the most negative weight
        rs = np.asarray(self.W.sum(axis=1)).ravel()
        bad = np.flatnonzero(np.abs(rs - 1.0) > 1e-8)
        if comm.allreduce(bad.size) > 0:
            raise RuntimeError(f"{bad.size} cut nodes are not covered by the recorded band (row sums != 1)")
        self.w_min = comm.allreduce(float(self.W.data.min(initial=0.0)), op=MPI.MIN)  # [-]
        if self.w_min < -MAX_EXTRAPOLATION:
            raise RuntimeError(
                f"cut nodes lie outside the recorded band (interpolation weight {self.w_min:.3g} < "
                f"-{MAX_EXTRAPOLATION}): the submodel cut is not inside the global model"
            )
        self.n_cut = comm.allreduce(nodes0.size)
        self.dt = model.dt
        # on the model's array backend (copied to a device once): the cut's displacement history W U_k, the entries
        be = self.be = model.backend
        self.xp, self.idx_step = be.xp, be.asarray(self.idx)
        self.cut_u = be.asarray(record_products(self.W, self.band_u))  # (n_rec, n_cut, gdim) [m]
        if not self.reads_band:  # the run reads the cut's own histories only
            del self.band_u
        # a checkpoint resumes only with the record it was driven by (rods.fe.model)
        self.checkpoint_identity = cut_identity(cut_file)
        # work done by the cut on the submodel (this rank's cut entries) [J]: the prescription adds the impulse
        # R = M (v_prescribed - v_free) [N s] per step, which moves through (v_{n-1/2} + v_{n+1/2})/2 Δt
        self.m_cut = be.asarray(model.mass[self.idx])  # [kg]
        self.v_prev = be.asarray(model.initial_velocity()[self.idx])  # v_{n-1/2} at the cut [m/s], v_0 at first
        self.work = 0.0
        self.cut_x = V0.tabulate_dof_coordinates()[nodes0]

    def state(self, step: int) -> dict[str, Any]:  # noqa: ARG002
        """What a restart needs (this rank, on the host): the cut's work so far and its last v_{n+1/2}."""
        return {"cut_work": self.work, "cut_v_prev": self.be.to_host(self.v_prev)}

    def restore(self, state: dict[str, np.ndarray]) -> None:
        self.work = float(state["cut_work"])
        self.v_prev = self.be.asarray(state["cut_v_prev"])

    def at(self, history, t: float):
        """A recorded ``history`` (n_rec, ...) at time t [s], linear in time between records (the scheme's own
        u(t)), extrapolated from the last two past the record (the last step's end, see the set-up)."""
        T = self._times_list  # bisect on a list: np.searchsorted on a scalar costs ~3 µs, 1-3 calls a step
        if len(T) == 1:
            return history[0]
        k = min(max(bisect.bisect_right(T, t) - 1, 0), len(T) - 2)  # (np.clip on a scalar: 20 µs)
        θ = (t - T[k]) / (T[k + 1] - T[k])
        return (1.0 - θ) * history[k] + θ * history[k + 1]

    def displacement(self, t: float) -> np.ndarray:
        """u at the owned cut nodes at time t [s]: W U_band(t), interpolated in time. (n_cut, gdim)"""
        return self.at(self.cut_u, t)

    def external_work(self) -> float:
        """Work done by the cut on the submodel so far (this rank's cut entries) [J]."""
        return self.work

    def after_step(self, step: int, t: float, state) -> None:  # noqa: ARG002
        """Overwrite v_{n+1/2} at the cut so that u_{n+1} = u_cut(t_{n+1})."""
        u, v, idx = state.u, state.v, self.idx_step
        target = self.displacement(t + self.dt)
        v_new = (target - u[idx]) / self.dt
        R = self.m_cut * (v_new - v[idx])  # impulse of the cut reaction [N s]
        self.work += float(self.xp.sum(R * 0.5 * (self.v_prev + v_new)))
        self.v_prev = v_new
        v[idx] = v_new
