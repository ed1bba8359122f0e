r"""REPORT.md: every table and figure of the paper job, with what agrees and what does not (rods.paper.report).

    python workflows/report.py [--results DIR] [--out output/paper/REPORT.md] \
        [--contact-study results/contact-study.json]

Reads table2.json, table3.json, fig4.json and accuracy-cost.json from --results (default: the folder of
--out) and the contact study's record; the main job passes --out results/REPORT.md.
"""

from __future__ import annotations

from pathlib import Path

import _cli
from rods import io
from rods.paper import report

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__)
    ap.add_argument("--results", default=None, help="folder of the stage JSON files (default: the folder of --out)")
    ap.add_argument("--out", default="output/paper/REPORT.md")
    ap.add_argument("--contact-study", default=str(ROOT / "results" / "contact-study.json"))
    args = ap.parse_args(argv)
    out = _cli.output_file(args.out, "--out")
    data = report.read(Path(args.results) if args.results else out.parent, Path(args.contact_study))
    io.atomic_write_text(out, report.render(data))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    _cli.entry(main)
