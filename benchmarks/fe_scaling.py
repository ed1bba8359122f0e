"""Parallel scaling of the 3D global FE model (issue #4): DOF-steps/s and parallel efficiency per rank count.

    python benchmarks/fe_scaling.py --ranks 2 [--steps 300] [--out results/fe-scaling.md]
    python benchmarks/fe_scaling.py --ranks 64 --no-paper-estimate     # on a bigger machine

For each rank count p in 1, 2, 4, ..., N (and N itself) the script runs itself under
``mpirun -n p`` (worker mode) on two 3D meshes of the paper's rods, shortened to keep the setup short
(the time step and the per-DOF cost of a step do not depend on the rod length):

* ``coarse``: the coarse scene (paper-3d-coarse.toml: 1 mm mean edge across, 4 mm along), full rods;
* ``paper-section``: the paper's resolution (0.25 mm across, 1.0 mm along), rods 30 + 40 mm.

Each worker times ``--steps`` steps of :meth:`rods.fe.model.ExplicitModel.run` (best of 2; loop wall
time, max over ranks) and reports DOFs, DOF-steps/s, the stable step, the setup time and the peak
resident memory per rank (``ru_maxrss``). Parallel efficiency E_p = r_p / (p r_1), r the DOF-steps/s.

From the paper-section numbers the script estimates the paper-resolution run (scene
``workflows/scenes/paper-3d.toml``: full-length rods, 1.5 ms): DOFs from the O-grid counts, steps
from the measured stable step, wall time = DOFs x steps / r_p for each measured p (and for larger p
assuming the largest measured efficiency persists — labelled as an extrapolation), and memory from
the measured bytes per DOF (sum over ranks of the peak RSS less the per-rank base, divided by DOFs).
Writes the table to ``--out`` (markdown).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "workflows"))  # _cli: the entry points' one error path
import _cli  # noqa: E402

PAPER = ROOT / "workflows" / "scenes" / "paper.toml"
MESHES = {  # name: overrides of the paper scene (fe.kind = 3d)
    "coarse": ["fe.axial_size=4e-3", "fe.tip_grading=0.25", "fe.radial_size=1e-3"],
    "paper-section": ["fe.axial_size=1e-3", "fe.radial_size=0.25e-3", "rod1.length=0.03", "rod2.length=0.04"],
}


def worker(mesh: str, steps: int) -> None:
    """Run under mpirun: time ``steps`` explicit steps; rank 0 prints one JSON line."""
    import resource

    import rods.fe  # noqa: F401  (dolfinx_solver first)

    # isort: split
    from mpi4py import MPI

    from rods.fe.model import ExplicitModel
    from rods.scene import load_scene

    comm = MPI.COMM_WORLD
    over = ["fe.kind='3d'", *MESHES[mesh], "simulation.output_interval=1e-3"]
    t0 = time.perf_counter()
    model = ExplicitModel(load_scene(PAPER, over), comm)
    setup = comm.allreduce(time.perf_counter() - t0, op=MPI.MAX)
    end = steps * model.dt
    model.scene = load_scene(PAPER, [*over[:-1], f"simulation.end_time={end}", f"simulation.output_interval={end}"])
    model.steps = steps
    best = math.inf
    for _ in range(2):
        r = model.run()
        best = min(best, r.summary["wall_time"])
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0  # [B] (Linux: kB)
    rss_all = comm.gather(rss, root=0)
    if comm.rank == 0:
        out = {
            "mesh": mesh,
            "ranks": comm.size,
            "dofs": model.n_global,
            "cells": model.rm.mesh.topology.index_map(3).size_global,
            "steps": steps,
            "wall_time": best,
            "dof_steps_per_second": model.n_global * steps / best,
            "dt": model.dt,
            "setup_time": setup,
            "rss_per_rank": rss_all,
        }
        print("RESULT " + json.dumps(out), flush=True)


def run_worker(ranks: int, mesh: str, steps: int) -> dict:
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", mesh, "--steps", str(steps)]
    mpirun = Path(sys.executable).parent / "mpirun"  # the mpich wheel's, beside the interpreter; else PATH's
    mpirun = mpirun if mpirun.exists() else Path(shutil.which("mpirun") or "mpirun")
    cmd = [str(mpirun), "-n", str(ranks), *cmd]
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{p.stderr[-3000:]}")
    line = next(x for x in p.stdout.splitlines() if x.startswith("RESULT "))
    return json.loads(line[len("RESULT ") :])


def paper_size() -> tuple[int, int]:
    """(hexahedra, DOFs) of workflows/scenes/paper-3d.toml from the O-grid counts (no meshing): the plan's own
    count (rods.cost.fe_cost, exact against built meshes: tests/test_cost.py)."""
    import rods.fe  # noqa: F401

    # isort: split
    from rods.cost import fe_cost
    from rods.scene import load_scene

    c = fe_cost(load_scene(ROOT / "workflows" / "scenes" / "paper-3d.toml"))
    return int(c.cells), int(c.dofs)


def paper_estimate(rows: list[dict]) -> list[str]:
    """The paper-resolution 3D model's cost from the paper-section rows (one per rank count): steps, memory and
    wall time, measured rank counts as measured, more extrapolated at the largest count's efficiency."""
    cells, dofs = paper_size()
    sc_end = 1.5e-3
    dt = rows[0]["dt"]
    steps = math.ceil(sc_end / dt)
    # memory: bytes per DOF from the run with the most DOFs per rank (base: a rank's RSS at import)
    base_rss = 125 * 2**20  # [B] python + dolfinx + petsc + gmsh per rank after import (measured 123 MiB)
    r1 = rows[0]
    bpd = (sum(r1["rss_per_rank"]) - base_rss * r1["ranks"]) / r1["dofs"]
    lines = [
        "",
        "## Estimate: paper-resolution 3D model (`workflows/scenes/paper-3d.toml`)",
        "",
        f"{cells:,} hexahedra, {dofs:,} DOFs; stable step {dt:.3g} s (measured at the paper section) -> "
        f"{steps:,} steps for 1.5 ms, i.e. {dofs * steps:.3g} DOF-steps. Memory ~{bpd:.0f} B/DOF measured "
        f"-> ~{bpd * dofs / 2**30:.1f} GiB in total plus ~{base_rss / 2**20:.0f} MiB per rank (rank 0 also "
        "holds the gmsh model while meshing).",
        "",
        "| ranks | basis | M DOF-steps/s | wall time | memory per rank |",
        "|---:|---|---:|---:|---:|",
    ]
    e_last = rows[-1]["dof_steps_per_second"] / (rows[-1]["ranks"] * rows[0]["dof_steps_per_second"])
    for p in sorted({*(r["ranks"] for r in rows), 8, 16, 32, 64}):
        meas = next((r for r in rows if r["ranks"] == p), None)
        if meas is not None:
            rate, basis = meas["dof_steps_per_second"], "measured"
        else:
            rate, basis = rows[0]["dof_steps_per_second"] * p * e_last, f"extrapolated (E = {e_last:.0%})"
        wall = dofs * steps / rate
        mem = bpd * dofs / p + base_rss
        lines.append(f"| {p} | {basis} | {rate / 1e6:.1f} | {wall / 3600:.1f} h | {mem / 2**30:.1f} GiB |")
    return lines


