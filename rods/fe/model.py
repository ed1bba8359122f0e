"""The paper's global FE model (Sec. 2.2), axisymmetric or 3D: both rods, penalty contact, explicit dynamics.

:class:`GlobalModel` sets everything up once — mesh, stiffness K (one PETSc block matrix, BAIJ with
block size 2 axisymmetric, 3 in 3D), row-sum lumped mass, contact, probes, stable step — and
:meth:`GlobalModel.run` marches the central-difference scheme (:mod:`rods.fe.explicit`) with Mat/Vec
operations and vectorised numpy only. Initial state: u = 0, Rod 1 moving at +s1 along z (the impact
direction; in 3D along Rod 2's axis also when Rod 1 is tilted), Rod 2 at rest, the tips touching at
one point. Free rods: no external work.

One code path for both geometry kinds (``fe.kind``): the kind selects the mesh builder
(:mod:`rods.fe.mesh` or :mod:`rods.fe.mesh3d`), the volume weight and strain in the forms, the block
size and axial index, the contact pairing (linear in r or bilinear over the face) and the
constrained entries with zero inverse mass (u_r on the axis; u_x on x = 0 and u_y on y = 0 for
half/quarter symmetry in 3D). A symmetry model reports extensive quantities (force, energies,
momentum, area) for the full rods. 3D adds the probes ``rod2_mid_*_plus_x``/``_minus_x`` (Rod 2's
midpoint at x = ±R2: their strain difference is the bending an offset or tilt induces) and the
contact-patch keys :data:`rods.fe.contact.PATCH_KEYS`.

Sign conventions of the outputs: velocity along +z (the impact direction) positive; strain
ε_zz, compression negative; contact force, pressure: compressive magnitudes >= 0.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

from rods import hertz, metrics
from rods.fe import checkpoint, forms
from rods.fe.contact import PenaltyContact, bilinear_pairing, face_quads, tip_nodes
from rods.fe.explicit import largest_eigenvalue, stable_step, switching_step
from rods.fe.guards import FINITE_EVERY, INVERSION_EVERY, Guard, SimulationError
from rods.fe.mesh import TAGS, RodsMesh, build_mesh, cell_sizes
from rods.fe.mesh3d import TAGS_3D, build_mesh_3d, cell_sizes_3d
from rods.fe.probes import PointProbes
from rods.scene import Scene, SceneError

__all__ = ["FEResult", "GlobalModel"]

DEFAULT_FIELD_INTERVAL = 10e-6  # [s] when "fields" is requested without fe.field_interval


@dataclass
class FEResult:
    history: dict[str, np.ndarray]
    units: dict[str, str]
    summary: dict[str, Any]
    pressure_profile: dict[str, np.ndarray] = field(default_factory=dict)  # r [m], p [Pa] at peak force


def _vec(comm: MPI.Comm, a: np.ndarray, n_global: int, bs: int) -> PETSc.Vec:
    """A PETSc Vec that shares the memory of the owned numpy array ``a``."""
    return PETSc.Vec().createWithArray(a, size=(a.size, n_global), bsize=bs, comm=comm)


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """a·b without BLAS (a threaded BLAS dot stalls the time loop when the cores are shared)."""
    return float(np.einsum("i,i->", a, b))


class GlobalModel:
    """Set up the global model of a scene (collective on ``comm``)."""

    def __init__(self, scene: Scene, comm: MPI.Comm = MPI.COMM_WORLD):
        t0 = time.perf_counter()
        self.scene, self.comm = scene, comm
        self.kind = kind = scene["fe.kind"]
        if kind not in forms.KINDS:
            raise SceneError("fe.kind", kind, f"must be one of {forms.KINDS}")
        if scene["fe.degree"] != 1:  # ∫ N_0 r dr = 0 for the P2 axis vertex: a zero (or negative) row sum
            raise SceneError(
                "fe.degree",
                scene["fe.degree"],
                "the explicit model supports 1 (row-sum lumped Q2 masses vanish on the axis; "
                "3D contact pairs Q1 face quadrilaterals)",
            )
        three_d = kind == "3d"
        self.axial = 2 if three_d else 1  # index of the axial (z) component
        self.tags = tags = TAGS_3D if three_d else TAGS
        rm: RodsMesh = build_mesh_3d(scene, comm) if three_d else build_mesh(scene, comm)
        self.rm = rm
        self.multiplicity = getattr(rm, "multiplicity", 1)  # full rods / modelled part [-]
        msh = rm.mesh
        V = dolfinx.fem.functionspace(msh, ("Lagrange", scene["fe.degree"], (msh.geometry.dim,)))
        self.V = V
        imap, bs = V.dofmap.index_map, V.dofmap.index_map_bs
        self.bs = bs
        self.n_local = imap.size_local * bs  # owned dofs on this rank
        self.n_global = imap.size_global * bs
        self.mat = forms.materials(msh, rm.cell_tags, scene, tags)

        # stiffness: assembled once, block AIJ (bs x bs node blocks: 2 axisymmetric, 3 in 3D)
        self.stiffness = dolfinx.fem.form(forms.stiffness_form(V, self.mat, kind))
        self.K = self._assemble_stiffness()

        # row-sum lumped mass (owned entries)
        self.mass = self._assemble_owned(forms.lumped_mass_form(V, self.mat, kind))  # [kg]
        # constrained entries get zero inverse mass (no acceleration): u_r = 0 on the axis (axisymmetric),
        # the normal component on a symmetry plane (3D: u_x on x = 0, u_y on y = 0)
        fdim = msh.topology.dim - 1

        def entries(tag: str, comp: int) -> np.ndarray:
            nodes = dolfinx.fem.locate_dofs_topological(V, fdim, rm.facet_tags.find(tags[tag]))
            return nodes[nodes < imap.size_local] * bs + comp

        self.axis_r = entries("axis", 0) if not three_d else np.zeros(0, dtype=np.int64)
        self.fixed = np.concatenate([entries("sym_x", 0), entries("sym_y", 1)]) if three_d else self.axis_r
        self.inv_mass = 1.0 / self.mass
        self.inv_mass[self.fixed] = 0.0

        # initial velocity: Rod 1 at +s1 along z
        rod1_nodes = dolfinx.fem.locate_dofs_topological(V, msh.topology.dim, rm.cell_tags.find(tags["rod1"]))
        rod1_nodes = rod1_nodes[rod1_nodes < imap.size_local]
        self.rod1_z = rod1_nodes * bs + self.axial

        # contact: Rod-1 tip nodes (slaves) against the Rod-2 tip face (master)
        ds = ufl.Measure("ds", domain=msh, subdomain_data=rm.facet_tags)
        area1 = self._assemble_owned(forms.tributary_area_form(V, ds(tags["rod1_tip"]), kind))
        area2 = self._assemble_owned(forms.tributary_area_form(V, ds(tags["rod2_tip"]), kind))
        slave = tip_nodes(V, rm.facet_tags.find(tags["rod1_tip"]), area1, self.axial)
        master = tip_nodes(V, rm.facet_tags.find(tags["rod2_tip"]), area2, self.axial)
        m1, m2 = scene.rod1.material, scene.rod2.material
        self.E_star = hertz.effective_modulus(m1.youngs_modulus, m1.poisson_ratio, m2.youngs_modulus, m2.poisson_ratio)
        self.h_normal = rm.h_tip  # element size normal to the contact faces [m]
        self.ε_pen = scene["fe.penalty"] * self.E_star / self.h_normal  # [Pa/m]
        pairing, mirrored = None, (False, False)
        if three_d:  # geometric search over the allgathered face (the same on every rank)
            quads = face_quads(V, rm.facet_tags.find(tags["rod2_tip"]), master)
            pairing = bilinear_pairing(slave.xy, master.xy, quads)
            mirrored = (rm.symmetry == "quarter", rm.symmetry != "full")
        self.contact = PenaltyContact(slave, master, self.ε_pen, comm, pairing, self.multiplicity, mirrored)

        # probes: stations on the rod surface (r = d/2); rod 2 at z = +x, rod 1 at z = -x from the tip
        # (3D: at x = +d/2, y = 0, Rod 1's placed with the rod), then in 3D Rod 2's midpoint at x = ±R2
        pts = []
        self.probe_keys = [(f"{s.name}_velocity", f"{s.name}_strain") for s in scene.stations]
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
                # quarter model: the -x side is the mirror image of the +x side
                pts.append([abs(x_side) if rm.symmetry == "quarter" else x_side, 0.0, z_mid])
                self.probe_keys.append((f"rod2_mid_velocity_{side}", f"rod2_mid_strain_{side}"))
        self.probes = PointProbes(V, np.array(pts, dtype=float), self.axial)

        # stable step
        self._stable_step()
        self.setup_time = time.perf_counter() - t0

    # ------------------------------------------------------------------------------------------
    def _assemble_stiffness(self) -> PETSc.Mat:
        """K as a PETSc block matrix (BAIJ, 2x2 node blocks). Measured at the paper mesh (51.5k DOFs, one
        process): MatMult 0.30 ms as BAIJ, 0.46 ms as AIJ with inodes, 0.50 ms without. A MatDuplicate
        copy multiplied ~4x slower in the same test, so a second matrix is assembled afresh instead."""
        K = dolfinx.fem.petsc.assemble_matrix(self.stiffness, kind="baij")
        K.assemble()
        return K

    def _assemble_owned(self, form: ufl.Form) -> np.ndarray:
        b = dolfinx.fem.petsc.assemble_vector(dolfinx.fem.form(form))
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        out = b.array_r[: self.n_local].copy()
        b.destroy()
        return out

    def _omega_max(self, with_contact: bool) -> float:
        """ω_max [rad/s] of M^-1 (K [+ K_c at full engagement]) via M^-½ (K + K_c) M^-½ (SLEPc)."""
        D = np.sqrt(self.inv_mass)
        z, Kz = np.zeros(self.n_local), np.zeros(self.n_local)
        zv, Kzv = _vec(self.comm, z, self.n_global, self.bs), _vec(self.comm, Kz, self.n_global, self.bs)

        def apply(x: np.ndarray, y: np.ndarray) -> None:
            np.multiply(D, x, out=z)
            self.K.mult(zv, Kzv)
            if with_contact:
                self.contact.apply_stiffness(z, Kz)
            y += D * Kz

        return math.sqrt(largest_eigenvalue(apply, self.n_local, self.comm))

    def _gershgorin(self) -> float:
        """Gershgorin bound on ω_max² [1/s²]: max_i Σ_j |(K + K_c)_ij| / m_i over unconstrained entries."""
        # DOLFINx's own CSR matrix (owned rows, all columns): no PETSc type conversion needed
        S = dolfinx.fem.assemble_matrix(self.stiffness).to_scipy()
        rows = np.asarray(abs(S).sum(axis=1)).ravel()[: self.n_local]
        del S
        self.contact.add_abs_row_sums(rows)
        return self.comm.allreduce(float(np.max(rows * self.inv_mass, initial=0.0)), op=MPI.MAX)

    def _stable_step(self) -> None:
        sc = self.scene
        self.ω_max_K = self._omega_max(False)
        self.ω_max = self._omega_max(True)
        self.ξ = sc["fe.bulk_viscosity"]
        self.dt_critical = stable_step(self.ω_max, self.ξ)  # [s]
        self.dt_critical_no_contact = stable_step(self.ω_max_K, self.ξ)
        self.dt_gershgorin = stable_step(math.sqrt(self._gershgorin()), self.ξ)  # a safe lower bound [s]
        self.ω_contact = self.contact.pair_frequency(self.inv_mass)  # [rad/s]
        self.dt_switching = switching_step(self.ω_contact)  # [s]
        h_min = min(cell_sizes_3d(self.rm.mesh) if self.kind == "3d" else cell_sizes(self.rm.mesh))
        self.h_min = h_min  # smallest element size [m] (element step estimate, run guards)
        c_d = max(r.material.dilatational_wave_speed for r in sc.rods)
        self.dt_element = h_min / c_d  # [s]
        req = sc["fe.dt"]
        if req == "auto":
            self.dt = min(sc["fe.dt_fraction"] * self.dt_critical, self.dt_switching)
        else:
            if req > self.dt_critical:
                raise SceneError("fe.dt", req, f"must be <= stable limit {self.dt_critical:g} s")
            if req > self.dt_switching:
                raise SceneError(
                    "fe.dt",
                    req,
                    f"must be <= contact-switching limit {self.dt_switching:g} s (stiff penalty: "
                    "contact nodes would rattle and pump energy; lower fe.penalty or fe.dt)",
                )
            self.dt = float(req)
        self.β_visc = 2.0 * self.ξ / self.ω_max  # stiffness-proportional damping C = β K [s]
        self.steps = math.ceil(sc.end_time / self.dt * (1 - 1e-12))

    def plan(self) -> dict[str, Any]:
        """What will run (printed by the workflow before the time loop)."""
        sc, rm = self.scene, self.rm
        mesh_text = getattr(rm, "description", None) or (
            f"{rm.n_radial} radial x ({rm.n_axial[0]} + {rm.n_axial[1]}) axial Q{sc['fe.degree']} cells, "
            f"h_r = {rm.h_radial * 1e3:.4g} mm, h_z = {rm.h_axial * 1e3:.4g} mm (tip {rm.h_tip * 1e3:.4g} mm)"
        )
        return {
            "model": self.model_name,
            "scene": sc.name,
            "mesh": mesh_text,
            "cells": rm.mesh.topology.index_map(rm.mesh.topology.dim).size_global,
            "dofs": self.n_global,
            "ranks": self.comm.size,
            "penalty": f"{self.ε_pen:.4g} Pa/m ({sc['fe.penalty']:g} x E*/h, "
            f"E* = {self.E_star:.4g} Pa, h = {self.h_normal:.4g} m)",
            "dt": self.dt,
            "dt_critical": self.dt_critical,
            "dt_critical_without_contact": self.dt_critical_no_contact,
            "dt_element_estimate": self.dt_element,
            "dt_gershgorin": self.dt_gershgorin,
            "dt_contact_switching": self.dt_switching,
            "steps": self.steps,
            "end_time": sc.end_time,
            "output_interval": sc.output_interval,
            "bulk_viscosity": self.ξ,
            "fields": self.wants_fields(),
        }

    @property
    def model_name(self) -> str:
        return "fe-3d" if self.kind == "3d" else "fe-axisymmetric"

    def wants_fields(self) -> bool:
        return "fields" in self.scene.effects or self.scene["fe.field_interval"] > 0

    # ------------------------------------------------------------------------------------------
    def run(
        self,
        out: Path | None = None,
        progress: Callable[[int, int, float], None] | None = None,
        step_hook: Callable[[int, float, np.ndarray, np.ndarray], None] | None = None,
        restart: bool = False,
    ) -> FEResult:
        """March the central-difference scheme to the scene's end time (collective).

        Per step: one block-matrix multiply-add v += A (u [+ β v]) with A = -Δt M^-1 K (assembled
        once; axis u_r rows are zero), the contact impulse Δt M^-1 f_c on the tip entries, and
        u += Δt v. Energies and probes are evaluated at output steps only.

        Guards (rods.fe.guards) stop a run whose energy grows or whose state turns non-finite with a
        SimulationError carrying the histories so far. With ``fe.checkpoint_interval`` > 0 the state is
        checkpointed into ``out`` (rods.fe.checkpoint); ``restart=True`` resumes from the last one.

        ``step_hook(step, t_n, u_n, v_{n+1/2})`` runs after the velocity update and may edit v (a driven
        submodel cut). A hook that does work on the model exposes ``step_hook.external_work()``: this
        rank's accumulated work [J]; it then enters the energy balance (history ``external_work``).
        """
        sc, comm, dt = self.scene, self.comm, self.dt
        n, N = self.n_local, self.steps
        u, v, z, y = (np.zeros(n) for _ in range(4))
        uv, vv, zv, yv = (_vec(comm, a, self.n_global, self.bs) for a in (u, v, z, y))
        v[:] = self.initial_velocity()
        dt_inv_mass = dt * self.inv_mass  # Δt M^-1 [s/kg]
        mass_dt = self.mass / dt  # M/Δt [kg/s]
        mass_z = np.zeros(n)
        mass_z[self.axial :: self.bs] = self.mass[self.axial :: self.bs]  # [kg]
        A = self._assemble_stiffness()
        A.diagonalScale(L=_vec(comm, -dt_inv_mass, self.n_global, self.bs))
        β = self.β_visc  # C = β K [s]
        damped = β > 0
        c, P = self.contact, self.probes.P

        # output steps: the step nearest to each output time
        n_out = int(math.floor(sc.end_time / sc.output_interval * (1 + 1e-12))) + 1
        out_steps = np.unique(np.rint(np.arange(n_out) * sc.output_interval / dt).astype(np.int64))
        out_steps = out_steps[out_steps <= N]
        is_out = np.zeros(N + 1, dtype=bool)
        is_out[out_steps] = True
        n_st = len(self.probe_keys)  # probe points: the stations (+ 3D midpoint sides)
        n_pk = len(c.patch_keys)  # 3D contact-patch columns
        m_sym = float(self.multiplicity)  # extensive outputs for the full rods
        # t, F, a, πa², p_max, E_k, E_s, E_c, probes (velocity, strain), patch, p_z
        rec = np.zeros((out_steps.size, 9 + 2 * n_st + n_pk))
        W_hist = np.zeros(out_steps.size)
        Wext_hist = np.zeros(out_steps.size)  # work done by the step hook (driven cut) [J]
        external_work = getattr(step_hook, "external_work", None)
        W_local, s_prev = 0.0, 0.0  # dissipated energy (this rank's partial sum) [J]; v_{n-1/2}·f_d,n-1
        force = np.zeros(N + 1)  # total contact force at every step [N]
        peak: dict[str, Any] = {"F": -1.0}
        p_max_all = 0.0

        fields = self._field_writer(out) if (self.wants_fields() and out is not None) else None
        field_every = 0
        if fields is not None:
            field_every = max(1, int(round((sc["fe.field_interval"] or DEFAULT_FIELD_INTERVAL) / dt)))

        dot = _dot
        k, step0, wall_before = 0, 0, 0.0
        guard = Guard(dt, self.dt_critical, sc["fe.energy_growth_limit"])
        ck_every = int(round(sc["fe.checkpoint_interval"] / dt)) if sc["fe.checkpoint_interval"] > 0 else 0
        ck_key = self._checkpoint_key()
        if restart and out is not None:
            state = checkpoint.load(out, comm, ck_key)
            if state is not None:
                u[:], v[:] = state["u"], state["v"]
                step0, k = int(state["next_step"]), int(state["k"])
                rec[:k], W_hist[:k], force[:step0] = state["rec"], state["W_hist"], state["force"]
                Wext_hist[:k] = state.get("Wext_hist", np.zeros(k))
                W_local, s_prev, p_max_all = float(state["W_local"]), float(state["s_prev"]), float(state["p_max_all"])
                wall_before = float(state["wall"])
                peak = {
                    key[5:]: (state[key] if state[key].ndim else float(state[key]))
                    for key in state
                    if key.startswith("peak_")
                }
                if progress is not None:
                    sys.stderr.write(f"restart from checkpoint at step {step0} (t = {step0 * dt:.6g} s)\n")
        failure: SimulationError | None = None
        E0 = float(rec[0, 5:8].sum()) if k > 0 else 0.0
        t_start = time.perf_counter()
        for step in range(step0, N + 1):
            c.evaluate(u)  # contact at u_n
            F = c.force
            force[step] = F
            if F > peak["F"]:
                peak = {"F": F, "t": step * dt, "a": c.radius(), "A_nodal": c.active_area(), "p": c.pressure.copy()}
                peak["patch"] = c.patch()
            record = is_out[step]
            if record:
                u_old, v_old = u.copy(), v.copy()
            if damped:  # f_d,n = C v_{n-1/2}; y = A v = -Δt M^-1 K v
                A.mult(vv, yv)
                vfd = -β * dot(mass_dt * v, y)
                if step > 0:
                    W_local += 0.5 * dt * (s_prev + vfd)
            if step == 0:  # half step: v_{1/2} = v_0 + ½ Δt a_0
                A.mult(uv, zv)
                if damped:
                    z += β * y
                z *= 0.5
                c.add_force(z, 0.5 * dt_inv_mass)
                v += z
            else:  # v_{n+1/2} = v_{n-1/2} + Δt M^-1 (f_c - K u_n - C v_{n-1/2})
                A.multAdd(uv, vv, vv)
                if damped:
                    vv.axpy(β, yv)
                c.add_force(v, dt_inv_mass)
            v_scheme = v
            if step_hook is not None:  # submodel cut: record (global) or prescribe v_{n+1/2} (rods.fe.submodel)
                if record:
                    v_scheme = v.copy()  # the strain energy below is recovered from the scheme's own increment
                step_hook(step, step * dt, u, v)  # u = u_n, v = v_{n+1/2} (owned arrays, v may be edited)
            uv.axpy(dt, vv)  # u_{n+1} = u_n + Δt v_{n+1/2}
            if damped:
                s_prev = -β * dot(mass_dt * v, y)
            if record:
                # K u_n recovered from the velocity increment: Δv_K = -Δt M^-1 K u_n
                dv = v_scheme - v_old
                c.add_force(dv, -(0.5 if step == 0 else 1.0) * dt_inv_mass)
                if damped:
                    dv -= (0.5 if step == 0 else 1.0) * β * y
                if step == 0:
                    dv *= 2.0
                Es_local = -0.5 * dot(mass_dt * u_old, dv)
                Ek_local = 0.5 * dot(self.mass * v_old, v)
                W_ext = external_work() if external_work is not None else 0.0
                loc = np.concatenate(
                    ([Ek_local, Es_local, W_local, W_ext], P @ (v_old + v), P @ u_old, [dot(mass_z, v)])
                )
                if comm.size > 1:
                    comm.Allreduce(MPI.IN_PLACE, loc, op=MPI.SUM)
                if m_sym != 1.0:
                    loc[:4] *= m_sym
                    loc[-1] *= m_sym
                pv, pu = loc[4 : 4 + 2 * n_st], loc[4 + 2 * n_st : 4 + 4 * n_st]
                pmax = float(c.pressure.max()) if c.ns else 0.0
                p_max_all = max(p_max_all, pmax)
                a = c.radius()
                rec[k, :8] = (step * dt, F, a, math.pi * a * a, pmax, loc[0], loc[1], c.energy)
                rec[k, 8 : 8 + n_st] = 0.5 * pv[0::2]  # axial velocity at t_n, mean of the half steps
                rec[k, 8 + n_st : 8 + 2 * n_st] = pu[1::2]  # ε_zz at t_n
                rec[k, 8 + 2 * n_st : 8 + 2 * n_st + n_pk] = c.patch()
                rec[k, -1] = loc[-1]  # axial momentum at t_{n+1/2}
                W_hist[k], Wext_hist[k] = loc[2], loc[3]
                if k == 0:
                    E0 = float(rec[0, 5:8].sum())
                k += 1
                try:
                    guard.check(step, step * dt, (loc[0], loc[1], c.energy, loc[2] - loc[3]), E0)
                except SimulationError as e:
                    failure = e
                    break
            if step % FINITE_EVERY == 0:
                # NaN/Inf anywhere poisons the dot product; inverted cells are counted every INVERSION_EVERY
                inv = self.inverted_cells(u) if step % INVERSION_EVERY == 0 else 0
                health = np.array([float(np.isfinite(dot(v, v))), -float(inv)])
                if comm.size > 1:
                    comm.Allreduce(MPI.IN_PLACE, health, op=MPI.MIN)
                try:
                    guard.check_finite(step, step * dt, bool(health[0]))
                    guard.check_inverted(step, step * dt, int(-health[1]))
                except SimulationError as e:
                    failure = e
                    break
            if ck_every and out is not None and step % ck_every == 0 and step > step0 and step < N:
                peak_state = {f"peak_{key}": np.asarray(val) for key, val in peak.items()}
                checkpoint.save(
                    out,
                    step,
                    step * dt,
                    {
                        "u": u, "v": v, "next_step": step + 1, "k": k, "rec": rec[:k], "W_hist": W_hist[:k],
                        "Wext_hist": Wext_hist[:k], "force": force[: step + 1], "W_local": W_local, "s_prev": s_prev,
                        "p_max_all": p_max_all,
                        "wall": wall_before + time.perf_counter() - t_start, **peak_state,
                    },
                    comm,
                    ck_key,
                )  # fmt: skip
            if fields is not None and step % field_every == 0:
                fields(step * dt, u - dt * v, v)  # u_n and v_{n+1/2}
            if progress is not None and (step % 500 == 0 or step == N):
                progress(step, N, time.perf_counter() - t_start)
        wall_loop = wall_before + comm.allreduce(time.perf_counter() - t_start, op=MPI.MAX)
        A.destroy()
        if fields is not None:
            fields(None, None, None)
        if failure is not None:  # keep what was recorded up to the failure, readable
            n_ok = k - 1 if k > 1 else k  # the last record is the one the guard refused
            try:
                failure.partial = self._result(
                    rec[:n_ok], W_hist[:n_ok], Wext_hist[:n_ok], force[: failure.step], peak, p_max_all, wall_loop
                )
                failure.partial.summary.update(status="failed", error=str(failure), failed_step=failure.step)
            except Exception:  # too little recorded for a summary: the message alone must do
                failure.partial = None
            raise failure
        return self._result(rec, W_hist, Wext_hist, force, peak, p_max_all, wall_loop)

    def initial_velocity(self) -> np.ndarray:
        """v_0 [m/s], owned entries: Rod 1 at +s1 along the impact direction, Rod 2 at rest."""
        v0 = np.zeros(self.n_local)
        v0[self.rod1_z] = self.scene.speed
        return v0

    def inverted_cells(self, u_owned: np.ndarray) -> int:
        """Number of this rank's cells with a corner whose deformed Jacobian changed sign (an inverted
        element; P1 cells, corner Jacobians from the edges to the corner's tensor-product neighbours)."""
        if not hasattr(self, "_corner"):
            V = self.V
            cells = V.dofmap.list  # (n_cells, corners) node indices, tensor-product vertex order
            nc = cells.shape[1]
            dim = int(round(np.log2(nc)))
            nbr = np.array([[k ^ (1 << d) for d in range(dim)] for k in range(nc)])  # (corners, dim)
            X = V.tabulate_dof_coordinates()[:, :dim]
            self._corner = (cells, nbr, dim, X, dolfinx.fem.Function(V))

            def dets(x: np.ndarray) -> np.ndarray:
                e = x[cells[:, nbr]] - x[cells][:, :, None, :]  # (cells, corners, dim, dim) edge vectors
                if dim == 2:
                    return e[..., 0, 0] * e[..., 1, 1] - e[..., 0, 1] * e[..., 1, 0]
                return np.einsum("...i,...i->...", e[..., 0, :], np.cross(e[..., 1, :], e[..., 2, :]))

            self._corner_dets = dets
            self._corner_sign = np.sign(dets(X))
        cells, nbr, dim, X, uf = self._corner
        uf.x.array[: self.n_local] = u_owned
        uf.x.scatter_forward()
        x = X + uf.x.array.reshape(-1, self.bs)[:, :dim]
        bad = self._corner_dets(x) * self._corner_sign <= 0
        return int(
            np.count_nonzero(bad.any(axis=1)[: self.rm.mesh.topology.index_map(self.rm.mesh.topology.dim).size_local])
        )

    def _checkpoint_key(self) -> str:
        """Identifies scene + step + partition: a checkpoint is only resumed by the same run."""
        import hashlib
        import json

        text = json.dumps([self.scene.as_dict(), self.dt, self.comm.size, self.n_global], sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    # ------------------------------------------------------------------------------------------
    def _result(self, rec, W_hist, Wext_hist, force, peak, p_max_all, wall_loop) -> FEResult:
        sc, dt = self.scene, self.dt
        n_st = len(self.probe_keys)
        hist: dict[str, np.ndarray] = {
            "time": rec[:, 0],
            "contact_force": rec[:, 1],
            "contact_radius": rec[:, 2],
            "contact_area": rec[:, 3],
            "peak_pressure": rec[:, 4],
        }
        units = {"time": "s", "contact_force": "N", "contact_radius": "m", "contact_area": "m^2", "peak_pressure": "Pa"}
        for i, (kv, ks) in enumerate(self.probe_keys):
            hist[kv] = rec[:, 8 + i]
            hist[ks] = rec[:, 8 + n_st + i]
            units[kv], units[ks] = "m/s", "-"
        for i, key in enumerate(self.contact.patch_keys):
            hist[key] = rec[:, 8 + 2 * n_st + i]
            units[key] = "m"
        hist["kinetic_energy"], hist["strain_energy"], hist["contact_energy"] = rec[:, 5], rec[:, 6], rec[:, 7]
        hist["dissipated_energy"] = W_hist
        hist["external_work"] = Wext_hist
        hist["momentum"] = rec[:, -1]
        units["momentum"] = "kg m/s"
        for key in ("kinetic_energy", "strain_energy", "contact_energy", "dissipated_energy", "external_work"):
            units[key] = "J"
        E_total = rec[:, 5] + rec[:, 6] + rec[:, 7]
        E0 = E_total[0]
        # E(t) + dissipated(t) - work in(t) = E0; relative to the largest of E0 and the work put in
        scale = max(E0, float(np.max(np.abs(Wext_hist), initial=0.0)))
        energy_error = float(np.max(np.abs(E_total + W_hist - Wext_hist - E0)) / scale)
        t_steps = np.arange(force.size) * dt
        a_peak = peak.get("a", 0.0)
        s_mid = sc.stations[0].name
        summary: dict[str, Any] = {
            "model": self.model_name,
            "scene": sc.name,
            "impact_speed": sc.speed,
            "peak_contact_force": peak["F"],
            "peak_force_time": peak.get("t", 0.0),
            "contact_radius": a_peak,
            "contact_area": math.pi * a_peak**2,
            "contact_area_nodal": peak.get("A_nodal", 0.0),
            "peak_contact_pressure": max(p_max_all, float(np.max(peak.get("p", [0.0])))),
            "contact_duration": metrics.contact_duration(t_steps, force),
            "contact_episodes": [list(e) for e in metrics.contact_episodes(t_steps, force)],
            "midpoint_peak_speed": metrics.midpoint_peak_speed(hist["time"], hist[f"{s_mid}_velocity"]),
            "midpoint_peak_strain": float(np.min(hist[f"{s_mid}_strain"])),
            "wall_time": wall_loop,
            "setup_time": self.setup_time,
            "dofs": self.n_global,
            "cells": self.rm.mesh.topology.index_map(self.rm.mesh.topology.dim).size_global,
            "steps": int(force.size - 1),
            "dt": dt,
            "dt_critical": self.dt_critical,
            "dt_critical_without_contact": self.dt_critical_no_contact,
            "dt_element_estimate": self.dt_element,
            "dt_gershgorin": self.dt_gershgorin,
            "dt_contact_switching": self.dt_switching,
            "energy_error": energy_error,
            "initial_energy": float(E0),
            "ranks": self.comm.size,
            "penalty": self.ε_pen,
            "penalty_factor": sc["fe.penalty"],
            "bulk_viscosity": self.ξ,
            "dof_steps_per_second": self.n_global * (force.size - 1) / wall_loop if wall_loop > 0 else 0.0,
            "mesh": {
                "radial_size": self.rm.h_radial,
                "axial_size": self.rm.h_axial,
                "tip_axial_size": self.rm.h_tip,
                "n_radial": self.rm.n_radial,
                "n_axial": list(self.rm.n_axial),
            },
            "pressure_profile": {"r": self.contact.slave.r.tolist(), "p": np.asarray(peak.get("p", [])).tolist()},
            "scene_values": sc.as_dict(),
        }
        if self.kind == "3d":  # off-axis effects: patch at peak force, midpoint bending
            summary["symmetry"] = self.rm.symmetry
            summary["impact_offset"] = sc["impact.offset"]
            summary["impact_tilt"] = sc["impact.tilt"]
            summary["rod1_placement_dz"] = self.rm.placement.dz
            summary.update(zip(self.contact.patch_keys, peak.get("patch", (0.0, 0.0, 0.0)), strict=True))
            bend = 0.5 * (hist["rod2_mid_strain_plus_x"] - hist["rod2_mid_strain_minus_x"])
            summary["midpoint_peak_bending_strain"] = float(np.max(np.abs(bend)))
            summary["mesh"]["n_core"] = self.rm.n_core
        profile = {"r": self.contact.slave.r.copy(), "p": np.asarray(peak.get("p", np.zeros(self.contact.ns)))}
        return FEResult(hist, units, summary, profile)

    # ------------------------------------------------------------------------------------------
    def _field_writer(self, out: Path):
        """XDMF time series of u, v (P1) and σ_zz, σ_rr, von Mises (DG0); call f(t, u, v); f(None, ..) closes."""
        import dolfinx.io

        V, msh, kind = self.V, self.rm.mesh, self.kind
        if self.scene["fe.degree"] != 1:
            return None  # XDMF needs fields on the (linear) geometry; degree 2 fields not written
        uf = dolfinx.fem.Function(V, name="displacement")
        vf = dolfinx.fem.Function(V, name="velocity")
        Q = dolfinx.fem.functionspace(msh, ("DG", 0))
        x = ufl.SpatialCoordinate(msh)
        σ = forms.stress(forms.strain(uf, x, kind), self.mat.λ, self.mat.μ)
        s = ufl.dev(σ)
        exprs = {
            "sigma_zz": σ[2, 2],
            "sigma_xx" if kind == "3d" else "sigma_rr": σ[0, 0],
            "von_mises": ufl.sqrt(1.5 * ufl.inner(s, s)),
        }
        qf = {}
        for name, e in exprs.items():
            fq = dolfinx.fem.Function(Q, name=name)
            qf[name] = (fq, dolfinx.fem.Expression(e, Q.element.interpolation_points))
        xdmf = dolfinx.io.XDMFFile(msh.comm, str(Path(out) / "fields.xdmf"), "w")
        xdmf.write_mesh(msh)
        n = self.n_local

        def write(t, u, v):
            if t is None:
                xdmf.close()
                return
            uf.x.array[:n] = u
            vf.x.array[:n] = v
            uf.x.scatter_forward()
            vf.x.scatter_forward()
            xdmf.write_function(uf, t)
            xdmf.write_function(vf, t)
            for fq, e in qf.values():
                fq.interpolate(e)
                xdmf.write_function(fq, t)

        return write
