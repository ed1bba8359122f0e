"""Submodel of the contact region (first fe.submodel_length of both rods) driven by a recorded global run.

    mpirun -n 2 python workflows/global.py --driver --out GDIR          # the library's driving global
    mpirun -n 2 python workflows/submodel.py --global GDIR --level fine --out DIR

Scene: the global run's unless --scene/--set are given. Levels: rods.scene.SUBMODEL_LEVEL_SIZES (--size
overrides; --phase K runs member K of the level's phase-averaged study, rods.scene.submodel_phase_size); end: the
driver's contact phase unless --end-time. A level is uniform at its size or, where the patch is small against a
rod's section, graded outside it to the global's sizes (fe.radial_grading "auto", rods.fe.submodel.submodel_grading;
--set "fe.radial_grading='uniform'" keeps it uniform, 'graded' grades it). Writes DIR/summary.json, history.csv,
pressure_profile.csv, sigma_r.csv and axis_stress.csv (rods.study.stages.submodel); default DIR
output/submodel/<level>/<scene>.
A Ctrl-C/SIGTERM stop leaves a checkpoint in DIR (fe.checkpoint_interval > 0: one every interval too); --restart
resumes there (same scene, level, rank count and cut record).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path

import rods.fe  # noqa: F401  (loads the wheel's dolfinx_solver first where installed)

# isort: split
from mpi4py import MPI

import _cli
from rods import cost, plan
from rods.fe import checkpoint
from rods.fe.submodel import REPLACED_KEYS, submodel_label, submodel_scene
from rods.preflight import InputError
from rods.scene import (
    SUBMODEL_LEVELS,
    SUBMODEL_PHASES,
    Scene,
    SceneError,
    parse_override,
    scene_from_summary,
)
from rods.study import stages
from rods.study.runs import driver_end, read_driver

# the option that sets each scene key the submodel replaces (rods.fe.submodel.REPLACED_KEYS): a --set of one is
# refused, it would be ignored; fe.field_interval has none (a submodel writes no fields)
OWN_OPTIONS = {
    "fe.radial_size": "--size or --level",
    "fe.axial_size": "--axial-size",
    "fe.tip_grading": "--size or --level",
    "fe.dt": "--dt",
    "fe.penalty": "--set submodel.penalty",
    "simulation.end_time": "--end-time",
}
SHOWN = ("model", "peak_contact_force", "contact_radius", "contact_area", "peak_contact_pressure")
SHOWN_RUN = ("hertz_at_own_force", "dofs", "steps", "dt", "wall_time", "peak_memory")  # its set-up and cost


def _step(text: str) -> float | str:
    """--dt: 'auto', 'global' or a time step > 0 [s]."""
    return text if text in ("auto", "global") else _cli.positive(text)


def _driver(args: argparse.Namespace, argv: Sequence[str] | None) -> tuple[Path, dict, Scene, float]:
    """(folder, summary, the submodel's scene, its end time [s]) of the driving global --global, checked before
    anything runs (rods.study.runs.read_driver), the scene's rods, impact and cut its own
    (rods.plan.check_driven_scene), the end within its cut record (rods.study.runs.driver_end)."""
    gdir, gsum, driver, recorded = read_driver(args.global_dir, "--global")
    given = any(a.startswith("--scene") for a in (argv if argv is not None else sys.argv[1:]))
    if given:
        scene = _cli.load(args)
    else:  # the driver's scene, named as it was (its --set) plus this run's overrides
        values, told = gsum["scene_values"], gsum.get("scene_overrides", ())
        scene = scene_from_summary(values, args.overrides, str(gdir), given=told)
    plan.check_driven_scene(scene, driver)
    return gdir, gsum, scene, driver_end(scene, gsum, recorded, args.end_time, gdir, "--global")


def _check_overrides(overrides: Sequence[str]) -> None:
    """--set of a key the submodel replaces by its own (rods.fe.submodel.REPLACED_KEYS), of a station or of the
    fields effect refused: it would be ignored."""
    for text in overrides:  # its mesh, step and end are its options': the scene's keys are the global's
        key, value = parse_override(text)
        if key == "station":  # dropped silently before (a fuzz): the cut region's rods have no scene positions
            why = "the submodel records its own midpoint station only; the stations are the global's"
            raise InputError(
                "--set", text, why, "leave it out (set stations on the global: global.py --set station=...)"
            )
        fields = key == "effects" and isinstance(value, (list, tuple)) and "fields" in value
        if key == "fe.field_interval" or fields:  # dropped silently before (a review)
            why = "a submodel writes no fields (submodel.py writes its contact: pressure_profile.csv, sigma_r.csv)"
            raise InputError(
                "--set", text, why, "leave it out (fields are the global's: global.py --set fe.field_interval=5e-6)"
            )
        if key in REPLACED_KEYS:
            why = f"{key} is the global's; the submodel takes its own from {OWN_OPTIONS[key]}"
            raise InputError("--set", text, why, f"give {OWN_OPTIONS[key]} instead")


def _flags(args: argparse.Namespace) -> dict[str, str]:
    """The submodel scene's keys that this script's options set: a refusal names the option the user gave."""
    size = "--size" if args.size else "--level"  # a level's size refused names the --level given (it said --size)
    return {
        "fe.radial_size": size,
        "fe.axial_size": "--axial-size" if args.axial_size else size,
        "fe.dt": "--dt",
        **({"simulation.end_time": "--end-time"} if args.end_time is not None else {}),
    }


@contextlib.contextmanager
def _named_by_options(args: argparse.Namespace) -> Iterator[None]:
    """A refused size, step or end time named by its option (--size, --axial-size, --dt, --end-time), not by the
    scene key it becomes."""
    flags = _flags(args)
    try:
        yield
    except SceneError as e:
        if e.key not in flags:
            raise
        flag = flags[e.key]
        if flag == "--level":  # the level's elements, in the range's unit
            raise InputError(
                flag, args.level, f"its {e.value:g} m elements: {e.allowed}", e.hint or "a finer --level, or --size"
            ) from None
        raise InputError(flag, e.value, e.allowed, e.hint or f"a smaller {flag}") from None


def _own_settings(scene: Scene, h: float, args: argparse.Namespace, end: float | None, dt: float | str) -> Scene:
    """The submodel scene (rods.fe.submodel.submodel_scene), validated before anything runs (refusals named by
    :func:`_named_by_options`)."""
    with _named_by_options(args):
        return submodel_scene(scene, h, args.axial_size, end, dt)


def _parser() -> argparse.ArgumentParser:
    """The command line: the driving global's folder, the level or size, the end time, the step, a restart."""
    ap = _cli.parser(__doc__, dry_run=True)
    ap.add_argument("--global", dest="global_dir", required=True, help="output folder of a global run with cut.h5")
    ap.add_argument("--level", default="fine", choices=SUBMODEL_LEVELS, help="mesh level (default %(default)s)")
    ap.add_argument("--size", type=_cli.positive, default=None, help="element size [m] (overrides --level)")
    ap.add_argument(
        "--phase",
        type=int,
        default=None,
        choices=range(SUBMODEL_PHASES),
        metavar=f"{{0..{SUBMODEL_PHASES - 1}}}",
        help="member of the level's phase-averaged study (rods.scene.submodel_phase_size; not with --size)",
    )
    ap.add_argument("--axial-size", type=_cli.positive, default=None, help="axial element size [m] (default = size)")
    ap.add_argument("--end-time", type=_cli.positive, default=None, help="end time [s] (default: the contact phase)")
    ap.add_argument(
        "--dt", type=_step, default="auto", help="time step [s], 'auto' (stable) or 'global' (the global's)"
    )
    ap.add_argument("--restart", action="store_true", help="resume from the last checkpoint in --out")
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    comm = MPI.COMM_WORLD
    args = _parser().parse_args(argv)
    if args.phase is not None and args.size is not None:
        raise InputError("--phase", args.phase, "sets the element size itself", "give --phase or --size, not both")
    _check_overrides(args.overrides)
    gdir, gsum, scene, end = _driver(args, argv)
    dt = gsum["dt"] if args.dt == "global" else args.dt
    level = submodel_label(args.level, args.size)
    if args.phase is not None:
        level = f"{args.level}-phase-{args.phase}"
    out = _cli.out_dir(args, f"submodel/{level}", scene)
    log, progress = _cli.rank0(comm)
    h = args.size or plan.submodel_size(scene, args.level, args.phase)
    what = f"the submodel {level}"
    own = _own_settings(scene, h, args, end, dt)  # its contact law and outputs, as it will run
    remedy = "a larger --size" if args.size else "a coarser --level"
    record = (gdir / "cut.h5").stat().st_size  # [B] every rank reads it whole
    with _named_by_options(args):  # an end time below one step: --end-time's
        c = cost.fe_cost(scene, comm.size, what=what, size=h, axial_size=args.axial_size, end_time=end, dt=dt,
                         remedy=remedy, cut_record_bytes=record)  # fmt: skip
    if args.restart:  # the folder held first: a run still writing it replaces its checkpoint under the read
        _cli.hold(out, comm)
        checkpoint.precheck(out, comm.size, own)  # before the set-up: exit 2 naming the remedy
    _cli.backend(scene, comm.size)  # refusals before the plan, which names a folder a refused run never makes
    log(f"{plan.fe_stage(own, what, end_time=end, size=h)} -> {out}")
    _cli.outlook(scene, log, wave=False)  # the contact phase only: no plateaus to measure
    _cli.afford(args, c, log=log, comm=comm, out=out)
    size = args.size if args.phase is None else h  # a phase member's size, resolved once (the cost above)
    try:
        s = stages.submodel(
            scene, gdir / "cut.h5", out, comm, args.level, size=size, axial_size=args.axial_size, end_time=end,
            dt=dt, progress=progress, phase=args.phase, restart=args.restart, driver_summary=gsum,
        ).summary  # fmt: skip
    except SceneError as e:  # the set-up's exact stable limit refused the step: named by its option, --dt
        flag = _flags(args).get(e.key)
        if flag is None:
            raise
        hint = "--dt auto takes a stable step" if flag == "--dt" else (e.hint or f"another {flag}")
        given = f"global ({dt:.3g} s)" if args.dt == "global" else args.dt  # the driver's step, as it was taken
        raise InputError(flag, given if flag == "--dt" else e.value, e.allowed, hint) from None
    log(json.dumps({k: s[k] for k in (*SHOWN, *SHOWN_RUN)}, indent=1))
    _cli.status(s, comm.rank)
    return 0


if __name__ == "__main__":
    _cli.entry(main)
