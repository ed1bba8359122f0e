"""Throughput of the explicit time loop on an array backend (issue 16): full step and SpMV against the copy rate.

    python benchmarks/gpu_throughput.py                      # CuPy on a GPU: coarse, medium, paper meshes
    python benchmarks/gpu_throughput.py --backend numpy --meshes tiny --steps 20 --run tiny --compare tiny \\
        --end-time 2e-5 --out /tmp/gpu.md --run-out /tmp/gpu-run        # the same script on the CPU (a check)

For each 3D mesh (``--meshes``: ``coarse`` = paper-3d-coarse.toml, ``medium`` = 2 x 0.5 mm, ``paper`` =
paper-3d.toml, ``tiny`` = a quarter model of 30 mm rods at 4 x 1 mm, for checks) the model is set up on
``--backend`` and ``--steps`` steps are timed twice after a warm-up:

* the full step, :meth:`rods.fe.explicit.CentralDifference.step` (drift, contact, multiply-add, impulse);
* the SpMV alone, the operator's ``mult_add`` (v += A u, A = -Δt M^-1 K in CSR);
* where the backend overlaps the kinematic contact's host work with the product (CuPy: rods.fe.kinematic,
  "Overlap"), the full step again on a stepper without the overlap, on the same model: the A/B of that change;
* on the array backends, the same product element by element (rods.fe.matrixfree, ``fe.operator =
  "matrix-free"``: per-cell geometry at the Gauss points, no assembled matrix), against the SpMV: the issue's
  "keep the faster" (``--set fe.operator=matrix-free`` runs the steps and the end-to-end run with it).

Rates are DOF-steps/s; the SpMV's memory traffic (CSR values 8 B and column indices 4 B per nonzero, row
pointers 4 B per row, x read, y read and written: 24 B per DOF) is set against the copy rate of the same
memory measured in the same run (``y[:] = x`` on 2 x ``--copy-mib`` arrays, 16 B per element, best of 5), so
figures from different machines are compared through their own ceiling.

End to end (``--run MESH``): the scene run to its end time (``--end-time`` overrides) through the library's
global stage (set-up, stepping, history/summary output into ``--run-out``), its summary against the
analytical model (peak force, energy error). ``--compare MESH``: the same on ``--backend`` and on the PETSc
path (CPU, serial) in this process, the latter at the former's step: wall times and the largest history
difference. Writes ``--out``
(markdown; default results/gpu-throughput.md). Nothing here is measured until it is run on a GPU.
"""

from __future__ import annotations

import dataclasses
import math
import platform
import sys
import time
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import numpy as np
from mpi4py import MPI

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "workflows"))  # _cli: the entry points' one error path
import _cli  # noqa: E402
from rods.fe import backend as backends  # noqa: E402
from rods.fe import forms, matrixfree  # noqa: E402
from rods.fe.model import ExplicitModel, loop_blas  # noqa: E402
from rods.scene import Scene, load_scene  # noqa: E402

SCENES = ROOT / "workflows" / "scenes"
MESHES = {  # name: (scene file, overrides)
    "tiny": (SCENES / "paper.toml", ["fe.kind='3d'", "fe.symmetry='quarter'", "fe.axial_size=4e-3",
                                     "fe.radial_size=1e-3", "rod1.length=0.03", "rod2.length=0.03",
                                     "simulation.end_time=1e-4"]),
    "coarse": (SCENES / "paper-3d-coarse.toml", []),
    "medium": (SCENES / "paper-3d.toml", ["fe.axial_size=2e-3", "fe.radial_size=0.5e-3"]),
    "paper": (SCENES / "paper-3d.toml", []),
}  # fmt: skip


SETS: list[str] = []  # --set overrides, applied to every scene of the run


def scene(mesh: str, backend: str, *extra: str) -> Scene:
    path, over = MESHES[mesh]
    assembled = ["fe.operator='assembled'"] if backend == "petsc" else []  # the PETSc path has no element kernel
    return load_scene(path, [*over, *SETS, f"fe.backend='{backend}'", *assembled, *extra])


