"""What accuracy costs in time: every model and resolution against its reference, with the Pareto front.

Errors (each against the best reference available for it):

* peak force — relative to the converged analytical model (rtol ``REFERENCE_RTOL``);
* contact radius — relative to closed-form Hertz at the model's *own* peak force (Eq. 10,
  :func:`rods.hertz.at_force`), so it measures how well the mesh resolves the patch, not the force;
* midpoint strain — RMS difference from the converged analytical model over
  :func:`rods.metrics.strain_window` (analytical rows have no contact-radius error by construction).

Cost: wall time of the run (setup + time loop where recorded) and DOFs. A run is on the Pareto front of
an error if no other run is both cheaper and at least as accurate. :func:`compute` gives the data
(``accuracy-cost.json``); :func:`render_md`, :func:`render_table` and :func:`plot` render it.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from rods import hertz, io, metrics
from rods.analytical import simulate
from rods.io import Run, write_data
from rods.scene import Scene
from rods.study.figures import pyplot

__all__ = ["ERRORS", "compute", "pareto", "plot", "render_md", "render_table", "write"]

REFERENCE_RTOL = 1e-13  # [-] the converged analytical model
ANALYTICAL_RTOLS = (1e-3, 1e-5, 1e-7, 1e-10)  # [-] the analytical model's own cost/accuracy ladder
ERRORS = {"peak_force_error": "peak force", "contact_radius_error": "contact radius", "strain_rms": "strain RMS"}


def pareto(cost: list[float], err: list[float]) -> list[bool]:
    """True where no other point has lower-or-equal cost and lower error (NaN errors never on the front)."""
    out = []
    for i, (c, e) in enumerate(zip(cost, err, strict=True)):
        dominated = any(
            j != i and math.isfinite(e2) and c2 <= c and e2 <= e and (c2 < c or e2 < e)
            for j, (c2, e2) in enumerate(zip(cost, err, strict=True))
        )
        out.append(math.isfinite(e) and not dominated)
    return out


def _strain_rms(h: dict[str, np.ndarray], ref: dict[str, np.ndarray], window: tuple[float, float]) -> float:
    """NaN for a run without the midpoint strain or shorter than the window (a submodel)."""
    if "rod2_mid_strain" not in h:
        return math.nan
    return metrics.window_rms_difference(h["time"], h["rod2_mid_strain"], ref["time"], ref["rod2_mid_strain"], window)


def _analytical_rows(scene: Scene, F_ref: float, ref: dict, window: tuple[float, float]) -> list[dict[str, Any]]:
    rows = []
    for rtol in ANALYTICAL_RTOLS:
        t0 = time.perf_counter()
        r = simulate(scene, rtol=rtol)
        rows.append(
            {
                "model": "analytical",
                "label": f"rtol {rtol:.0e}",
                "dofs": 1,
                "wall_time": time.perf_counter() - t0,
                "peak_force_error": abs(r.summary["peak_contact_force"] / F_ref - 1),
                "contact_radius_error": math.nan,
                "strain_rms": _strain_rms(r.history, ref, window),
            }
        )
    return rows


def _run_row(run: Run, scene: Scene, F_ref: float, ref: dict, window: tuple[float, float]) -> dict[str, Any]:
    s = run.summary
    F = s["peak_contact_force"]
    a_hertz = hertz.at_force(F, *hertz.contact_constants(scene.rod1, scene.rod2))["contact_radius"]
    device = s.get("device", "CPU")  # runs before 2026-11-27 name none: they ran on the CPU
    return {
        "model": s["model"],
        "label": run.label if device == "CPU" else f"{run.label} (GPU: {device})",
        "device": device,
        "dofs": s.get("dofs", 0),
        "wall_time": float(s.get("wall_time", math.nan)) + float(s.get("setup_time", 0.0)),
        "peak_force_error": abs(F / F_ref - 1),
        "contact_radius_error": abs(s["contact_radius"] / a_hertz - 1),
        "strain_rms": _strain_rms(run.history, ref, window),
    }


def compute(scene: Scene, runs: list[Run]) -> dict[str, Any]:
    """Every row's errors and cost, and its place on each error's Pareto front against wall time."""
    reference = simulate(scene, rtol=REFERENCE_RTOL)
    F_ref, window = reference.summary["peak_contact_force"], metrics.strain_window(scene.rod2)
    rows = _analytical_rows(scene, F_ref, reference.history, window)
    rows += [_run_row(r, scene, F_ref, reference.history, window) for r in runs]
    walls = [r["wall_time"] for r in rows]
    fronts = {k: pareto(walls, [r[k] for r in rows]) for k in ERRORS}
    for i, r in enumerate(rows):
        r["on_front"] = {k: fronts[k][i] for k in ERRORS}
    return {
        "scene": scene.label,
        "impact_speed": scene.speed,
        "reference": {"rtol": REFERENCE_RTOL, "peak_contact_force": F_ref, "strain_window": list(window)},
        "rows": rows,
    }


def render_table(data: dict[str, Any]) -> list[str]:
    def cell(r: dict[str, Any], k: str, fmt: str, scale: float = 1.0) -> str:
        v = r[k] * scale
        return "-" if not math.isfinite(v) else fmt.format(v) + (" *" if r["on_front"][k] else "")

    return [
        "| model | run | DOFs | wall time [s] | peak-force error | contact-radius error | strain RMS [µε] |",
        "|---|---|---:|---:|---:|---:|---:|",
        *(
            f"| {r['model']} | {r['label']} | {r['dofs']:,} | {r['wall_time']:.3g} "
            f"| {cell(r, 'peak_force_error', '{:.2e}')} | {cell(r, 'contact_radius_error', '{:.1%}')} "
            f"| {cell(r, 'strain_rms', '{:.3g}', 1e6)} |"
            for r in data["rows"]
        ),
    ]


GUIDE = [
    "## Which model for which question",
    "",
    "* **Peak force, contact duration, rigid-body and wave response** (Table 2, Fig. 4): the analytical model. "
    "It is converged to 1e-7 in milliseconds; the FE global model agrees with it (peak force to a fraction "
    "of a percent) but costs seconds to minutes and adds nothing for these quantities on a centric impact.",
    "* **Contact patch and pressure** (Table 3, Fig. 5c): closed-form Hertz at the analytical force is the "
    "cheapest accurate answer for this elastic, frictionless, centric case. The global FE mesh cannot resolve "
    "the patch (its radius error is about one element); when the FE answer is needed (other geometry, "
    "plasticity later), use the axisymmetric submodel at mid/fine level driven by the global run.",
    "* **Subsurface stress** (Fig. 6): the submodel at its finest cheap level; the global model is too coarse.",
    "* **Off-axis impact** (offset, tilt): only the 3D model answers it; use the coarse 3D scene to explore "
    "and the finer one to confirm.",
]


def render_md(data: dict[str, Any]) -> str:
    ref = data["reference"]
    lines = [
        "# Accuracy against cost",
        "",
        f"Paper scene ({data['impact_speed']} m/s). References: converged analytical model (rtol "
        f"{ref['rtol']:.0e}: peak force {ref['peak_contact_force']:.2f} N; midpoint strain over the first "
        f"{metrics.STRAIN_PERIODS} periods 2 L2/c2, {ref['strain_window'][1] * 1e6:.0f} µs) and closed-form Hertz at "
        "each model's own peak force (contact radius). Wall time includes set-up where recorded; runs measured on "
        "this 2-core machine (ranks in each run's summary)"
        + (
            ', except rows marked GPU, whose time loop ran on the named GPU (fe.backend = "cupy"; set-up on that '
            "machine's CPU)"
            if any(r.get("device", "CPU") != "CPU" for r in data["rows"])
            else ""
        )
        + "; submodel rows exclude the global run that drives them. `*` = on the Pareto front of that error against "
        "wall time.",
        "",
        *render_table(data),
        "",
        *GUIDE,
    ]
    return "\n".join(lines) + "\n"


def _panel(a: Any, rows: list[dict], cost: list[float], err: np.ndarray, shown: np.ndarray, marker: dict) -> None:
    """One log-log panel: the ``shown`` points per model and their Pareto front, labelled."""
    for m, mk in marker.items():
        idx = [i for i, r in enumerate(rows) if r["model"] == m and shown[i]]
        a.loglog([cost[i] for i in idx], err[idx], mk, ls="none", label=m)
    front_of = pareto(cost, list(err))
    front = [i for i in np.argsort(cost) if front_of[i] and shown[i]]
    a.loglog([cost[i] for i in front], err[front], "k--", lw=0.8, label="Pareto front")
    for i in front:
        a.annotate(rows[i]["label"], (cost[i], err[i]), fontsize=7, xytext=(3, 3), textcoords="offset points")


def plot(data: dict[str, Any], path: Path) -> None:
    """Each error against wall time and against DOFs (log-log), one marker per model, Pareto fronts dashed."""
    rows = data["rows"]
    plt = pyplot()
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.5))
    models = sorted({r["model"] for r in rows})
    marker = dict(zip(models, "osD^v<>p", strict=False))
    costs = (("wall time [s]", [r["wall_time"] for r in rows]), ("DOFs", [max(r["dofs"], 1) for r in rows]))
    for axes_row, (cost_name, cost) in zip(axes, costs, strict=True):
        for a, (key, name) in zip(axes_row, ERRORS.items(), strict=True):
            scale = 1e6 if key == "strain_rms" else 1.0
            err = np.array([r[key] * scale for r in rows])
            shown = np.isfinite(err) & (err > 0)  # a log axis has no 0 (a run that is its own reference)
            if shown.any():
                _panel(a, rows, cost, err, shown, marker)
            else:
                a.text(0.5, 0.5, "no nonzero errors", ha="center", transform=a.transAxes)
            unit = " [µε]" if key == "strain_rms" else " (relative)"
            a.set(xlabel=cost_name, ylabel=name + unit, title=f"{name} vs {cost_name}")
            a.grid(alpha=0.3, which="both")
    if axes[0, 0].get_legend_handles_labels()[0]:  # none where every peak-force error is 0 (nothing to mark)
        axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"Accuracy against cost ({data['scene']} scene)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


SUFFIXES = (".json", ".md", ".png")  # the files write makes of its prefix


def write(scene: Scene, runs: list[Run], out: Path) -> dict[str, Any]:
    """The stage: ``out`` + .json, .md, .png."""
    data = compute(scene, runs)
    json_file, md_file, png_file = (Path(out).with_suffix(s) for s in SUFFIXES)
    write_data(json_file, data)
    io.atomic_write_text(md_file, render_md(data))
    plot(data, png_file)
    return data
