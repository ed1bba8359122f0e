"""What a scene asks for, and therefore what runs: effects -> models (the plan), and the study's recipe.

A scene names the effects it needs (``effects = [...]``) and the workflow simulates only that:

* ``wave_response`` — Rod-2 midpoint speed and strain over the whole ``end_time``: the analytical model
  and the global FE model; no submodel.
* ``contact_patch`` — contact area, radius and pressure: the global model only through the contact phase
  (it stops after the analytical contact end plus a margin), then the submodel levels, driven by the
  library's driving global (:func:`submodel_driver`), then the comparison (Table 3).
* ``subsurface_stress`` — σ_r near the surface (Fig. 6) and the field along the axis, whose largest shear (first
  yield) the submodel compares with Hertz's: as contact_patch (every submodel samples both).
* ``fields`` — displacement, velocity and stress fields for ParaView from the global model (nothing else
  writes field files).
* ``misalignment`` — offset/tilted impact: needs the 3D model (``fe.kind = "3d"``, checked by the scene).

The analytical model always runs: it costs milliseconds and is every model's reference.

The recipe, defined once here and used by every door (``workflows/run.py``, ``global.py --driver``,
``submodel.py``, the Snakefile):

* the **contact phase** = :data:`CONTACT_MARGIN` x the end of the analytical model's *first* contact episode
  (:func:`contact_phase`): the end of a contact-only global run, the driver's record window and the
  submodels' end time;
* the **submodel driver** (:func:`submodel_driver`): the scene's own global (:data:`DRIVER_OVERRIDES` is empty);
* the **most refined model wins** (:func:`most_refined`): each contract key of a run's summary comes from
  the most refined stage that computed it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

from rods import checks, metrics
from rods.io import CONTACT_KEYS, WAVE_KEYS  # the summary contract's, named there once
from rods.scene import (
    SUBMODEL_EFFECTS,
    SUBMODEL_LEVEL_SIZES,
    SUBMODEL_LEVELS,
    Scene,
    SceneError,
    override,
    submodel_phase_size,
)

__all__ = [
    "CONTACT_KEYS",
    "CONTACT_MARGIN",
    "DRIVER_OVERRIDES",
    "WAVE_KEYS",
    "MISALIGNMENT_KEYS",
    "Plan",
    "check_driven_scene",
    "check_first_contact",
    "scene_difference",
    "contact_phase",
    "driver_phase",
    "submodel_end",
    "fe_stage",
    "first_contact_end",
    "first_contact_summary",
    "planning_summary",
    "global_drives",
    "make_plan",
    "most_refined",
    "offers",
    "study_plan",
    "submodel_driver",
]

CONTACT_MARGIN = 1.2  # contact phase: this x the analytical first contact episode's end [-]
# The driving global of the submodels: the scene's own global, no special settings. The default mixed cut
# driving (rods.fe.traction) passes on the waves entering the region but not the global's contact compliance,
# which a displacement-driven cut carries into every submodel (the old driver needed tips graded to 0.25 mm and
# 8 x E*/h and still put the submodels' force +2.3% above the analytical model; results/driver-study.md); an
# override here would be a per-scene knob.
DRIVER_OVERRIDES: tuple[str, ...] = ()

# what a misalignment study measures that no centric model has: the 3D global's patch centroid [m], its farthest
# contact node from it [m] and the Rod-2 midpoint's bending strain [-] (a fuzz found a study asked for misalignment
# summarised without any of them, docs/models.md's 3D section)
MISALIGNMENT_KEYS = ("contact_centroid_x", "contact_centroid_y", "contact_radius_max", "midpoint_peak_bending_strain")


def first_contact_end(analytical_summary: Mapping[str, Any]) -> float | None:
    """End [s] of the analytical model's first contact episode (None: no contact)."""
    episodes = analytical_summary["contact_episodes"]
    return float(episodes[0][1]) if episodes else None


PLAN_SAMPLES = 100_000  # most history samples a plan's analytical run records (the paper scene: 6001) [-]


