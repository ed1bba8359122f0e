"""Scenes beyond the verification matrix: the global FE model at default settings against the analytical model.

    mpirun -n 2 python benchmarks/scene_probe.py [--probe NAME ...] [--out results/scene-probe]
    mpirun -n 2 python benchmarks/scene_probe.py --random 14 --seed 23 --out output/random-probe

Issue 13's defaults must hold on scenes no issue lists. Each probe is the paper scene with a few overrides
(:data:`PROBES`: other materials, diameters, lengths, tips, speeds), run through the analytical model and the
global FE model at the scene's defaults over its contact phase (1.3 x rods.plan.contact_phase: the peak force
and the first contact are settled there; no midpoint plateaus, so no peak speed), and compared with the
verification matrix's targets (rods.study.verification.TARGETS) and its definitions (rods.metrics). The
run's own warnings name where a model leaves its range. A gap is only the FE's when a finer mesh moves it:
``workflows/verify.py --case paper --set ...`` adds that mesh check for one probe. Writes --out + .json and .md.
``--random N --seed S``: N scenes drawn at random from wide physical ranges (:func:`random_probes`: six materials,
3-40 mm rods at least 5 diameters long, any tips, 0.05-20 m/s) instead of the named ones: scenes nobody chose. A
drawn scene whose run this benchmark would make is estimated above :data:`RANDOM_BUDGET` on one rank is listed under
the table as drawn and not run, and the draw goes on: a seed's scenes are the seed's alone, whatever the prices.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "workflows"))  # _cli: the entry points' one error path
from mpi4py import MPI  # noqa: E402

import _cli  # noqa: E402
from rods import checks, cost, io, plan  # noqa: E402
from rods.compare import cell, difference, percent  # noqa: E402
from rods.scene import load_scene  # noqa: E402
from rods.study import stages  # noqa: E402
from rods.study.sweep import warning_key  # noqa: E402
from rods.study.verification import NOT_ENDED, TARGETS, duration_words, passes  # noqa: E402

PAPER = ROOT / "workflows" / "scenes" / "paper.toml"
PHASE = 1.3  # the FE run's end, in contact phases [-]
ALUMINIUM = ("youngs_modulus=70e9", "density=2700.0", "poisson_ratio=0.33", "yield_strength='none'")
PEEK = ("youngs_modulus=3.6e9", "density=1300.0", "poisson_ratio=0.4", "yield_strength='none'")
GLASS = ("youngs_modulus=70e9", "density=2500.0", "poisson_ratio=0.22", "yield_strength='none'")
TITANIUM = ("youngs_modulus=114e9", "density=4430.0", "poisson_ratio=0.34", "yield_strength='none'")
NO_YIELD = ("rod1.material.yield_strength='none'", "rod2.material.yield_strength='none'")
PROBES: dict[str, tuple[str, tuple[str, ...]]] = {  # name: (what, overrides of the paper scene)
    "both-tips": (
        "two 0.5 m rods, both tips 35 mm, 1.0 m/s",
        ("rod1.length=0.5", "rod2.length=0.5", "rod2.tip_radius=0.035", "impact.speed=1.0"),
    ),
    "aluminium": (
        "aluminium rods, 3.0 m/s",
        (*(f"rod{i}.material.{k}" for i in (1, 2) for k in ALUMINIUM), "impact.speed=3.0"),
    ),
    "thick": (
        "25 mm rods, 0.2 / 0.4 m, 50 mm tip",
        ("rod1.diameter=0.025", "rod2.diameter=0.025", "rod1.length=0.2", "rod2.length=0.4", "rod1.tip_radius=0.05"),
    ),
    "slow": ("paper rods at 0.1 m/s", ("impact.speed=0.1",)),
    "hemisphere": (
        "Rod 1 with a 6.5 mm tip (near a hemisphere), 0.5 m/s",
        ("rod1.tip_radius=0.0065", "impact.speed=0.5"),
    ),
    "tip-1m": ("Rod 1 with a 1 m tip, 2.0 m/s", ("rod1.tip_radius=1.0", "impact.speed=2.0")),
    "peek-rod2": ("PEEK Rod 2, 2.0 m/s", (*(f"rod2.material.{k}" for k in PEEK), "impact.speed=2.0")),
    "short-rod2": ("Rod 1 0.5 m onto a 0.2 m Rod 2", ("rod1.length=0.5", "rod2.length=0.2")),
    "flat-rod1": ("flat Rod 1 onto a 35 mm Rod 2 tip", ("rod1.tip_radius=inf", "rod2.tip_radius=0.035")),
    "thin": ("5 mm rods", ("rod1.diameter=0.005", "rod2.diameter=0.005")),
    "rod2-20mm": ("Rod 2 of 20 mm diameter, 1.5 m/s", ("rod2.diameter=0.02", "impact.speed=1.5")),
    "steel-on-aluminium": (
        "steel Rod 1 onto an aluminium Rod 2, 2.0 m/s",
        (*(f"rod2.material.{k}" for k in ALUMINIUM), "impact.speed=2.0"),
    ),
    "slender": (
        "10 mm rods, 1.0 m onto 2.0 m",
        ("rod1.diameter=0.01", "rod2.diameter=0.01", "rod1.length=1.0", "rod2.length=2.0"),
    ),
    # added 2026-11-27 (a second round: Poisson ratios at and below 0, unequal diameters both ways, two curved tips,
    # high speeds, other materials, millimetre rods)
    "auxetic": (
        "ν = -0.3 on both rods, 2 m/s",
        ("rod1.material.poisson_ratio=-0.3", "rod2.material.poisson_ratio=-0.3", *NO_YIELD, "impact.speed=2.0"),
    ),
    "nu-0": ("ν = 0 on both rods", ("rod1.material.poisson_ratio=0.0", "rod2.material.poisson_ratio=0.0")),
    "thick-onto-thin": (
        "25 mm Rod 1 onto a 6 mm Rod 2, 1 m/s",
        ("rod1.diameter=0.025", "rod2.diameter=0.006", "impact.speed=1.0"),
    ),
    "thin-onto-thick": (
        "6 mm Rod 1 onto a 25 mm Rod 2, 2 m/s",
        ("rod1.diameter=0.006", "rod2.diameter=0.025", "impact.speed=2.0"),
    ),
    "two-tips": (
        "tips of 20 mm and 50 mm, 3 m/s",
        ("rod1.tip_radius=0.02", "rod2.tip_radius=0.05", "impact.speed=3.0"),
    ),
    "fast": ("paper rods at 15 m/s", ("impact.speed=15.0",)),
    "v100": ("paper rods at 100 m/s (the schema's maximum)", ("impact.speed=100.0",)),
    "glass-on-titanium": (
        "glass Rod 1 onto a titanium Rod 2, 1.5 m/s",
        (*(f"rod1.material.{k}" for k in GLASS), *(f"rod2.material.{k}" for k in TITANIUM), "impact.speed=1.5"),
    ),
    "mini": (
        "2 mm rods 20 / 40 mm long, 5 mm tip, 1 m/s",
        (
            "rod1.diameter=0.002",
            "rod2.diameter=0.002",
            "rod1.length=0.02",
            "rod2.length=0.04",
            "rod1.tip_radius=0.005",
            "impact.speed=1.0",
        ),
    ),  # fmt: skip
    # added 2026-11-30: a contact whose peak rests on its stiffness (rods.scene.Scene.stiffness_sensitivity 0.23), the
    # scene that read +0.515% at 4 elements across the patch
    "thick-30mm": ("30 mm rods, 2 m/s", ("rod1.diameter=0.03", "rod2.diameter=0.03", *NO_YIELD, "impact.speed=2.0")),
}


def probe_scene(sc, analytical_summary: dict | None = None):
    """The scene a probe's FE run solves: ``sc`` to :data:`PHASE` x its contact phase (rods.plan.contact_phase of
    the analytical model's summary; without one, rods.plan.driver_phase runs it to its first contact)."""
    phase = plan.driver_phase(sc) if analytical_summary is None else plan.contact_phase(analytical_summary, sc.end_time)
    return sc.with_overrides(f"simulation.end_time={PHASE * phase!r}")


