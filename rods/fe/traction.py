"""Traction and mixed driving of a submodel at its cuts: the global's cut stress as nodal forces, with a
bar-impedance dashpot to the global's cut velocity in mixed driving (``submodel.driving``).

The displacement driver (:class:`rods.fe.cut.CutDriver`) prescribes the global's motion at the cut, so
a submodel inherits whatever compliance the global has between the cut and the contact (a penalty layer's
penetration, the paper's Abaqus practice). Surface-based submodelling (Abaqus) drives the cut with the
global's traction instead: the submodel's cut nodes move freely under

    f_i(t) = A_i t(x_i, t),    t = σ(u_global) · n,    A_i = ∫_cut N_i w ds,

n the submodel's outward normal at the cut (−e_z at Rod 1's cut z = −L_s, +e_z at Rod 2's), w = 2πr
(axisymmetric) or 1 (3D; the cut planes are taken normal to z, as for the displacement driver), σ Hooke's
stress of the recorded band's P1 displacement (:mod:`rods.fe.forms`), projected onto the band's nodes
(lumped L², as the field output's stresses) and interpolated onto the cut nodes (DOLFINx non-matching
interpolation). σ is linear in u, so the map from the band's displacement to the cut forces is built once, as
a sparse matrix T, from unit band fields; at run time f(t_n) = T U_band(t_n), the band history interpolated
linearly in time as for the displacement driver.

In the central-difference scheme the force enters as the impulse Δt f(t_n) on v_{n+1/2} (added after the
stepper's update: its M⁻¹(f_ext − K u_n) lacked it); its work Δt f · (v_{n−1/2} + v_{n+1/2})/2 enters the
energy balance. The submodel then carries no kinematic constraint at the cut: whatever its own contact does
differently from the global's leaves as waves that the prescribed traction reflects back (a free end for the
difference), and the submodel rings in its contact-and-rod-pieces mode (paper scene: +1.4% peak force at the
fine level from the penalty-free global, ``results/driver-study.md``).

Mixed driving (``submodel.driving = "mixed"``, the default) adds a dashpot to the global's cut velocity:

    f_i = A_i t(x_i, t) + c_i (v_g(x_i, t) − v_i),    c_i = A_i sqrt(E ρ) on the axial entry,

sqrt(E ρ) = ρ c_0 the bar impedance of the cut's rod. For the rod's long waves (the contact lasts ~200 µs,
wavelengths ≫ the diameter) this is the characteristic condition of the wave equation: t + ρ c_0 v is the
wave entering the region, which is taken from the global, while the wave leaving it is the submodel's own
and passes out unreflected. If the submodel moves as the global, the dashpot does nothing and the force is
the global's traction; what differs, the submodel's own contact (its compliance, its resolution), leaves
without ringing, so the global's contact error does not reach the submodel: from a penalty global whose peak
force is +0.43% (and whose displacement drives a penalty-free submodel to +5.9%) the mixed-driven
submodel is +0.04% to +0.05%. The dashpot is taken mid-step, implicit in v_{n+1/2} (unconditionally stable),
and its work is part of the cut's work. v_g is the central difference of the recorded displacement over
[t_n − Δt/2, t_n + Δt/2]. Only the axial entries get a dashpot: the transverse traction is small at the cut
and its waves are not the rod's long waves.
"""

from __future__ import annotations

import time
from pathlib import Path

import dolfinx
import numpy as np
import scipy.sparse
import ufl
from mpi4py import MPI

from rods.fe import forms
from rods.fe.cut import (
    INTERPOLATION_TOL,
    CutDriver,
    band_adjacency,
    band_space,
    cut_space,
    cut_weights,
    node_colouring,
    record_products,
)
from rods.fe.model import ExplicitModel

__all__ = ["TractionDriver", "cut_force_operator"]


