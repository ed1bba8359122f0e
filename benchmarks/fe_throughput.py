"""Throughput of the explicit time step of the global model (issue #3): DOF-steps/s and bandwidth fraction.

    python benchmarks/fe_throughput.py [--steps 400] [--no-paper] [--out results/fe-throughput.md]

For meshes from the paper's (~52k DOFs) up to ~400k DOFs, runs ``--steps`` steps of
:meth:`rods.fe.model.ExplicitModel.run` and reports DOF-steps/s and the memory traffic of one step
(matrix values + column indices + row pointers of the plain AIJ form, and the vectors: the multiply-add
reads u, v and writes v, the update reads u, v and writes u: 48 B/DOF) divided by the step time,
as a fraction of a STREAM-like bandwidth measured in the same run with numpy (the 'Add' kernel
a = b + c on 3 x 160 MB arrays, 24 B per element). Matrices that fit in the last-level cache can
exceed 100%. Then times the full paper run (1.5 ms at the paper mesh, one process).
"""

from __future__ import annotations

import platform
import sys
import time
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "workflows"))  # _cli: the entry points' one error path
import _cli  # noqa: E402
from rods.fe.model import ExplicitModel  # noqa: E402
from rods.scene import load_scene  # noqa: E402

PAPER = ROOT / "workflows" / "scenes" / "paper.toml"
MESHES = [  # (axial, radial) element sizes [m]
    (1.0e-3, 0.25e-3),
    (0.5e-3, 0.25e-3),
    (0.5e-3, 0.125e-3),
    (0.25e-3, 0.125e-3),
]


def stream_add(n: int = 20_000_000, reps: int = 5) -> float:
    """Best-of-``reps`` bandwidth [B/s] of a = b + c (STREAM 'Add', 24 B/element counted)."""
    a, b, c = np.zeros(n), np.random.default_rng(0).random(n), np.random.default_rng(1).random(n)
    best = np.inf
    for _ in range(reps):
        t = time.perf_counter()
        np.add(b, c, out=a)
        best = min(best, time.perf_counter() - t)
    return 24.0 * n / best


def step_bytes(model: ExplicitModel) -> float:
    """Memory traffic of one time step [B] (see module docstring)."""
    nz = model.K.getInfo()["nz_used"]  # the time loop's plain AIJ form (rods.fe.backend.plain_aij): one index each
    return nz * (8 + 4) + (model.n_local + 1) * 4 + 48 * model.n_local


def mesh_rows(steps: int, bw: float) -> list[tuple]:
    """Per mesh of MESHES: (h_z, h_r, DOFs, best s/step of 3 runs of ``steps``, DOF-steps/s, traffic [B/s],
    fraction of the bandwidth ``bw`` [B/s])."""
    rows = []
    for h_z, h_r in MESHES:
        sc = load_scene(PAPER, [f"fe.axial_size={h_z}", f"fe.radial_size={h_r}", "simulation.output_interval=1e-3"])
        model = ExplicitModel(sc)
        end = steps * model.dt
        sc = load_scene(PAPER, [f"fe.axial_size={h_z}", f"fe.radial_size={h_r}", f"simulation.end_time={end}",
                                f"simulation.output_interval={end / 4}"])  # fmt: skip
        model = ExplicitModel(sc)
        best = np.inf
        for _ in range(3):
            r = model.run()
            best = min(best, r.summary["wall_time"] / r.summary["steps"])
        traffic = step_bytes(model) / best
        rows.append((h_z, h_r, model.n_global, best, model.n_global / best, traffic, traffic / bw))
        msg = f"h_z={h_z * 1e3:g} mm h_r={h_r * 1e3:g} mm: {model.n_global} DOFs, {best * 1e3:.3f} ms/step, "
        msg += f"{model.n_global / best / 1e6:.1f} M DOF-steps/s, {traffic / 1e9:.1f} GB/s = {traffic / bw:.0%}"
        print(msg, flush=True)
    return rows


def main() -> int:
    ap = _cli.bare_parser(__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=400)
    ap.add_argument("--no-paper", action="store_true", help="skip the full 1.5 ms paper run")
    ap.add_argument("--out", default=str(ROOT / "results" / "fe-throughput.md"))
    args = ap.parse_args()
    bw = stream_add()
    print(f"STREAM-like add bandwidth: {bw / 1e9:.1f} GB/s", flush=True)
    rows = mesh_rows(args.steps, bw)
    paper = None
    if not args.no_paper:
        model = ExplicitModel(load_scene(PAPER))
        r = model.run()
        paper = (model.n_global, r.summary["steps"], r.summary["wall_time"], model.setup_time)
        print(f"paper run: {paper[0]} DOFs, {paper[1]} steps, loop {paper[2]:.1f} s, setup {paper[3]:.1f} s")
    lines = [
        "# Throughput of the global FE time step (issue #3)",
        "",
        f"Machine: {platform.processor() or platform.machine()}, one process; `benchmarks/fe_throughput.py`, "
        f"{args.steps} steps per mesh, best of 3. Bandwidth bound: numpy STREAM-like add a = b + c "
        f"(3 x 160 MB) = **{bw / 1e9:.1f} GB/s** measured in the same run.",
        "",
        "Per step: one AIJ multiply-add `v += A u` (PETSc's plain loop, rods.fe.backend.plain_aij) with "
        "A = -dt M^-1 K, the contact impulse on the tip entries, `u += dt v`. Traffic = matrix values + column "
        "indices + row pointers + vectors (48 B/DOF). The meshes are coarsened across away from the tips where "
        "three elements fit the bar's size, min(axial size, R/8) (fe.radial_coarsening 'auto'): all but the 0.5 x "
        "0.25 mm mesh.",
        "",
        "| axial [mm] | radial [mm] | DOFs | ms/step | M DOF-steps/s | GB/s | fraction of bound |",
        "|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for h_z, h_r, n, t, rate, traffic, frac in rows:
        cells = [f"{h_z * 1e3:g}", f"{h_r * 1e3:g}", str(n), f"{t * 1e3:.3f}", f"{rate / 1e6:.1f}"]
        lines.append("| " + " | ".join([*cells, f"{traffic / 1e9:.1f}", f"{frac:.0%}"]) + " |")
    if paper:
        lines += [
            "",
            f"Paper scene (1.5 ms, its default mesh: the sizes auto, merged 3:1 across away from the tips): "
            f"{paper[0]} DOFs, {paper[1]} steps, time loop "
            f"**{paper[2]:.1f} s** (setup incl. mesh, assembly, eigenvalue: {paper[3]:.1f} s).",
        ]
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    _cli.tool(main)
