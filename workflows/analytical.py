"""The paper's analytical model (Section 2.1) on one scene.

    python workflows/analytical.py --scene workflows/scenes/paper.toml --set impact.speed=1.848 --out DIR

Writes DIR/history.csv and DIR/summary.json (rods.study.stages.analytical); prints the plan first and the
summary last. Default DIR: output/analytical/<scene>. Under mpirun every rank computes it (milliseconds); rank 0
prints and writes.
"""

from __future__ import annotations

import json
from collections.abc import Sequence

from mpi4py import MPI

import _cli
from rods import cost, io
from rods.study import stages


def main(argv: Sequence[str] | None = None) -> int:
    comm = MPI.COMM_WORLD
    args = _cli.parser(__doc__, dry_run=True).parse_args(argv)
    scene = _cli.load(args)
    out = _cli.out_dir(args, "analytical", scene)
    log, _ = _cli.rank0(comm)
    log(
        f"plan: analytical model (1D waves + Hertz, contact law '{scene['analytical.contact']}'), scene "
        f"'{scene.label}', s1 = {scene.speed} m/s, "
        f"t_end = {scene.end_time:g} s every {scene.output_interval:g} s, rtol = {scene['analytical.rtol']:g}; "
        f"stations: {', '.join(s.name for s in scene.stations)} -> {out}"
    )
    _cli.outlook(scene, log)
    _cli.afford(args, cost.analytical_cost(scene), log=log, comm=comm, out=out)
    s = stages.analytical(scene, out, comm).summary
    log(json.dumps({k: s[k] for k in [*io.SUMMARY_KEYS[2:], "rigid_velocity_rod1", "rigid_velocity_rod2"]}, indent=1))
    _cli.status(s, comm.rank)
    return 0


if __name__ == "__main__":
    _cli.entry(main)
