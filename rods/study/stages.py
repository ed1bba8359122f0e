"""The stages of a study, each a function: run one model on a scene, write its files, return typed results.

Every stage writes ``summary.json`` and ``history.csv`` (plus its own extras) under its folder, on rank 0,
atomically; FE stages are collective on ``comm`` (None: MPI.COMM_WORLD). ``log`` (rank 0's printer, or None)
receives the plan of each FE model before it runs; ``progress(step, total, elapsed)`` is passed to the FE time
loop.

* :func:`analytical` — the paper's analytical model (every rank computes it: milliseconds).
* :func:`global_model` — the global FE model; optionally records the submodel cut (cut.h5).
* :func:`driver` — the submodels' driving global (:func:`rods.plan.submodel_driver`), run and recorded over
  the contact phase (:func:`rods.plan.contact_phase`) only.
* :func:`submodel` — one submodel level driven by a recorded cut, to the contact phase.
* :func:`comparison` — Table 3 (table3.json, .md, .csv), Fig. 5c and Fig. 6 (rank 0, serial).
* :func:`finished` — an FE stage already finished in its folder for the same scene (a study's restart keeps it).
"""

from __future__ import annotations

import dataclasses
import json
import math
import numbers
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rods import checks, io, metrics, plan
from rods.scene import RESULT_NEUTRAL, SUBMODEL_PHASES, Scene, cut_record_end, values_without

__all__ = [
    "Comparison",
    "Stage",
    "analytical",
    "comparison",
    "driver",
    "driver_keys",
    "global_model",
    "kept_global",
    "submodel",
    "world",
    "write_analytical",
]

Log = Callable[[str], None] | None
Progress = Callable[[int, int, float], None] | None


@dataclass(frozen=True)
class Stage:
    """A finished stage: its name, folder, scene, summary (every rank) and history (rank 0 for FE stages)."""

    name: str
    folder: Path
    scene: Scene
    summary: dict[str, Any]
    history: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    cut_file: Path | None = None  # the recorded cut band (globals with record_cut)
    kept: bool = False  # found finished in its folder by a study's restart (:func:`finished`), not run
    units: dict[str, str] = field(default_factory=dict, repr=False)  # the history's (:func:`write_analytical`)


@dataclass(frozen=True)
class Comparison:
    """The comparison stage: its folder and the table3.json data (:func:`rods.study.table3.table3`)."""

    folder: Path
    data: dict[str, Any]


def _root(comm: Any) -> bool:
    return comm is None or comm.rank == 0


def folder(out: str | Path) -> Path:
    """A stage's output folder ``out`` as a Path (a library caller's string too), refused (rods.preflight.InputError)
    before anything is set up where a stage could not write there (an existing file: NotADirectoryError after the
    whole set-up; None: a bare TypeError)."""
    from rods.preflight import InputError

    if not isinstance(out, str | Path) or str(out) == "":
        raise InputError("out", out, "is no folder", "give a folder path (a str or pathlib.Path)")
    p = Path(out)
    if p.exists() and not p.is_dir():  # only looked at: a probe file made in it would touch a kept stage's folder
        raise InputError("out", p, "is an existing file, not a folder", "give a folder path")
    return p


def world(comm: Any) -> Any:
    """``comm``, or MPI.COMM_WORLD for None (a library caller need not build one)."""
    if comm is not None:
        return comm
    from mpi4py import MPI

    return MPI.COMM_WORLD


def analytical(scene: Scene, out: Path, comm: Any = None, write: bool = True) -> Stage:
    """The analytical model (paper Sec. 2.1); Hertz yield warnings are kept in the summary. ``write=False``: its
    files are left to :func:`write_analytical` (a study writes them once its scene passed the FE set-up)."""
    from rods.analytical import simulate
    from rods.hertz import YieldWarning

    out = folder(out)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", YieldWarning)
        result = simulate(scene)
    result.summary["yield_warnings"] = [str(w.message) for w in caught]
    result.summary["scene_values"] = scene.as_dict()
    checks.apply(result.summary, result.history, scene, scene.end_time, force=result.force_trace)
    stage = Stage("analytical", out, scene, result.summary, result.history, units=result.units)
    if write:
        write_analytical(stage, comm)
    return stage


