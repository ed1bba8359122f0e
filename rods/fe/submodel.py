"""Submodel of the contact region driven at its cut by the global solution (paper Sec. 2.2).

The submodel is the same :class:`rods.fe.model.ExplicitModel` machinery on a shorter region: the first
L_s = ``fe.submodel_length`` of each rod (cut planes z = -L_s for Rod 1 and z = +L_s for Rod 2,
measured from the apexes), meshed with a size h across and along (aspect 1:1, as the paper), uniform or,
where the patch is small against a rod's section, h in a core around it and graded outward, across and along, to
its global's sizes (:func:`submodel_grading`).
It is built by :func:`submodel_scene`: a copy of the scene with both rod lengths set to L_s, so the
"far ends" (facet tags ``rod1_end``/``rod2_end``) *are* the cut planes and no mesher change is needed.

The cut band the global records and the drivers that read it: :mod:`rods.fe.cut` (displacement driving)
and :mod:`rods.fe.traction` (traction and mixed driving).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import dolfinx
import dolfinx.mesh
import numpy as np
import ufl
from mpi4py import MPI

from rods import compare, hertz
from rods.fe import forms
from rods.fe.cut import CutDriver
from rods.fe.layout import cap_depth
from rods.fe.model import ExplicitModel, FEResult
from rods.fe.traction import TractionDriver
from rods.scene import (
    SUBMODEL_LEVEL_SIZES,
    Scene,
    SceneError,
    Station,
    check_submodel_length,
    last_per_key,
    override,
    scene_from_dict,
)

__all__ = [
    "LEVEL_SIZES",
    "make_driver",
    "PeakField",
    "SubmodelResult",
    "run_submodel",
    "submodel_label",
    "submodel_grading",
    "submodel_name",
    "submodel_scene",
    "contact_axis",
    "surface_gauss_stress",
    "axis_gauss_stress",
]

# element size across and along per level [m] (paper: coarse/mid/fine; finer: axisymmetric only): the scene's table
LEVEL_SIZES = SUBMODEL_LEVEL_SIZES


# ----------------------------------------------------------------------------------------------
# region
# ----------------------------------------------------------------------------------------------
def submodel_grading(scene: Scene) -> str:
    """``fe.radial_grading`` of ``scene``'s submodels, one for all its levels: "uniform" or "graded" as the key
    asks; "auto" (the default) "graded" where the global's rule (rods.fe.layout.radial_columns, "auto": grading leaves
    at most GRADED_SHARE of the uniform elements across) grades a rod at the auto levels' start
    (:attr:`~rods.scene.Scene.submodel_start_size`), else uniform; 3D: uniform (an O-grid).

    A graded level keeps its size h in a core of CORE_RADII Hertz radii a_P around the axis and as deep from each
    tip (at least rods.fe.layout.CAP_HEIGHTS cap heights: the patch and the stresses that vary on its scale), and grows
    outward by at most GROWTH per element to its global's sizes (across its bar size,
    :attr:`~rods.scene.Scene.bar_axial_size`; along its axial size, :attr:`~rods.scene.Scene.axial_core`): nowhere
    coarser than the global. Its levels halve h where the patch is; outside, their elements grow to the same sizes.
    Where the patch is small against a rod's section a uniform level spends nearly all of its elements far from
    it: a 10 mm tungsten rod with a 6 mm tip onto a 34.4 mm brass rod at 0.362 m/s, fine level (0.0625 mm), 454k
    DOFs uniform against 42k graded, peak force -0.06%, p0 against Hertz at its own force -3.08% / -2.48%; the paper
    scene forced graded, fine level, 93k against 25k DOFs, force +0.011%, area and p0 against Hertz -0.12 / -0.21%
    and -0.76 / -0.53% (2026-12-06, docs/run-log.md). The paper scene's and every scene's whose rods grading saves
    less than half of across stays uniform, as the paper's submodel; below the start a uniform level quadruples, so a
    study's plan names grading for a level it would bring to at most half its time (rods.study.pipeline: a 37 mm
    steel rod with a 226 mm tip onto an 8.6 mm glass rod at 0.427 m/s, extra-fine 1.93e6 DOFs uniform, 1.17e5
    graded; the graded study's area and p0 there -0.09% and -0.12% from Hertz at its own force)."""
    grading = scene["fe.radial_grading"]
    if scene["fe.kind"] == "3d" or grading != "auto":
        return "uniform" if scene["fe.kind"] == "3d" else grading
    from rods.fe.layout import radial_columns  # the mesher's own columns

    h, h_bar, core = scene.submodel_start_size, scene.bar_axial_size, scene.graded_core
    graded = any(len(radial_columns(rod, h, h_bar, core, "auto")) > 1 for rod in scene.rods)
    return "graded" if graded else "uniform"


