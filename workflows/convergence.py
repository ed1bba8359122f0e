r"""Mesh convergence of the contact: submodel levels and global meshes against Hertz at their own force and the
analytical force, least-squares order, extrapolation and band (rods.paper.convergence).

    python workflows/convergence.py --run output/paper/submodel/fine [--run DIR ...] \
        [--scene workflows/scenes/paper.toml] [--out output/convergence/paper]

Each --run is a folder with summary.json (a submodel level or a global mesh of the scene's bodies and impact;
anything else is refused, exit 2, nothing written). Writes convergence.json, .md and
.png into --out (the main job passes --out results); the recipe is rods.paper.convergence.for_scene.
"""

from __future__ import annotations

import _cli
from rods.paper import convergence
from rods.preflight import InputError, distinct, output_names
from rods.study.runs import parse_run, read_summary


def main(argv: list[str] | None = None) -> int:
    ap = _cli.parser(__doc__)
    ap.add_argument("--run", action="append", default=[], help="[LABEL=]DIR of a run with summary.json")
    args = ap.parse_args(argv)
    scene = _cli.load(args)
    out = _cli.output_dir(
        args.out if args.out is not None else _cli.scene_default(args, "convergence", scene), "--out"
    )  # one per scene
    output_names(out, convergence.FILES)
    if not args.run:
        raise InputError("--run", [], "no runs given", "give --run DIR of a submodel level or a global mesh")
    given = [parse_run(spec, "--run") for spec in args.run]
    distinct([folder for _, folder in given], "--run")  # a run given twice is a level counted twice
    runs = [(label, read_summary(folder, "--run", scene=scene, whole_contact=True)) for label, folder in given]
    convergence.one_run_per_size(runs, [folder for _, folder in given])  # the fit's abscissae
    convergence.one_driver(runs, [folder for _, folder in given])  # one refinement, not two drivers'
    data = convergence.for_scene(scene, runs, out)
    print(convergence.render_markdown(data))
    return 0


if __name__ == "__main__":
    _cli.entry(main)