def write_analytical(stage: Stage, comm: Any = None) -> None:
    """Rank 0 writes the analytical ``stage``'s history.csv and summary.json into its folder: apart from
    :func:`analytical` where a study (rods.study.pipeline.run_study) writes nothing before its FE set-up has
    accepted the scene (the exact stable step), so a refused input leaves no half study."""
    if _root(comm):
        io.write_history(stage.folder / "history.csv", stage.history, stage.units)
        io.write_summary(stage.folder / "summary.json", stage.summary)


# scene keys a stage's run does not read, so a restart keeps it when only they changed (another submodel level
# added to a study: its global and the levels already run are kept, only the new level runs; checkpoints turned
# on for the restart: rods.scene.RESULT_NEUTRAL)
GLOBAL_IGNORES = ("submodel.levels", "submodel.penalty", "submodel.driving", *RESULT_NEUTRAL)  # the submodels' own
SUBMODEL_IGNORES = ("submodel.levels", *RESULT_NEUTRAL)  # the other levels (its own size: its scene's fe.radial_size)


def finished(
    name: str, out: Path, scene: Scene, comm: Any, cut_until: float | None = None, ignore: Sequence[str] = ()
) -> Stage | None:
    """The FE stage ``name`` as it already finished in ``out`` (a study's restart keeps it, :func:`global_model`
    and :func:`submodel` with ``resume``), else None (it runs): its summary.json ends "ok" or "warnings" (not a
    guard's stop or an interrupt's partial), holds ``scene``'s values but the ``ignore`` keys, which the stage
    does not read (the stage's scene, its end time and mesh included) and its history.csv reads to the end time; with
    ``cut_until`` [s] its cut.h5 was recorded by that scene to that time. Collective: rank 0 reads, every rank
    gets the summary, rank 0 the history."""
    found = _read_finished(Path(out), scene, cut_until, ignore) if comm.rank == 0 else None
    summary = comm.bcast(found[0] if found else None, root=0)
    if summary is None:
        return None
    cut = Path(out) / "cut.h5" if cut_until is not None else None
    return Stage(name, Path(out), scene, summary, found[1] if found else {}, cut, kept=True)


def _read_finished(out: Path, scene: Scene, cut_until: float | None, ignore: Sequence[str]) -> tuple[dict, dict] | None:
    """(summary, history) of a finished run of ``scene`` in ``out`` (:func:`finished`); None: none there."""
    from rods.fe.cut import recorded_until

    ours = values_without(scene.as_dict(), ignore)
    try:
        summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
        theirs = values_without(summary["scene_values"], ignore)
        if summary.get("status") not in ("ok", "warnings") or theirs != ours:
            return None
        if cut_until is not None:
            t, values = recorded_until(out / "cut.h5")  # [s]
            if values_without(values, ignore) != ours or t < cut_until * (1 - 1e-9):
                return None
        history = io.read_history(out / "history.csv")
        return (summary, history) if metrics.reaches_end(history["time"], scene) else None  # not cut short
    except (OSError, ValueError, KeyError, TypeError, AttributeError, IndexError):  # absent, partial: run it
        return None


# pressure_profile.csv's columns (rods.fe.model.pressure_profile: x and y in 3D only)
PROFILE_UNITS = {"r": "m", "x": "m", "y": "m", "p": "Pa"}
AXIS_UNITS = {"depth": "m", "r": "m", "sigma_r": "Pa", "sigma_z": "Pa", "tau": "Pa"}  # a submodel's axis_stress.csv