# scene keys the region replaces by its own (:func:`submodel_scene`): a value given for one is not the region's
REPLACED_KEYS = (
    "fe.radial_size",
    "fe.axial_size",
    "fe.tip_grading",
    "fe.dt",
    "fe.penalty",
    "fe.field_interval",  # a submodel writes no fields (the driving global's are the whole rods')
    "simulation.end_time",
)


def submodel_scene(
    scene: Scene,
    h: float,
    h_axial: float | None = None,
    end_time: float | None = None,
    dt: float | str = "auto",
) -> Scene:
    """The submodel region as a scene: rods cut to L_s = ``fe.submodel_length`` [m], size h [m] across and
    ``h_axial`` (default h) along (uniform, or at the patch and graded outward: :func:`submodel_grading`), no tip
    grading, the scene's contact law (under the penalty law its own layer ε = ``submodel.penalty`` x E*/h), the
    default mid station only (at L_s/2 of Rod 2), end time ``end_time`` [s] (default the scene's), time step
    ``dt``."""
    L_s = scene["fe.submodel_length"]
    check_submodel_length(L_s, scene.rods)
    if h_axial is not None and h_axial > L_s:
        raise SceneError("fe.axial_size", h_axial, f"longer than the submodel (fe.submodel_length = {L_s:g} m)")
    d = scene.as_dict(json_safe=False)
    d["station"] = []
    d["fe"].update(
        {
            "radial_size": h,
            "axial_size": h_axial or h,
            "tip_grading": 1.0,
            "radial_grading": submodel_grading(scene),  # one for all levels: they refine alike at the patch
            "dt": dt,
            "penalty": scene.submodel_penalty(h),  # resolved: the level's own
            "submodel_length": L_s,  # resolved: "auto" on the cut rods would give another length
        }
    )
    end = scene.end_time if end_time is None else end_time
    d["simulation"]["end_time"] = end
    d["simulation"]["output_interval"] = min(scene.output_interval, end)
    d["effects"] = [e for e in d.get("effects", []) if e != "fields"]
    d["fe"]["field_interval"] = 0.0
    sub = scene_from_dict(d, source=scene.source)
    # the cut rods are not slender (L_s < 2 d): set the lengths after validation, past that cross-check
    values = dict(sub.values)
    values["rod1.length"] = values["rod2.length"] = L_s
    return dataclasses.replace(
        sub,
        rod1=dataclasses.replace(sub.rod1, length=L_s),
        rod2=dataclasses.replace(sub.rod2, length=L_s),
        stations=(Station(2, L_s / 2, "rod2_mid"),),
        values=values,
        global_axial_size=scene.bar_axial_size,  # a graded level's sizes outside the patch: its global's
        overrides=scene.overrides,  # named as the scene it cuts (Scene.label)
        settings=last_per_key(
            (  # what the region changed of it (its summary's stage_settings), each key once
                *scene.settings,
                *(
                    override(f"fe.{k}", v)
                    for k, v in d["fe"].items()
                    if k in ("radial_size", "axial_size", "radial_grading", "dt", "penalty")
                ),
                override("rod1.length", L_s),
                override("rod2.length", L_s),
                override("simulation.end_time", end),
            )
        ),  # fmt: skip
    )


