"""Fig. 4 with both models: Rod-2 midpoint speed, strain and contact force, FE runs over the analytical model.

:func:`compute` measures each FE run against the analytical run (``fig4.json``): peak force, contact
duration, average peak speed and the strain RMS difference over :func:`rods.metrics.strain_window`, all
defined in :mod:`rods.metrics`. :func:`render_table`/:func:`render_md` and :func:`plot` render it.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from rods import io, metrics
from rods.compare import cell, difference, percent
from rods.preflight import InputError
from rods.scene import Scene, scene_from_summary
from rods.study.figures import pyplot

__all__ = ["check_whole_run", "compute", "force_panel_end", "plot", "render_md", "render_table", "write"]

CONTACT_SETTINGS = ("penalty", "tip_grading")  # fe.* keys that tune the contact, not the mesh


def _contact_overrides(run: io.Run, reference: dict[str, Any]) -> dict[str, Any]:
    """The run's fe contact settings that differ from the analytical scene's (empty: a run at the scene's
    own contact settings, i.e. a validation run rather than a tuned one)."""
    fe = run.summary.get("scene_values", {}).get("fe", {})
    return {k: fe[k] for k in CONTACT_SETTINGS if k in fe and fe[k] != reference.get(k)}


def _measures(run: io.Run, analytical: io.Run, window: tuple[float, float], reference_fe: dict) -> dict[str, Any]:
    s, sa, h, ha = run.summary, analytical.summary, run.history, analytical.history
    return {
        "label": run.label,
        "model": s.get("model", ""),
        "peak_contact_force": s["peak_contact_force"],
        "force_vs_analytical": percent(s["peak_contact_force"], sa["peak_contact_force"]) / 100,
        "contact_duration": s["contact_duration"],  # None: the contact had not ended (rods.checks)
        "duration_vs_analytical": difference(s["contact_duration"], sa["contact_duration"]),
        "midpoint_peak_speed": s["midpoint_peak_speed"],
        "strain_rms_difference": metrics.rms_difference(
            h["time"], h["rod2_mid_strain"], ha["time"], ha["rod2_mid_strain"], window
        ),
        "energy_error": float(s.get("energy_error", math.nan)),
        "wall_time": float(s.get("wall_time", math.nan)),
        "contact_overrides": _contact_overrides(run, reference_fe),
    }


def check_whole_run(run: io.Run, scene: Scene, folder: str | Path, flag: str = "--fe") -> None:
    """Fig. 4 compares whole runs: an FE run ``run`` (in ``folder``) ending before the analytical run's ``scene``
    end is refused (:class:`InputError` naming ``flag``); its average peak speed and strain would be of fewer
    plateaus (a fuzz: a 0.3 ms global's average of one plateau sat beside the analytical model's of five,
    unremarked). A driving global (it carries the contact phase it stops after) is told to give the scene's own
    global; a study's own global records the cut beside its whole run and is Fig. 4's."""
    theirs = scene_from_summary(run.summary["scene_values"])
    end = theirs.end_time  # [s]
    if end >= (1.0 - 1e-9) * scene.end_time:
        if not metrics.reaches_end(run.history["time"], theirs):  # damaged from outside: cut short
            last = float(run.history["time"][-1])  # [s]
            why = f"its history.csv stops at {last:.3g} s, before its end time {end:.3g} s (cut short from outside)"
            raise InputError(flag, folder, why, "rerun it")
        return
    if "contact_phase" in run.summary:
        why = f"a driving global (global.py --driver): it stops at {end:.3g} s, after the contact phase"
        fix = "give the scene's own global run (workflows/global.py)"
    else:
        why = f"it ends at {end:.3g} s"
        fix = f"run it to the --analytical run's end, or that run to its end (--set simulation.end_time={end:g})"
    why += f", before the --analytical run's end ({scene.end_time:.3g} s): Fig. 4 compares the whole runs"
    raise InputError(flag, folder, why, fix)


def force_panel_end(analytical: dict[str, Any], end: float) -> float:
    """The force panel's end [s after first contact]: FORCE_PANEL_CONTACTS x the analytical model's first contact
    (the contact and as long after it; it was 400 µs on every scene, twice the paper's), the run's ``end`` [s] where
    that contact has not ended."""
    duration = analytical.get("contact_duration")
    return end if duration is None else min(metrics.FORCE_PANEL_CONTACTS * float(duration), end)


def compute(analytical: io.Run, fe: list[io.Run]) -> dict[str, Any]:
    """Fig. 4's agreement measures as data (SI units); the scene is the analytical run's own."""
    if "scene_values" not in analytical.summary:
        raise ValueError("the analytical run's summary.json has no scene_values (rerun workflows/paper.py)")
    scene = scene_from_summary(analytical.summary["scene_values"])
    periods = metrics.strain_window(scene.rod2)
    # cut to the runs' common end: beyond a history's last sample the RMS would compare against its last value
    # held constant (an analytical run to 0.3 ms against an FE run to 1.5 ms read 247 µε instead of 10 µε)
    ends = [float(r.history["time"][-1]) for r in (analytical, *fe)]
    window = (periods[0], min(periods[1], *ends))
    sa = analytical.summary
    reference_fe = analytical.summary["scene_values"].get("fe", {})
    return {
        "impact_speed": sa["impact_speed"],
        "strain_window": list(window),
        "strain_periods_end": periods[1],
        "force_panel_end": force_panel_end(sa, ends[0]),
        "analytical": {
            **{k: sa[k] for k in ("peak_contact_force", "contact_duration", "midpoint_peak_speed")},
            "contact_law": sa.get("contact_law", "hertz"),  # rods.analytical: the reference's contact law
        },
        "runs": [_measures(r, analytical, window, reference_fe) for r in fe],
    }


def _window_text(data: dict[str, Any]) -> str:
    """The strain window in words: the first periods 2 L2/c2, or the runs' common end where that comes first."""
    end, full = data["strain_window"][1], data.get("strain_periods_end", data["strain_window"][1])
    periods = f"the first {metrics.STRAIN_PERIODS} periods 2 L2/c2 ({full * 1e6:.0f} µs)"
    if end < full * (1 - 1e-9):
        return f"Strain RMS difference over the first {end * 1e6:.0f} µs only (the runs' common end, not {periods})"
    return f"Strain RMS difference over {periods}"


def validation_runs(data: dict[str, Any]) -> list[dict[str, Any]]:
    """The runs at the scene's own contact settings (the tuned submodel driver is not one)."""
    return [r for r in data["runs"] if not r["contact_overrides"]]


def render_table(data: dict[str, Any]) -> list[str]:
    rows = [
        f"| {r['label']} | {r['peak_contact_force']:.1f} | {100 * r['force_vs_analytical']:+.2f}% "
        f"| {cell(r['contact_duration'], '.2f', scale=1e6)} | {cell(r['duration_vs_analytical'], '+.2f', scale=1e6)} "
        f"| {cell(r['midpoint_peak_speed'], '.4f')} | {cell(r['strain_rms_difference'], '.2f', scale=1e6)} "
        f"| {cell(r['energy_error'], '.1e')} | {cell(r['wall_time'], '.1f')} |"
        for r in data["runs"]
    ]
    return [
        "| model | peak force [N] | vs analytical | duration [µs] | Δ duration [µs] | avg. peak speed [m/s] "
        "| strain RMS Δ [µε] | energy error | wall time [s] |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
        *rows,
    ]


def render_md(data: dict[str, Any], png: str = "fig4.png") -> str:
    a = data["analytical"]
    md = [
        "# Fig. 4: FE global model against the analytical model",
        "",
        f"![Fig. 4]({png})",
        "",
        f"Analytical: peak force {a['peak_contact_force']:.1f} N, contact duration "
        f"{cell(a['contact_duration'], '.2f', scale=1e6)} µs, average peak speed "
        f"{cell(a['midpoint_peak_speed'], '.4f')} m/s. "
        f"{_window_text(data)}. The force panel shows the first "
        f"{data['force_panel_end'] * 1e6:.0f} µs.",
        "",
        *render_table(data),
    ]
    return "\n".join(md) + "\n"


def plot(analytical: io.Run, fe: list[io.Run], data: dict[str, Any], path: Path) -> None:
    """Three panels (midpoint speed, midpoint strain, contact force), every run over the analytical curves."""
    plt = pyplot()
    fig, ax = plt.subplots(3, 1, figsize=(9, 9))
    columns = [("rod2_mid_velocity", 1.0), ("rod2_mid_strain", 1e6), ("contact_force", 1.0)]
    for run, style in [(analytical, {"color": "k", "lw": 1.4}), *((r, {"lw": 0.9}) for r in fe)]:
        label = "analytical" if run is analytical else run.label
        for a, (col, scale) in zip(ax, columns, strict=True):
            a.plot(run.history["time"] * 1e6, run.history[col] * scale, label=label, **style)
    ax[0].set(ylabel="speed [m/s]", title="a) Rod-2 midpoint speed (surface)")
    ax[1].set(
        ylabel="strain [µε]", xlabel="time since first contact [µs]", title="b) Rod-2 midpoint axial strain (surface)"
    )
    ax[2].set(ylabel="force [N]", xlabel="time since first contact [µs]", title="c) contact force")
    ax[2].set_xlim(0, data["force_panel_end"] * 1e6)
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8, loc="upper right")
    fig.suptitle(f"Fig. 4: FE global model over the analytical model ({data['impact_speed']} m/s)")
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write(analytical: io.Run, fe: list[io.Run], png: Path, md: Path) -> dict[str, Any]:
    """The stage: fig4.json next to ``md``, the markdown and the figure."""
    data = compute(analytical, fe)
    io.write_data(Path(md).with_suffix(".json"), data)
    plot(analytical, fe, data, png)
    io.atomic_write_text(md, render_md(data, Path(png).name))
    return data
