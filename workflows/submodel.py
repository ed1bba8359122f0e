"""Submodel of the contact region (first fe.submodel_length of both rods) driven by a global run.

    python workflows/global.py --record-cut --record-until 2.6e-4 --out GDIR          # the global run
    python workflows/submodel.py --global GDIR --level fine --out DIR
    mpirun -n 2 python workflows/submodel.py --global GDIR --level mid --out DIR

The scene is the global run's (GDIR/summary.json scene_values) unless --scene/--set are given. Levels
(uniform element size across and along): coarse/mid/fine/extra-fine/ultra-fine =
0.25/0.125/0.0625/0.03125/0.015625 mm; --size overrides. The run ends at --end-time [s] (default:
1.2 x the analytical contact end, capped by the recorded global time). Writes DIR/summary.json
(peak force, contact radius/area, peak pressure, Hertz at the same force, DOFs, wall time, the
sigma_r profile at the Gauss points nearest the surface), DIR/history.csv, DIR/pressure_profile.csv
(p(r) at peak force) and DIR/sigma_r.csv (r, depth, sigma_r at peak force).

3D (fe.kind = "3d" in the global run) works the same way; the submodel keeps the global's fe.symmetry
(use a quarter model for a centric impact), and sigma_r is radial about Rod 1's axis (x-y plane).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from pathlib import Path

import rods.fe  # noqa: F401  (loads the wheel's dolfinx_solver first where installed)

# isort: split
from mpi4py import MPI

import _cli
from rods import io
from rods.fe.submodel import LEVEL_SIZES, run_submodel
from rods.scene import SceneError, load_scene, scene_from_summary

END_FACTOR = 1.2  # default end time: this x the analytical contact end [-]


def main(argv: Sequence[str] | None = None) -> int:
    comm = MPI.COMM_WORLD
    root = comm.rank == 0
    ap = _cli.parser(__doc__.splitlines()[0])
    ap.add_argument("--global", dest="global_dir", required=True, help="output folder of a global run with cut.h5")
    ap.add_argument("--level", default="fine", choices=list(LEVEL_SIZES), help="mesh level (default %(default)s)")
    ap.add_argument("--size", type=float, default=None, help="element size [m] (overrides --level)")
    ap.add_argument("--axial-size", type=float, default=None, help="axial element size [m] (default = size)")
    ap.add_argument("--end-time", type=float, default=None, help="end time [s] (default 1.2 x contact end)")
    ap.add_argument("--dt", default="auto", help="time step [s], 'auto' (stable) or 'global' (the global run's)")
    args = ap.parse_args(argv)
    gdir = Path(args.global_dir)
    cut = gdir / "cut.h5"
    if not cut.exists():
        _cli.fail(f"{cut} not found: run workflows/global.py --record-cut --out {gdir} first")
    gsum = json.loads((gdir / "summary.json").read_text())
    given = any(a == "--scene" or a.startswith("--scene=") for a in (argv if argv is not None else sys.argv[1:]))
    try:
        if given:
            scene = load_scene(args.scene, args.overrides)
        else:
            scene = scene_from_summary(gsum["scene_values"], args.overrides, source=str(gdir / "summary.json"))
    except SceneError as e:
        _cli.fail(str(e))
    h = args.size or LEVEL_SIZES[args.level]
    level = args.level if args.size is None else f"h={h:g}"
    end = args.end_time
    if end is None:
        from rods.analytical import simulate

        episodes = simulate(scene).summary["contact_episodes"]
        end = END_FACTOR * episodes[0][1] if episodes else scene.end_time
    end = min(end, scene.end_time)
    dt = args.dt
    if dt == "global":
        dt = gsum["dt"]
    elif dt != "auto":
        dt = float(dt)
    out = _cli.out_dir(args, f"submodel/{level}", scene)
    sr = run_submodel(scene, cut, h, args.axial_size, end, dt, comm, _cli.progress_bar if root else None, level)
    if root:
        s = sr.summary
        s["global_dir"] = str(gdir)
        io.write_history(out / "history.csv", sr.result.history, sr.result.units)
        io.write_history(out / "pressure_profile.csv", sr.result.pressure_profile, {"r": "m", "p": "Pa"})
        io.write_history(out / "sigma_r.csv", sr.sigma_r, {"r": "m", "depth": "m", "sigma_r": "Pa"})
        io.write_summary(out / "summary.json", s)
        keys = [
            "model",
            "peak_contact_force",
            "contact_radius",
            "contact_area",
            "peak_contact_pressure",
            "hertz_at_own_force",
            "dofs",
            "steps",
            "dt",
            "wall_time",
            "ranks",
        ]
        print(json.dumps({k: s[k] for k in keys}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(_cli.guarded(main)())