def main() -> int:
    ap = _cli.bare_parser(__doc__.splitlines()[0])
    ap.add_argument("--ranks", type=int, default=2, help="largest rank count N (runs 1, 2, 4, ..., N)")
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--meshes", nargs="+", default=list(MESHES), choices=list(MESHES))
    ap.add_argument("--no-paper-estimate", action="store_true")
    ap.add_argument("--out", default=str(ROOT / "results" / "fe-scaling.md"))
    ap.add_argument("--worker", choices=list(MESHES), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args.worker, args.steps)
        return 0
    counts = sorted({*(2**k for k in range(int(math.log2(args.ranks)) + 1)), args.ranks})
    results: dict[str, list[dict]] = {}
    for mesh in args.meshes:
        for p in counts:
            r = run_worker(p, mesh, args.steps)
            results.setdefault(mesh, []).append(r)
            base = results[mesh][0]["dof_steps_per_second"]
            eff = r["dof_steps_per_second"] / (p * base)
            print(
                f"{mesh:14s} p={p:3d}: {r['dofs']} DOFs, {r['wall_time'] / r['steps'] * 1e3:.2f} ms/step, "
                f"{r['dof_steps_per_second'] / 1e6:.2f} M DOF-steps/s, efficiency {eff:.0%}, "
                f"setup {r['setup_time']:.1f} s, peak RSS/rank {max(r['rss_per_rank']) / 2**20:.0f} MiB",
                flush=True,
            )
    lines = [
        "# Parallel scaling of the 3D global FE model (issue #4)",
        "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores visible "
        f"(shared with other work: timings are indicative); `benchmarks/fe_scaling.py --ranks {args.ranks}`, "
        f"{args.steps} steps, best of 2, loop wall time (max over ranks). Efficiency E_p = r_p / (p r_1).",
        "",
        "| mesh | ranks | DOFs | ms/step | M DOF-steps/s | per rank | efficiency | setup [s] | peak RSS/rank [MiB] |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for mesh, rows in results.items():
        r1 = rows[0]["dof_steps_per_second"]
        for r in rows:
            rate, p = r["dof_steps_per_second"], r["ranks"]
            lines.append(
                f"| {mesh} | {p} | {r['dofs']} | {r['wall_time'] / r['steps'] * 1e3:.2f} | {rate / 1e6:.2f} | "
                f"{rate / p / 1e6:.2f} | {rate / (p * r1):.0%} | {r['setup_time']:.1f} | "
                f"{max(r['rss_per_rank']) / 2**20:.0f} |"
            )
    if not args.no_paper_estimate and "paper-section" in results:
        lines += paper_estimate(results["paper-section"])
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    _cli.tool(main)