def _write_fe(out: Path, res: Any, comm: Any, extra: Mapping[str, Any] | None = None) -> None:
    if comm.rank == 0:
        io.write_history(out / "history.csv", res.history, res.units)
        if res.pressure_profile:
            io.write_history(out / "pressure_profile.csv", res.pressure_profile, PROFILE_UNITS)
        io.write_summary(out / "summary.json", {**res.summary, **(extra or {})})


def check_cut_options(
    scene: Scene,
    *,
    driver: bool = False,
    record_cut: bool = False,
    record_until: float | None = None,
    record_every: int = 1,
    restart: bool = False,
    step: float | None = None,
) -> None:
    """The cut-record options of a global run of ``scene`` (workflows/global.py's --driver, --record-cut,
    --record-until, --record-every, --restart), checked before anything runs (:class:`InputError` naming the
    option, exit 2): the record's window and spacing only with a record of the user's (a driver records its
    contact phase every step), not past the run's end nor shorter than one time step ``step`` [s] (then the record
    holds t = 0 alone), the submodel region a cylinder of the rods (:func:`rods.scene.check_submodel_length`: refused
    now, not by every submodel after), and no restart (the cut record is not checkpointed)."""
    from rods.preflight import InputError
    from rods.scene import check_submodel_length

    recording = record_cut or driver
    if (record_until is not None or record_every != 1) and (driver or not record_cut):
        why = "the driver records the contact phase, every step" if driver else "nothing is recorded without it"
        given = record_until if record_until is not None else record_every
        raise InputError("--record-until/--record-every", given, f"go with --record-cut ({why})", "leave them out")
    if record_until is not None and record_until > scene.end_time:
        why = f"beyond the run's end, simulation.end_time = {scene.end_time:g} s"
        raise InputError("--record-until", record_until, why, f"give --record-until {scene.end_time:g} or less")
    if record_until is not None and step is not None and record_until < step:
        why = f"shorter than one time step (about {step:.3g} s), the cut record would hold t = 0 alone"
        raise InputError("--record-until", record_until, why, f"give --record-until {10 * step:.3g} or more")
    if recording:
        check_submodel_length(scene.submodel_length, scene.rods)
    if restart and recording:
        why = "cannot be combined with --record-cut/--driver (the cut record is not checkpointed)"
        raise InputError("--restart", True, why, "rerun the recording global into an empty folder")


def global_model(
    scene: Scene,
    out: Path,
    comm: Any = None,
    *,
    record_cut: bool = False,
    record_until: float | None = None,
    record_every: int = 1,
    restart: bool = False,
    progress: Progress = None,
    log: Log = None,
    name: str = "global",
    extra: Mapping[str, Any] | None = None,
    model: Any = None,
    resume: bool = False,
) -> Stage:
    """The global FE model of ``scene`` to its end time. ``record_cut``: record the cut band up to
    ``record_until`` [s] every ``record_every`` steps into out/cut.h5 (an earlier out/cut.h5 is removed first: it
    recorded another run). A guard's stop writes the partial
    histories (summary status "failed") and re-raises :class:`rods.fe.guards.SimulationError`. ``extra``:
    keys added to the summary. ``model``: the :class:`rods.fe.model.ExplicitModel` of ``scene`` when the
    caller has set it up already (a benchmark that times its stepper first). ``resume`` (a study's restart): a
    run finished in ``out`` for ``scene`` is kept (:func:`finished`), else the run resumes from a checkpoint
    there where it can (not while recording the cut, which is not checkpointed) or starts afresh."""
    from rods.fe import checkpoint
    from rods.fe.cut import CutRecorder
    from rods.fe.guards import SimulationError
    from rods.fe.model import ExplicitModel

    out = folder(out)
    options = {"record_cut": record_cut, "record_until": record_until, "record_every": record_every}
    check_cut_options(scene, **options, restart=restart)
    comm = world(comm)
    if resume:
        kept = kept_global(scene, out, comm, record_cut, record_until, name)
        if kept is not None:
            return kept
        restart = not record_cut
    model = ExplicitModel(scene, comm) if model is None else model
    if record_cut:  # the exact step now: the caller's check had the estimate's
        check_cut_options(scene, **options, step=model.dt)
    if log is not None:
        log("plan: " + "\n      ".join(f"{k}: {v}" for k, v in model.plan().items()) + f"\n      outputs -> {out}")
    recorder = CutRecorder(model, record_until, record_every) if record_cut else None
    if comm.rank == 0:  # an earlier run's record in this folder would drive another scene, also when this run, which
        (out / "cut.h5").unlink(missing_ok=True)  # records its own, stops before writing it (a fuzz, 2026-12-06)
    try:
        res = model.run(out, progress, observers=(recorder,) if recorder else (), restart=restart, keep_checkpoint=True)
    except SimulationError as e:
        if e.partial is not None:
            _write_fe(out, e.partial, comm)
        raise
    cut = out / "cut.h5" if recorder is not None else None
    if recorder is not None:
        recorder.write(cut)
    # status, warnings (yield at the FE force); the force checks read every step's force, not the output samples
    checks.apply(res.summary, res.history, scene, scene.end_time, force=res.force_trace, driver=_drives(scene, extra))
    _write_fe(out, res, comm, extra)
    checkpoint.discard(out, comm)  # the results written: it resumes nothing now (a kill before them keeps it)
    return Stage(name, out, scene, {**res.summary, **(extra or {})}, res.history, cut)


