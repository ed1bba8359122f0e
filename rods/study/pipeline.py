"""One study, end to end: what a scene's effects ask for (rods.plan), run in order, with typed results.

    study = run_study(scene, Path("output/run/paper"))        # collective on comm (mpirun -n N works)

Folders under ``out``: ``analytical/`` (always), ``global/`` (the scene's global FE model to the planned end
time; with cut.h5 when it drives the submodels), ``driver/`` (a separate driving global over the contact phase, only
when the driver's settings differ from the scene's: rods.plan.DRIVER_OVERRIDES, empty), ``submodel/LEVEL/``
per planned level, ``compare/`` (Table 3, Figs. 5c/6 for contact effects; Fig. 4, the global over the analytical
model, for the wave response; contact-fields.png, the contact region at peak pressure, for fields), and
``summary.json``: the plan, the stage folders and the contract keys, each from the most refined stage that computed
it (rods.plan.most_refined).
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rods import checks, cost, io, plan
from rods.preflight import short
from rods.scene import RESULT_NEUTRAL, SUBMODEL_LEVEL_SIZES, Scene, cut_record_end, first_difference, override
from rods.study import stages
from rods.study.runs import check_reuse, stage_kind

__all__ = ["Study", "run_study", "stage_costs"]


@dataclass(frozen=True)
class Study:
    plan: plan.Plan
    stages: dict[str, stages.Stage]
    comparison: stages.Comparison | None
    summary: dict[str, Any]  # the run summary (contract keys from the most refined stage, sources, plan)


FIG4 = "fig4"  # compare/fig4.png, .md, .json: the wave response's figure and its data
CONTACT_PICTURE = "contact-fields"  # compare/contact-fields.png, .json: the fields' contact picture


def stage_costs(scene: Scene, p: plan.Plan, ranks: int) -> list[cost.Cost]:
    """The estimated costs (rods.cost.fe_cost) of the FE stages :func:`run_study` runs for plan ``p`` of ``scene``
    on ``ranks`` ranks: the global to the planned end time, a separate driving global only where the global does
    not record the cut (rods.plan.global_drives), each submodel level on the driver's scene, and the products the
    study makes from them on rank 0 (:func:`_finish`: Table 3 and its figures, Fig. 4, the contact picture)."""
    drives = plan.global_drives(p)  # the global records the cut to the contact phase
    until = p.contact_phase if drives else None
    costs = (
        [cost.fe_cost(scene, ranks, what="the global", end_time=p.global_end_time, record_until=until)]
        if p.global_model
        else []
    )
    if p.submodel_levels:
        driver = plan.submodel_driver(scene, p.contact_phase)
        if not drives:
            costs.append(cost.fe_cost(driver, ranks, what="the driving global", record_until=cut_record_end(driver)))
        graded = _graded_alternative(driver)
        for lv in p.submodel_levels:
            # the user set no size for a level: submodel.levels (or its "auto") chose it, so a refusal names that
            remedy = f"submodel.levels without '{lv}' (the plan's: {', '.join(p.submodel_levels)})"
            size = SUBMODEL_LEVEL_SIZES[lv]
            c = cost.fe_cost(driver, ranks, what=f"the submodel {lv}", size=size, remedy=remedy)
            costs.append(c if graded is None else _with_grading_remedy(c, graded, size))
    products = [name for name, made in _products(p).items() if made]
    return costs + ([cost.products_cost(products, ranks)] if products else [])


def _products(p: plan.Plan) -> dict[str, bool]:
    """Which products a study of plan ``p`` makes from its stages (:func:`_finish`; their seconds:
    rods.cost.PRODUCT_SECONDS): Table 3 with its figures where submodels ran, Fig. 4 where the global ran for the
    wave response, the contact picture where it wrote fields."""
    return {
        "the comparison": bool(p.submodel_levels),
        "the wave figure": "wave_response" in p.effects and p.global_model,
        "the contact picture": p.fields and p.global_model,
    }


def _graded_alternative(driver: Scene) -> Scene | None:
    """The submodels' driver with ``fe.radial_grading = "graded"`` where "auto" keeps its axisymmetric submodels
    uniform (rods.fe.submodel.submodel_grading: it decides once, at the auto levels' start, where the paper's
    levels save less than half across); else None. The levels below the start quadruple a uniform region's
    elements, a graded one's only at the patch: on a 37 mm steel rod with a 226 mm tip onto an 8.6 mm glass rod
    at 0.427 m/s the extra-fine level is 1.93e6 DOFs uniform, 1.17e5 graded."""
    from rods.fe.submodel import submodel_grading

    if driver["fe.kind"] == "3d" or driver["fe.radial_grading"] != "auto" or submodel_grading(driver) != "uniform":
        return None
    return driver.with_overrides("fe.radial_grading='graded'")


def _with_grading_remedy(c: cost.Cost, graded: Scene, size: float) -> cost.Cost:
    """``c`` (a uniform submodel level of ``size`` [m]) with grading added to its remedy where the graded level
    (:func:`_graded_alternative`) takes at most rods.fe.layout.GRADED_SHARE of its time: what a refusal and the
    plan's total name for the level that is most of a study."""
    from dataclasses import replace

    from rods.fe.layout import GRADED_SHARE

    g = cost.fe_cost(graded, c.ranks, what=c.what, size=size)
    if g.wall_time > GRADED_SHARE * c.wall_time:
        return c
    why = f"the global and the submodels graded outside the patch: {g.dofs:.3g} DOFs at this level, not {c.dofs:.3g}"
    return replace(
        c, remedy=f"{c.remedy}, or fe.radial_grading='graded' ({why}, about {g.wall_time / c.wall_time:.2g} x the time)"
    )