def probe(name: str, out: Path, comm) -> dict | None:
    """Run probe ``name`` into ``out/name`` (collective); its row on rank 0."""
    what, overrides = PROBES[name]
    sc = load_scene(PAPER, overrides)
    t0 = time.perf_counter()
    a = stages.analytical(sc, out / name / "analytical", comm)
    fe_scene = probe_scene(sc, a.summary)
    (estimate,) = cost.calibrated([cost.fe_cost(fe_scene, comm.size)], comm)  # what the run's plan says
    t1 = time.perf_counter()
    g = stages.global_model(fe_scene, out / name / "global", comm)
    fe_wall = time.perf_counter() - t1
    if comm.rank != 0:
        return None
    sa, sf = a.summary, g.summary
    row = {
        "probe": name,
        "description": what,
        "overrides": list(overrides),
        "peak_force_analytical": sa["peak_contact_force"],
        "peak_force_fe": sf["peak_contact_force"],
        "peak_force_pct": percent(sf["peak_contact_force"], sa["peak_contact_force"]),
        "duration_analytical": sa["contact_duration"],
        "duration_difference": difference(sf["contact_duration"], sa["contact_duration"]),  # NaN: not ended
        "energy_error": sf["energy_error"],
        "dofs": sf["dofs"],
        "steps": sf["steps"],
        "wall_time": time.perf_counter() - t0,
        "fe_wall_time": fe_wall,  # [s] the global stage, set-up to summary
        "fe_wall_estimate": estimate.wall_time,  # [s] rods.cost's estimate of it, as the run's plan prints it
        "fe_wall_estimate_method": cost.ESTIMATE_METHOD,  # how rods.cost estimated it (estimate_spread)
        # each model's own, less the midpoint plateaus' (they lie past this short run: their warning says only that)
        "warnings": {
            m: [w for w in s.get("warnings", []) if not w.startswith("midpoint_peak_speed")]
            for m, s in (("analytical", sa), ("FE", sf))
        },
    }
    row["duration_target"] = checks.agree_duration(sc)  # [s]
    row["passes"] = passes(
        row["peak_force_pct"], row["duration_difference"], row["energy_error"], row["duration_target"]
    )
    return row