def _drives(scene: Scene, extra: Mapping[str, Any] | None) -> bool:
    """Whether a global is the submodels' driver that stops after the contact phase (its ``extra`` keys carry the
    phase: rods.study.stages.driver_keys, the library chose its end), not a study's one global that records the cut
    over the contact phase but runs to the scene's end (its plateaus are its own)."""
    phase = (extra or {}).get("contact_phase")
    return phase is not None and scene.end_time <= phase * (1.0 + 1e-9)


def kept_global(
    scene: Scene,
    out: Path,
    comm: Any,
    record_cut: bool = False,
    record_until: float | None = None,
    name: str = "global",
) -> Stage | None:
    """The global stage of ``scene`` finished in ``out`` that a study's restart keeps (:func:`finished`; one that
    records the cut: with its record to ``record_until`` [s], default the end time), else None: it runs."""
    cut_until = cut_record_end(scene, record_until) if record_cut else None
    return finished(name, out, scene, world(comm), cut_until, GLOBAL_IGNORES)


def driver(
    scene: Scene,
    out: Path,
    comm: Any = None,
    contact_phase: float | None = None,
    progress: Progress = None,
    log: Log = None,
    resume: bool = False,
) -> Stage:
    """The submodels' driving global: ``scene`` with the library's driver settings (rods.plan.submodel_driver),
    run and recorded over the contact phase [s] only (default: from the analytical model of ``scene``). Its
    summary carries ``contact_phase``, the end time of the submodels it drives. ``resume``: as
    :func:`global_model`'s."""
    if contact_phase is None:
        contact_phase = plan.driver_phase(scene)
    sc = plan.submodel_driver(scene, contact_phase)
    extra = driver_keys(contact_phase)
    kw = {"progress": progress, "log": log, "name": "driver", "extra": extra, "resume": resume}
    return global_model(sc, out, comm, record_cut=True, **kw)


def _check_level(level: str, size: float | None) -> None:
    """A library caller's submodel ``level`` and ``size`` [m] (workflows/submodel.py's --level choices and --size
    check them alike): an unknown level was a bare KeyError, a size of 0 ran the level's own size."""
    from rods.preflight import InputError
    from rods.scene import SUBMODEL_LEVEL_SIZES, SUBMODEL_LEVELS

    if level not in SUBMODEL_LEVEL_SIZES:
        raise InputError("level", level, "is no submodel level", f"give one of {', '.join(SUBMODEL_LEVELS)}")
    if size is not None and not (isinstance(size, numbers.Real) and math.isfinite(size) and size > 0):
        raise InputError("size", size, "must be a positive element size [m]", "give one, or None for the level's")