def copy_rate(be: backends.Backend, mib: int = 256, reps: int = 5) -> float:
    """Best-of-``reps`` rate [B/s] of y[:] = x on 2 x ``mib`` MiB arrays of ``be`` (16 B per element)."""
    n = mib * (1 << 20) // 8
    x, y = be.xp.ones(n), be.xp.zeros(n)
    best = np.inf
    for _ in range(reps):
        be.synchronize()
        t = time.perf_counter()
        y[:] = x
        be.synchronize()
        best = min(best, time.perf_counter() - t)
    del x, y
    return 16.0 * n / best


def timed(be: backends.Backend, f, steps: int, warm: int = 5) -> float:
    """Seconds per call of ``f()``, averaged over ``steps`` calls after ``warm`` calls (synchronised), on the BLAS
    threads of a run's loop (rods.fe.model.loop_blas: the host's LCP solves as a run makes them)."""
    with loop_blas():
        for _ in range(warm):
            f()
        be.synchronize()
        t = time.perf_counter()
        for _ in range(steps):
            f()
        be.synchronize()
    return (time.perf_counter() - t) / steps


def throughput(model: ExplicitModel, mesh: str, be: backends.Backend, steps: int, copy: float) -> dict:
    """Full step and SpMV of ``model`` (set up on ``be``): seconds per step, DOF-steps/s, SpMV traffic and
    its share of the copy rate ``copy`` [B/s]. A stepper of its own: the model's run starts afresh."""
    st = model.stepper()  # the stepper alone: no recorder
    n, overlap = model.n_global, st.overlap
    t_step = timed(be, st.step, steps)
    # the assembled product (the stepper's own, or built from the model's K when the scene's is the element kernel)
    spmv = st.op if not isinstance(st.op, matrixfree.ElementOperator) else be.operator(model.K, -st.dt_inv_mass, ())
    t_spmv = timed(be, lambda: spmv.mult_add(st.u, st.v), steps)
    A = spmv.A
    nnz = A.nnz if hasattr(A, "nnz") else A.getInfo()["nz_used"]
    traffic = 12.0 * nnz + 4.0 * (n + 1) + 24.0 * n  # [B] per SpMV
    t_element = math.nan  # the same product element by element (rods.fe.matrixfree), on the array backends
    if be is not backends.PETSC:  # the model's own kernel arrays where its scene asks for them
        es = model.element
        if es is None:
            form = forms.stiffness_form(model.V, model.mat, model.kind)
            es = matrixfree.element_stiffness(model.V, model.mat, model.kind, form, model.K)
        element = es.operator(be, -st.dt_inv_mass)
        t_element = timed(be, lambda: element.mult_add(st.u, st.v), steps)
        element.destroy()
    st.destroy()
    t_serial = math.nan  # the same step with the host's contact work after the product (no overlap): A/B
    if overlap:
        model.backend = dataclasses.replace(be, overlap=False)
        st = model.stepper()
        t_serial = timed(be, st.step, steps)
        st.destroy()
        model.backend = be
    row = {"mesh": mesh, "dofs": n, "nnz": int(nnz), "setup": model.setup_time, "step": t_step, "spmv": t_spmv,
           "overlap": overlap, "step_serial": t_serial, "element": t_element}  # fmt: skip
    row.update(step_rate=n / t_step, spmv_rate=n / t_spmv, spmv_bw=traffic / t_spmv, spmv_share=traffic / t_spmv / copy)
    msg = f"{mesh}: {n} DOFs, set-up {model.setup_time:.1f} s, step {t_step * 1e3:.3f} ms "
    msg += f"({n / t_step / 1e6:.1f} M DOF-steps/s), SpMV {t_spmv * 1e3:.3f} ms = {traffic / t_spmv / 1e9:.1f} GB/s "
    msg += f"= {row['spmv_share']:.0%} of copy" + (f"; without overlap step {t_serial * 1e3:.3f} ms" if overlap else "")
    msg += f"; element kernel {t_element * 1e3:.3f} ms" if t_element == t_element else ""
    print(msg, flush=True)
    return row


