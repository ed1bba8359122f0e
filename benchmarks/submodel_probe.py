"""Scenes beyond the paper's: the contact-patch study (global + submodels) at default settings against Hertz.

    mpirun -n 2 python benchmarks/submodel_probe.py [--probe NAME ...] [--out results/submodel-probe]
    mpirun -n 2 python benchmarks/submodel_probe.py --random 6 --seed 3 --out output/random-submodel-probe

Issue 13's submodel must be right without per-scene settings: each probe is the paper scene with a few
overrides (:data:`PROBES`: tips, speeds, materials, rods from 2 to 100 mm thick) and ``effects =
["contact_patch"]``, run through the same study as ``workflows/run.py`` (rods.study.pipeline.run_study: the
auto submodel levels and cut length, the default mixed driving). Each row is the study's comparison data
(rods.study.table3): the finest level's peak force against the analytical model and its contact area and peak
pressure against Hertz at its own force, whether those errors shrink monotonically over the levels, and the
study's status with the keys of its warnings. Targets (issue 13, for the level the paper calls fine, which auto
places at 16 or more elements across the patch): force within :data:`FORCE`, area and peak pressure within
:data:`HERTZ` of Hertz. Writes --out + .json and .md. ``--random N --seed S``: N scenes drawn as
scene_probe.py draws them (scene_probe.random_probes), each study estimated within its budget
(:func:`study_wall_time`; a scene above it listed under the table as not run), instead of the named ones.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "benchmarks"), str(ROOT / "workflows")]  # the library; scene_probe; _cli

import scene_probe  # noqa: E402  (its probes' scenes and its command line)

import _cli  # noqa: E402  (the entry points' one error path)
from rods import checks, cost, plan  # noqa: E402
from rods.scene import load_scene  # noqa: E402
from rods.study.pipeline import run_study, stage_costs  # noqa: E402
from rods.study.verification import CASES  # noqa: E402

PAPER = ROOT / "workflows" / "scenes" / "paper.toml"
FORCE = 100 * checks.AGREE_FORCE  # [%] the finest level's peak force against the analytical model (a study's "ok")
HERTZ = 100 * checks.HERTZ_OK  # [%] its contact area and peak pressure against Hertz at its own force (likewise)
SHARED = ("aluminium", "flat-rod1", "tip-1m", "fast", "mini")  # scene_probe's probes, run here as studies
PROBES: dict[str, tuple[str, tuple[str, ...]]] = {  # name: (what, overrides of the paper scene)
    "paper": ("the paper scene", ()),
    "tip-20mm": ("Rod 1 with a 20 mm tip, 3 m/s", ("rod1.tip_radius=0.02", "impact.speed=3.0")),
    "titanium": ("titanium Rod 2, 2.5 m/s (the verification matrix's)", CASES["titanium-rod2"][1]),
    **{name: scene_probe.PROBES[name] for name in SHARED},
    "fat": (
        "100 mm rods, 200 mm tip, 1 m/s",
        ("rod1.diameter=0.1", "rod2.diameter=0.1", "rod1.tip_radius=0.2", "impact.speed=1.0"),
    ),
    # patches small against a rod's section: the submodel levels graded across (rods.fe.submodel.submodel_grading)
    "onto-40mm": ("the paper's Rod 1 onto a 40 mm Rod 2, 1 m/s", ("rod2.diameter=0.04", "impact.speed=1.0")),
    "thin-onto-25mm": (
        "a 6 mm Rod 1 with a 10 mm tip onto a 25 mm Rod 2",
        ("rod1.diameter=0.006", "rod1.tip_radius=0.01", "rod2.diameter=0.025"),
    ),
}


def _study_scene(overrides: tuple[str, ...]):
    return load_scene(PAPER, (*overrides, "effects=['contact_patch']"))


def study_wall_time(overrides: tuple[str, ...]) -> float:
    """The estimated wall time [s] of the FE stages and the products of the contact-patch study of the paper scene with
    ``overrides``, on one rank (rods.study.pipeline.stage_costs of its plan, which runs the analytical model to
    its first contact: seconds)."""
    sc = _study_scene(overrides)
    return sum(c.wall_time for c in stage_costs(sc, plan.study_plan(sc), 1))


def _monotone(errors: list[float]) -> bool:
    """The errors' magnitudes shrink at every refinement (coarse to fine)."""
    return all(abs(b) < abs(a) for a, b in zip(errors, errors[1:], strict=False))