def planning_summary(scene: Scene) -> dict[str, Any]:
    """The analytical model's summary where a plan needs it (a contact phase, a phase radius), its yield warnings
    kept quiet: the analytical stage reports them in its own summary (they printed as raw Python warnings in a
    --dry-run). A plan runs before the stages' cost checks, so it records at most :data:`PLAN_SAMPLES` samples (a
    scene's 1e-10 s output interval took 17 s and 2 GB to plan, 5e-324 s failed) and refuses, exit 2, a run above
    the free memory (the solver steps of a contact stiff against thin rods); the stage's own run is checked in full."""
    import warnings

    from rods import cost
    from rods.analytical import simulate
    from rods.hertz import YieldWarning

    if scene.end_time / scene.output_interval > PLAN_SAMPLES:
        scene = scene.with_overrides(override("simulation.output_interval", scene.end_time / PLAN_SAMPLES))
    cost.check(cost.analytical_cost(scene), force=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", YieldWarning)
        return simulate(scene).summary


FIRST_CONTACT_ROUND_TRIPS = 8  # window of first_contact_summary: this x the slower rod's round trip 2L/c [-]


def first_contact_summary(scene: Scene) -> dict[str, Any]:
    """The analytical model's summary over a window that holds the first contact (what the contact phase needs):
    :data:`FIRST_CONTACT_ROUND_TRIPS` x the slower rod's round trip 2L/c, or the whole run where that is shorter or
    the first contact outlasts the window (a 1 s paper scene: 0.34 s instead of minutes)."""
    window = FIRST_CONTACT_ROUND_TRIPS * max(r.round_trip_time for r in scene.rods)  # [s]
    if window < scene.end_time:
        over = (
            override("simulation.end_time", window),
            override("simulation.output_interval", min(scene.output_interval, window)),
        )
        s = planning_summary(scene.with_overrides(*over))
        if s["contact_episodes"] and not metrics.first_contact_open(s["contact_episodes"], window):
            return s
    return planning_summary(scene)


def driver_phase(scene: Scene) -> float:
    """The contact phase [s] a driving global of ``scene`` runs and records (its submodels' end time), from the
    analytical model's first contact (:func:`first_contact_summary`), capped by the scene's end time: a driver of
    the loading alone (a submodel to the peak force) is a driver's own choice (its contact warning says it has not
    ended), where a study, which compares whole contacts, refuses it (:func:`study_plan`)."""
    return contact_phase(first_contact_summary(scene), scene.end_time)


def check_first_contact(scene: Scene, analytical_summary: Mapping[str, Any]) -> None:
    """Refuse (SceneError, before any FE run) an end time that the analytical model's first contact outlasts, where
    a study's submodels need that contact whole, compared whole by its comparison (rods.study.runs refuses an open
    contact, after the runs: a fuzz, 2026-12-07, ran a contact study to 10 µs of a 204 µs contact, "ok" but for
    warnings, and compare.py refused its folders). A driver alone may stop in the loading (:func:`driver_phase`)."""
    if checks.contact_warning(analytical_summary, scene.end_time, scene) is None:
        return
    state = "has not ended" if analytical_summary.get("contact_episodes") else "has not begun"
    raise SceneError(
        "simulation.end_time",
        scene.end_time,
        f"the submodels of contact_patch/subsurface_stress need the whole first contact, which {state} by then (the "
        "analytical model)",
        f"remedy: {checks.AUTO_END}, or a longer end time",
    )


def submodel_end(scene: Scene, driver_summary: Mapping[str, Any] | None = None) -> float:
    """A submodel's end time [s] when none is asked: the contact phase its driver recorded over (the driver
    summary's ``contact_phase``, rods.study.stages.driver_keys), else :func:`driver_phase` of ``scene``; never past
    the scene's end. The one rule of the study's submodel stages and workflows/submodel.py."""
    recorded = (driver_summary or {}).get("contact_phase")
    return min(recorded or driver_phase(scene), scene.end_time)


def contact_phase(analytical_summary: Mapping[str, Any], end_time: float) -> float:
    """The contact phase [s]: CONTACT_MARGIN x the first contact episode's end, capped by ``end_time`` [s]
    (the whole run when there is no contact). Later episodes (re-contact after the waves return) are not
    part of it: the submodel resolves the first impact, which sets the patch and the peak force."""
    return _phase(first_contact_end(analytical_summary), end_time)


def phase_radius(scene: Scene, analytical_summary: Mapping[str, Any] | None = None) -> float:
    """The contact radius [m] the phase-averaged submodel members are placed about
    (rods.scene.submodel_phase_size): Hertz at the analytical model's peak force (run here if its summary is
    not given); a flat-on-flat scene (no Hertz radius) is refused by the caller's level check."""
    from rods import hertz

    if analytical_summary is None:
        analytical_summary = planning_summary(scene)
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    return float(hertz.at_force(analytical_summary["peak_contact_force"], E_star, R_star)["contact_radius"])


def submodel_size(
    scene: Scene, level: str, phase: int | None = None, analytical_summary: Mapping[str, Any] | None = None
) -> float:
    """Element size [m] of submodel ``level`` (rods.scene.SUBMODEL_LEVEL_SIZES), or of its member ``phase`` of the
    phase-averaged study (rods.scene.submodel_phase_size about :func:`phase_radius`)."""
    h = SUBMODEL_LEVEL_SIZES[level]
    return h if phase is None else submodel_phase_size(h, phase_radius(scene, analytical_summary), phase)


def _phase(contact_end: float | None, end_time: float) -> float:
    return end_time if contact_end is None else min(end_time, CONTACT_MARGIN * contact_end)


def submodel_driver(scene: Scene, end_time: float | None = None) -> Scene:
    """The global run that drives the submodels: ``scene`` with :data:`DRIVER_OVERRIDES`, run to
    ``end_time`` [s] (the contact phase; default the scene's end time), its output interval at most that."""
    extra = () if end_time is None else (override("simulation.end_time", end_time),)
    if end_time is not None and scene.output_interval > end_time:  # as a submodel's (submodel_scene): at most its
        # run, not refused for an end the library chose (a fuzz: output_interval 1e-3 s against a 0.55 ms phase)
        extra += (override("simulation.output_interval", end_time),)
    return scene.with_overrides(*DRIVER_OVERRIDES, *extra)


def fe_stage(scene: Scene, what: str, end_time: float | None = None, size: float | None = None) -> str:
    """One line saying what an FE stage of ``scene`` will run, from the scene alone (before the mesh: what a
    --dry-run prints; the set-up's own plan, with cells and the stable step, follows in a real run).
    ``size``: the submodel's element size [m] (default: the scene's resolved global mesh)."""
    sym = "" if scene["fe.symmetry"] == "full" else f", {scene['fe.symmetry']} symmetry"
    if size is None:
        mesh = f"mesh {scene.axial_size * 1e3:.4g} mm axial x {scene.radial_size * 1e3:.4g} mm radial"
        if scene["fe.kind"] == "axisymmetric":
            from rods.fe.layout import graded_words, scene_columns

            columns = scene_columns(scene)
            graded = tuple(len(c) > 1 for c in columns)
            if any(graded):
                core = min(c[0].r_end for c, g in zip(columns, graded, strict=True) if g)  # [m]
                mesh += f" ({graded_words(graded)} graded across outside r = {core * 1e3:.3g} mm)"
    else:
        mesh = f"mesh {size * 1e3:.4g} mm at the contact"
        if scene["fe.kind"] == "axisymmetric":
            from rods.fe.submodel import submodel_grading

            if submodel_grading(scene) == "graded":  # rods.fe.submodel.submodel_scene: its global's sizes outside
                mesh += f", graded beyond {scene.graded_core * 1e3:.3g} mm from the patch to the global's sizes"
    law = scene["fe.contact"]
    if law == "penalty":
        law += f" ({scene['fe.penalty']:.4g} x E*/h{', auto' if scene.values['fe.penalty'] == 'auto' else ''})"
    t_end = scene.end_time if end_time is None else end_time
    fields = f"fields every {scene.field_interval:g} s" if scene.field_interval > 0 else "no fields"
    backend = scene["fe.backend"] + (", K element by element" if scene["fe.operator"] == "matrix-free" else "")
    return (
        f"plan: {what} ({scene['fe.kind']}{sym}, {mesh}, {law} contact, backend {backend}, {fields}), "
        f"scene '{scene.label}', s1 = {scene.speed:g} m/s, t_end = {t_end:g} s every {scene.output_interval:g} s"
    )


# what a submodel shares with its driving global: the bodies, the impact and the cut (the cut record carries that
# global's motion at L_s; the rest, e.g. the contact law, the output interval, is the submodel's own)
DRIVEN_PREFIXES = ("rod1.", "rod2.", "impact.")
DRIVEN_KEYS = ("fe.kind", "fe.symmetry", "fe.submodel_length")
UNDRIVEN_SUFFIXES = (".yield_strength",)  # the yield check's, not the motion's


def scene_difference(scene: Scene, other: Scene, cut: bool = True) -> tuple[str, Any, Any] | None:
    """The first (key, scene's value, other's value) where two scenes' bodies or impact differ (yield strengths
    aside), and with ``cut`` the model kind, symmetry and cut length as well; None where they agree."""
    for key in scene.values:
        shared = key.startswith(DRIVEN_PREFIXES) or (cut and key in DRIVEN_KEYS)
        if shared and not key.endswith(UNDRIVEN_SUFFIXES) and key in other.values and scene[key] != other[key]:
            return key, scene[key], other[key]  # resolved: "auto" and the length it gives are one cut
        if shared and key not in other.values:
            return key, scene[key], None
    return None


def check_driven_scene(scene: Scene, driver: Scene) -> None:
    """Refuse (SceneError) a submodel scene whose bodies, impact or cut differ from its driving global's: such a
    run ends "ok" with another scene's motion at its cuts, or fails after the set-up when the cut nodes miss the
    recorded band."""
    diff = scene_difference(scene, driver)
    if diff is not None:
        key, value, theirs = diff
        raise SceneError(
            key, value, f"differs from the driving global's {theirs!r} (its cut record carries that scene's motion)",
            "drive it from a global run of this scene: workflows/global.py --driver --scene ...",
        )  # fmt: skip


@dataclass(frozen=True)
class Plan:
    effects: tuple[str, ...]
    analytical: bool
    global_model: bool
    global_kind: str
    global_end_time: float  # [s]
    submodel_levels: tuple[str, ...]
    fields: bool
    contact_phase: float  # [s] the driver's record window and the submodels' end time
    driver_overrides: tuple[str, ...] = ()  # the driving global's settings (empty: no submodel)
    reasons: tuple[str, ...] = field(default=())

    def describe(self) -> str:
        lines = [f"effects: {', '.join(self.effects) or 'none (the analytical model only)'}"]
        lines.append("  analytical model: yes")
        if self.global_model:
            lines.append(f"  global FE model ({self.global_kind}): until t = {self.global_end_time * 1e6:.1f} µs")
        else:
            lines.append("  global FE model: no")
        if self.submodel_levels:
            until = f"t = {self.contact_phase * 1e6:.1f} µs"
            driver = f"global with {', '.join(self.driver_overrides)}" if self.driver_overrides else "the global above"
            lines.append(f"  submodel driver: {driver}, recording the cut until {until}")
        lines.append(f"  submodel levels: {', '.join(self.submodel_levels) or 'none'}")
        lines.append(f"  field files: {'yes' if self.fields else 'none'}")
        lines += [f"  - {r}" for r in self.reasons]
        return "\n".join(lines)

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def study_plan(scene: Scene, analytical_summary: Mapping[str, Any] | None = None) -> Plan:
    """The plan a study of ``scene`` runs (rods.study.pipeline.run_study), bounded by the analytical model's first
    contact: from its ``analytical_summary`` (the study's analytical stage), or, for a plan before the run (a
    dry run, the cost estimate), from the model run to its first contact (:func:`first_contact_summary`)."""
    s = analytical_summary if analytical_summary is not None else first_contact_summary(scene)
    if set(scene.effects) & set(SUBMODEL_EFFECTS):
        check_first_contact(scene, s)
    return make_plan(scene, first_contact_end(s))


def check_levels(scene: Scene) -> None:
    """Refuse (SceneError, before anything runs) ``submodel.levels`` given as a list that no submodel would use: the
    effects ask for none (no contact_patch or subsurface_stress), or none of them is finer across the contact than
    the global mesh while the ladder has one (the submodels would add cost, not resolution; where even the finest
    level is not finer, "auto" picks none and :func:`make_plan` says so)."""
    levels = scene.values["submodel.levels"]
    if levels == "auto":
        return
    if not set(scene.effects) & set(SUBMODEL_EFFECTS):
        why = f"given, but effects = {list(scene.effects)} run no submodel (contact_patch or subsurface_stress do)"
        fix = "add 'contact_patch' to effects, or --set \"submodel.levels='auto'\""
        raise SceneError("submodel.levels", levels, why, fix)
    finest = _no_finer(levels, scene.radial_size)
    finer = [lv for lv in SUBMODEL_LEVELS if SUBMODEL_LEVEL_SIZES[lv] < scene.radial_size]
    if finest is not None and finer:
        why = (
            f"no level finer than the global mesh across the contact ({scene.radial_size * 1e3:.4g} mm; finest given: "
            f"{finest}, {SUBMODEL_LEVEL_SIZES[finest] * 1e3:.4g} mm): the submodels would add cost, not resolution"
        )
        raise SceneError("submodel.levels", levels, why, f"'auto', or levels from {finer[0]} on")


def _no_finer(levels: Sequence[str], radial_size: float) -> str | None:
    """The finest of ``levels`` where none is finer than the global's ``radial_size`` [m] across the contact (the
    submodels add cost, not resolution), else None."""
    finest = min(levels, key=SUBMODEL_LEVEL_SIZES.__getitem__) if levels else None
    return finest if finest is not None and SUBMODEL_LEVEL_SIZES[finest] >= radial_size else None


def make_plan(scene: Scene, contact_end: float | None = None) -> Plan:
    """The plan for ``scene``; ``contact_end`` [s] (the end of the analytical model's first contact
    episode, :func:`first_contact_end`) bounds the global run when only contact effects are asked for."""
    fx = set(scene.effects)
    reasons = []
    wave = "wave_response" in fx
    contact = bool(fx & set(SUBMODEL_EFFECTS))
    fields = scene.field_interval > 0
    global_model = wave or contact or fields or "misalignment" in fx
    phase = _phase(contact_end, scene.end_time)
    end = scene.end_time
    if global_model and not (wave or fields) and contact_end is not None:
        end = phase
        reasons.append(f"contact effects only: the global run stops at {CONTACT_MARGIN} x the analytical contact end")
    levels = tuple(scene["submodel.levels"]) if contact else ()
    if contact:
        reasons.append("contact_patch/subsurface_stress: the submodel refines the contact region")
    if (finest := _no_finer(levels, scene.radial_size)) is not None:
        reasons.append(
            f"no submodel level is finer than the global mesh across the contact (finest: {finest}, "
            f"{SUBMODEL_LEVEL_SIZES[finest] * 1e3:.4g} mm; global {scene.radial_size * 1e3:.4g} mm): the submodels "
            f"add cost, not resolution (the ladder ends at {SUBMODEL_LEVELS[-1]}); the global's contact values are "
            "as resolved"
        )
    elif contact and not levels:  # "auto" past the ladder's end (Scene.submodel_levels): no submodel runs
        reasons.append(
            f"no submodel level is finer than the global mesh across the contact (the ladder ends at "
            f"{SUBMODEL_LEVELS[-1]}, {SUBMODEL_LEVEL_SIZES[SUBMODEL_LEVELS[-1]] * 1e3:.4g} mm; global "
            f"{scene.radial_size * 1e3:.4g} mm): no submodel runs; the global's contact values are the finest"
        )
    if wave:
        reasons.append("wave_response: the global run covers the whole end_time; no submodel needed for it")
    if "misalignment" in fx and not scene.misaligned:
        reasons.append(
            "misalignment asked, but impact.offset = impact.tilt = 0: a centric impact (set impact.offset [m] or "
            "impact.tilt [rad] to misalign it)"
        )
    return Plan(
        effects=tuple(scene.effects),
        analytical=True,
        global_model=global_model,
        global_kind=scene["fe.kind"],
        global_end_time=end,
        submodel_levels=levels,
        fields=fields,
        contact_phase=phase,
        driver_overrides=DRIVER_OVERRIDES if levels else (),
        reasons=tuple(reasons),
    )


def global_drives(p: Plan) -> bool:
    """The scene's global run is the submodels' driver (no driver settings, :data:`DRIVER_OVERRIDES`): the study
    runs it once, recording the cut over the contact phase, rather than a second time as a separate driver."""
    return bool(p.global_model and p.submodel_levels and not p.driver_overrides)


def _refinement(stage: str, summary: Mapping[str, Any]) -> tuple[float, float, bool]:
    """Sort key of a stage, larger = more refined: the analytical model, then the FE stages by the element size
    across the contact (``mesh.radial_size``: a submodel level is not finer than a global sized to a small
    patch, e.g. 0.0625 mm against 0.025 mm on 1 mm rods), a submodel before a global of the same size."""
    if stage == "analytical":
        return (0.0, 0.0, False)
    h = summary.get("mesh", {}).get("radial_size")
    by_name = 1.0 / SUBMODEL_LEVEL_SIZES.get(stage.split("/", 1)[-1], 1.0)  # a summary without its mesh
    return (1.0, 1.0 / h if h else by_name, stage.startswith("submodel/"))


def offers(plan: Plan, stage: str) -> tuple[str, ...]:
    """The contract keys that ``stage`` (``analytical``, ``global``, ``submodel/<level>``, others: none) offers
    under ``plan``: the analytical model every key; the global model the peak force and the duration, the
    patch's radius, area and pressure only where the plan resolves the patch (submodels: then the finest across
    it wins, a global finer than the submodels included), and the wave keys only when it ran the whole end time
    (the wave response or the fields asked for; a contact-only global stops after the contact phase), the
    misalignment's (:data:`MISALIGNMENT_KEYS`) when that effect was asked for (the 3D global, which it needs); a
    submodel the contact keys but the
    duration (its run ends at the contact phase, cut by the driver's record). Without submodels the patch is
    the analytical model's Hertz at its own force: the global's auto mesh puts 4-6 elements across the patch
    (paper scene: area to 0.02%, peak pressure -4.85%), which its own summary keeps."""
    if stage == "analytical":
        return CONTACT_KEYS + WAVE_KEYS
    if stage == "global":
        contact = CONTACT_KEYS if plan.submodel_levels else (CONTACT_KEYS[0], CONTACT_KEYS[-1])
        contact += MISALIGNMENT_KEYS if "misalignment" in plan.effects else ()  # the 3D global's alone
        # a global over the whole end time (the wave response's, or the fields'): its midpoint is the finer model's
        # (a docs audit found a fields study quoting the analytical midpoint beside its own global's)
        whole = "wave_response" in plan.effects or plan.fields
        return contact + WAVE_KEYS if whole else contact
    return CONTACT_KEYS[:-1] if stage.startswith("submodel/") else ()


def most_refined(plan: Plan, summaries: Mapping[str, Mapping[str, Any]]) -> tuple[dict[str, Any], dict[str, str]]:
    """Each contract key of a run's summary from the most refined stage that computed it: (values, sources).

    ``summaries`` maps stage names to their summaries; what each offers is :func:`offers`.
    Refinement: the analytical model < the FE stages, the finer across the contact wins (:func:`_refinement`)."""
    values: dict[str, Any] = {}
    sources: dict[str, str] = {}
    for stage in sorted((s for s in summaries if offers(plan, s)), key=lambda s: _refinement(s, summaries[s])):
        for k in offers(plan, stage):
            values[k], sources[k] = summaries[stage][k], stage
    return values, sources