def misses(passes: dict[str, bool]) -> dict[str, str]:
    """Each target's mark in a probe table: " ✗" where the probe misses it, nothing where it meets it."""
    return {k: "" if ok else " ✗" for k, ok in passes.items()}


def tally(rows: list[dict]) -> list[str]:
    """The lines under a probe table: how many probes meet every target."""
    n = sum(all(r["passes"].values()) for r in rows)
    return ["", f"{n} of {len(rows)} probes meet every target.", ""]


def command(script: str, data: dict) -> str:
    """The command line that wrote ``data`` (``script``: the benchmark's file name), with its draw (--random)."""
    draw = data.get("draw")
    return f"python benchmarks/{script}" + (f" --random {draw['n']} --seed {draw['seed']}" if draw else "")


def study_keys(warnings: list[str]) -> str:
    """A study's warnings by the stages that gave them (rods.study.sweep.warning_key), once each; "–" for none."""
    return ", ".join(dict.fromkeys(warning_key(w) for w in warnings)) or "–"


def study_tail(rows: list[dict]) -> list[str]:
    """The lines under a study probe's table: the tally, then every row's warnings in full."""
    return tally(rows) + [f"* {r['description']}: {w}" for r in rows for w in r["warnings"]]


def render(data: dict) -> str:
    """scene-probe.md from the data."""
    t = data["targets"]
    draw = data.get("draw")  # --random N --seed S
    lines = [
        "# Scenes beyond the verification matrix: global FE at default settings against the analytical model",
        "",
        f"`mpirun -n {data['ranks']} {command('scene_probe.py', data)}`; "
        + (f"{draw['n']} scenes drawn at random ({draw['ranges']}); " if draw else "")
        + f"each FE run over {PHASE:g} x the contact "
        f"phase. Targets as the verification matrix: peak force within {t['peak_force']:g}%, first contact "
        f"duration within {duration_words(data)}, energy error below {t['energy']:g}; ✗ marks a miss. "
        "Warnings: the runs' own, by model, the midpoint plateaus' left out (the runs end before them).",
        "",
        "| probe | peak force FE [N] | vs analytical | duration analytical [µs] | Δ duration [µs] | energy error "
        "| DOFs | wall [s] | FE wall estimated / measured | warnings |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in data["rows"]:
        mark = misses(r["passes"])
        warn = "; ".join(dict.fromkeys(warning_key(w) for ws in r["warnings"].values() for w in ws)) or "–"
        lines.append(
            f"| {r['description']} | {r['peak_force_fe']:.1f} | {r['peak_force_pct']:+.3f}%{mark['peak_force']} "
            f"| {cell(r['duration_analytical'], '.2f', scale=1e6, missing=NOT_ENDED)} "
            f"| {cell(r['duration_difference'], '+.2f', scale=1e6)}{mark['duration']} "
            f"| {r['energy_error']:.1e}{mark['energy']} | {r['dofs']:,} | {r['wall_time']:.1f} "
            f"| {estimate_ratio(r)} | {warn} |"
        )
    lines += tally(data["rows"]) + reruns(data) + not_run(data) + estimate_spread(data["rows"])
    for r in data["rows"]:
        for model, ws in r["warnings"].items():
            lines += [f"* {r['description']}, {model}: {w}" for w in ws]
    return "\n".join(lines) + "\n"


def estimate_ratio(row: dict) -> str:
    """A row's FE wall time estimate over its measured wall time ("–" for a row from before the estimate)."""
    if "fe_wall_estimate" not in row:
        return "–"
    est, wall = row["fe_wall_estimate"], row["fe_wall_time"]
    return f"{est:.3g} / {wall:.3g} s = {est / wall:.2f}"


# how rods.cost estimated a row's wall time (its "fe_wall_estimate_method"; rows from before 2026-12-06 have none)
ESTIMATE_WORDS = {
    "working-set probe": "the reference rates scaled by a sparse product of each run's own working set per rank, timed "
    "before it",
    None: "as planned before 2026-12-06: this machine's probed memory rate for a memory-bound loop over 10 s, the "
    "reference rate below",
}


def estimate_spread(rows: list[dict], what: str = "global stage") -> list[str]:
    """The lines on how the plans' cost estimates (rods.cost, what a run prints before it starts) met the runs
    (``what``: the measured run each estimate is of), one per way the estimates were made (ESTIMATE_WORDS)."""
    lines = []
    for method, words in ESTIMATE_WORDS.items():
        ratios = [
            r["fe_wall_estimate"] / r["fe_wall_time"]
            for r in rows
            if "fe_wall_estimate" in r and r.get("fe_wall_estimate_method") == method
        ]
        if ratios:
            lines += [
                f"The plans' wall-time estimates (rods.cost as a run's plan prints it: {words}) over the measured "
                f"{what}: {min(ratios):.2f} to {max(ratios):.2f} (median {statistics.median(ratios):.2f}"
                f"{'' if len(ratios) == len(rows) else f', {len(ratios)} rows'}).",
                "",
            ]
    return lines


# --random: materials drawn for each rod, (E [Pa], ρ [kg/m^3], ν [-]), yield strengths unset
MATERIALS = {
    "steel": (210e9, 7850.0, 0.30),
    "aluminium": (70e9, 2700.0, 0.33),
    "titanium": (114e9, 4430.0, 0.34),
    "brass": (100e9, 8500.0, 0.34),
    "glass": (70e9, 2500.0, 0.22),
    "tungsten": (400e9, 19300.0, 0.28),
}
DIAMETERS = (3e-3, 40e-3)  # [m] log-uniform
SLENDERNESS = 5.0  # a rod at least this many diameters long, and 0.05 m [-]
LENGTHS = (0.05, 1.0)  # [m] log-uniform
TIP_RADII = (0.6, 0.3)  # a curved tip: from 0.6 x the diameter (a cap below a hemisphere) to 0.3 m, log-uniform
SPEEDS = (0.05, 20.0)  # [m/s] log-uniform
# [s] a drawn scene's estimated wall time on one rank (rods.cost, of the run the benchmark makes) at most; a scene
# above it is listed as drawn and not run
RANDOM_BUDGET = 600.0
RANGES = (
    f"each rod of {', '.join(MATERIALS)} (yield unset), {DIAMETERS[0] * 1e3:g}-{DIAMETERS[1] * 1e3:g} mm in diameter, "
    f"{LENGTHS[0]:g}-{LENGTHS[1]:g} m and at least {SLENDERNESS:g} diameters long; Rod 1's tip curved, Rod 2's half "
    f"the time, radii {TIP_RADII[0]:g} diameters to {TIP_RADII[1]:g} m; {SPEEDS[0]:g}-{SPEEDS[1]:g} m/s; all "
    f"log-uniform; a scene estimated above {RANDOM_BUDGET:g} s listed as not run and the draw going on"
)


def global_wall_time(overrides: tuple[str, ...]) -> float:
    """The estimated wall time [s] of the global FE model of the paper scene with ``overrides`` to its end_time, on
    one rank (rods.cost.fe_cost: the scene alone, nothing run; wave_probe.py's runs)."""
    return cost.fe_cost(load_scene(PAPER, overrides)).wall_time


def probe_wall_time(overrides: tuple[str, ...]) -> float:
    """The estimated wall time [s] of this benchmark's FE run of the paper scene with ``overrides`` (to
    :data:`PHASE` x its contact phase, :func:`probe_scene`: the analytical model run to its first contact, seconds),
    on one rank: what a drawn scene is held to the budget by."""
    return cost.fe_cost(probe_scene(load_scene(PAPER, overrides))).wall_time


def random_probes(
    n: int,
    seed: int,
    wall_time: Callable[[tuple[str, ...]], float] = global_wall_time,
    skipped: list[dict] | None = None,
) -> dict[str, tuple[str, tuple[str, ...]]]:
    """``n`` scenes drawn (numpy's PCG64 from ``seed``: the same list on every rank and every run) from the ranges
    above: two rods of any two materials, diameters, lengths and tips (Rod 1 curved; Rod 2 curved half the time),
    one impact speed. Each is inside the schema and within :data:`RANDOM_BUDGET` of ``wall_time(overrides)``, the
    probe's estimated wall time [s] (default :func:`global_wall_time`). A scene above the budget is appended to
    ``skipped`` (its description and estimate: a table lists it as drawn and not run) and the draw goes on. The
    candidates' sequence is the seed's alone (the prices only say which of them run), so a change to the cost model
    moves a scene between the run and the skipped, never swaps one scene for another unseen."""
    import numpy as np

    rng = np.random.default_rng(seed)

    def log_uniform(lo: float, hi: float) -> float:
        return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))

    probes: dict[str, tuple[str, tuple[str, ...]]] = {}
    while len(probes) < n:
        overrides, what = [], []
        for i in (1, 2):
            name = str(rng.choice(sorted(MATERIALS)))
            E, ρ, ν = MATERIALS[name]
            d = log_uniform(*DIAMETERS)
            L = log_uniform(max(LENGTHS[0], SLENDERNESS * d), LENGTHS[1])
            R = log_uniform(TIP_RADII[0] * d, TIP_RADII[1]) if i == 1 or rng.random() < 0.5 else math.inf
            overrides += [f"rod{i}.material.youngs_modulus={E!r}", f"rod{i}.material.density={ρ!r}"]
            overrides += [f"rod{i}.material.poisson_ratio={ν!r}", f"rod{i}.material.yield_strength='none'"]
            overrides += [f"rod{i}.diameter={d:.4g}", f"rod{i}.length={L:.4g}", f"rod{i}.tip_radius={R:.4g}"]
            tip = "flat" if R == math.inf else f"{R * 1e3:.0f} mm tip"
            what.append(f"{name} {d * 1e3:.1f} mm x {L:.2f} m, {tip}")
        v = log_uniform(*SPEEDS)
        overrides.append(f"impact.speed={v:.3g}")
        description = f"{' onto '.join(what)}, {v:.3g} m/s"
        estimate = wall_time(tuple(overrides))  # [s]
        if estimate > RANDOM_BUDGET:
            if skipped is not None:
                skipped.append({"description": description, "overrides": overrides, "estimate": estimate})
            continue
        probes[f"random-{seed}-{len(probes)}"] = (description, tuple(overrides))
    return probes