def make_driver(model: ExplicitModel, cut_file: str | Path, driving: str) -> CutDriver:
    """The cut driver of ``submodel.driving``: ``displacement`` (:class:`CutDriver`), ``traction``
    (:class:`rods.fe.traction.TractionDriver`, the global's cut stress as nodal forces) or ``mixed`` (that
    traction plus a bar-impedance dashpot to the global's cut velocity)."""
    if driving in ("traction", "mixed"):
        return TractionDriver(model, cut_file, absorbing=driving == "mixed")
    return CutDriver(model, cut_file)


# ----------------------------------------------------------------------------------------------
# stresses at the integration points nearest the surface (paper Fig. 6)
# ----------------------------------------------------------------------------------------------
def _rod1_frame(model: ExplicitModel, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(r, z) [m] of points ``x`` (..., gdim) in Rod 1's own frame: r from its axis, z along it (apex at 0).

    Axisymmetric: (x[0], x[1]). 3D: x_1 = R_y(θ)^T (x - (e, 0, δz)) undoes Rod 1's placement
    (:class:`rods.fe.mesh3d.Placement`), r = sqrt(x_1² + y_1²), z = z_1 (a centric rod: r = sqrt(x² + y²))."""
    if model.kind == "axisymmetric":
        return x[..., 0], x[..., 1]
    p = model.rm.placement
    c, s = math.cos(p.tilt), math.sin(p.tilt)
    dx, dz = x[..., 0] - p.offset, x[..., 2] - p.dz
    return np.hypot(c * dx - s * dz, x[..., 1]), s * dx + c * dz  # R_y(θ)^T (x - (e, 0, δz))


def contact_axis(model: ExplicitModel) -> tuple[np.ndarray, np.ndarray]:
    """(C, n) [m, -]: the 3D contact's axis, the line through C along the unit n that Hertz's radial coordinate
    runs from: the line of the two tips' sphere centres (the common normal, through Rod 1's centre C1 =
    R_y(θ)(0, 0, -R1) + (e, 0, δz); Rod 2's at (0, 0, R2)); a flat Rod 2: its face normal e_z through C1; a flat
    Rod 1: its face normal R_y(θ) e_z through Rod 2's centre. A centric impact: the rods' axis. A tilted tip's patch
    lies R1 sin θ off Rod 1's own axis (rods.scene.first_contact_offsets), about which σ_r was taken before."""
    p = model.rm.placement
    a1 = np.array([math.sin(p.tilt), 0.0, math.cos(p.tilt)])  # Rod 1's axis, towards Rod 2
    apex = np.array([p.offset, 0.0, p.dz])
    R1, R2 = model.scene.rod1.tip_radius, model.scene.rod2.tip_radius
    C2 = np.array([0.0, 0.0, R2])
    if math.isinf(R1):
        return (apex, a1) if math.isinf(R2) else (C2, a1)  # two flat faces: Rod 1's axis (no Hertz)
    C1 = apex - R1 * a1
    n = np.array([0.0, 0.0, 1.0]) if math.isinf(R2) else (C2 - C1) / np.linalg.norm(C2 - C1)
    return C1, n


def _gauss_stress(model: ExplicitModel, u_owned: np.ndarray, cells: np.ndarray) -> dict[str, np.ndarray]:
    """σ_rr and σ_zz [Pa] of the displacement ``u_owned`` at the 2^tdim Gauss points (reference coordinates ½ ± ½/√3
    in each direction: 2x2 quadrilateral, 2x2x2 hexahedron) of this rank's ``cells``, with each point's r [m] from
    the contact's axis and depth [m] below Rod 1's tip surface z_s(r) = -(r_k - sqrt(r_k² - r²)) in Rod 1's own frame
    (:func:`_rod1_frame`), each (cells, 2^tdim). Axisymmetric: σ[0, 0] and σ[2, 2] in the (r, θ, z) ordering; 3D:
    e_r·σ·e_r and n·σ·n, n the contact's axis and e_r the unit radial vector from it (:func:`contact_axis`; centric:
    the rods' axis)."""
    msh = model.V.mesh
    tdim, gdim = msh.topology.dim, msh.geometry.dim
    uf = dolfinx.fem.Function(model.V)
    uf.x.array[: model.n_local] = u_owned
    uf.x.scatter_forward()
    g = 0.5 / math.sqrt(3.0)
    X = np.array(list(itertools.product((0.5 - g, 0.5 + g), repeat=tdim)))  # (2^tdim, tdim) Gauss points
    n_g = X.shape[0]
    x = ufl.SpatialCoordinate(msh)
    σ = forms.stress(forms.strain(uf, x, model.kind), model.mat.λ, model.mat.μ)
    if model.kind == "axisymmetric":
        s_rr, s_zz = σ[0, 0], σ[2, 2]
    else:  # radial about the contact's axis (:func:`contact_axis`): the z axis if centric
        C, n = contact_axis(model)
        a = ufl.as_vector([float(v) for v in n])
        d = x - ufl.as_vector([float(v) for v in C])
        ρ = d - ufl.dot(d, a) * a
        e_r = ρ / ufl.sqrt(ufl.dot(ρ, ρ))
        s_rr, s_zz = ufl.dot(e_r, ufl.dot(σ, e_r)), ufl.dot(a, ufl.dot(σ, a))
    exprs = [dolfinx.fem.Expression(e, X) for e in (s_rr, s_zz, x)]
    if cells.size:
        S_rr, S_zz = (e.eval(msh, cells).reshape(cells.size, n_g) for e in exprs[:2])
        P = exprs[2].eval(msh, cells).reshape(cells.size, n_g, gdim)
    else:
        S_rr, S_zz, P = np.zeros((0, n_g)), np.zeros((0, n_g)), np.zeros((0, n_g, gdim))
    r1, z = _rod1_frame(model, P)  # the depth below the tip's surface, in Rod 1's own frame
    depth = -np.asarray(cap_depth(r1, model.scene.rod1.tip_radius)) - z  # the surface: the meshes' own profile
    if model.kind == "axisymmetric":
        r = r1
    else:  # [m] from the contact's axis (C, n above), as e_r
        d = P - C
        r = np.linalg.norm(d - (d @ n)[..., None] * n, axis=-1)
    return {"r": r, "depth": depth, "sigma_r": S_rr, "sigma_z": S_zz}


def _gathered(model: ExplicitModel, columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """``columns`` (equal 1D arrays on each rank) from every rank, sorted by their values in order: the same rows
    in the same order on any rank count, on every rank."""
    rows = np.vstack(model.comm.allgather(np.column_stack(list(columns.values()))))
    rows = rows[np.lexsort(rows.T[::-1])]
    return {k: rows[:, i] for i, k in enumerate(columns)}


def surface_gauss_stress(model: ExplicitModel, u_owned: np.ndarray) -> dict[str, np.ndarray]:
    """σ_rr [Pa] at the Gauss points of the Rod-1 tip cells nearest the tip surface (the paper's Fig. 6: "the
    element integration points closest to the surface").

    For each cell on the Rod-1 tip face, σ_rr of ``u_owned`` at its Gauss points (:func:`_gauss_stress`); the half
    closest to the surface is kept (one layer: the cells' reference axis normal to the tip runs along z on both
    meshes). Returns, on every rank, sorted by r: r [m], depth below the surface [m], sigma_r [Pa].
    """
    msh, rm = model.V.mesh, model.rm
    fdim, tdim = msh.topology.dim - 1, msh.topology.dim
    facets = rm.facet_tags.find(model.tags["rod1_tip"])
    cells = dolfinx.mesh.compute_incident_entities(msh.topology, facets, fdim, tdim)
    cells = cells[cells < msh.topology.index_map(tdim).size_local].astype(np.int32)
    f = _gauss_stress(model, u_owned, cells)
    near = np.argsort(f["depth"], axis=1)[:, : f["depth"].shape[1] // 2]
    return _gathered(model, {k: np.take_along_axis(f[k], near, 1).ravel() for k in ("r", "depth", "sigma_r")})


AXIS_DEPTH = 3.0  # [-] the axis profile's depth below the tip surface, in Hertz contact radii (τ_max at 0.48 a)
AXIS_COLUMN = 1.5  # [-] Gauss points within this x the nearest one's distance from the axis: the first column


def axis_gauss_stress(model: ExplicitModel, u_owned: np.ndarray, depth: float) -> dict[str, np.ndarray]:
    """σ_rr, σ_zz and the principal shear τ = |σ_zz - σ_rr|/2 [Pa] at the Gauss points nearest the contact's axis in
    Rod 1, down to ``depth`` [m] below its tip surface: the subsurface field on the axis, which Hertz gives in closed
    form (rods.hertz.axis_stresses, Johnson Eq. 3.45) and where its largest shear, the site of first yield, lies
    (0.31 p0 at 0.48 a for ν = 0.3: rods.hertz.max_shear). A centric impact's (the contact's axis is Rod 1's, on
    which the meshes' columns and the O-grid's centre lie): the points are (½ - ½/√3) h from the axis (the first
    column's Gauss points, :data:`AXIS_COLUMN`; 1, 2 and 4 of them a layer in a quarter, half and full 3D model), so
    they read the field a fraction of an element off it; on the axis σ_rr is a principal stress (σ_θθ its equal), so
    τ is the largest shear there. A tilted or offset impact's axis crosses the mesh: :func:`run_submodel` samples
    none there. Returns, on every rank, sorted by depth: r, depth [m], sigma_r, sigma_z, tau [Pa]."""
    msh = model.V.mesh
    tdim = msh.topology.dim
    cells = model.rm.cell_tags.find(model.tags["rod1"])
    cells = cells[cells < msh.topology.index_map(tdim).size_local].astype(np.int32)
    mid = dolfinx.mesh.compute_midpoints(msh, tdim, cells)[:, : msh.geometry.dim]
    r1, z = _rod1_frame(model, mid)
    below = -np.asarray(cap_depth(r1, model.scene.rod1.tip_radius)) - z
    cells = cells[(r1 < depth) & (below < 1.2 * depth)]  # a box about the axis, below the tip: the candidates
    f = _gauss_stress(model, u_owned, cells)
    within = f["depth"] <= depth  # the nearest column is the nearest above that depth (a deeper cell may be nearer)
    r_min = model.comm.allreduce(float(f["r"][within].min()) if within.any() else math.inf, op=MPI.MIN)
    keep = (f["r"] <= AXIS_COLUMN * r_min) & within
    out = {k: f[k][keep] for k in ("depth", "r", "sigma_r", "sigma_z")}
    out["tau"] = 0.5 * np.abs(out["sigma_z"] - out["sigma_r"])
    return _gathered(model, out)


class PeakField:
    """Observer: keeps u_n at the (latest) largest contact force, copying at most every ``every`` steps."""

    def __init__(self, model: ExplicitModel, every: int):
        self.model, self.every = model, max(1, every)
        self.F, self.step, self.last = -1.0, -1, -(10**9)
        self.u = np.zeros(model.n_local)

    def after_step(self, step: int, t: float, state) -> None:  # noqa: ARG002
        F = self.model.contact.force  # at u_n (evaluated at the start of the step)
        if F > self.F and step - self.last >= self.every:
            self.F, self.step, self.last = F, step, step
            self.u[:] = self.model.backend.to_host(state.u)

    def state(self, step: int) -> dict[str, Any]:  # noqa: ARG002
        """What a restart needs (this rank): the peak so far and its displacement field."""
        return {"peak_field_u": self.u, "peak_field_at": np.array([self.F, self.step, self.last], dtype=float)}

    def restore(self, state: dict[str, np.ndarray]) -> None:
        self.u[:] = state["peak_field_u"]
        F, step, last = state["peak_field_at"]
        self.F, self.step, self.last = float(F), int(step), int(last)


# ----------------------------------------------------------------------------------------------
# one submodel run
# ----------------------------------------------------------------------------------------------
@dataclass
class SubmodelResult:
    result: FEResult
    sigma_r: dict[str, np.ndarray] = field(default_factory=dict)  # r, depth [m], sigma_r [Pa]
    summary: dict[str, Any] = field(default_factory=dict)


def submodel_label(level: str, size: float | None = None) -> str:
    """A submodel run's label: its level, or ``h=<size>`` when an element size [m] overrides the level (a phase
    member's size is its level's: pass None)."""
    return level if size is None else f"h={size:g}"


def submodel_name(level: str) -> str:
    """The ``model`` a submodel's summary names (rods.study.runs.run_kind tells it by its prefix)."""
    return f"fe-submodel-{level}" if level else "fe-submodel"


def run_submodel(
    scene: Scene,
    cut_file: str | Path,
    h: float,
    h_axial: float | None = None,
    end_time: float | None = None,
    dt: float | str = "auto",
    comm: MPI.Comm = MPI.COMM_WORLD,
    progress=None,
    level: str = "",
    out: Path | None = None,
    restart: bool = False,
    keep_checkpoint: bool = False,
) -> SubmodelResult:
    """Set up and run the submodel of ``scene`` (the *global* scene) at size h [m], driven by ``cut_file``;
    checkpoints into ``out`` when ``fe.checkpoint_interval`` > 0 (``restart``: resume from the last one;
    ``keep_checkpoint``: rods.fe.model.ExplicitModel.run's)."""
    sub = submodel_scene(scene, h, h_axial, end_time, dt)
    model = ExplicitModel(sub, comm)
    driver = make_driver(model, cut_file, scene["submodel.driving"])  # first: it sets v_{n+1/2} before any record
    peak = PeakField(model, max(1, int(round(sub.output_interval / model.dt))))
    res = model.run(out, progress, observers=(driver, peak), restart=restart, keep_checkpoint=keep_checkpoint)
    sig = surface_gauss_stress(model, peak.u)
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)  # R* = inf: two flat tips, no Hertz
    s = res.summary
    s["model"] = submodel_name(level)
    s.update(rigid_velocity_rod1=None, rigid_velocity_rod2=None)  # its rods are the cut region's, driven at the cuts
    H = hertz.at_force(s["peak_contact_force"], E_star, R_star)
    s.update(
        {
            "level": level,
            "element_size": h,
            "element_size_axial": h_axial or h,
            "submodel_length": scene["fe.submodel_length"],
            "cut_nodes": driver.n_cut,
            "driving": scene["submodel.driving"],
            "driver_build_time": driver.build_time,
            "stress_field_time": peak.step * model.dt,
            "stress_field_force": peak.F,
            "cut_work": float(res.history["external_work"][-1]),  # [J]
            "hertz_at_own_force": {
                **{k: H[k] for k in ("contact_radius", "contact_area", "peak_pressure")},
                "E_star": E_star,
                "R_star": R_star,
            },
            "sigma_r_profile": {k: v.tolist() for k, v in sig.items()},
            "plan": {k: v for k, v in model.plan().items() if k in ("mesh", "cells", "dofs", "dt", "steps")},
        }
    )
    # the subsurface field on the axis and its largest shear against Hertz at the stored field's own force (null: two
    # flat tips, or a misaligned impact, whose axis crosses the mesh: axis_gauss_stress)
    H_field = compare.stress_field_hertz(s)
    a = H_field["contact_radius"]
    axis = axis_gauss_stress(model, peak.u, AXIS_DEPTH * a) if math.isfinite(a) and not scene.misaligned else None
    s["axis_profile"] = None if axis is None else {k: v.tolist() for k, v in axis.items()}
    s["max_shear"] = None if axis is None else compare.max_shear_error(axis, H_field, scene.rod1.material.poisson_ratio)
    return SubmodelResult(res, sig, s)