def end_to_end(
    mesh: str, name: str, end_time: float | None, out: Path, model: ExplicitModel | None = None, *extra: str
) -> dict:
    """The scene of ``mesh`` on backend ``name`` through the library's global stage (set-up, stepping, output);
    ``model``: that scene's model set up already (its set-up time is counted in the wall time); ``extra``: more
    scene overrides."""
    from rods.study import stages

    sc = model.scene if model is not None else scene(mesh, name, *ends(end_time), *extra)
    t = time.perf_counter()
    st = stages.global_model(sc, out / f"{mesh}-{name}", MPI.COMM_SELF, model=model, progress=progress_log(mesh))
    s = st.summary
    wall = time.perf_counter() - t + (s["setup_time"] if model is not None else 0.0)
    print(f"{mesh} on {name}: {wall:.1f} s end to end (set-up {s['setup_time']:.1f} s, loop {s['wall_time']:.1f} s), "
          f"status {s.get('status')}", flush=True)  # fmt: skip
    return {"mesh": mesh, "backend": name, "wall": wall, "summary": s, "history": st.history, "scene": sc}


def progress_log(mesh: str, every: float = 10.0):
    """A progress callback printing, about every ``every`` seconds, the steps done and the loop's rate since the
    last line (a run killed at a time limit leaves its rates in the log; contact closed or open shows in them)."""
    last = [0.0, 0]  # [elapsed s, step] of the last line

    def progress(step: int, total: int, elapsed: float, *_start) -> None:
        if elapsed - last[0] >= every or step == total:
            rate = (step - last[1]) / max(elapsed - last[0], 1e-9)
            print(f"  {mesh}: step {step}/{total}, {elapsed:.0f} s, {rate:.0f} steps/s since the last line", flush=True)
            last[:] = [elapsed, step]

    return progress


def ends(end_time: float | None) -> list[str]:
    """The scene override of ``--end-time`` (none without it)."""
    return [f"simulation.end_time={end_time}"] if end_time else []


def analytical_peak(sc: Scene) -> float:
    from rods import analytical

    return float(analytical.simulate(sc).summary["peak_contact_force"])


