r"""REPORT.md: every table and figure of the paper job, with what agrees and what does not (rods.paper.report).

    python workflows/report.py [--results DIR] [--out output/paper/REPORT.md] \
        [--contact-study results/contact-study.json]

Reads table2.json, table3.json, fig4.json and accuracy-cost.json from --results (default: the folder of
--out), with contact-fields, verification, convergence, driver-study and edge-scatter JSON there where present
(rods.paper.report.OPTIONAL_SOURCES), and the contact study's record; the main job passes --out results/REPORT.md.
"""

from __future__ import annotations

from pathlib import Path

import _cli
from rods import io
from rods.paper import report
from rods.preflight import InputError

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_STUDY = ROOT / "results" / f"{report.CONTACT_STUDY}.json"  # benchmarks/contact_study.py's record


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__)
    ap.add_argument("--results", default=None, help="folder of the stage JSON files (default: the folder of --out)")
    ap.add_argument("--out", default="output/paper/REPORT.md")
    ap.add_argument("--contact-study", default=None, help=f"the contact study's record (default {DEFAULT_STUDY})")
    args = ap.parse_args(argv)
    out = _cli.output_file(args.out, "--out")
    study = Path(args.contact_study) if args.contact_study is not None else DEFAULT_STUDY
    if args.contact_study is not None and not study.is_file():  # the default may be absent; one asked for may not
        raise InputError("--contact-study", study, "no such file", "give the contact study's JSON, or leave it out")
    if args.results == "":  # given empty: not the default (out's folder), which it silently became
        raise InputError("--results", "", "is empty", "give the folder of the stage JSON files, or leave it out")
    results = Path(args.results) if args.results else out.parent
    data = report.read(results, study if study.is_file() else None)
    failed = (KeyError, TypeError, AttributeError, IndexError, ValueError, StopIteration)
    try:  # a stage file that parses but is not its stage's data fails in the rendering
        text = report.render(data)
    except failed as e:
        why = f"({type(e).__name__}: {e})"
        try:  # the stages render without the contact study: it is the file at fault (an accuracy_cost.py JSON given
            report.render(report.read(results, None))  # as --contact-study was blamed on --results, a fuzz found)
        except failed:
            raise InputError(
                "--results",
                results,
                f"a stage file is not that stage's data {why}",
                "rerun the main job's stages (make paper)",
            ) from None
        hint = "give benchmarks/contact_study.py's record (results/contact-study.json), or leave it out"
        raise InputError("--contact-study", study, f"not the contact study's record {why}", hint) from None
    io.atomic_write_text(out, text)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    _cli.entry(main)