def _compare(scene: Scene, done: dict[str, stages.Stage], out: Path) -> stages.Comparison:
    from rods.study.table3 import ModelRun

    shared = done.get("global") is done["driver"]  # the scene's global drove the submodels: one row
    runs = [ModelRun("global-uniform", done["global"].summary)] if "global" in done and not shared else []
    runs.append(ModelRun("global-driver", done["driver"].summary))
    runs += [ModelRun("submodel", s.summary, s.history) for k, s in done.items() if k.startswith("submodel/")]
    return stages.comparison(scene, done["analytical"].summary, runs, out)


def _wave_figure(done: dict[str, stages.Stage], out: Path) -> None:
    """Fig. 4 of the scene (rods.study.fig4): the global's Rod-2 midpoint speed and strain and its contact force
    over the analytical model's, with the agreement table (fig4.png, fig4.md, fig4.json in ``out``)."""
    from rods.io import Run
    from rods.study import fig4

    analytical, fe = (Run(k, done[k].history, done[k].summary) for k in ("analytical", "global"))
    fig4.write(analytical, [fe], out / f"{FIG4}.png", out / f"{FIG4}.md")


def _contact_picture(global_stage: stages.Stage, out: Path, log: Any) -> None:
    """The contact region at its peak pressure from the global's fields (rods.fe.fields.contact_picture:
    ``out``/contact-fields.png and .json), where people would rather look than read. A picture VTK cannot render
    here (no off-screen OpenGL) is said on the log, not raised: the numbers and the fields (ParaView) stand."""
    from rods.fe.fields import contact_picture

    out.mkdir(parents=True, exist_ok=True)
    try:
        contact_picture(global_stage.folder, out / CONTACT_PICTURE)
    except Exception as e:  # VTK's rendering failures surface as several types; the study's results are written
        if log is not None:
            log(
                f"contact picture not rendered ({type(e).__name__}: {e}); the fields: {global_stage.folder}/fields.xdmf"
            )