def reruns(data: dict) -> list[str]:
    """The lines under a table some of whose rows were rerun with ``--merge`` (:func:`merged`): which, and their wall
    time; nothing for a table run whole."""
    runs = data.get("reruns", [])
    lines = [
        f"Rerun with `--probe ... --merge` (the other rows as first run): {', '.join(r['probes'])} "
        f"({r['wall_time']:.0f} s on the same ranks)."
        for r in runs
    ]
    return ["", *lines, ""] if runs else []


def not_run(data: dict) -> list[str]:
    """The lines under a drawn table naming the scenes the draw skipped (over :data:`RANDOM_BUDGET`), so that a table
    of cheap scenes says it is one; nothing for named probes."""
    draw = data.get("draw")
    if draw is None or "skipped" not in draw:  # named probes (or a draw recorded before skipped scenes were)
        return []
    skipped = draw["skipped"]
    if not skipped:
        return ["", f"Every scene the draw made ran (none estimated above the {RANDOM_BUDGET:g} s budget).", ""]
    return [
        "",
        f"Drawn and not run, their plans above the {RANDOM_BUDGET:g} s budget on one rank (in the draw's order, "
        f"among the {draw['n'] + len(skipped)} it made):",
        "",
        *(f"* {s['description']}: estimated {s['estimate']:.0f} s" for s in skipped),
        "",
    ]


