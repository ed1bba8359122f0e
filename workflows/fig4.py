"""Fig. 4 with both models: Rod-2 midpoint speed, strain and contact force, FE over analytical.

    python workflows/fig4.py --analytical output/paper/analytical/trial-1-3 --fe output/paper/global \
        [--fe LABEL=DIR ...] --png results/fig4.png --md results/fig4.md

Reads each run's history.csv and summary.json; writes the figure and a small table of the
agreement measures (peak force, contact duration, average peak speed, strain RMS difference over
the first five periods 2 L2/c2), all defined in rods/metrics.py.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from rods import io, metrics


def load(d: str | Path) -> tuple[dict[str, np.ndarray], dict]:
    d = Path(d)
    return io.read_history(d / "history.csv"), json.loads((d / "summary.json").read_text())


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--analytical", required=True)
    ap.add_argument("--fe", action="append", required=True, help="FE run folder, or LABEL=FOLDER (repeatable)")
    ap.add_argument("--png", default="results/fig4.png")
    ap.add_argument("--md", default="results/fig4.md")
    args = ap.parse_args(argv)
    h_a, s_a = load(args.analytical)
    sv = s_a.get("scene_values", {})
    L2 = float(sv.get("rod2", {}).get("length", 0.70099))
    ρ2 = float(sv.get("rod2", {}).get("material", {}).get("density", 7803.0))
    E2 = float(sv.get("rod2", {}).get("material", {}).get("youngs_modulus", 204.3e9))
    window = (0.0, 5 * 2 * L2 / np.sqrt(E2 / ρ2))  # first five periods of the midpoint strain [s]

    fe_runs = []
    for spec in args.fe:
        label, _, d = spec.rpartition("=")
        h, s = load(d)
        fe_runs.append((label or s.get("model", "FE"), h, s))

    fig, ax = plt.subplots(3, 1, figsize=(9, 9))
    t_a = h_a["time"] * 1e6
    ax[0].plot(t_a, h_a["rod2_mid_velocity"], "k-", lw=1.4, label="analytical")
    ax[1].plot(t_a, h_a["rod2_mid_strain"] * 1e6, "k-", lw=1.4, label="analytical")
    ax[2].plot(t_a, h_a["contact_force"], "k-", lw=1.4, label="analytical")
    rows = []
    for label, h, s in fe_runs:
        t = h["time"] * 1e6
        ax[0].plot(t, h["rod2_mid_velocity"], lw=0.9, label=label)
        ax[1].plot(t, h["rod2_mid_strain"] * 1e6, lw=0.9, label=label)
        ax[2].plot(t, h["contact_force"], lw=0.9, label=label)
        rms = metrics.rms_difference(h["time"], h["rod2_mid_strain"], h_a["time"], h_a["rod2_mid_strain"], window)
        dF = 100 * (s["peak_contact_force"] / s_a["peak_contact_force"] - 1)
        rows.append(
            f"| {label} | {s['peak_contact_force']:.1f} | {dF:+.2f}% "
            f"| {s['contact_duration'] * 1e6:.2f} | {(s['contact_duration'] - s_a['contact_duration']) * 1e6:+.2f} "
            f"| {s['midpoint_peak_speed']:.4f} | {rms * 1e6:.2f} | {s.get('energy_error', float('nan')):.1e} "
            f"| {s.get('wall_time', float('nan')):.1f} |"
        )
    ax[0].set(ylabel="speed [m/s]", title="a) Rod-2 midpoint speed (surface)")
    ax[1].set(
        ylabel="strain [µε]", xlabel="time since first contact [µs]", title="b) Rod-2 midpoint axial strain (surface)"
    )
    ax[2].set(ylabel="force [N]", xlabel="time since first contact [µs]", title="c) contact force")
    ax[2].set_xlim(0, 400)
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8, loc="upper right")
    fig.suptitle(f"Fig. 4: FE global model over the analytical model ({s_a['impact_speed']} m/s)")
    fig.tight_layout()
    Path(args.png).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.png, dpi=110)
    md = [
        "# Fig. 4: FE global model against the analytical model",
        "",
        f"![Fig. 4]({Path(args.png).name})",
        "",
        f"Analytical: peak force {s_a['peak_contact_force']:.1f} N, contact duration "
        f"{s_a['contact_duration'] * 1e6:.2f} µs, average peak speed {s_a['midpoint_peak_speed']:.4f} m/s. "
        f"Strain RMS difference over the first five periods ({window[1] * 1e6:.0f} µs). "
        "The force panel shows the first 400 µs.",
        "",
        "| model | peak force [N] | vs analytical | duration [µs] | Δ duration [µs] | avg. peak speed [m/s] "
        "| strain RMS Δ [µε] | energy error | wall time [s] |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
        *rows,
    ]
    io.atomic_write_text(args.md, "\n".join(md) + "\n")
    print("\n".join(md))
    return 0


if __name__ == "__main__":
    sys.exit(main())