def run_study(
    scene: Scene, out: Path, comm: Any = None, progress: Any = None, log: Any = None, restart: bool = False
) -> Study:
    """Run the plan of ``scene`` into ``out`` (collective on ``comm``, default MPI.COMM_WORLD) and return the
    stages' results; ``log`` (rank 0's printer) receives the plan first, ``progress`` drives FE progress bars.
    A guard's stop in an FE stage raises rods.fe.guards.SimulationError after writing that stage's partial
    histories. ``restart`` (a stopped study resumed): an FE stage finished in its folder for the same scene is
    kept (rods.study.stages.finished; the submodels only behind a kept driver, whose cut drove them), an
    unfinished one resumes from its checkpoint where it has one (its stop's, or fe.checkpoint_interval's; not a
    global that records the cut), the rest run; the analytical model and the comparison always run (seconds). Nothing is
    written before the global's set-up has accepted the scene (:func:`_set_up_global`): a refused input leaves no
    half study and deletes nothing."""
    from rods.preflight import output_dir

    t0 = time.perf_counter()
    # the entry point's own checks, for a library caller too (a useless submodel ran; a study over a global's folder
    # left its histories beside the study's summary; a file as out raised NotADirectoryError: a fuzz, 2026-12-07)
    plan.check_levels(scene)
    out = output_dir(out, "out")
    check_reuse(out, stage_kind("run"), "out")
    comm = stages.world(comm)
    done: dict[str, stages.Stage] = {"analytical": stages.analytical(scene, out / "analytical", comm, write=False)}
    p = plan.study_plan(scene, done["analytical"].summary)
    if log is not None:
        log(f"plan for scene '{scene.label}' -> {out}\n{p.describe()}")
    shared = plan.global_drives(p)
    g, kw, kept, model = scene, {}, None, None  # the global's scene, its cut recording, its kept stage or model
    if p.global_model:
        g = scene.with_overrides(override("simulation.end_time", p.global_end_time))
        drives = {"record_cut": True, "record_until": p.contact_phase, "extra": stages.driver_keys(p.contact_phase)}
        kw = drives if shared else {}
    if restart:
        _precheck_restart(p, out, comm, g if p.global_model and not shared else None, shared, scene)
    if p.global_model:
        kept, model = _set_up_global(g, out / "global", comm, restart, kw)
    stages.write_analytical(done["analytical"], comm)  # the scene passed every check: the study writes from here
    if not restart:  # afresh: a stage summary left from an earlier run here must not be kept by a later --restart
        _forget_stages(p, out, comm, shared)
    if p.global_model:
        resume = restart and not kw.get("record_cut", False)  # from a checkpoint: not while recording the cut
        done["global"] = _said(
            kept or stages.global_model(g, out / "global", comm, progress=progress, log=log, restart=resume,
                                        model=model, **kw),
            log,
        )  # fmt: skip
    if p.submodel_levels:
        _submodels(scene, p, done, shared, out, comm, progress, log, restart)
    return _finish(scene, p, done, out, comm, log, t0)


def _finish(
    scene: Scene, p: plan.Plan, done: dict[str, stages.Stage], out: Path, comm: Any, log: Any, t0: float
) -> Study:
    """The study's products from its stages (rank 0): the comparison with its figures, the wave figure, the contact
    picture and the summary; an earlier run's products its plan does not ask for are removed first."""
    root = comm.rank == 0
    if root:  # an earlier run's comparisons and pictures: this run writes those its plan asks for
        _forget_products(out / "compare")
    made = _products(p)
    comparison = _compare(scene, done, out / "compare") if (made["the comparison"] and root) else None
    waves = made["the wave figure"]
    if waves and root:
        _wave_figure(done, out / "compare")
    if made["the contact picture"] and root:
        _contact_picture(done["global"], out / "compare", log)
    summary = _study_summary(scene, p, done, comparison, waves, out, comm, t0)
    if root:
        io.write_summary(out / "summary.json", summary)
    return Study(p, done, comparison, summary)


def _submodels(
    scene: Scene,
    p: Any,
    done: dict[str, stages.Stage],
    shared: bool,
    out: Path,
    comm: Any,
    progress: Any,
    log: Any,
    restart: bool,
) -> None:
    """The plan's submodel levels into ``done`` ("driver", "submodel/LEVEL"), driven by the study's global where it
    records the cut (``shared``), else by a driver stage of its own."""
    d = done["global"] if shared else _said(
        stages.driver(scene, out / "driver", comm, p.contact_phase, progress, log, resume=restart), log
    )  # fmt: skip
    done["driver"] = d
    for level in p.submodel_levels:
        done[f"submodel/{level}"] = _said(stages.submodel(
            d.scene, d.cut_file, out / "submodel" / level, comm, level, end_time=p.contact_phase,
            progress=progress, resume=restart and d.kept, driver_summary=d.summary,
        ), log)  # fmt: skip