def main(argv: list[str] | None = None) -> int:
    """The named probes, or with ``--random N [--seed S]`` N scenes drawn by :func:`random_probes` instead."""
    return run_probes(argv, __doc__, "scene-probe", PROBES, probe, render, TARGETS, probe_wall_time)


def drawn(argv: list[str] | None, probes: dict, wall_time: Callable) -> tuple[list[str], dict | None, str]:
    """``--random N [--seed S]`` taken from ``argv``: where given, ``probes`` replaced by N scenes of
    :func:`random_probes` under ``wall_time``. Returns the rest of ``argv``, the draw (kept in the data; None for
    the named probes) and the help's epilog."""
    ap = argparse.ArgumentParser(add_help=False)
    ap.add_argument("--random", type=int, default=0, help="draw N scenes instead of the named probes")
    ap.add_argument("--seed", type=int, default=0, help="the draw's seed")
    known, rest = ap.parse_known_args(argv)
    draw = None
    if known.random > 0:
        skipped: list[dict] = []
        probes.clear()
        probes.update(random_probes(known.random, known.seed, wall_time, skipped))
        draw = {"n": known.random, "seed": known.seed, "ranges": RANGES, "skipped": skipped}
    return rest, draw, "--random N [--seed S]: N scenes drawn at random instead of the named probes (" + RANGES + ")"