class _BandTraction:
    """σ(u)·n of a band displacement ``u`` as P1 nodal values (lumped L² projection, as the field output's
    stresses: quadrature points only, so the hoop strain u_r/r is never evaluated on the axis, and a node on
    a face between two cells gets the average of both)."""

    def __init__(self, Vb_vec: dolfinx.fem.FunctionSpace, scene, kind: str, axial: int):
        band = Vb_vec.mesh
        tdim = band.topology.dim
        n_cells = band.topology.index_map(tdim).size_local + band.topology.index_map(tdim).num_ghosts
        z = band.geometry.x[band.geometry.dofmaps[0][:n_cells], axial].mean(axis=1)  # cell centroids [m]
        Q0 = dolfinx.fem.functionspace(band, ("DG", 0))
        side, λ, μ = (dolfinx.fem.Function(Q0) for _ in range(3))
        rod1 = z < 0.0  # Rod 1 lies at z < 0 (apexes at z = 0), its cut at z = −L_s: outward normal −e_z
        side.x.array[:] = np.where(rod1, -1.0, 1.0)
        for mask, rod in ((rod1, scene.rod1), (~rod1, scene.rod2)):
            λ.x.array[mask], μ.x.array[mask] = rod.material.lame
        self.u = dolfinx.fem.Function(Vb_vec)
        self.t = dolfinx.fem.Function(Vb_vec)
        x = ufl.SpatialCoordinate(band)
        σ = forms.stress(forms.strain(self.u, x, kind), λ, μ)  # 3x3; axisymmetric ordered (r, θ, z)
        rows = (0, 2) if kind == "axisymmetric" else (0, 1, 2)  # the in-plane components of σ e_z
        q, w = ufl.TestFunction(Vb_vec), forms.measure_weight(x, kind)
        dx = ufl.dx(metadata={"quadrature_degree": 2})
        self.form = dolfinx.fem.form(ufl.inner(ufl.as_vector([side * σ[i, 2] for i in rows]), q) * w * dx)
        one = ufl.as_vector([1.0] * len(rows))
        self.inv_m = 1.0 / self._assemble(dolfinx.fem.form(ufl.inner(one, q) * w * dx))

    def _assemble(self, form) -> np.ndarray:
        imap = self.u.function_space.dofmap.index_map
        return forms.assemble_owned(form, imap.size_local * self.u.function_space.dofmap.index_map_bs)

    def evaluate(self) -> dolfinx.fem.Function:
        """The P1 traction [Pa] of the current ``u``."""
        n = self.inv_m.size
        self.t.x.array[:n] = self._assemble(self.form) * self.inv_m
        self.t.x.scatter_forward()
        return self.t


def cut_force_operator(
    model: ExplicitModel, d: dict, tol: float = INTERPOLATION_TOL
) -> tuple[scipy.sparse.csr_matrix, np.ndarray, np.ndarray]:
    """T (owned cut entries x band entries) with f_cut = T U_band.ravel() [N], the cut nodes (parents) and their
    tributary areas A_i [m^2], for the band record ``d`` as the model reads it (:func:`rods.fe.cut.read_band`)."""
    Vb, node_of_dof = band_space(d, model.comm)
    V0, nodes0, cut_cells, cut_nodes = cut_space(model)
    n_nodes = d["nodes"].shape[0]
    W = cut_weights(V0, nodes0, cut_cells, Vb, node_of_dof, d["cells"], n_nodes, tol)
    T, area = _force_operator(model, Vb, node_of_dof, d["cells"], n_nodes, cut_nodes, W)
    return T, cut_nodes, area


def _band_traction_matrix(model: ExplicitModel, Vb, node_of_dof, cells: np.ndarray, n_nodes: int):
    """B (band entries x band entries, every rank): t = B u, the lumped-projected traction of a band displacement
    (:class:`_BandTraction`, linear in u). Its columns from unit fields on one colour of nodes and one component
    at a time (:func:`rods.fe.cut.node_colouring`, two hops: each node k then has at most one node j of the
    colour among the nodes it shares a cell with, the only ones its traction depends on, so t_k is column j's
    entry); bs x 125 projections for structured hexahedra instead of bs per band node."""
    bs = model.bs
    Vb_vec = dolfinx.fem.functionspace(Vb.mesh, ("Lagrange", 1, (bs,)))
    traction = _BandTraction(Vb_vec, model.scene, model.kind, model.axial)
    graph = band_adjacency(cells, n_nodes)
    A = graph.tocoo()  # (k, j): k's traction may depend on u_j
    colour = node_colouring(graph, 2)
    own = np.arange(Vb.dofmap.index_map.size_local)
    dof_of_node = np.full(n_nodes, -1, dtype=np.int64)
    dof_of_node[node_of_dof[own]] = own
    mine = dof_of_node[A.row] >= 0  # pairs whose k this rank owns (its t_k is complete here)
    k_pairs, j_pairs = A.row[mine], A.col[mine]
    rows, cols, vals = [], [], []
    for κ in range(int(colour.max(initial=-1)) + 1):  # collective: every rank has every colour
        on = colour[node_of_dof[own]] == κ
        of_colour = colour[j_pairs] == κ
        k, j = k_pairs[of_colour], j_pairs[of_colour]
        for c in range(bs):
            traction.u.x.array[:] = 0.0
            traction.u.x.array[own[on] * bs + c] = 1.0
            traction.u.x.scatter_forward()
            t = traction.evaluate().x.array
            for r in range(bs):
                rows.append(k * bs + r)
                cols.append(j * bs + c)
                vals.append(t[dof_of_node[k] * bs + r])
    gathered = model.comm.allgather((np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)))
    r, c, v = (np.concatenate([g[i] for g in gathered]) for i in range(3))
    keep = v != 0.0
    return scipy.sparse.csr_matrix((v[keep], (r[keep], c[keep])), shape=(n_nodes * bs, n_nodes * bs))


