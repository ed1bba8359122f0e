"""The paper's global FE model (Section 2.2), axisymmetric or 3D: both rods, penalty contact, explicit dynamics.

    python workflows/global.py --scene workflows/scenes/paper.toml --set fe.axial_size=2e-3 --out DIR
    mpirun -n 2 python workflows/global.py ...          # same histories to round-off
    mpirun -n 2 python workflows/global.py --scene workflows/scenes/paper-3d-coarse.toml   # 3D (fe.kind = "3d")

Writes DIR/history.csv (contact force, radius, area, peak pressure, velocity and strain at every
station, energies), DIR/summary.json, DIR/pressure_profile.csv (p(r) at peak force) and, only when
the scene asks ("fields" in effects or fe.field_interval > 0), DIR/fields.xdmf; with --record-cut,
DIR/cut.h5 (the band of displacements that drives workflows/submodel.py, every global step by
default). Prints the plan
first, a progress bar while stepping, and the summary last (rank 0).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence

import rods.fe  # noqa: F401  (loads the wheel's dolfinx_solver first where installed)

# isort: split
from mpi4py import MPI

import _cli
from rods import io
from rods.fe.guards import SimulationError
from rods.fe.model import GlobalModel


def main(argv: Sequence[str] | None = None) -> int:
    comm = MPI.COMM_WORLD
    root = comm.rank == 0
    ap = _cli.parser(__doc__.splitlines()[0])
    ap.add_argument(
        "--record-cut",
        action="store_true",
        help="write DIR/cut.h5: the displacement band around the submodel cut planes (rods.fe.submodel)",
    )
    ap.add_argument("--record-until", type=float, default=None, help="last recorded time [s] (default end time)")
    ap.add_argument(
        "--restart",
        action="store_true",
        help="resume from the last checkpoint in --out (written when fe.checkpoint_interval > 0)",
    )
    ap.add_argument("--record-every", type=int, default=1, help="record every k-th global step (default 1)")
    args = ap.parse_args(argv)
    # parameters
    scene = _cli.load(args)
    out = _cli.out_dir(args, "global", scene)
    # set up: mesh, K, M, contact, probes, stable step (a requested fe.dt too large exits 2)
    model = GlobalModel(scene, comm)
    if root:
        plan = model.plan()
        print(
            "plan: " + "\n      ".join(f"{k}: {v}" for k, v in plan.items()) + f"\n      outputs -> {out}", flush=True
        )
    # solve
    recorder = None
    if args.record_cut:
        from rods.fe.submodel import CutRecorder

        recorder = CutRecorder(model, args.record_until, args.record_every)
    if args.restart and recorder is not None:
        _cli.fail("--restart cannot be combined with --record-cut (the cut record is not checkpointed)")
    try:
        result = model.run(out, _cli.progress_bar if root else None, step_hook=recorder, restart=args.restart)
    except SimulationError as e:  # a guard stopped the run: keep what was recorded, readable, then exit 1
        if root:
            if e.partial is not None:
                io.write_history(out / "history.csv", e.partial.history, e.partial.units)
                io.write_summary(out / "summary.json", e.partial.summary)
            print(f"error: run stopped: {e}\n       histories up to the failure are in {out}", file=sys.stderr)
        return 1
    if recorder is not None:
        recorder.write(out / "cut.h5")
    # output (scalars on rank 0; fields were written collectively during the run)
    if root:
        io.write_history(out / "history.csv", result.history, result.units)
        io.write_history(out / "pressure_profile.csv", result.pressure_profile, {"r": "m", "p": "Pa"})
        io.write_summary(out / "summary.json", result.summary)
        keys = [
            *io.SUMMARY_KEYS[2:],
            "dofs",
            "steps",
            "dt",
            "dt_critical",
            "dt_element_estimate",
            "energy_error",
            "ranks",
            "penalty",
            "dof_steps_per_second",
        ]
        print(json.dumps({k: result.summary[k] for k in keys}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(_cli.guarded(main)())