def merged(record: dict, rerun: dict) -> dict:
    """``record`` (a probe table's data) with the ``rerun`` rows in place of its rows of the same probe, in the
    record's order (a probe it does not hold appended); the rerun's rows and wall time listed under "reruns"."""
    new = {r["probe"]: r for r in rerun["rows"]}
    rows = [new.pop(r["probe"], r) for r in record["rows"]] + list(new.values())
    reruns = [
        *record.get("reruns", []),
        {"probes": [r["probe"] for r in rerun["rows"]], "wall_time": rerun["wall_time"]},
    ]
    return {**record, "rows": rows, "reruns": reruns}


def run_probes(argv, doc: str, name: str, probes: dict, run, render_data, targets: dict, random: Callable) -> int:
    """A probe benchmark's command line (also benchmarks/submodel_probe.py's): run ``probes`` (``run(name, runs,
    comm)``: a row on rank 0), or ``--random N [--seed S]`` scenes drawn within :data:`RANDOM_BUDGET` of
    ``random(overrides)``, a probe's estimated wall time [s] (:func:`drawn`), then write OUT.json and OUT.md
    (``render_data``; the draw kept in the data) on rank 0 and print the table. ``--merge``: the rows run replace
    the record's rows of the same probe in OUT.json, the others kept as they are (:func:`merged`)."""
    argv, draw, epilog = drawn(argv, probes, random)
    ap = _cli.bare_parser(doc.splitlines()[0], epilog=epilog)
    ap.add_argument("--probe", action="append", choices=list(probes), help="probe (repeatable; default all)")
    ap.add_argument("--out", default=str(ROOT / "results" / name), help="tables: OUT.json, OUT.md")
    ap.add_argument("--runs", default=str(ROOT / "output" / name), help="folder of the runs")
    ap.add_argument(
        "--merge", action="store_true", help="replace the --probe rows in OUT.json, keep its others (a partial rerun)"
    )
    args = ap.parse_args(argv)
    _cli.output_file(args.out), _cli.output_dir(args.runs)  # before the runs: found at the last write before
    record, path = None, Path(args.out + ".json")
    if args.merge:  # before the runs, too
        if not path.is_file():
            _cli.fail(f"--merge: {path} does not exist: there is no record to merge the rows into; drop --merge")
        record = io.read_data(path)
    comm = MPI.COMM_WORLD
    t0 = time.perf_counter()
    rows = [run(p, Path(args.runs), comm) for p in args.probe or probes]
    if comm.rank == 0:
        data = {"ranks": comm.size, "targets": targets, "wall_time": time.perf_counter() - t0, "rows": rows}
        if draw is not None:
            data["draw"] = draw
        if record is not None:
            data = merged(record, data)
        text = render_data(data)
        io.write_data(Path(args.out + ".json"), data)
        io.atomic_write_text(Path(args.out + ".md"), text)
        print(text)
    return 0


if __name__ == "__main__":
    _cli.tool(main)