def _force_operator(model, Vb, node_of_dof, cells: np.ndarray, n_nodes: int, cut_nodes, W):
    """T and A_i of :func:`cut_force_operator` on a built band space, cut and cut weights W
    (:func:`rods.fe.cut.cut_weights`): σ is linear in u, so T = diag(A_i) (W ⊗ I) B, the band traction
    (:func:`_band_traction_matrix`) interpolated onto the cut nodes with W per component (the non-matching
    interpolation of the P1 traction, as one field) times the cut nodes' tributary areas A_i."""
    bs = model.bs
    msh, rm, tags = model.V.mesh, model.rm, model.tags
    ds = ufl.Measure("ds", domain=msh, subdomain_data=rm.facet_tags)((tags["rod1_end"], tags["rod2_end"]))
    area = model._assemble_owned(forms.tributary_area_form(model.V, ds, model.kind))[cut_nodes * bs + model.axial]
    B = _band_traction_matrix(model, Vb, node_of_dof, cells, n_nodes)
    interpolate = scipy.sparse.kron(W, scipy.sparse.identity(bs), format="csr")  # rows i*bs + c, columns j*bs + c
    T = scipy.sparse.diags(np.repeat(area, bs)) @ interpolate @ B  # [N per m of band displacement]
    return T.tocsr(), area


class TractionDriver(CutDriver):
    """Observer of the submodel run: the global's cut traction as nodal forces on the cut (module docstring);
    their work (``external_work()``) enters the energy balance. ``absorbing``: mixed driving, the traction plus
    a dashpot to the global's cut velocity (module docstring)."""

    reads_band = True  # its traction history is a record product too

    def __init__(
        self, model: ExplicitModel, cut_file: str | Path, tol: float = INTERPOLATION_TOL, absorbing: bool = False
    ):
        super().__init__(model, cut_file, tol)  # the band history, the cut's coverage checks, the backend
        t0 = time.perf_counter()
        T, area = _force_operator(model, *self.band, self.cut_nodes, self.W)  # the band, cut and weights built once
        self.build_time += model.comm.allreduce(time.perf_counter() - t0, op=MPI.MAX)
        be = model.backend
        self.cut_f = be.asarray(record_products(T, self.band_u))  # (n_rec, n_cut bs) [N]: T U_k of every record
        del self.band_u  # the run reads the cut's own histories only
        # Δt M⁻¹ [s/kg] on the cut entries, zero where constrained (u_r on the axis, a symmetry plane's normal)
        self.dt_inv_m = be.asarray(model.dt * model.inv_mass[self.idx])
        self.c = None
        if absorbing:  # each cut's rod's bar impedance per area Z/A = ρ c [kg/(m^2 s)] on the axial entries [N s/m]
            c = np.zeros(self.idx.shape)
            rod1 = self.cut_x[:, model.axial] < 0.0
            for mask, rod in ((rod1, model.scene.rod1), (~rod1, model.scene.rod2)):
                c[mask, model.axial] = area[mask] * rod.impedance / rod.area
            self.c = be.asarray(c)
            k = 0.5 * self.dt_inv_m * self.c  # the dashpot's mid-step share ½ Δt M⁻¹ c: a constant of the run
            self._k = (k, 1.0 + k)

    def force(self, t: float):
        """Nodal forces [N] on the owned cut entries at time t [s], shaped like the cut entries (n_cut, bs)."""
        return self.at(self.cut_f, t).reshape(self.idx_step.shape)

    def after_step(self, step: int, t: float, state) -> None:  # noqa: ARG002
        """Add the impulse Δt f(t_n) to v_{n+1/2} at the cut (with the dashpot, mid-step implicit in v); its work
        enters the balance."""
        v, idx, dt = state.v, self.idx_step, self.dt
        v_free, f = v[idx], self.force(t)
        if self.c is None:
            v_new = v_free + self.dt_inv_m * f
        else:  # m (v_new - v_free)/Δt = f + c (v_g - (v_prev + v_new)/2), v_g the global's cut velocity at t_n
            v_g = (self.displacement(t + 0.5 * dt) - self.displacement(t - 0.5 * dt)) / dt
            k, one_k = self._k  # ½ Δt M⁻¹ c and 1 + ½ Δt M⁻¹ c, formed once at the set-up
            v_new = (v_free + self.dt_inv_m * (f + self.c * v_g) - k * self.v_prev) / one_k
        R = self.m_cut * (v_new - v_free)  # the impulse over the step [N s]
        self.work += float(self.xp.sum(R * 0.5 * (self.v_prev + v_new)))
        self.v_prev = v_new
        v[idx] = v_new
