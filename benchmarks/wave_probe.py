"""Scenes beyond the verification matrix: the wave-response study (global FE against analytical) at default settings.

    mpirun -n 2 python benchmarks/wave_probe.py [--probe NAME ...] [--out results/wave-probe]
    mpirun -n 2 python benchmarks/wave_probe.py --random 6 --seed 77 --out results/wave-probe-random

scene_probe.py stops each global after its contact phase; this runs what a user's ``effects = ["wave_response"]``
runs (rods.study.pipeline.run_study, as ``workflows/run.py``): the analytical model and the global FE model to the
scene's end_time, so the Rod-2 midpoint's plateaus are there. Each row: the peak force, first contact duration and
average peak speed of the global against the analytical model, against the bands a study holds them to
(rods.checks.AGREE_FORCE, agree_duration, AGREE_PEAK_SPEED: the verification matrix's agreement), the energy error,
and the study's status with the keys of its warnings. An average peak speed a model itself calls unreliable (its
plateau warnings) is not held to its band (the study does not compare it either). ``--random N --seed S``: N scenes
drawn as scene_probe.py draws them (its global's whole run estimated within the budget; a scene above it listed under
the table as not run). Writes --out + .json and .md.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "benchmarks"), str(ROOT / "workflows")]  # the library; scene_probe; _cli

import scene_probe  # noqa: E402  (its probes' scenes, its draw and its command line)

import _cli  # noqa: E402  (the entry points' one error path)
from rods import checks  # noqa: E402
from rods.compare import cell, difference, percent  # noqa: E402
from rods.scene import load_scene  # noqa: E402
from rods.study.pipeline import run_study  # noqa: E402
from rods.study.verification import TARGETS, duration_words, passes  # noqa: E402

PAPER = scene_probe.PAPER
SHARED = ("thick", "aluminium", "short-rod2", "thin")  # scene_probe's probes, run here over the whole end_time
PROBES: dict[str, tuple[str, tuple[str, ...]]] = {
    "paper": ("the paper scene", ()),
    **{name: scene_probe.PROBES[name] for name in SHARED},
}
# [%], [s], [-], [%]: what a study holds its global to (rods.checks): the verification matrix's targets and the midpoint
BANDS = {**TARGETS, "peak_speed": 100 * checks.AGREE_PEAK_SPEED}


def _wave_scene(overrides: tuple[str, ...]):
    return load_scene(PAPER, (*overrides, "effects=['wave_response']"))


def probe(name: str, out: Path, comm) -> dict | None:
    """Run probe ``name``'s wave-response study into ``out/name`` (collective); its row on rank 0."""
    what, overrides = PROBES[name]
    t0 = time.perf_counter()
    run_study(_wave_scene(overrides), out / name, comm)
    if comm.rank != 0:
        return None
    read = {k: json.loads((out / name / k / "summary.json").read_text()) for k in ("analytical", "global")}
    study = json.loads((out / name / "summary.json").read_text())
    sa, sf = read["analytical"], read["global"]
    unreliable = [m for m, s in read.items() if checks.average_unreliable(s)]
    row = {
        "probe": name,
        "description": what,
        "overrides": list(overrides),
        "peak_force_pct": percent(sf["peak_contact_force"], sa["peak_contact_force"]),
        "duration_difference": difference(sf["contact_duration"], sa["contact_duration"]),  # NaN: not ended
        "peak_speed_analytical": sa["midpoint_peak_speed"],
        "peak_speed_pct": percent(sf["midpoint_peak_speed"], sa["midpoint_peak_speed"]),
        "peak_speed_unreliable": unreliable,  # the models that call their own average unreliable
        "energy_error": sf["energy_error"],
        "status": study["status"],
        "warnings": study.get("warnings", []),
        "dofs": sf["dofs"],
        "wall_time": time.perf_counter() - t0,
    }
    # the verification matrix's targets (rods.study.verification.passes), and the study's midpoint check
    row["duration_target"] = checks.agree_duration(_wave_scene(overrides))  # [s]
    row["passes"] = {
        **passes(row["peak_force_pct"], row["duration_difference"], row["energy_error"], row["duration_target"]),
        "peak_speed": bool(unreliable) or abs(row["peak_speed_pct"]) <= BANDS["peak_speed"],
    }
    return row


def render(data: dict) -> str:
    """wave-probe.md from the data."""
    b, draw = data["targets"], data.get("draw")
    scenes = (
        f"{draw['n']} scenes drawn at random ({draw['ranges']})"
        if draw
        else "each probe the paper scene with a few overrides"
    )
    lines = [
        "# Scenes beyond the verification matrix: the wave-response study at default settings",
        "",
        f"`mpirun -n {data['ranks']} {scene_probe.command('wave_probe.py', data)}`: {scenes} and "
        '`effects = ["wave_response"]`, the study of '
        "`workflows/run.py`: the analytical model and the global FE model over the whole end_time. The global against "
        f"the analytical model, held to the bands a study holds it to (peak force {b['peak_force']:g}%, first "
        f"contact duration {duration_words(data)}, average peak speed {b['peak_speed']:g}%, energy error "
        f"below {b['energy']:g}); ✗ a miss, (u) an average a model itself calls unreliable (not held to its band). "
        f"Wall: the whole study on {data['ranks']} ranks.",
        "",
        "| probe | peak force | Δ duration [µs] | avg. peak speed analytical [m/s] | FE vs analytical | energy error "
        "| DOFs | status | wall [s] |",
        "|---|---:|---:|---:|---:|---:|---:|---|---:|",
    ]
    for r in data["rows"]:
        mark = scene_probe.misses(r["passes"])
        speed = cell(r["peak_speed_pct"], "+.2f", "%") + (" (u)" if r["peak_speed_unreliable"] else mark["peak_speed"])
        lines.append(
            f"| {r['description']} | {r['peak_force_pct']:+.3f}%{mark['peak_force']} "
            f"| {cell(r['duration_difference'], '+.2f', scale=1e6)}{mark['duration']} "
            f"| {cell(r['peak_speed_analytical'], '.4g')} | {speed} | {r['energy_error']:.1e}{mark['energy']} "
            f"| {r['dofs']:,} | {r['status']} ({scene_probe.study_keys(r['warnings'])}) | {r['wall_time']:.0f} |"
        )
    lines += scene_probe.study_tail(data["rows"]) + scene_probe.reruns(data) + scene_probe.not_run(data)
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    return scene_probe.run_probes(
        argv, __doc__, "wave-probe", PROBES, probe, render, BANDS, scene_probe.global_wall_time
    )


if __name__ == "__main__":
    _cli.tool(main)
