"""Verification matrix: the global FE model at default settings against the analytical model, scene by scene.

One recipe, run by ``workflows/verify.py`` (``make verify``) and the slow test: each case is the paper scene
with a few overrides (:data:`CASES`), run through the analytical model and the global FE model at the
scene's defaults (no per-case tuning). Per case the matrix reports

* peak contact force, FE against analytical [%] — target :data:`TARGETS` ``peak_force``;
* first contact duration, FE minus analytical [s] (rods.metrics.contact_duration) — target ``duration``;
* Rod-2 midpoint average peak speed, FE against analytical [%] (rods.metrics.midpoint_peak_speed);
* midpoint strain RMS difference over the strain window [-] (rods.metrics.strain_window, rms_difference);
* the FE energy-balance error [-] — target ``energy``;
* wall time of the FE run (set-up + time loop) [s].

A case *passes* when every targeted column is inside its target. The targets are issue 13's acceptance
figures; the matrix reports what the defaults give, it does not tune them.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from rods import io, metrics
from rods.compare import percent
from rods.scene import Scene

__all__ = ["CASES", "TARGETS", "case_row", "render_markdown", "run_matrix"]

# case name -> (what it checks, scene overrides of the paper scene)
CASES: dict[str, tuple[str, tuple[str, ...]]] = {
    "paper": ("the paper scene, 2.197 m/s", ()),
    "speed-1.0": ("paper rods at 1.0 m/s", ("impact.speed=1.0",)),
    "speed-4.0": ("paper rods at 4.0 m/s", ("impact.speed=4.0",)),
    "titanium-rod2": (
        "titanium Rod 2 (E = 114 GPa, ρ = 4430 kg/m³, ν = 0.34) at 2.5 m/s",
        (
            "impact.speed=2.5",
            "rod2.material.youngs_modulus=114e9",
            "rod2.material.density=4430.0",
            "rod2.material.poisson_ratio=0.34",
        ),
    ),
    "tip-20mm": ("Rod 1 with a 20 mm tip radius", ("rod1.tip_radius=0.020",)),
    "equal-0.35m": ("two equal 0.35 m rods, flat Rod 2", ("rod1.length=0.35", "rod2.length=0.35")),
}
TARGETS = {"peak_force": 0.5, "duration": 2e-6, "energy": 1e-3}  # [%], [s], [-]


def case_row(name: str, analytical: Mapping[str, Any], fe: Mapping[str, Any], scene: Scene) -> dict[str, Any]:
    """One matrix row from the two models' summaries and histories (``{"summary", "history"}`` each)."""
    sa, sf = analytical["summary"], fe["summary"]
    ha, hf = analytical["history"], fe["history"]
    window = metrics.strain_window(scene.rod2)
    covered = hf["time"][-1] >= 0.999 * window[1] and ha["time"][-1] >= 0.999 * window[1]
    rms = (
        metrics.rms_difference(hf["time"], hf["rod2_mid_strain"], ha["time"], ha["rod2_mid_strain"], window)
        if covered
        else math.nan
    )
    d_dur = sf["contact_duration"] - sa["contact_duration"]
    row = {
        "case": name,
        "description": CASES[name][0] if name in CASES else name,
        "overrides": list(CASES[name][1]) if name in CASES else [],
        "impact_speed": scene.speed,
        "peak_force_analytical": sa["peak_contact_force"],
        "peak_force_fe": sf["peak_contact_force"],
        "peak_force_pct": percent(sf["peak_contact_force"], sa["peak_contact_force"]),
        "duration_analytical": sa["contact_duration"],
        "duration_fe": sf["contact_duration"],
        "duration_difference": d_dur,
        "peak_speed_pct": percent(sf["midpoint_peak_speed"], sa["midpoint_peak_speed"]),
        "strain_rms": rms,
        "strain_window": list(window),
        "energy_error": sf["energy_error"],
        "wall_time": sf["wall_time"] + sf.get("setup_time", 0.0),
        "dofs": sf["dofs"],
        "steps": sf["steps"],
        "penalty_factor": sf.get("penalty_factor"),
    }
    row["passes"] = {
        "peak_force": abs(row["peak_force_pct"]) <= TARGETS["peak_force"],
        "duration": abs(d_dur) <= TARGETS["duration"],
        "energy": sf["energy_error"] <= TARGETS["energy"],
    }
    return row