def probe(name: str, out: Path, comm) -> dict | None:
    """Run probe ``name``'s study into ``out/name`` (collective); its row on rank 0."""
    what, overrides = PROBES[name]
    sc = _study_scene(overrides)
    # what run.py's plan prints before the study: the analytical model and the FE stages at this machine's rate
    costs = [cost.analytical_cost(sc), *stage_costs(sc, plan.study_plan(sc), comm.size)]
    estimate = sum(c.wall_time for c in cost.calibrated(costs, comm))  # [s]
    t0 = time.perf_counter()
    run_study(sc, out / name, comm)
    if comm.rank != 0:
        return None
    table = json.loads((out / name / "compare" / "table3.json").read_text())
    study = json.loads((out / name / "summary.json").read_text())
    subs = [r for r in table["rows"] if r["role"] == "submodel"]
    f = subs[-1]
    area, p0 = [r["d_area_vs_hertz_pct"] for r in subs], [r["d_p0_vs_hertz_pct"] for r in subs]
    row = {
        "probe": name,
        "description": what,
        "overrides": list(overrides),
        "levels": [r["level"] for r in subs],
        "h_mm": f["h_mm"],
        "patch_elements": f["radius_mm"] / f["h_mm"],  # [-] across the finest level's contact radius
        "submodel_length_mm": 1e3 * sc["fe.submodel_length"],
        "force_pct": f["d_force_vs_analytical_pct"],
        "area_pct": area,
        "p0_pct": p0,
        "area_monotone": _monotone(area),
        "p0_monotone": _monotone(p0),
        "status": study["status"],
        "warnings": study.get("warnings", []),
        "dofs": f["dofs"],
        "wall_time": time.perf_counter() - t0,
        # the estimate against the study's wall time, as scene_probe.py's FE stage (its estimate_ratio, spread)
        "fe_wall_estimate": estimate,
        "fe_wall_estimate_method": cost.ESTIMATE_METHOD,
    }
    row["fe_wall_time"] = row["wall_time"]
    row["passes"] = {
        "force": abs(row["force_pct"]) <= FORCE,
        "area": abs(area[-1]) <= HERTZ,
        "p0": abs(p0[-1]) <= HERTZ,
    }
    return row


def render(data: dict) -> str:
    """submodel-probe.md from the data."""
    draw = data.get("draw")  # --random N --seed S
    scenes = (
        f"{draw['n']} scenes drawn at random ({draw['ranges']}, each study's estimate on one rank)"
        if draw
        else "each probe the paper scene with the overrides below"
    )
    lines = [
        "# Scenes beyond the paper's: the contact-patch study at default settings",
        "",
        f"`mpirun -n {data['ranks']} {scene_probe.command('submodel_probe.py', data)}`: {scenes} and "
        '`effects = ["contact_patch"]`, the study of `workflows/run.py` (auto levels, auto cut '
        f"length, mixed driving). Finest level: force against the analytical model "
        f"(target ±{data['targets']['force']:g}%), area and peak pressure against Hertz at its own force "
        f"(±{data['targets']['hertz']:g}%), ✗ a miss; the levels' errors coarse to fine, ↓ where their magnitudes "
        "shrink at every refinement. Wall: the whole study "
        f"(analytical, global, submodels, comparison) on {data['ranks']} ranks.",
        "",
        "| probe | levels | finest h [mm] | elements across a | cut [mm] | force | area [%] | p0 [%] | status "
        "| wall [s] | wall estimated / measured |",
        "|---|---|---:|---:|---:|---:|---|---|---|---:|---:|",
    ]
    for r in data["rows"]:
        mark = scene_probe.misses(r["passes"])
        errs = {
            q: " / ".join(f"{e:+.2f}" for e in r[f"{q}_pct"]) + (" ↓" if r[f"{q}_monotone"] else "") + mark[q]
            for q in ("area", "p0")
        }
        lines.append(
            f"| {r['description']} | {', '.join(r['levels'])} | {r['h_mm']:.4g} | {r['patch_elements']:.1f} "
            f"| {r['submodel_length_mm']:.3g} | {r['force_pct']:+.2f}%{mark['force']} | {errs['area']} "
            f"| {errs['p0']} | {r['status']} ({scene_probe.study_keys(r['warnings'])}) | {r['wall_time']:.0f} "
            f"| {scene_probe.estimate_ratio(r)} |"
        )
    lines += scene_probe.study_tail(data["rows"]) + scene_probe.reruns(data) + scene_probe.not_run(data)
    lines += scene_probe.estimate_spread(data["rows"], "study")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    targets = {"force": FORCE, "hertz": HERTZ}
    return scene_probe.run_probes(argv, __doc__, "submodel-probe", PROBES, probe, render, targets, study_wall_time)


if __name__ == "__main__":
    _cli.tool(main)
