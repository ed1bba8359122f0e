r"""Comparison stage (paper Table 3, Figs. 5c and 6): global and submodel levels against Hertz and experiment.

    python workflows/compare.py --global output/paper/driver --global-uniform output/paper/global-paper \
        --submodel output/paper/submodel/coarse --submodel output/paper/submodel/mid ... [--out DIR]

--global is the driving global (workflows/global.py --driver), --global-uniform the scene's own global.
The scene (--scene/--set, default the paper scene) gives the analytical model and Hertz; every run must be of its
bodies and impact (else exit 2). Writes
DIR/table3.json (the data), DIR/table3.md and table3.csv rendered from it, fig6-sigma-r.png,
fig5c-pressure.png and fig5c-profile.png (rods.study.stages.comparison). Default DIR:
output/compare/<scene>; the record (results/) only with --out results.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import _cli
from rods import cost
from rods.preflight import distinct, output_names
from rods.scene import Scene
from rods.study import stages, table3
from rods.study.runs import check_driven_by, read_run, read_summary
from rods.study.table3 import ModelRun


def _run(role: str, folder: str, scene: Scene) -> ModelRun:
    """A run's summary (and a submodel's history); a missing, unreadable, wrong-kind or other scene's one is bad
    input (exit 2, rods.study.runs.read_summary)."""
    if role == "submodel":  # its first contact ended, as the globals' (a submodel cut short reads a force still rising)
        run = read_run(folder, flag="--submodel", kinds=("submodel",), scene=scene, whole_contact=True)
        return ModelRun(role, run.summary, run.history)
    flag = {"global-driver": "--global", "global-uniform": "--global-uniform"}[role]
    return ModelRun(role, read_summary(folder, flag, ("global",), scene, whole_contact=True))


def main(argv: Sequence[str] | None = None) -> int:
    ap = _cli.parser(__doc__)
    ap.add_argument("--global", dest="global_dir", required=True, help="the driving global run (global.py --driver)")
    ap.add_argument("--global-uniform", default=None, help="optional: the scene's own global run")
    ap.add_argument("--submodel", action="append", default=[], help="submodel level folder (repeatable)")
    args = ap.parse_args(argv)
    scene = _cli.load(args)
    distinct([Path(d) for d in args.submodel], "--submodel")  # a level given twice is two rows of Table 3
    runs = [_run("global-uniform", args.global_uniform, scene)] if args.global_uniform else []
    driver = _run("global-driver", args.global_dir, scene)
    subs = [_run("submodel", d, scene) for d in args.submodel]
    for folder, run in zip(args.submodel, subs, strict=True):
        check_driven_by(folder, run.summary, args.global_dir)
    runs += [driver, *subs]
    cost.check(cost.analytical_cost(scene))  # the reference run below: refused (exit 2) before it, as its stage is
    out = _cli.out_dir(args, "compare", scene)  # after the inputs: a refused run leaves no folder
    output_names(out, stages.COMPARISON_FILES)
    # the reference through its stage (its yield warnings kept in its summary, not printed as Python's warnings)
    reference = stages.analytical(scene, out, write=False).summary
    comparison = stages.comparison(scene, reference, runs, out)
    print(table3.render_markdown(comparison.data))
    _cli.status(comparison.data)  # the finest submodel level's checks, as a study's "compare:" warnings
    return 0


if __name__ == "__main__":
    _cli.entry(main)
