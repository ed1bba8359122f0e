"""Submodel driver study (issue 13, item 2): how the cut is driven, and from which global, on the paper scene.

    python benchmarks/driver_study.py [--levels coarse mid fine] [--drivings D ...] [--out results/driver-study]

``--drivings`` runs only those drivings and merges their rows into an existing --out record (the others kept).

Two driving globals over the contact phase (rods.study.stages.driver: the scene's own global, recorded at
the cuts), one per contact law: the kinematic (penalty-free, the default) and the penalty law at its default
factor (the paper's Abaqus practice). Each drives submodels at every level, with the cut driven by the
global's displacement (rods.fe.cut.CutDriver), by its traction, or mixed: its traction plus a
bar-impedance dashpot to its velocity (rods.fe.traction; the default), the submodel's own contact under
either law. Rows: peak force (raw and smoothed over rods.metrics.smoothing)
and first-contact duration against the analytical model, contact area and peak pressure against Hertz at
the row's own force, the energy-balance error, the wall time (set-up + loop, one process unless run under
mpirun). Writes --out + .json, .md and .png (force curves of the finest level).
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import numpy as np  # noqa: E402
from mpi4py import MPI  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "workflows"))  # _cli: the entry points' one error path
import _cli  # noqa: E402
from rods import io, metrics, plan  # noqa: E402
from rods.analytical import simulate  # noqa: E402
from rods.hertz import YieldWarning  # noqa: E402
from rods.paper import report  # noqa: E402  (the record's name in results/)
from rods.scene import SUBMODEL_DRIVINGS, SUBMODEL_LEVELS, load_scene  # noqa: E402
from rods.study import stages  # noqa: E402
from rods.study.figures import pyplot  # noqa: E402

PAPER = ROOT / "workflows" / "scenes" / "paper.toml"
# (global contact law, submodel contact law, cut driving): the paper's practice, the default, and the crossings
CASES = [
    (g, s, d)
    for g, s in (("penalty", "penalty"), ("penalty", "kinematic"), ("kinematic", "kinematic"))
    for d in ("displacement", "traction", "mixed")
]


def row(case: tuple[str, str, str], level: str, st: stages.Stage, analytical: dict, wall: float) -> dict:
    """One submodel run's figures against the analytical model and Hertz at its own force (SI units)."""
    s, h = st.summary, st.history
    H = s["hertz_at_own_force"]
    return {
        "global": case[0],
        "submodel": case[1],
        "driving": case[2],
        "level": level,
        "element_size": s["element_size"],
        "peak_force_vs_analytical": s["peak_contact_force"] / analytical["peak_contact_force"] - 1,
        "smoothed_peak_vs_analytical": metrics.smoothed_peak(h["time"], h["contact_force"], metrics.smoothing(st.scene))
        / analytical["peak_contact_force"]
        - 1,
        "duration_vs_analytical": s["contact_duration"] - analytical["contact_duration"],
        "area_vs_hertz": s["contact_area"] / H["contact_area"] - 1,
        "pressure_vs_hertz": s["peak_contact_pressure"] / H["peak_pressure"] - 1,
        "energy_error": s["energy_error"],
        "wall_time": wall,
    }