def run_matrix(
    base: Scene,
    out: Path,
    comm: Any,
    cases: Sequence[str] = tuple(CASES),
    extra: Sequence[str] = (),
    log: Callable[[str], None] | None = None,
    progress: Any = None,
    tables: Path | None = None,
) -> dict[str, Any]:
    """Run ``cases`` (names of :data:`CASES`) on ``base`` plus ``extra`` overrides into ``out/<case>/``
    (analytical/ and global/ per case; collective on ``comm``) and return the matrix data, written as
    ``verification.json`` with its markdown rendering ``verification.md`` into ``tables`` (default ``out``)
    on rank 0."""
    from rods.study import stages

    rows, t0 = [], time.perf_counter()
    for name in cases:
        sc = base.with_overrides(*CASES[name][1], *extra)
        if log is not None:
            log(f"verification case '{name}': {CASES[name][0]}")
        a = stages.analytical(sc, out / name / "analytical", comm)
        g = stages.global_model(sc, out / name / "global", comm, progress=progress, log=log)
        hist = g.history if comm.rank == 0 else {}
        if comm.rank == 0:
            rows.append(
                case_row(
                    name, {"summary": a.summary, "history": a.history}, {"summary": g.summary, "history": hist}, sc
                )
            )
    data = {
        "base_scene": base.name,
        "extra_overrides": list(extra),
        "targets": TARGETS,
        "ranks": comm.size,
        "wall_time": time.perf_counter() - t0,
        "rows": rows,
    }
    if comm.rank == 0:
        tables = out if tables is None else Path(tables)
        io.write_data(tables / "verification.json", data)
        io.atomic_write_text(tables / "verification.md", render_markdown(data))
    return data


def _mark(ok: bool) -> str:
    return "" if ok else " ✗"


def render_markdown(data: Mapping[str, Any]) -> str:
    """verification.md from the matrix data (nothing else)."""
    t = data["targets"]
    lines = [
        "# Verification matrix: global FE model at default settings against the analytical model",
        "",
        f"Base scene `{data['base_scene']}`"
        + (f" with {', '.join(data['extra_overrides'])}" if data["extra_overrides"] else "")
        + f"; {data['ranks']} rank(s). Targets (issue 13): peak force within {t['peak_force']:g}%, first contact "
        f"duration within {t['duration'] * 1e6:g} µs, energy error below {t['energy']:g}. ✗ marks a miss. "
        "Strain RMS: midpoint strain over the first five periods 2 L2/c2 (rods.metrics.strain_window).",
        "",
        "| case | peak force FE [N] | vs analytical | duration FE [µs] | Δ duration [µs] | avg. peak speed vs "
        "analytical | strain RMS [µε] | energy error | DOFs | steps | wall [s] |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in data["rows"]:
        p = r["passes"]
        lines.append(
            f"| {r['description']} | {r['peak_force_fe']:.1f} | {r['peak_force_pct']:+.3f}%{_mark(p['peak_force'])} "
            f"| {r['duration_fe'] * 1e6:.2f} | {r['duration_difference'] * 1e6:+.2f}{_mark(p['duration'])} "
            f"| {r['peak_speed_pct']:+.2f}% | {_num(r['strain_rms'] * 1e6, '.2f')} "
            f"| {r['energy_error']:.1e}{_mark(p['energy'])} | {r['dofs']:,} | {r['steps']:,} | {r['wall_time']:.1f} |"
        )
    n_pass = sum(all(r["passes"].values()) for r in data["rows"])
    lines += ["", f"{n_pass} of {len(data['rows'])} cases meet every target."]
    return "\n".join(lines) + "\n"


def _num(x: float, fmt: str) -> str:
    return "–" if x is None or not math.isfinite(x) else format(x, fmt)
