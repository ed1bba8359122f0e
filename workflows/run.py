"""Run what a scene asks for: its effects decide the models (rods.plan), the plan is printed first.

    python workflows/run.py --scene workflows/scenes/paper.toml --set 'effects=["contact_patch"]' --out DIR
    mpirun -n 2 python workflows/run.py --scene ... --set 'submodel.levels=["fine"]' --out DIR
    python workflows/run.py --scene ... --dry-run   # the plan and its cost estimate only; nothing runs
    mpirun -n 2 python workflows/run.py --scene ... --out DIR --restart   # resume a stopped study in DIR

The study pipeline (rods.study.pipeline.run_study): DIR/analytical/, DIR/global/ (to the planned end time), and
for contact effects its cut.h5 (the global drives the submodels: rods.plan.global_drives), DIR/submodel/LEVEL/
and DIR/compare/ (Table 3, Figs. 5c/6). DIR/summary.json holds the plan, the stage folders and the contract
keys, each from the most refined model that computed it. Default DIR: output/run/<scene>.

--restart resumes a study stopped by Ctrl-C, a guard or a lost job: the FE stages that finished in DIR for the
same scene are kept, an unfinished one resumes from its checkpoint (one at a Ctrl-C/SIGTERM stop, others every
fe.checkpoint_interval > 0; not a global recording the cut), the rest run. Exit codes (workflows/_cli.py): 2 bad
input, 1 when a guard stops a stage, 130 on Ctrl-C/SIGTERM.
"""

from __future__ import annotations

import json
from collections.abc import Sequence

import rods.fe  # noqa: F401  (loads the wheel's dolfinx_solver first where installed)

# isort: split
from mpi4py import MPI

import _cli
from rods import cost, io, plan
from rods.study.pipeline import run_study, stage_costs


def main(argv: Sequence[str] | None = None) -> int:
    comm = MPI.COMM_WORLD
    ap = _cli.parser(__doc__, dry_run=True)
    ap.add_argument("--restart", action="store_true", help="resume a stopped study in --out: finished stages kept")
    args = ap.parse_args(argv)
    scene = _cli.load(args)
    plan.check_levels(scene)  # levels no submodel would use: refused before the analytical model runs
    out = _cli.out_dir(args, "run", scene)
    _cli.backend(scene, comm.size)  # refused before the plan, which names a folder a refused run never makes
    log, progress = _cli.rank0(comm)
    if plan.make_plan(scene).global_model:  # its mesh before the plan runs the analytical model (minutes on a µm rod)
        cost.check_mesh(scene, comm.size, comm)
    analytical = cost.check(cost.analytical_cost(scene), args.force, comm=comm)
    log(_cli.planning(analytical))  # before the plan, which runs the analytical model to the first contact
    p = plan.study_plan(scene)  # run_study's plan, from the analytical model to its first contact
    if args.dry_run:  # a real run prints the plan from run_study, after the analytical stage
        log(f"plan for scene '{scene.label}' -> {out}\n{p.describe()}")
    _cli.outlook(scene, log, fe=p.global_model)
    if args.restart:
        log("restart: FE stages finished in the folder for this scene are kept; the costs below are a whole run's")
    _cli.afford(args, analytical, *stage_costs(scene, p, comm.size), log=log, comm=comm, out=out)
    s = run_study(scene, out, comm, progress, log, restart=args.restart).summary  # a guard's stop: exit 1 (_cli)
    shown = ("sources", *io.SUMMARY_KEYS)  # the contract keys, each from its most refined model (sources)
    log(json.dumps({k: s[k] for k in shown if k in s}, indent=1))
    _cli.status(s, comm.rank)
    return 0


if __name__ == "__main__":
    _cli.entry(main)
