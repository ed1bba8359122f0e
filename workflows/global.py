"""The paper's global FE model (Section 2.2), axisymmetric or 3D: both rods in contact, explicit dynamics.

    mpirun -n 2 python workflows/global.py --scene workflows/scenes/paper.toml --set fe.axial_size=2e-3 --out DIR
    mpirun -n 2 python workflows/global.py --driver --out DIR   # the submodels' driver (rods.plan), with cut.h5

Writes DIR/history.csv, summary.json, pressure_profile.csv, fields.xdmf when the scene asks ("fields" or
fe.field_interval > 0) and, with --record-cut or --driver, cut.h5 (drives workflows/submodel.py); --driver runs
rods.plan.submodel_driver over the contact phase (rods.study.stages.driver). Default DIR: output/global/<scene>
(output/driver/<scene>). Exit codes (workflows/_cli.py): 2 bad input, 1 when a guard stops the run, 130 on
Ctrl-C/SIGTERM (both write the histories so far). --restart needs the checkpoint of the same scene and rank count.
"""

from __future__ import annotations

import json
from collections.abc import Sequence

import rods.fe  # noqa: F401  (loads the wheel's dolfinx_solver first where installed)

# isort: split
from mpi4py import MPI

import _cli
from rods import cost, io, plan
from rods.fe import checkpoint
from rods.study import jobs, stages

SHOWN = ("dofs", "steps", "dt", "dt_critical", "dt_element_estimate", "energy_error", "ranks", "contact", "penalty")


def main(argv: Sequence[str] | None = None) -> int:
    comm = MPI.COMM_WORLD
    ap = _cli.parser(__doc__, dry_run=True)
    ap.add_argument("--driver", action="store_true", help="the submodels' driving global, recorded (rods.plan)")
    ap.add_argument("--record-cut", action="store_true", help="write DIR/cut.h5, the band around the submodel cut")
    ap.add_argument("--record-until", type=_cli.positive, help="last recorded time [s] (default end time)")
    ap.add_argument("--record-every", type=_cli.count, default=1, help="record every k-th global step (default 1)")
    ap.add_argument("--restart", action="store_true", help="resume from the last checkpoint in --out")
    args = ap.parse_args(argv)
    scene = _cli.load(args)
    out = _cli.out_dir(args, "driver" if args.driver else "global", scene)
    options = {"driver": args.driver, "record_cut": args.record_cut, "record_until": args.record_until,
               "record_every": args.record_every, "restart": args.restart}  # fmt: skip
    stages.check_cut_options(scene, **options)  # before any cost: the step is checked below, from the estimate
    if args.restart:  # the folder held first: a run still writing it replaces its checkpoint under the read
        _cli.hold(out, comm)
        checkpoint.precheck(out, comm.size, scene)  # before the set-up: exit 2 naming the remedy
    log, progress = _cli.rank0(comm)
    if args.driver:  # its phase runs the analytical model to the first contact: within its budgets first
        cost.check_mesh(scene, comm.size, comm, "the driving global")  # the mesh the phase is planned for
        log(_cli.planning(cost.check(cost.analytical_cost(scene), args.force, comm=comm)))
    phase = plan.driver_phase(scene) if args.driver else None  # [s] the driver's record, the submodels' end
    sc = plan.submodel_driver(scene, phase) if args.driver else scene  # the driver: over the contact phase
    _cli.backend(scene, comm.size)  # refusals before the plan, which names a folder a refused run never makes
    c = jobs.global_cost(scene, comm.size, driver=args.driver, record_cut=args.record_cut,
                         record_until=args.record_until, record_every=args.record_every, phase=phase)  # fmt: skip
    step = sc.end_time / max(c.steps, 1.0)  # [s] the estimate's stable step (the set-up solves it exactly)
    stages.check_cut_options(scene, **options, step=step)
    log(f"{plan.fe_stage(sc, c.what)} -> {out}")  # c.what: the driving global or the global (rods.study.jobs)
    _cli.outlook(scene, log, wave=not args.driver, fe=True)  # a driver stops after the contact phase
    _cli.afford(args, c, log=log, comm=comm, out=out)
    if args.driver:
        s = stages.driver(scene, out, comm, phase, progress=progress, log=log).summary
    else:
        kw = {"record_until": args.record_until, "record_every": args.record_every, "restart": args.restart}
        s = stages.global_model(scene, out, comm, record_cut=args.record_cut, progress=progress, log=log, **kw)
        s = s.summary
    log(json.dumps({k: s[k] for k in (*io.SUMMARY_KEYS[2:], *SHOWN, "dof_steps_per_second", "peak_memory")}, indent=1))
    _cli.status(s, comm.rank)
    return 0


if __name__ == "__main__":
    _cli.entry(main)