def _study_summary(
    scene: Scene, p: Any, done: dict[str, stages.Stage], comparison: Any, waves: bool, out: Path, comm: Any, t0: float
) -> dict[str, Any]:
    """The study's summary: the most refined stage's values with their sources, the status, plan and folders."""
    values, sources = plan.most_refined(p, {k: s.summary for k, s in done.items()})
    folders = {k: str(s.folder) for k, s in done.items()}
    folders |= {"compare": str(out / "compare")} if (waves or p.submodel_levels or p.fields) else {}
    return {
        "model": "workflow",
        **scene.identity,
        "impact_speed": scene.speed,
        **values,
        "wall_time": comm.allreduce(time.perf_counter() - t0, op=_max()),
        **_status(p, done, comparison, comm, sources.get("peak_contact_pressure")),
        "sources": sources,
        "plan": p.as_dict(),
        "stages": folders,
        "scene_values": scene.as_dict(),
    }


def _set_up_global(g: Scene, out: Path, comm: Any, restart: bool, kw: dict[str, Any]) -> tuple[Any, Any]:
    """(the global stage a restart keeps, else None; the global FE model of ``g``, rods.fe.model.ExplicitModel,
    else None), found or set up before the study writes anything: the set-up is the scene's last check (the
    exact stable step: an ``fe.dt`` above it is refused, exit 2, where the cost estimate let it pass), so a
    refused input leaves no analytical stage behind, nor an earlier run's stages forgotten. A kept global needs
    no set-up and is read once, here."""
    from rods.fe.model import ExplicitModel

    kept = stages.kept_global(g, out, comm, kw.get("record_cut", False), kw.get("record_until")) if restart else None
    return kept, (ExplicitModel(g, comm) if kept is None else None)


def _said(stage: stages.Stage, log: Any) -> stages.Stage:
    """``stage``, its keeping by a restart said on rank 0's log (the run's own plan says the rest)."""
    if stage.kept and log is not None:
        log(f"{stage.name}: finished in {stage.folder} for this scene, kept (--restart)")
    return stage


def _stage_folders(p: plan.Plan, shared: bool) -> list[str]:
    """The planned FE stages' folders in a study's ``--out``."""
    folders = ["global"] if p.global_model else []
    folders += ["driver"] if p.submodel_levels and not shared else []
    return folders + [f"submodel/{level}" for level in p.submodel_levels]


def _forget_stages(p: plan.Plan, out: Path, comm: Any, shared: bool) -> None:
    """Remove the planned FE stages' summary.json from an earlier run in ``out`` (collective; rank 0 deletes): a
    fresh study killed before it rewrote them would leave an older run's finished stages for ``--restart`` to
    keep (the same scene's, but maybe another code version's), beside the new ones it had written."""
    if comm.rank == 0:
        for folder in _stage_folders(p, shared):
            (out / folder / "summary.json").unlink(missing_ok=True)
    comm.Barrier()


# what a study writes into its compare/ folder: Table 3 and Figs. 5c/6, Fig. 4, the contact picture
COMPARE_PRODUCTS = (
    *stages.COMPARISON_FILES,
    *(f"{FIG4}.{ext}" for ext in ("json", "md", "png")),  # rods.study.fig4.write: the data beside the table
    *(f"{CONTACT_PICTURE}.{ext}" for ext in ("png", "json")),  # rods.fe.fields.contact_picture
)


def _forget_products(folder: Path) -> None:
    """Remove an earlier run's :data:`COMPARE_PRODUCTS` from ``folder`` (rank 0) before this run writes its own: a
    fresh 1.5 m/s study kept the 2.197 m/s fields study's contact picture beside its new Fig. 4 (a fuzz, 2026-12-07),
    and a study planned without submodels would keep another's Table 3."""
    for name in COMPARE_PRODUCTS:
        (folder / name).unlink(missing_ok=True)


