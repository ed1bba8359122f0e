r"""What accuracy costs in time: every model and resolution against its reference, with the Pareto front
(rods.paper.accuracy_cost).

    python workflows/accuracy_cost.py --run "global 1.0 mm=output/paper/global" [--run LABEL=DIR ...] \
        [--scene workflows/scenes/paper.toml] [--out output/paper/accuracy-cost]

Writes --out + .json, .md, .png (the main job passes --out results/accuracy-cost). Runs without a
summary.json are skipped with a note.
"""

from __future__ import annotations

import sys

import _cli
from rods.paper import accuracy_cost
from rods.paper.data import parse_run, read_run


def main(argv: list[str] | None = None) -> int:
    ap = _cli.parser(__doc__)
    ap.add_argument("--run", action="append", default=[], help="LABEL=DIR of a run with summary.json, history.csv")
    ap.set_defaults(out="output/paper/accuracy-cost")
    args = ap.parse_args(argv)
    _cli.output_file(args.out, "--out")  # --out is a prefix: OUT.json, OUT.md, OUT.png
    scene = _cli.load(args)
    runs = []
    for label, folder in map(parse_run, args.run):
        if not (folder / "summary.json").is_file():
            print(f"skipping {label}={folder}: no summary.json", file=sys.stderr)
            continue
        runs.append(read_run(folder, label or folder.name))
    data = accuracy_cost.write(scene, runs, args.out)
    print("\n".join(accuracy_cost.render_table(data)))
    return 0


if __name__ == "__main__":
    sys.exit(_cli.guarded(main)())
