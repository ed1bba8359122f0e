r"""Fig. 4 with both models: Rod-2 midpoint speed, strain and contact force, FE over analytical (rods.study.fig4).

    python workflows/fig4.py --analytical output/paper/analytical/trial-1-3 --fe output/paper/global-paper \
        [--fe LABEL=DIR ...] [--png output/paper/fig4.png] [--md output/paper/fig4.md]

Reads each run's history.csv and summary.json (an FE run of another impact than the analytical run's is
refused); writes the figure, the agreement table (markdown) and its data (fig4.json next to --md). The main job
passes --png results/fig4.png --md results/fig4.md.
"""

from __future__ import annotations

from pathlib import Path

import _cli
from rods.preflight import distinct
from rods.scene import scene_from_summary
from rods.study import fig4
from rods.study.runs import parse_run, read_run


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__)
    ap.add_argument("--analytical", required=True, help="the analytical run's folder")
    ap.add_argument("--fe", action="append", required=True, help="FE run folder, or LABEL=FOLDER (repeatable)")
    ap.add_argument("--png", default="output/paper/fig4.png", help="the figure (default %(default)s)")
    ap.add_argument("--md", default="output/paper/fig4.md", help="the table of its numbers (default %(default)s)")
    args = ap.parse_args(argv)
    for flag, f in (("--png", args.png), ("--md", args.md)):
        _cli.output_file(f, flag)  # before any run is read: a refused call writes nothing
    _cli.figure_file(args.png, "--png")
    _cli.output_file(Path(args.md).with_suffix(".json"), "--md")  # the data beside the table (rods.study.fig4.write)
    analytical = read_run(args.analytical, "analytical", "--analytical", ("analytical",))
    scene = scene_from_summary(analytical.summary["scene_values"])  # the FE runs must be of the same impact
    # fig4.py has no --scene/--set: the scene is the --analytical run's
    remedy = "give an FE run of the --analytical run's scene, or an --analytical run of that FE run's scene"
    # Fig. 4 is the Rod-2 midpoint over the whole run: a global's, not a submodel's (its "midpoint" is the cut
    # region's) nor a driver's (it stops after the contact phase, before most plateaus)
    given = [parse_run(spec, "--fe") for spec in args.fe]
    distinct([folder for _, folder in given], "--fe")  # a run given twice is two identical rows
    fe = [read_run(folder, label, "--fe", ("global",), scene, remedy) for label, folder in given]
    for (_, folder), run in zip(given, fe, strict=True):
        fig4.check_whole_run(run, scene, folder, "--fe")
    data = fig4.write(analytical, fe, args.png, args.md)
    print(fig4.render_md(data, args.png))
    return 0


if __name__ == "__main__":
    _cli.entry(main)