def driver_keys(contact_phase: float) -> dict[str, Any]:
    """The keys a driving global adds to its summary: the submodels' end time [s] and the driver's settings."""
    return {"contact_phase": contact_phase, "driver_overrides": list(plan.DRIVER_OVERRIDES)}


def submodel(
    scene: Scene,
    cut_file: Path,
    out: Path,
    comm: Any = None,
    level: str = "fine",
    *,
    size: float | None = None,
    axial_size: float | None = None,
    end_time: float | None = None,
    dt: float | str = "auto",
    progress: Progress = None,
    phase: int | None = None,
    restart: bool = False,
    resume: bool = False,
    driver_summary: Mapping[str, Any] | None = None,
) -> Stage:
    """One submodel of ``scene`` (the driving global's scene) at ``level`` (rods.scene.SUBMODEL_LEVEL_SIZES;
    ``size`` [m] overrides it), driven by ``cut_file``, to ``end_time`` [s] (default rods.plan.submodel_end: the
    driver's contact phase; capped by the scene's end). ``phase``: the level's member of the phase-averaged study
    instead (rods.plan.submodel_size; a ``size`` given with it is that member's size, as
    the caller resolved it). Writes history, pressure_profile, sigma_r (r, depth, σ_r at peak force) and the
    summary; checkpoints when ``fe.checkpoint_interval`` > 0 (``restart``: resume from the last one in ``out``).
    ``resume`` (a study's restart, from a kept driver): a run finished in ``out`` for this submodel scene and cut
    file is kept (:func:`finished`), else it resumes from a checkpoint there or starts afresh. ``driver_summary``:
    the driving global's summary, whose peak force the submodel's is checked against (rods.checks.driver_warning)."""
    from rods.fe.guards import SimulationError
    from rods.fe.submodel import run_submodel, submodel_label, submodel_name, submodel_scene
    from rods.io import cut_identity

    comm, out = world(comm), folder(out)
    _check_level(level, size)
    h = plan.submodel_size(scene, level, phase) if size is None else size
    name = submodel_label(level, size if phase is None else None)
    end = plan.submodel_end(scene, driver_summary) if end_time is None else min(end_time, scene.end_time)
    if resume:  # kept only if driven by this very record (a global rerun here wrote another)
        sub = submodel_scene(scene, h, axial_size, end, dt)
        kept = finished(f"submodel/{name}", out, sub, comm, None, SUBMODEL_IGNORES)
        if kept is not None and Path(cut_file).exists() and kept.summary.get("cut_record") == cut_identity(cut_file):
            return dataclasses.replace(kept, scene=scene)
        restart = True
    try:
        sr = run_submodel(
            scene, cut_file, h, axial_size, end, dt, comm, progress, name, out, restart, keep_checkpoint=True
        )
    except SimulationError as e:  # a guard's stop or an interrupt: the histories so far, readable, as a global's
        if e.partial is not None:
            e.partial.summary["model"] = submodel_name(name)
            _write_fe(out, e.partial, comm)
        raise
    _finish_submodel(sr, scene, cut_file, end, phase, driver_summary, out, comm)
    return Stage(f"submodel/{name}", out, scene, sr.summary, sr.result.history)