# scene keys a study's restart may change: which stages run (a level added, an effect), and the checkpoints' spacing
RESTART_FREE = ("effects", "submodel.levels", *RESULT_NEUTRAL)


def _precheck_restart(p: plan.Plan, out: Path, comm: Any, g: Scene | None, shared: bool, scene: Scene) -> None:
    """A study's restart refused before any set-up or write (CheckpointError, exit 2): ``out`` holds no study begun
    (a study writes analytical/summary.json before any FE stage) or one of another ``scene`` (its values there but
    :data:`RESTART_FREE`: a changed mesh size reran and overwrote every finished stage, silently, a fuzz,
    2026-12-07), or a planned FE stage's checkpoint there is damaged, of another rank count or, the global's ``g``
    (the global that resumes from its checkpoint; None: none does), of another scene (rods.fe.checkpoint.precheck;
    the other stages' scenes are derived at their set-up, whose load checks them). Every rank reads the same files,
    so all refuse together."""
    from rods.fe import checkpoint

    begun = out / "analytical" / "summary.json"
    if not begun.is_file():
        why = "no stopped study in this folder (a study writes analytical/summary.json before its FE stages)"
        raise checkpoint.CheckpointError("--restart", str(out), why, "run without --restart, or give the study's --out")
    try:
        theirs = json.loads(begun.read_text(encoding="utf-8")).get("scene_values")  # null stays None (read_data: NaN)
    except (OSError, ValueError, AttributeError):
        theirs = None  # damaged: the analytical stage reruns and overwrites it
    if theirs is not None and (found := first_difference(scene.as_dict(), theirs, RESTART_FREE)):
        key, here, there = found
        why = f"the study stopped there ran another scene ({key} = {short(there)} there, {short(here)} here)"
        fix = "give that study's settings, or run without --restart (afresh: its stages are replaced)"
        raise checkpoint.CheckpointError("--restart", str(out), why, fix)
    for folder in _stage_folders(p, shared):
        if (out / folder / checkpoint.MANIFEST).exists():
            checkpoint.precheck(out / folder, comm.size, g if folder == "global" else None)


def _status(
    p: plan.Plan,
    done: dict[str, stages.Stage],
    comparison: stages.Comparison | None,
    comm: Any,
    pressure_source: str | None = None,
) -> dict[str, Any]:
    """The study's status: "ok" when every stage's checks and the study's own (rods.checks.agreement_warnings:
    the global FE model against the analytical model; rods.checks.submodel_warnings: the finest submodel level
    against Hertz and the last refinement) passed; the warnings, each named by its stage ("study" and "compare"
    for the study's own). A stage that stops at the contact phase (a contact-only global, the driver, the
    submodels) offers no wave keys (rods.plan.offers), so its warnings about them (two midpoint plateaus in
    263 µs) stay in its own summary. The yield check (Hertz's p0 at each model's force, the same within a
    fraction of a percent) is the study's once, from ``pressure_source``, the stage its peak pressure comes
    from (every stage's own summary keeps its own). ``comparison`` exists on rank 0 only; its warnings reach
    every rank."""
    found = []
    for k, st in done.items():
        if k == "driver" and st is done.get("global"):  # one run, its warnings once
            continue
        unused = set(plan.WAVE_KEYS) - set(plan.offers(p, k))
        repeated = set(st.summary.get("yield_warnings", [])) if pressure_source in done and k != pressure_source else ()
        kept = [w for w in st.summary.get("warnings", []) if w.split(":", 1)[0] not in unused and w not in repeated]
        found += [f"{k}: {w}" for w in kept]
    if "global" in done:
        waves = "midpoint_peak_speed" in plan.offers(p, "global")  # a contact-only global stops before the plateaus
        g = done["global"]
        agree = checks.agreement_warnings(done["analytical"].summary, g.summary, g.scene, waves)
        found += [f"study: {w}" for w in agree]
    converged = comparison.data["warnings"] if comparison is not None else []  # rods.study.stages.comparison
    found += [f"compare: {w}" for w in comm.bcast(converged, root=0)]
    return {"status": "warnings" if found else "ok", "warnings": found}


def _max() -> Any:
    from mpi4py import MPI

    return MPI.MAX