def render_md(data: dict) -> str:  # data written before its smoothing window was kept: 2 µs (rods.metrics then)
    lines = [
        "# Submodel driver study: how the cut is driven, from a penalty or a penalty-free global",
        "",
        "`python benchmarks/driver_study.py` on the paper scene. Each global is the scene's own (default mesh, "
        "recorded over the contact phase) under the named contact law; the submodel's own contact law is "
        "named separately. Peak force and duration against the analytical model "
        f"({data['analytical']['peak_contact_force']:.1f} N, "
        f"{data['analytical']['contact_duration'] * 1e6:.2f} µs); smoothed: the sliding "
        f"{data.get('smoothing', 2e-6) * 1e6:.3g} µs average; area and p0 against Hertz at the row's own "
        "peak force.",
        "",
        "| global | submodel | driving | level | peak force | smoothed | duration | area | p0 | energy error "
        "| wall [s] |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in data["rows"]:
        lines.append(
            f"| {r['global']} | {r['submodel']} | {r['driving']} | {r['level']} "
            f"| {r['peak_force_vs_analytical']:+.2%} | {r['smoothed_peak_vs_analytical']:+.2%} "
            f"| {r['duration_vs_analytical'] * 1e6:+.2f} µs | {r['area_vs_hertz']:+.2%} "
            f"| {r['pressure_vs_hertz']:+.2%} | {r['energy_error']:.1e} | {r['wall_time']:.0f} |"
        )
    lines += ["", "Driving globals:", ""]
    for law, g in data["globals"].items():
        lines.append(
            f"* {law}: peak force {g['peak_contact_force'] / data['analytical']['peak_contact_force'] - 1:+.2%}, "
            f"duration {(g['contact_duration'] - data['analytical']['contact_duration']) * 1e6:+.2f} µs"
        )
    return "\n".join(lines) + "\n"


def plot(curves: dict, analytical: dict, path: Path) -> None:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(analytical["time"] * 1e6, analytical["contact_force"] / 1e3, "k-", lw=2, label="analytical")
    for name, c in curves.items():
        ax.plot(np.asarray(c["time"]) * 1e6, np.asarray(c["force"]) / 1e3, lw=1, label=name)
    top = float(np.max(analytical["contact_force"])) / 1e3  # [kN]
    ax.set(xlim=(0, 230), ylim=(-0.05 * top, 1.55 * top), xlabel="t [µs]", ylabel="contact force [kN]")
    ax.set_title("submodel force, finest level")
    ax.legend(fontsize=6.5, ncol=2, loc="upper center")  # above the curves: the plateau and release stay in sight
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = _cli.bare_parser(__doc__.splitlines()[0])
    ap.add_argument("--levels", nargs="+", default=["coarse", "mid", "fine"], choices=SUBMODEL_LEVELS)
    ap.add_argument(
        "--drivings", nargs="+", choices=SUBMODEL_DRIVINGS, default=None, help="run only these, merged into --out"
    )
    ap.add_argument("--out", type=Path, default=ROOT / "results" / report.DRIVER_STUDY)
    args = ap.parse_args()
    _cli.output_file(args.out)  # before the runs: an unwritable --out was found at the last write
    cases = [c for c in CASES if args.drivings is None or c[2] in args.drivings]
    comm = MPI.COMM_WORLD
    root = comm.rank == 0
    scene = load_scene(PAPER)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", YieldWarning)
        a = simulate(scene)
    phase = plan.contact_phase(a.summary, scene.end_time)
    rows, curves, globals_ = [], {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(comm.bcast(tmp if root else None))
        drivers = {}
        for law in dict.fromkeys(c[0] for c in cases):
            d = stages.driver(scene.with_overrides(f"fe.contact='{law}'"), tmp / f"driver-{law}", comm, phase)
            drivers[law], globals_[law] = d, {k: d.summary[k] for k in ("peak_contact_force", "contact_duration")}
        for case in cases:
            g_law, s_law, driving = case
            d = drivers[g_law]
            sc = d.scene.with_overrides(f"fe.contact='{s_law}'", f"submodel.driving='{driving}'")
            for level in args.levels:
                t0 = time.perf_counter()
                st = stages.submodel(sc, d.cut_file, tmp / "sub", comm, level, end_time=phase)
                r = row(case, level, st, a.summary, time.perf_counter() - t0)
                rows.append(r)
                if level == args.levels[-1]:
                    h = st.history
                    name = f"{g_law} global, {s_law} submodel, {driving}"
                    curves[name] = {"time": h["time"][::2].tolist(), "force": h["contact_force"][::2].tolist()}
                if root:
                    print(
                        f"{g_law} -> {s_law}, {driving}, {level}: force {r['peak_force_vs_analytical']:+.2%} "
                        f"(smoothed {r['smoothed_peak_vs_analytical']:+.2%}), area {r['area_vs_hertz']:+.2%}, "
                        f"p0 {r['pressure_vs_hertz']:+.2%}, {r['wall_time']:.0f} s",
                        flush=True,
                    )
    if not root:
        return
    data = {"analytical": {k: a.summary[k] for k in ("peak_contact_force", "contact_duration")}, "globals": globals_}
    data["rows"], data["curves"] = rows, curves  # curves: the finest level's force histories (every 2nd sample)
    data["smoothing"] = metrics.smoothing(load_scene(PAPER))  # [s] the window the rows' smoothed peaks used
    old = args.out.with_suffix(".json")
    if args.drivings is not None and old.is_file():  # merge: the other drivings' rows and curves are kept
        prev = json.loads(old.read_text())
        kept = [r for r in prev["rows"] if r["driving"] not in args.drivings]
        order = {c: i for i, c in enumerate(CASES)}
        data["rows"] = sorted(kept + rows, key=lambda r: (order[(r["global"], r["submodel"], r["driving"])],))
        data["curves"] = {**prev.get("curves", {}), **curves}
    io.write_data(args.out.with_suffix(".json"), data)
    io.atomic_write_text(args.out.with_suffix(".md"), render_md(data))
    plot(data["curves"], a.history, args.out.with_suffix(".png"))
    print(f"wrote {args.out.with_suffix('.json')}, .md and .png")


if __name__ == "__main__":
    _cli.tool(main)
