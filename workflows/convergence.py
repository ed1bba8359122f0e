"""Mesh convergence of the contact: submodel levels and global meshes against Hertz at their own force and the
analytical force, least-squares order, extrapolation and band (rods.paper.convergence).

    python workflows/convergence.py --run output/paper/submodel/fine [--run DIR ...] \
        [--scene workflows/scenes/paper.toml] [--out output/paper/convergence]

Each --run is a folder with summary.json (a submodel level or a global mesh). Writes convergence.json, .md and
.png into --out (the main job passes --out results). The analytical reference force is computed here.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import _cli
from rods import hertz
from rods.analytical import simulate
from rods.paper import convergence
from rods.paper.data import parse_run


def main(argv: list[str] | None = None) -> int:
    ap = _cli.parser(__doc__.splitlines()[0])
    ap.add_argument("--run", action="append", default=[], help="[LABEL=]DIR of a run with summary.json")
    ap.set_defaults(out="output/paper/convergence")
    args = ap.parse_args(argv)
    out = _cli.output_dir(Path(args.out), "--out")
    scene = _cli.load(args)
    records = []
    for label, folder in map(parse_run, args.run):
        f = folder / "summary.json"
        if not f.is_file():
            print(f"skipping {folder}: no summary.json", file=sys.stderr)
            continue
        records.append(convergence.record(json.loads(f.read_text(encoding="utf-8")), label))
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    F_an = simulate(scene).summary["peak_contact_force"]
    data = convergence.write(records, F_an, E_star, R_star, out)
    print(convergence.render_markdown(data))
    return 0


if __name__ == "__main__":
    sys.exit(_cli.guarded(main)())
