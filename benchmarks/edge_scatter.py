"""Edge scatter of the submodel's contact radius: how much of a level's radius/area error is where its nodes fall.

    python benchmarks/edge_scatter.py [--levels fine extra-fine ...] [--work DIR] [--out results/edge-scatter]

The submodel's contact radius is placed from the nodal gaps around the edge (rods.fe.contact.edge_radius); the
discrete contact set closes node by node, so the radius at one element size depends on where the Hertz edge falls
between two tip nodes, not only on the size. This benchmark runs the default driver (rods.study.stages.driver, the
scene's own global over the contact phase) once and the submodel at element sizes a few per cent either side of
the mid and fine levels (0.125, 0.0625 mm), one process, and reports for each size the errors against Hertz at its
own peak force: the contact radius at the peak, its mean over the loading phase (F > 0.5 F_peak, before the
peak: the edge sweeps across elements there), the area, and the peak pressure; and the band each spans per group.
A level's radius that lies inside its neighbours' band is scatter, not a trend: the convergence table's
monotonicity test over halvings cannot see past it. Writes --out + .json and .md.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "workflows"))  # _cli: the entry points' one error path
import numpy as np  # noqa: E402
from mpi4py import MPI  # noqa: E402

import _cli  # noqa: E402
from rods import hertz, io  # noqa: E402
from rods.hertz import YieldWarning  # noqa: E402
from rods.paper import report  # noqa: E402  (the record's name in results/)
from rods.scene import SUBMODEL_LEVEL_SIZES, load_scene  # noqa: E402
from rods.study import stages  # noqa: E402

PAPER = ROOT / "workflows" / "scenes" / "paper.toml"
SPREAD = (0.93, 0.96, 1.0, 1.04, 1.07)  # element sizes around a level, as multiples of it [-]
LOADING = 0.5  # the loading phase: F > LOADING x F_peak before the peak [-]


def errors(summary: dict, history: dict, E_star: float, R_star: float) -> dict:
    """Errors [-] of one submodel run against Hertz at its own force (module docstring)."""
    F, a = np.asarray(history["contact_force"]), np.asarray(history["contact_radius"])
    ip = int(np.argmax(F))
    load = (np.arange(F.size) <= ip) & (F > LOADING * F[ip])
    H = hertz.at_force(summary["peak_contact_force"], E_star, R_star)
    return {
        "radius_peak": summary["contact_radius"] / H["contact_radius"] - 1,
        "radius_loading_mean": float(np.mean(a[load] / hertz.contact_radius(F[load], E_star, R_star) - 1)),
        "area": summary["contact_area"] / H["contact_area"] - 1,
        "peak_pressure": summary["peak_contact_pressure"] / H["peak_pressure"] - 1,
    }


def render_md(data: dict) -> str:
    lines = [
        "# Edge scatter of the submodel's contact radius",
        "",
        "`python benchmarks/edge_scatter.py` — paper scene, default driver, one process. Errors against Hertz at each "
        "run's own peak force; radius (loading mean): a/a_H(F) - 1 averaged while F > 0.5 F_peak before the peak.",
        "",
        "| group | h [mm] | h / level | radius at peak | radius (loading mean) | area | peak pressure |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in data["rows"]:
        e = r["errors"]
        lines.append(
            f"| {r['level']} | {r['h'] * 1e3:.4f} | {r['h'] / SUBMODEL_LEVEL_SIZES[r['level']]:.2f} "
            f"| {e['radius_peak']:+.3%} | {e['radius_loading_mean']:+.3%} | {e['area']:+.3%} "
            f"| {e['peak_pressure']:+.3%} |"
        )
    lines += ["", "Band over each group (min to max):", ""]
    for level in data["levels"]:
        rows = [r["errors"] for r in data["rows"] if r["level"] == level]
        band = {k: (min(e[k] for e in rows), max(e[k] for e in rows)) for k in rows[0]}
        lines.append(
            f"* {level}: radius at peak {band['radius_peak'][0]:+.2%} to {band['radius_peak'][1]:+.2%}; loading mean "
            f"{band['radius_loading_mean'][0]:+.2%} to {band['radius_loading_mean'][1]:+.2%}; area "
            f"{band['area'][0]:+.2%} to {band['area'][1]:+.2%}; peak pressure {band['peak_pressure'][0]:+.2%} to "
            f"{band['peak_pressure'][1]:+.2%}"
        )
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__.splitlines()[0])
    ap.add_argument("--levels", nargs="+", default=["mid", "fine"], choices=list(SUBMODEL_LEVEL_SIZES))
    ap.add_argument("--work", type=Path, default=ROOT / "output" / "edge-scatter", help="run folders")
    ap.add_argument("--out", type=Path, default=ROOT / "results" / report.EDGE_SCATTER)
    args = ap.parse_args(argv)
    comm = MPI.COMM_WORLD
    scene = load_scene(PAPER)
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", YieldWarning)
        drv = stages.driver(scene, args.work / "driver", comm)
        cut = args.work / "driver" / "cut.h5"
        for level in args.levels:
            for f in SPREAD:
                h = SUBMODEL_LEVEL_SIZES[level] * f
                st = stages.submodel(scene, cut, args.work / f"{level}-{f:g}", comm, size=h,
                                     end_time=drv.summary["contact_phase"])  # fmt: skip
                e = errors(st.summary, st.history, E_star, R_star)
                rows.append(
                    {"level": level, "h": h, "errors": e, "peak_contact_force": st.summary["peak_contact_force"]}
                )
                print(f"{level} h = {h * 1e3:.4f} mm: " + ", ".join(f"{k} {v:+.3%}" for k, v in e.items()), flush=True)
    data = {"scene": scene.name, "levels": args.levels, "spread": SPREAD, "rows": rows}
    if comm.rank == 0:
        io.write_data(args.out.with_suffix(".json"), data)
        io.atomic_write_text(args.out.with_suffix(".md"), render_md(data))
        print(f"wrote {args.out.with_suffix('.json')} and .md")
    return 0


if __name__ == "__main__":
    _cli.tool(main)
