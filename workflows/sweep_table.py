r"""A sweep's table (the Snakefile's ``sweep_table`` rule): one row per point, the record's row for a key it holds,
else the point's run summary.

    python workflows/sweep_table.py --out output/sweep/sweep-speed.csv \
        --points '[["output/sweep/.../summary.json", "speed=1.0"], ...]' --record results/sweep-speed.csv

A shell rule, not Snakemake's ``run:``, whose job Snakemake starts through an unquoted interpreter path (a clone
under a folder with a space failed: snakemake#3211).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import _cli
from rods.preflight import InputError
from rods.study.sweep import read_record, write_sweep_table


def _points(text: str) -> list[tuple[str, str]]:
    """--points: a JSON list of [summary path, key] pairs."""
    try:
        points = json.loads(text)
        if not isinstance(points, list) or not all(
            isinstance(p, list) and len(p) == 2 and all(isinstance(x, str) for x in p) for p in points
        ):
            raise ValueError("not a list of [path, key] pairs")
    except ValueError as e:
        raise InputError("--points", text, f"is not a JSON list of [summary path, key] pairs ({e})") from None
    return [(p, k) for p, k in points]


def main(argv: Sequence[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__)
    ap.add_argument("--out", required=True, help="the table (CSV) to write")
    ap.add_argument("--points", required=True, help="JSON list of [summary path, key] pairs, in the table's order")
    ap.add_argument("--record", required=True, help="the published table whose rows stand for keys it holds")
    args = ap.parse_args(argv)
    points, out = _points(args.points), _cli.output_file(args.out)
    record = read_record(args.record)
    for path, key in points:
        if key not in record and not Path(path).is_file():  # a point's run that did not write its summary
            raise InputError("--points", path, f"point {key!r} has no summary there", "run the sweep's runs first")
    write_sweep_table(out, points, record)
    return 0


if __name__ == "__main__":
    _cli.entry(main)
