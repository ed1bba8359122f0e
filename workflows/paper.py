"""The main job's first stage: the analytical model on the six Table-2 trials, Table 2 and Fig. 4's
analytical curves (rods.paper.table2).

    python workflows/paper.py [--out output/paper] [--results output/paper]

Runs leave history.csv and summary.json under --out/analytical/<trial>; table2.{json,csv,md,png} and
fig4-analytical.png go to --results (the main job passes --results results).
"""

from __future__ import annotations

from pathlib import Path

import _cli
from rods.paper import table2
from rods.preflight import output_names

SCENES = Path(__file__).resolve().parent / "scenes"


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__)
    ap.add_argument("--out", default="output/paper", help="folder for per-run histories and summaries")
    ap.add_argument("--results", default=None, help="folder for tables and figures (default: --out)")
    args = ap.parse_args(argv)
    results = args.out if args.results is None else args.results
    for flag, f in (("--out", args.out), ("--results", results)):
        _cli.output_dir(f, flag)
    output_names(results, table2.FILES, "--results")  # before the six trials run
    out, results = Path(args.out), Path(results)
    print(f"plan: analytical model on the Table-2 trials -> {out}/analytical/<trial>; tables -> {results}")
    data = table2.write(SCENES, out, results)
    for r in data["trials"]:
        print(
            f"  {r['name']}: s1 = {r['impact_speed']} m/s, F = {r['peak_contact_force']:.1f} N, "
            f"a = {r['radius'] * 1e3:.4f} mm"
        )
    print(f"wrote {results}/table2.{{json,csv,md,png}}, {results}/fig4-analytical.png")
    return 0


if __name__ == "__main__":
    _cli.entry(main)