def _finish_submodel(
    sr: Any, scene: Scene, cut_file: Path, end: float, phase: int | None, driver_summary: Any, out: Path, comm: Any
) -> None:
    """Annotate the submodel run ``sr`` (rods.fe.submodel.run_submodel's) with its driver, phase member and checks
    against ``scene`` (the driving global's) up to ``end`` [s], and write its files into ``out`` (rank 0), then remove
    its checkpoint (collective)."""
    from rods.fe import checkpoint
    from rods.io import cut_identity

    sr.summary["cut_file"] = str(cut_file)
    # the driving global's scene: the submodel's own scene_values are the cut region's (rods L_s long, not a scene
    # of the schema), so the later stages check a submodel's bodies and impact against this one
    sr.summary["driver_scene_values"] = scene.as_dict()
    sr.summary["cut_record"] = cut_identity(cut_file)  # which recording drove it (a study's restart keeps only that)
    if phase is not None:
        sr.summary["phase"] = {"member": phase, "members": SUBMODEL_PHASES}
    # its station sits at the cut region's middle (L_s/2 from the tip), not at Rod 2's: the contract's midpoint keys
    # are Rod 2's (README), so a submodel has none (its history keeps its own station's columns; a docs audit found
    # a submodel's "midpoint_peak_speed" of 1.08 m/s from one plateau there, status ok)
    sr.summary.update(midpoint_peak_speed=None, midpoint_peak_strain=None)
    # its midpoint is no Rod-2 midpoint: no plateau check; its end is the driver's contact phase or --end-time
    remedy = "a later --end-time of submodel.py, or none (the driver's contact phase)"
    checks.apply(sr.summary, {}, scene, end, end_remedy=remedy)
    if driver_summary is not None and (w := checks.driver_warning(sr.summary, driver_summary, scene)) is not None:
        sr.summary["warnings"].append(w)
        sr.summary["status"] = "warnings"
    if comm.rank == 0:
        write_submodel_files(sr, out)
    checkpoint.discard(out, comm)  # the results written: it resumes nothing now (a kill before them keeps it)


def write_submodel_files(sr: Any, out: Path) -> None:
    """Write the submodel run ``sr``'s histories, profiles and summary (last) into ``out`` (rank 0's call)."""
    io.write_history(out / "history.csv", sr.result.history, sr.result.units)
    io.write_history(out / "pressure_profile.csv", sr.result.pressure_profile, PROFILE_UNITS)
    io.write_history(out / "sigma_r.csv", sr.sigma_r, {"r": "m", "depth": "m", "sigma_r": "Pa"})
    if (axis := sr.summary.get("axis_profile")) is not None:  # the subsurface field on the axis (none: flat tips,
        io.write_history(out / "axis_stress.csv", axis, AXIS_UNITS)  # a tilted or offset impact)
    else:  # an earlier run's profile in a reused folder is not this run's (a session's note, 2026-12-07)
        (out / "axis_stress.csv").unlink(missing_ok=True)
    io.write_summary(out / "summary.json", sr.summary)


# what the comparison stage writes into its folder (rods.preflight.output_names checks them before it runs)
COMPARISON_FILES = (
    "table3.json",
    "table3.md",
    "table3.csv",
    "fig6-sigma-r.png",
    "fig5c-pressure.png",
    "fig5c-profile.png",
)


def comparison(
    scene: Scene,
    analytical_summary: Mapping[str, Any],
    runs: Sequence[Any],
    out: Path,
) -> Comparison:
    """Table 3 and Figs. 5c/6 of ``runs`` (rods.study.table3.ModelRun) into ``out``: table3.json (the data),
    table3.md and table3.csv rendered from it, fig6-sigma-r.png, fig5c-profile.png, fig5c-pressure.png.
    Serial: call on one rank."""
    from rods import hertz
    from rods.study import figures, table3

    data = table3.table3(scene, analytical_summary, runs)
    # the finest submodel level against the analytical force and Hertz (rods.checks.submodel_warnings): judged here, so
    # compare.py says what a study says of the same runs (it printed no status where the study warned)
    data["warnings"] = checks.submodel_warnings(data)
    data["status"] = "warnings" if data["warnings"] else "ok"
    io.write_data(out / "table3.json", data)
    io.atomic_write_text(out / "table3.md", table3.render_markdown(data))
    io.atomic_write_text(out / "table3.csv", table3.render_csv(data))
    subs = sorted((r.summary for r in runs if r.role == "submodel"), key=lambda s: -s["element_size"])
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    figures.fig6(out, subs, scene.rod1.material.poisson_ratio)
    finest = subs[-1] if subs else next(r.summary for r in runs if r.role == "global-driver")
    figures.fig5c(out, finest, E_star, R_star)
    return Comparison(out, data)