def report(args, be_name: str, copy: float, rows: list[dict], run: dict | None, cmp: list[dict]) -> str:
    """The markdown of ``--out``."""
    dev = "CPU (host memory)"
    if be_name == "cupy":
        import cupy

        dev = cupy.cuda.runtime.getDeviceProperties(0)["name"].decode() + f" (CuPy {cupy.__version__})"
    lines = [
        "# Explicit time loop on an array backend (issue 16)",
        "",
        f"`benchmarks/gpu_throughput.py --backend {be_name}`, {platform.node() or 'this machine'}, {dev}; "
        f"{args.steps} steps per mesh after 5 warm-up steps. Copy rate y[:] = x (2 x {args.copy_mib} MiB, "
        f"16 B/element) measured in the same run: **{copy / 1e9:.1f} GB/s**."
        + (f" Scene overrides: `{' '.join(args.set)}`." if args.set else ""),
        "",
        "| mesh | DOFs | nonzeros | set-up [s] | step [ms] | M DOF-steps/s | SpMV [ms] | SpMV M DOF-steps/s "
        "| SpMV GB/s | of copy | step without overlap [ms] | element kernel [ms] | element / SpMV |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        cells = [r["mesh"], str(r["dofs"]), str(r["nnz"]), f"{r['setup']:.1f}", f"{r['step'] * 1e3:.3f}",
                 f"{r['step_rate'] / 1e6:.1f}", f"{r['spmv'] * 1e3:.3f}", f"{r['spmv_rate'] / 1e6:.1f}",
                 f"{r['spmv_bw'] / 1e9:.1f}", f"{r['spmv_share']:.0%}",
                 f"{r['step_serial'] * 1e3:.3f}" if r["overlap"] else "- (off)",
                 *((f"{r['element'] * 1e3:.3f}", f"{r['element'] / r['spmv']:.2f}") if r["element"] == r["element"]
                   else ("-", "-"))]  # fmt: skip
        lines.append("| " + " | ".join(cells) + " |")
    if run is not None:
        s = run["summary"]
        lines += [
            "",
            f"End to end, `{run['mesh']}` to {run['scene'].end_time:g} s on {be_name}: **{run['wall']:.1f} s** "
            f"(set-up {s['setup_time']:.1f} s, loop {s['wall_time']:.1f} s, {s['dofs']} DOFs, {s['steps']} steps, "
            f"{s['dof_steps_per_second'] / 1e6:.1f} M DOF-steps/s); peak force {s['peak_contact_force']:.1f} N "
            f"({s['peak_contact_force'] / run['analytical_peak'] - 1:+.2%} against the analytical model), "
            f"energy error {s['energy_error']:.2e}.",
        ]
    if cmp:
        a, b = cmp
        diff = max(
            float(np.abs(b["history"][k] - h).max() / max(np.abs(h).max(), 1e-300))
            for k, h in a["history"].items()
            if not k.startswith("contact_centroid")
        )
        lines += [
            "",
            f"Same scene, same process, `{a['mesh']}` to {a['scene'].end_time:g} s: {a['backend']} "
            f"{a['wall']:.1f} s end to end (loop {a['summary']['wall_time']:.1f} s), {b['backend']} "
            f"{b['wall']:.1f} s (loop {b['summary']['wall_time']:.1f} s), at the former's step "
            f"({a['summary']['dt']:.6g} s; stable limits {a['summary']['dt_critical']:.6g} s and "
            f"{b['summary']['dt_critical']:.6g} s, equal within the eigenvalue's tolerance); largest history "
            f"difference {diff:.1e} of each column's largest magnitude.",
        ]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__.splitlines()[0])
    ap.add_argument("--backend", default="cupy", choices=["cupy", "numpy", "petsc"])
    ap.add_argument("--meshes", nargs="*", default=["coarse", "medium", "paper"], choices=list(MESHES))
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--run", default="paper", choices=[*MESHES, "none"], help="mesh run end to end")
    ap.add_argument("--compare", default="coarse", choices=[*MESHES, "none"], help="mesh run here and on PETSc")
    ap.add_argument("--end-time", type=float, default=None, help="end time of the end-to-end runs [s]")
    ap.add_argument("--copy-mib", type=int, default=256, help="size of each array of the copy-rate test [MiB]")
    ap.add_argument("--out", default=str(ROOT / "results" / "gpu-throughput.md"))
    ap.add_argument("--run-out", default=str(ROOT / "output" / "gpu-throughput"), help="folder of the runs' outputs")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="scene override (repeatable)")
    args = ap.parse_args(argv)
    SETS[:] = args.set
    be = backends.select(args.backend, 1)
    copy = copy_rate(be, args.copy_mib)
    print(f"copy rate ({be.name}): {copy / 1e9:.1f} GB/s", flush=True)
    rows, kept = [], None
    for m in args.meshes:  # the run's mesh is set up once: its stepper is timed, then it runs
        model = ExplicitModel(scene(m, be.name, *(ends(args.end_time) if m == args.run else [])), MPI.COMM_SELF)
        rows.append(throughput(model, m, be, args.steps, copy))
        kept = model if m == args.run else kept
        del model
    run_out = Path(args.run_out)
    run = None
    if args.run != "none":
        run = end_to_end(args.run, be.name, args.end_time, run_out, kept)
        kept = None
        run["analytical_peak"] = analytical_peak(run["scene"])
    cmp = []
    if args.compare != "none":
        # the PETSc run marches at the backend run's step: the two eigenvalue routes agree to EIGEN_TOL, not to
        # round-off (rods.fe.explicit), and the difference of the histories should be the arithmetic's alone
        cmp = [end_to_end(args.compare, be.name, args.end_time, run_out)]
        step = f"fe.dt={cmp[0]['summary']['dt']!r}"
        cmp.append(end_to_end(args.compare, "petsc", args.end_time, run_out, None, step))
    text = report(args, be.name, copy, rows, run, cmp)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(text)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    _cli.tool(main)
