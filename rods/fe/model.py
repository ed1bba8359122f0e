"""The paper's explicit FE model (Sec. 2.2), axisymmetric or 3D: both rods, penalty contact, explicit dynamics.

:class:`ExplicitModel` sets everything up once — mesh, stiffness K (one PETSc matrix as DOLFINx assembles it,
multiplied in the loop as plain AIJ, :func:`rods.fe.backend.plain_aij`; a SciPy CSR matrix on the serial array
backends), row-sum lumped mass,
constraints, contact, probes, stable step, plan — for the global model and for the submodel alike
(:mod:`rods.fe.submodel` runs the same class on a shorter region). :meth:`ExplicitModel.run` is the loop: the
central-difference stepper (:class:`rods.fe.explicit.CentralDifference` on the array backend ``fe.backend``
names, :mod:`rods.fe.backend`: PETSc Mat/Vec by default and under MPI, NumPy/SciPy or CuPy serial), then the
observers (:mod:`rods.fe.observers`): the caller's (a submodel cut), the recorder (:mod:`rods.fe.recorder`),
the guards (:mod:`rods.fe.guards`), checkpoints (:mod:`rods.fe.checkpoint`), field output
(:mod:`rods.fe.fields`) and progress. Initial state: u = 0, Rod 1 moving at +s1 along z (the impact direction;
in 3D along Rod 2's axis also when Rod 1 is tilted), Rod 2 at rest, the tips touching at one point. Free rods:
no external work.

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

import contextlib
import json
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import scipy.sparse
import ufl
from mpi4py import MPI
from petsc4py import PETSc

from rods import cost, hertz, metrics
from rods.fe import backend as backends
from rods.fe import checkpoint, fields, forms, matrixfree
from rods.fe.contact import PenaltyContact, bilinear_pairing, face_quads, tip_nodes
from rods.fe.explicit import CentralDifference
from rods.fe.fields import FieldOutput
from rods.fe.guards import CornerJacobians, Guard, InterruptCheck, Interrupted, RunGuard
from rods.fe.kinematic import KinematicContact
from rods.fe.layout import graded_words
from rods.fe.mesh import TAGS, RodsMesh, build_mesh
from rods.fe.mesh3d import TAGS_3D, build_mesh_3d
from rods.fe.observers import Observer, Progress, march
from rods.fe.probes import PointProbes, station_points
from rods.fe.recorder import Recorder, output_steps
from rods.fe.timestep import time_step
from rods.scene import Scene, SceneError

__all__ = ["LOOP_BLAS_THREADS", "ExplicitModel", "FEResult", "loop_blas"]

# BLAS threads in the time loop: its dense work is the kinematic contact's LCP (a Cholesky of the active block, up to
# hundreds of pairs on a 3D patch), too small to gain from threads; under mpirun each rank's OpenBLAS started as many
# threads as the node has cores, and the oversubscribed threads made that factorisation ~300x slower: a 3D tilted
# submodel (897k DOFs, blocks of 1-291 pairs) spent 23 s of a 3 µs run in 232 factorisations on each of 2 ranks,
# 0.07 s serially; its loop ran ~2x slower on 2 ranks than on one, the study 9 min 6 s, now 2 min 36 s (2026-12-06)
LOOP_BLAS_THREADS = 1
try:  # pinned in requirements.txt; a bare install without it (a GPU machine's own Python) keeps the BLAS default
    from threadpoolctl import threadpool_limits
except ImportError:  # pragma: no cover
    threadpool_limits = None


def loop_blas() -> contextlib.AbstractContextManager:
    """The time loop's BLAS threads (:data:`LOOP_BLAS_THREADS`) while the context lasts, the caller's after it: a
    run's loop, and a benchmark's timed steps so that they time what a run does; a no-op without threadpoolctl."""
    return threadpool_limits(LOOP_BLAS_THREADS, "blas") if threadpool_limits else contextlib.nullcontext()


# 3: the histories and the force appended to a log per rank (rods.fe.checkpoint.Appended); 2: the state after a step
# is (u_n, v_{n+1/2}) (deferred drift); 1 held u_{n+1}
CHECKPOINT_FORMAT = 3


@dataclass
class FEResult:
    """An FE run (:meth:`ExplicitModel.run`): the histories at the output interval with their units, the summary
    (summary.json's keys), the contact pressure profile at the peak force, and the force at every step."""

    history: dict[str, np.ndarray]
    units: dict[str, str]
    summary: dict[str, Any]
    pressure_profile: dict[str, np.ndarray] = field(default_factory=dict)  # r [m], p [Pa] at peak force
    # time [s] and contact_force [N] at every step: the force the checks read (rods.checks.apply's ``force``),
    # not the history's output samples (a 50 µs output interval read a contact tail of 40 µs)
    force_trace: dict[str, np.ndarray] = field(default_factory=dict)


class ExplicitModel:
    """Set up the explicit model of a scene, global or submodel (collective on ``comm``)."""

    def __init__(self, scene: Scene, comm: MPI.Comm | None = MPI.COMM_WORLD):
        t0 = time.perf_counter()
        self.scene = scene
        self.comm = comm = MPI.COMM_WORLD if comm is None else comm  # None: as the stages take it
        self.kind = kind = scene["fe.kind"]
        if kind not in forms.KINDS:
            raise SceneError("fe.kind", kind, f"must be one of {forms.KINDS}")
        self.backend = backends.select(scene["fe.backend"], comm.size, scene["fe.operator"])  # refused before the mesh
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

        # stiffness: assembled once, block AIJ (bs x bs node blocks: 2 axisymmetric, 3 in 3D); on the serial
        # array backends DOLFINx's own CSR, kept for the step's limits and the stepper (never assembled again)
        stiffness = forms.stiffness_form(V, self.mat, kind)
        self.stiffness = dolfinx.fem.form(stiffness)
        self.K = self._assemble_stiffness() if self.backend is backends.PETSC else forms.assemble_csr(self.stiffness)
        # fe.operator = "matrix-free": the loop applies K element by element (rods.fe.matrixfree); K stays for the
        # step's limits and the contact's rows
        self.element = None
        if scene["fe.operator"] == "matrix-free":
            self.element = matrixfree.element_stiffness(V, self.mat, kind, stiffness, self.K)

        self.mass = self._assemble_owned(forms.lumped_mass_form(V, self.mat, kind))  # row-sum lumped [kg]
        self._constraints()
        self._contact()
        self.contact.use(self.backend)  # the step's limits run on the backend's arrays (rods.fe.timestep)
        self._probes()

        # stable step
        self._stable_step()
        self.setup_time = self.comm.allreduce(time.perf_counter() - t0, op=MPI.MAX)  # [s] the slowest rank's

    # ------------------------------------------------------------------------------------------
    def _constraints(self) -> None:
        """Constrained entries get zero inverse mass (no acceleration): u_r = 0 on the axis (axisymmetric),
        the normal component on a symmetry plane (3D: u_x on x = 0, u_y on y = 0); Rod 1's axial entries."""
        V, rm, tags, bs = self.V, self.rm, self.tags, self.bs
        msh, n_own = rm.mesh, V.dofmap.index_map.size_local
        fdim = msh.topology.dim - 1

        def entries(tag: str, comp: int) -> np.ndarray:
            nodes = dolfinx.fem.locate_dofs_topological(V, fdim, rm.facet_tags.find(tags[tag]))
            return nodes[nodes < n_own] * bs + comp

        three_d = self.kind == "3d"
        self.axis_r = entries("axis", 0) if not three_d else np.zeros(0, dtype=np.int64)
        self.fixed = np.concatenate([entries("sym_x", 0), entries("sym_y", 1)]) if three_d else self.axis_r
        self.inv_mass = 1.0 / self.mass
        self.inv_mass[self.fixed] = 0.0
        # initial velocity: Rod 1 at +s1 along z
        rod1_nodes = dolfinx.fem.locate_dofs_topological(V, msh.topology.dim, rm.cell_tags.find(tags["rod1"]))
        self.rod1_z = rod1_nodes[rod1_nodes < n_own] * bs + self.axial

    def _contact(self) -> None:
        """Rod-1 tip nodes (slaves) against the Rod-2 tip face (master), ε = fe.penalty x E*/h_tip."""
        V, rm, tags, kind, sc = self.V, self.rm, self.tags, self.kind, self.scene
        ds = ufl.Measure("ds", domain=rm.mesh, subdomain_data=rm.facet_tags)
        area1 = self._assemble_owned(forms.tributary_area_form(V, ds(tags["rod1_tip"]), kind))
        area2 = self._assemble_owned(forms.tributary_area_form(V, ds(tags["rod2_tip"]), kind))
        slave = tip_nodes(V, rm.facet_tags.find(tags["rod1_tip"]), area1, self.axial)
        master = tip_nodes(V, rm.facet_tags.find(tags["rod2_tip"]), area2, self.axial)
        self.E_star, self.R_star = hertz.contact_constants(sc.rod1, sc.rod2)  # [Pa], [m]
        self.h_normal = rm.h_tip  # element size normal to the contact faces [m]
        self.ε_pen = sc["fe.penalty"] * self.E_star / self.h_normal  # [Pa/m]
        pairing, mirrored = None, (False, False)
        if kind == "3d":  # geometric search over the allgathered face (the same on every rank)
            quads = face_quads(V, rm.facet_tags.find(tags["rod2_tip"]), master)
            pairing = bilinear_pairing(slave.xy, master.xy, quads)
            mirrored = (rm.symmetry == "quarter", rm.symmetry != "full")
        if sc["fe.contact"] == "kinematic":
            args = (slave, master, self.comm, self.inv_mass, pairing, self.multiplicity, mirrored)
            self.contact = KinematicContact(*args)
        else:
            self.contact = PenaltyContact(slave, master, self.ε_pen, self.comm, pairing, self.multiplicity, mirrored)

    def _probes(self) -> None:
        """Point probes at the scene's stations (:func:`rods.fe.probes.station_points`)."""
        points, self.probe_keys = station_points(self.scene, self.rm, self.kind == "3d")
        self.probes = PointProbes(self.V, points, self.axial)

    # ------------------------------------------------------------------------------------------
    def _assemble_stiffness(self) -> PETSc.Mat:
        """K as a PETSc block matrix (BAIJ, 2x2 node blocks) as DOLFINx assembles it; the time loop multiplies its
        plain AIJ form (rods.fe.backend.plain_aij: 1.2-1.5 ms against 0.47 ms a product at 52k DOFs, 2026-11-27;
        an earlier session measured the BAIJ product at 0.30 ms and AIJ at 0.46-0.50 ms on this machine). A
        MatDuplicate copy multiplied ~4x slower in that earlier test, so a second matrix is assembled afresh
        instead."""
        K = dolfinx.fem.petsc.assemble_matrix(self.stiffness, kind="baij")
        K.assemble()
        return K

    def _assemble_owned(self, form: ufl.Form) -> np.ndarray:
        return forms.assemble_owned(dolfinx.fem.form(form), self.n_local)

    def _stable_step(self) -> None:
        """The step's limits and the step (rods.fe.timestep), kept as attributes (dt, dt_critical, ω_max, ...)."""
        self.__dict__.update(asdict(time_step(self)))
        if self.scene["fe.contact"] == "penalty" and self.scene["fe.contact_damping"] > 0:
            self.contact.set_damping(self.scene["fe.contact_damping"], self.inv_mass, self.dt)

    def plan(self) -> dict[str, Any]:
        """What will run (printed by the workflow before the time loop)."""
        sc, rm = self.scene, self.rm
        return {
            "model": self.model_name,
            "scene": sc.label,
            "mesh": _mesh_text(rm, sc["fe.degree"]),
            "cells": rm.mesh.topology.index_map(rm.mesh.topology.dim).size_global,
            "dofs": self.n_global,
            "ranks": self.comm.size,
            "contact": _contact_text(self),
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
        return self.scene.field_interval > 0

    # ------------------------------------------------------------------------------------------
    def run(
        self,
        out: Path | None = None,
        progress: Callable[[int, int, float], None] | None = None,
        observers: Sequence[Observer] = (),
        restart: bool = False,
        keep_checkpoint: bool = False,
    ) -> FEResult:
        """March the central-difference scheme to the scene's end time (collective).

        Each step: the stepper (:class:`rods.fe.explicit.CentralDifference`), then the observers:
        ``observers`` first (they see u_n and v_{n+1/2} and may prescribe v, a driven submodel cut; one with
        ``external_work()`` enters the energy balance, history ``external_work``), then the recorder, the
        guards (a SimulationError carrying the histories so far), checkpoints into ``out`` (one at a Ctrl-C/SIGTERM
        stop, one every ``fe.checkpoint_interval`` > 0; ``restart=True`` resumes from the last one), fields into ``out``
        when the scene asks (a run afresh first removes an earlier run's there, :func:`rods.fe.fields.discard`;
        a restart appends to them), and ``progress(step, total, elapsed)``. An observer with ``state(step)`` and
        ``restore(state)`` (a submodel's cut driver) is checkpointed with the stepper and the recorder, and one with
        ``checkpoint_identity`` (its input file) enters the checkpoint's key. A finished run removes its checkpoint
        (it resumes nothing), unless ``keep_checkpoint``: a caller that writes the results removes it after them
        (rods.study.stages: a kill between the last step and the files had left neither, nothing to --restart).
        """
        stepper = self.stepper()
        recorder = self.recorder(observers)
        parts = (stepper, recorder, *(o for o in observers if hasattr(o, "state")))  # what a checkpoint holds
        inputs = [o.checkpoint_identity for o in observers if hasattr(o, "checkpoint_identity")]
        key = checkpoint.run_key(self.scene, self.dt, self.comm.size, self.n_global, CHECKPOINT_FORMAT, inputs)
        step0 = self._restore(out, parts, key, progress) if restart and out is not None else 0
        if step0 == 0 and out is not None:  # afresh: an earlier run's verdict and field series here are not this run's
            if self.comm.rank == 0:  # its summary.json beside this run's partial series (killed) read as finished
                (Path(out) / "summary.json").unlink(missing_ok=True)
                for tmp in Path(out).glob(".*.tmp"):  # a result file's temporary name a kill left mid-write
                    if not tmp.name.startswith((".checkpoint", ".fields")):  # theirs: checkpoint and fields discard
                        tmp.unlink(missing_ok=True)
            fields.discard(out, self.comm)  # (a barrier)
        # a run whose record a checkpoint cannot hold (the driver's cut band: rods.fe.cut.CutRecorder) writes none
        resumable = all(getattr(o, "resumable", True) for o in observers)
        own = self._observers(stepper, recorder, out, progress, step0, parts, key, checkpoints=resumable)
        recorder.start()
        with loop_blas():  # the caller's setting is restored after the loop
            failure = march(stepper, range(step0, self.steps + 1), [*observers, recorder, *own], recorder.is_out)
        wall_loop = recorder.wall_before + self.comm.allreduce(time.perf_counter() - recorder.t_start, op=MPI.MAX)
        stepper.destroy()
        if failure is not None:  # keep what was recorded up to the failure, readable
            k = recorder.k
            # an interrupt stops after step n (done and checkpointed: n steps run); a guard refused step n's record
            done = isinstance(failure, Interrupted)
            n_ok = k if done or k <= 1 else k - 1
            try:
                failure.partial = fe_result(self, recorder, n_ok, failure.step + done, wall_loop)
                failure.partial.summary.update(status=failure.status, error=str(failure), failed_step=failure.step)
                _unknown_duration(failure.partial, metrics.min_gap(self.scene))
            except Exception:  # too little recorded for a summary: the message alone must do
                failure.partial = None
            raise failure
        if out is not None and not keep_checkpoint:  # finished: it resumes nothing (a --restart reran from it, "ok")
            checkpoint.discard(out, self.comm)
        return fe_result(self, recorder, recorder.k, self.steps + 1, wall_loop)

    def stepper(self) -> CentralDifference:
        """The central-difference integrator at the initial state on the scene's backend (a fresh K, scaled
        in place, or converted to CSR once), the contact moved to that backend."""
        self.contact.use(self.backend)
        kept = self.backend is not backends.PETSC and scipy.sparse.issparse(self.K)  # the array backends' CSR
        return CentralDifference(
            self.element if self.element is not None else self.K if kept else self._assemble_stiffness,
            self.mass,
            self.inv_mass,
            self.dt,
            self.initial_velocity(),
            self.β_visc,
            self.contact,
            self.backend,
        )

    def recorder(self, sources: Sequence[Observer] = ()) -> Recorder:
        """The recorder of this model's histories at the scene's output steps (``sources``: external work)."""
        sc = self.scene
        mass_axial = np.zeros(self.n_local)
        mass_axial[self.axial :: self.bs] = self.mass[self.axial :: self.bs]  # [kg]
        steps = output_steps(sc.end_time, sc.output_interval, self.dt, self.steps)
        probes = (self.probes.P, self.probe_keys)
        args = (self.contact, probes, mass_axial, steps, self.steps, self.dt, self.comm, self.multiplicity)
        return Recorder(*args, sources, self.backend)

    def _observers(
        self, stepper, recorder, out, progress, step0: int, parts, key: str, checkpoints: bool = True
    ) -> list[Observer]:
        """The model's own observers after the recorder: guards, fields, checkpoints (after ``step0``; none where
        not ``checkpoints``), the interrupt check. Fields precede checkpoints: a checkpoint at step c (a restart at
        c + 1 keeps the frames before (c + ½)Δt) then implies that the frames up to step c are on disk, whenever the
        run is killed."""
        sc, dt = self.scene, self.dt
        guard = Guard(dt, self.dt_critical, sc["fe.energy_growth_limit"], self.dt_switching)
        run_guard = RunGuard(guard, recorder, self.inverted_cells, self.comm, self.backend.dot)  # reads a device's
        own: list[Observer] = [run_guard]
        if self.wants_fields() and out is not None and sc["fe.degree"] == 1:
            view = backends.HostView(stepper, self.backend) if self.backend.on_device else stepper
            own.append(FieldOutput(self, out, sc.field_interval, view, step0))
        stop = InterruptCheck(self.comm)  # Ctrl-C/SIGTERM: all ranks stop together, a checkpoint first
        if out is not None and step0 == 0:  # afresh: an earlier run's checkpoint here is stale from now on, also
            checkpoint.discard(out, self.comm)  # where this run writes none (a driver: a restart would resume it)
        if out is not None and checkpoints:  # periodic ones where fe.checkpoint_interval > 0; one at a stop in any case
            interval = sc["fe.checkpoint_interval"]
            every = checkpoint.stride(interval, dt) if interval > 0 else self.steps + 1  # [steps]
            h = checkpoint.scene_hash(sc)  # the restart's pre-set-up check
            values = json.loads(json.dumps(sc.as_dict()))  # the manifest's: a restart names a differing key
            own.append(checkpoint.Checkpoints(out, every, parts, self.comm, key, step0, self.steps, h, values))
            stop.on_stop = own[-1].save_now
        own.append(stop)
        if self.backend.on_device:  # checkpoints, fields, the stop check: on the host
            own = [o if o is run_guard else backends.OnHost(o, self.backend) for o in own]
        if progress is not None:
            own.append(Progress(progress, self.steps, start=max(step0 - 1, 0)))  # a resumed run: its checkpoint
        return own

    def _restore(self, out: Path, parts: Sequence[Any], key: str, progress) -> int:
        """Resume the stepper, the recorder and the observers with state (``parts``) from the last checkpoint in
        ``out``; the first step to run."""
        state = checkpoint.load(out, self.comm, key)
        if state is None:
            return 0
        for part in parts:
            part.restore(state)
        stepper = parts[0]
        step0 = stepper.n + 1
        if progress is not None:
            t = stepper.n * self.dt
            sys.stderr.write(f"restart from the checkpoint of step {stepper.n} (t = {t:.6g} s): on from step {step0}\n")
        return step0

    def initial_velocity(self) -> np.ndarray:
        """v_0 [m/s], owned entries: Rod 1 at +s1 along the impact direction, Rod 2 at rest."""
        v0 = np.zeros(self.n_local)
        v0[self.rod1_z] = self.scene.speed
        return v0

    def inverted_cells(self, u_owned: np.ndarray) -> int:
        """Number of this rank's cells inverted at the displacement ``u_owned`` (:class:`CornerJacobians`)."""
        if not hasattr(self, "_corners"):
            msh = self.rm.mesh
            self._corners = CornerJacobians(self.V, self.n_local, msh.topology.index_map(msh.topology.dim).size_local)
            self._corners.use(self.backend)  # a device counts there (serial), else the host
        return self._corners.count(u_owned)


def _unknown_duration(partial: FEResult, min_gap: float) -> None:
    """A stopped run's summary (in place): a first contact still on at the stop, or none yet, has no duration (null,
    with a warning), not the time up to the stop (a fuzz, 2026-12-06: an interrupt at 104 µs, 5138 N still on,
    wrote a 104.3 µs contact and no warning)."""
    t, F = partial.force_trace["time"], partial.force_trace["contact_force"]
    episodes = metrics.contact_episodes(t, F, min_gap)
    if t.size and episodes and not metrics.first_contact_open(episodes, float(t[-1])):
        return
    partial.summary["contact_duration"] = None
    state = "had not ended" if episodes else "had not begun"
    partial.summary["warnings"] = [
        f"contact_duration: the first contact {state} when the run stopped at t = {t[-1] if t.size else 0.0:g} s "
        "(duration unknown, written as null)"
    ]


def fe_result(model: ExplicitModel, recorder: Recorder, rows: int, steps: int, wall_loop: float) -> FEResult:
    """The run's FEResult: histories (the first ``rows`` records), units, summary (force over the first
    ``steps`` steps, the model's set-up, 3D extras), pressure profile at the peak force."""
    sc = model.scene
    hist = recorder.history(rows)
    units = {name: recorder.units[name] for name in hist}
    derived = recorder.summary(hist, steps, sc.stations[0].name, *metrics.plateau_bounds(sc), metrics.min_gap(sc))
    energy = {k: derived.pop(k) for k in ("energy_error", "initial_energy")}
    n_steps = min(steps, recorder.force.size) - 1
    penalty = sc["fe.contact"] == "penalty"
    # scene_overrides: what the label lists (a standalone submodel's driver: its own)
    summary: dict[str, Any] = {"model": model.model_name, **sc.identity, "impact_speed": sc.speed}
    summary.update(derived)  # peak, contact, midpoint
    summary.update(
        {
            "wall_time": wall_loop,
            "setup_time": model.setup_time,
            "dofs": model.n_global,
            "cells": model.rm.mesh.topology.index_map(model.rm.mesh.topology.dim).size_global,
            "steps": int(n_steps),
            "dt": model.dt,
            "dt_critical": model.dt_critical,
            "dt_critical_without_contact": model.dt_critical_no_contact,
            "dt_element_estimate": model.dt_element,
            "dt_gershgorin": model.dt_gershgorin,
            "dt_contact_switching": model.dt_switching,
            **energy,
            "ranks": model.comm.size,
            "backend": model.backend.name,  # where the loop ran (fe.backend as resolved: "auto" is not one)
            "device": model.backend.device,  # "CPU" or the GPU's name
            "operator": sc["fe.operator"],  # how the loop applied K: the assembled matrix or the element kernel
            "contact": sc["fe.contact"],  # the law that ran; the penalty only where it is the penalty law's
            "penalty": model.ε_pen if penalty else None,
            "penalty_factor": sc["fe.penalty"] if penalty else None,
            "bulk_viscosity": model.ξ,
            "dof_steps_per_second": model.n_global * n_steps / wall_loop if wall_loop > 0 else 0.0,
            "peak_memory": cost.peak_memory(model.comm),  # [B] the ranks' summed peak RSS, beside the plan's memory
        }
    )
    summary.update(_mesh_summary(model, recorder.peak, hist))
    summary.update(_edge_period(model, hist, summary["contact_radius"], summary["peak_contact_force"]))
    profile = pressure_profile(model, recorder.peak)
    trace = {k: v.copy() for k, v in recorder.force_trace(steps).items()}
    summary.update(rigid_velocities(sc, trace["contact_force"], model.dt))
    return FEResult(hist, units, summary, profile, trace)


def rigid_velocities(scene: Scene, force: np.ndarray, dt: float) -> dict[str, float]:
    """Rod 1's and Rod 2's mean (rigid-body) velocities at the run's end [m/s]: the contact impulse Σ F_n Δt (the
    force of every step, [N]; Δt [s]) on the rods' masses (rods.scene.Rod.mass), the analytical model's definition
    (rods.analytical.WaveModel.rigid_velocities), so the two summaries carry the same keys."""
    impulse = float(np.sum(force)) * dt  # [N s]
    return {
        "rigid_velocity_rod1": scene.speed - impulse / scene.rod1.mass,
        "rigid_velocity_rod2": impulse / scene.rod2.mass,
    }


def _edge_period(model: ExplicitModel, hist: dict[str, np.ndarray], a_peak: float, F_peak: float) -> dict[str, Any]:
    """The contact radius and area at the peak force ``F_peak`` [N] averaged over the last node spacing the edge
    swept (:func:`rods.metrics.edge_period_radius`): the spacing of the slave nodes around the peak radius
    ``a_peak`` [m] (axisymmetric; 3D: ``fe.radial_size``, the nodes are not in rings there)."""
    sc, r = model.scene, model.contact.slave.r
    if model.kind == "3d" or r.size < 2:
        spacing = float(sc["fe.radial_size"])
    else:
        i = int(np.clip(np.searchsorted(r, a_peak), 1, r.size - 1))
        spacing = float(r[i] - r[i - 1])
    E_star, R_star = hertz.contact_constants(sc.rod1, sc.rod2)
    F, a = hist["contact_force"], hist["contact_radius"]
    a, ratio, n = metrics.edge_period_radius(F, a, spacing, E_star, R_star, F_peak)
    return {
        "contact_radius_edge_mean": a,
        "contact_area_edge_mean": np.pi * a * a,
        "edge_period": {"spacing": spacing, "ratio_to_hertz": ratio, "samples": n},
    }


def _mesh_text(rm: RodsMesh, degree: int) -> str:
    """The plan's line on the mesh: the 3D mesh's own description, else the axisymmetric cells and sizes."""
    return getattr(rm, "description", None) or (
        f"{rm.n_radial} radial{' at the tips' if any(rm.coarsened) else ''} x ({rm.n_axial[0]} + {rm.n_axial[1]}) "
        f"axial Q{degree} cells, "
        f"h_r = {rm.h_radial * 1e3:.4g} mm, h_z = {rm.h_axial * 1e3:.4g} mm (tip {rm.h_tip * 1e3:.4g} mm)"
        + _grading_text(rm)
    )


def _contact_text(model: ExplicitModel) -> str:
    """The plan's line on the contact law: kinematic, or the penalty with its stiffness [Pa/m] and what sets it."""
    sc = model.scene
    if sc["fe.contact"] == "kinematic":
        return "kinematic (forward-increment Lagrange multipliers, no penalty; dissipation counted)"
    return (
        f"penalty {model.ε_pen:.4g} Pa/m ({sc['fe.penalty']:.4g} x E*/h, "
        f"E* = {model.E_star:.4g} Pa, h = {model.h_normal:.4g} m)"
    )


def _grading_text(rm: RodsMesh) -> str:
    """The plan's words for a radially graded mesh (rods.fe.layout.radial_columns): which rods, core, largest size; and
    for a coarsened one (rods.fe.layout.coarsening) where its columns merge into how many."""
    text = ""
    if any(rm.graded):
        text = (
            f"; {graded_words(rm.graded)} graded across outside r = {rm.core_radius * 1e3:.4g} mm, up to "
            f"{rm.h_rim * 1e3:.4g} mm at the rim"
        )
    merged = [f"{co.n_far} on rod {k} from {co.z * 1e3:.4g} mm" for k, co in enumerate(rm.coarsened, 1) if co]
    return text + (f"; merged 3:1 across away from the tips ({', '.join(merged)})" if merged else "")


def pressure_profile(model: ExplicitModel, peak: dict[str, Any]) -> dict[str, np.ndarray]:
    """The contact pressure on the Rod-1 tip's nodes at peak force, by radius r; 3D also each node's x, y (the
    nodes are not in rings and a misaligned patch is not axisymmetric: rows of one r differ by their angle)."""
    slave = model.contact.slave
    out = {"r": slave.r.copy()}
    if slave.xy is not None:
        out |= {"x": slave.xy[:, 0].copy(), "y": slave.xy[:, 1].copy()}
    return out | {"p": np.asarray(peak.get("p", np.zeros(slave.r.size)), dtype=float)}


def _mesh_summary(model: ExplicitModel, peak: dict[str, Any], hist: dict[str, np.ndarray]) -> dict[str, Any]:
    """Mesh, pressure profile and scene; 3D: symmetry, placement, patch at peak force, midpoint bending."""
    sc, rm = model.scene, model.rm
    summary: dict[str, Any] = {
        "mesh": {
            "radial_size": rm.h_radial,
            "axial_size": rm.h_axial,
            "tip_axial_size": rm.h_tip,
            "n_radial": rm.n_radial,
            "n_axial": list(rm.n_axial),
            "radial_grading": sc["fe.radial_grading"],
            "graded": list(rm.graded),
        },
        "pressure_profile": {k: v.tolist() for k, v in pressure_profile(model, peak).items()},
        "scene_values": sc.as_dict(),
    }
    if any(rm.coarsened):  # per rod: where its columns merge and how many run on (rods.fe.layout.coarsening)
        summary["mesh"]["coarsened"] = [
            None if co is None else {"from": co.z, "across": co.n_far} for co in rm.coarsened
        ]
    if any(summary["mesh"]["graded"]):  # the patch's uniform core and the largest size across (rods.fe.layout)
        summary["mesh"] |= {"core_radius": rm.core_radius, "rim_radial_size": rm.h_rim}
    if model.kind == "3d":  # off-axis effects: patch at peak force, midpoint bending
        summary["symmetry"] = rm.symmetry
        summary["impact_offset"] = sc["impact.offset"]
        summary["impact_tilt"] = sc["impact.tilt"]
        summary["rod1_placement_dz"] = rm.placement.dz
        summary.update(zip(model.contact.patch_keys, peak.get("patch", (0.0, 0.0, 0.0)), strict=True))
        bend = 0.5 * (hist["rod2_mid_strain_plus_x"] - hist["rod2_mid_strain_minus_x"])
        summary["midpoint_peak_bending_strain"] = float(np.max(np.abs(bend)))
        summary["mesh"]["n_core"] = rm.n_core
    return summary
