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
from rods.analytical import simulate
from rods.io import cut_identity
from rods.paper.data import read_run, read_summary
from rods.preflight import InputError, distinct, output_names
from rods.scene import Scene
from rods.study import stages, table3
from rods.study.table3 import ModelRun


def _run(role: str, folder: str, scene: Scene) -> ModelRun:
    """A run's summary (and a submodel's history); a missing, unreadable, wrong-kind or other scene's one is bad
    input (exit 2, rods.paper.data.read_summary)."""
    if role == "submodel":  # its first contact ended, as the globals' (a submodel cut short reads a force still rising)
        run = read_run(folder, flag="--submodel", kinds=("submodel",), scene=scene, whole_contact=True)
        return ModelRun(role, run.summary, run.history)
    flag = {"global-driver": "--global", "global-uniform": "--global-uniform"}[role]
    return ModelRun(role, read_summary(folder, flag, ("global",), scene, whole_contact=True))


def _driven_by(folder: str, summary: dict, driver: Path) -> None:
    """A submodel level was driven by the --global run's cut record (its summary's ``cut_record``, the record's own
    id: rods.io.cut_identity), else bad input: Table 3 would call another global its driver (a fuzz, 2026-12-06,
    had a contact-only global with no cut record labelled "drives the submodels"). A level written before the id
    was recorded is not checked."""
    recorded = summary.get("cut_record")
    if recorded is None:
        return
    cut = driver / "cut.h5"
    if not cut.is_file():
        why = "records no cut (no cut.h5): it drove no submodel"
        raise InputError("--global", driver, why, f"give the global that drove them ({summary.get('cut_file')})")
    if cut_identity(cut) != recorded:
        why = f"driven by another global's cut record ({summary.get('cut_file')}), not by --global {driver}'s"
        raise InputError("--submodel", folder, why, "give --global the run that drove it, or rerun it from this one")


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
        _driven_by(folder, run.summary, Path(args.global_dir))
    runs += [driver, *subs]
    cost.check(cost.analytical_cost(scene))  # the reference run below: refused (exit 2) before it, as its stage is
    out = _cli.out_dir(args, "compare", scene)  # after the inputs: a refused run leaves no folder
    output_names(out, stages.COMPARISON_FILES)
    comparison = stages.comparison(scene, simulate(scene).summary, runs, out)
    print(table3.render_markdown(comparison.data))
    _cli.status(comparison.data)  # the finest submodel level's checks, as a study's "compare:" warnings
    return 0


if __name__ == "__main__":
    _cli.entry(main)
