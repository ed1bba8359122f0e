"""Verification matrix: the global FE model at default settings against the analytical model (rods.study.verification).

    mpirun -n 2 python workflows/verify.py                     # every case -> output/verify/<scene>
    mpirun -n 2 python workflows/verify.py --tables results    # the committed record (make verify)
    python workflows/verify.py --case speed-1.0 --set fe.axial_size=2e-3 --out DIR

Runs each case's analytical/ and global/ models under DIR/<case>/ and writes verification.json (the data) and
verification.md (rendered from it) into --tables (default DIR). Default DIR: output/verify/<scene>.
"""

from __future__ import annotations

from collections.abc import Sequence

import rods.fe  # noqa: F401  (loads the wheel's dolfinx_solver first where installed)

# isort: split
from mpi4py import MPI

import _cli
from rods.preflight import distinct
from rods.study import verification


def main(argv: Sequence[str] | None = None) -> int:
    comm = MPI.COMM_WORLD
    ap = _cli.parser(__doc__, dry_run=True)
    ap.add_argument("--case", action="append", choices=list(verification.CASES), help="case (repeatable; default all)")
    ap.add_argument("--tables", default=None, help="folder for verification.json/.md (default: the output folder)")
    args = ap.parse_args(argv)
    base = _cli.load(args)
    out = _cli.out_dir(args, "verify", base)
    if args.tables is not None:
        _cli.output_dir(args.tables, "--tables")
    log, progress = _cli.rank0(comm)
    cases = args.case or list(verification.CASES)
    distinct(cases, "--case")  # a case given twice would run twice into its one folder
    costs = [
        c
        for name in cases
        for c in verification.case_costs(base, name, args.overrides, comm.size, args.force, comm, cases)
    ]
    for name in cases:
        _cli.backend(verification.case_scene(base, name, args.overrides), comm.size)
    log(f"plan: verification matrix, {len(cases)} case(s) of scene '{base.name}' ({', '.join(cases)}) -> {out}")
    _cli.afford(args, *costs, log=log, comm=comm, out=out)  # every case's runs, before the first is started
    data = verification.run_matrix(base, out, comm, cases, args.overrides, log, progress, args.tables)
    if comm.rank == 0:
        log(verification.render_markdown(data))
    return 0


if __name__ == "__main__":
    _cli.entry(main)
