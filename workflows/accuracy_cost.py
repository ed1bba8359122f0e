r"""What accuracy costs in time: every model and resolution against its reference, with the Pareto front
(rods.paper.accuracy_cost).

    python workflows/accuracy_cost.py --run "global 1.0 mm=output/paper/global" [--run LABEL=DIR ...] \
        [--scene workflows/scenes/paper.toml] [--out output/accuracy-cost/paper/accuracy-cost]

Writes --out + .json, .md, .png (default output/accuracy-cost/<scene folder>/accuracy-cost, one per scene; the main
job passes --out results/accuracy-cost). Every --run must be a
finished run of the scene's bodies and impact (else exit 2, nothing written).
"""

from __future__ import annotations

import _cli
from rods.paper import accuracy_cost
from rods.preflight import InputError, distinct
from rods.study.runs import parse_run, read_run


def main(argv: list[str] | None = None) -> int:
    prefix = (
        "file prefix: writes OUT.json, OUT.md, OUT.png (default: output/accuracy-cost/<scene folder>/accuracy-cost)"
    )
    ap = _cli.parser(__doc__, out_help=prefix)
    ap.add_argument("--run", action="append", default=[], help="LABEL=DIR of a run with summary.json, history.csv")
    args = ap.parse_args(argv)
    scene = _cli.load(args)
    if args.out is None:  # one per scene: another scene's study does not overwrite the paper's tables
        args.out = str(_cli.scene_default(args, "accuracy-cost", scene) / "accuracy-cost")
    out = _cli.output_file(args.out, "--out")  # --out is a prefix: OUT.json, OUT.md, OUT.png
    for suffix in accuracy_cost.SUFFIXES:
        _cli.output_file(out.with_suffix(suffix), "--out")
    if not args.run:
        raise InputError("--run", [], "no runs given", "give at least one --run LABEL=DIR")
    given = [parse_run(spec, "--run") for spec in args.run]
    distinct([folder for _, folder in given], "--run")
    distinct([label or folder.name for label, folder in given], "--run label")  # two rows one cannot tell apart
    # each a finished run: its first contact ended (an FE run stopped before it reads a peak force still rising)
    runs = [read_run(folder, label or folder.name, "--run", scene=scene, whole_contact=True) for label, folder in given]
    data = accuracy_cost.write(scene, runs, args.out)
    print("\n".join(accuracy_cost.render_table(data)))
    return 0


if __name__ == "__main__":
    _cli.entry(main)
