"""Accuracy and speed of the analytical model's DDE solver, and a benchmark against ``ddeint``.

    .venv/bin/python benchmarks/analytical_vs_ddeint.py [--end-time 3e-4] [--out results]

Both solvers integrate the same system (rods.analytical's δ' with the delayed Hertz forces, state
(δ, I)) at the paper scene from first touch to ``--end-time`` (default 0.3 ms: the whole first
contact and the first returning waves). The reference is rods.analytical at rtol = 1e-13.
Errors: relative error of the peak contact force, and the max-norm error of the force history
on a common 0.05 µs grid, relative to the peak force. Wall times are the best of three runs
measured in this one process (the machine is shared; compare ratios, not absolute times).
Writes analytical-vs-ddeint.md and analytical-convergence.png into --out (default results/).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from ddeint import ddeint
from ddeint.ddeint import dde, ddeVar

from rods.analytical import WaveModel
from rods.scene import load_scene
from rods.study.figures import pyplot

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"
sys.path.insert(0, str(ROOT / "workflows"))

import _cli  # noqa: E402  (the entry points' one error path)


def best_of(fn, n=3):
    best, out = np.inf, None
    for _ in range(n):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def ddeint_force(model: WaveModel, end_time: float, n: int, tight: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Solve the same DDE with ddeint on ``n`` equal steps; returns (t, P).

    ``tight``: ddeint's own classes, but its inner integrator (scipy's vode, default rtol 1e-6)
    set to rtol 1e-10 so that only the linear history interpolation limits its accuracy."""
    K, s1 = model.K, model.speed
    Zs = 1 / model.Z[0] + 1 / model.Z[1]

    def rhs(Y, t):
        δ = Y(t)[0]
        d = 0.0
        for Z, T in zip(model.Z, model.T, strict=True):
            τ = t - T
            while τ > 0:
                d += 2 / Z * K * max(Y(τ)[0], 0.0) ** 1.5
                τ -= T
        P = K * max(δ, 0.0) ** 1.5
        return np.array([s1 - d - P * Zs, P])

    tt = np.linspace(0.0, end_time, n + 1)
    if not tight:
        y = ddeint(rhs, lambda t: np.zeros(2), tt)
    else:
        solver = dde(rhs)
        solver.set_integrator("vode", rtol=1e-10, atol=[1e-10 * model.delta_scale, 1e-10])
        solver.set_initial_value(ddeVar(lambda t: np.zeros(2), 0.0))
        solver.set_f_params([])
        y = np.array([np.zeros(2)] + [solver.integrate(solver.t + dt) for dt in np.diff(tt)])
    return tt, K * np.maximum(y[:, 0], 0.0) ** 1.5


def measure(scene, T_end: float) -> tuple[list[tuple], float]:
    """Rows (solver, setting, rtol or step [-, s], steps, wall [s], peak-force error, history error [-]) of both
    solvers against rods.analytical at rtol 1e-13, and that reference's peak force [N]."""

    def ours(rtol):
        return WaveModel(scene.rod1, scene.rod2, scene.speed, rtol=rtol).run(T_end)

    ref = ours(1e-13)
    grid = np.linspace(0, T_end, int(round(T_end / 0.05e-6)) + 1)
    P_ref = ref.force(grid)
    F_ref = ref.peak()[1]
    rows = []
    for rtol in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]:
        wall, m = best_of(lambda r=rtol: ours(r))
        e_peak = abs(m.peak()[1] - F_ref) / F_ref
        e_hist = np.max(np.abs(m.force(grid) - P_ref)) / F_ref
        rows.append(("rods.analytical", f"rtol={rtol:.0e}", rtol, m.steps, wall, e_peak, e_hist))
        print(rows[-1])
    for tight in (False, True):
        for n in [250, 500, 1000, 2000, 4000, 8000, 16000]:
            wall, (tt, P) = best_of(lambda n=n, tight=tight: ddeint_force(ref, T_end, n, tight), n=1 if n > 2000 else 3)
            e_peak = abs(P.max() - F_ref) / F_ref
            e_hist = np.max(np.abs(np.interp(grid, tt, P) - P_ref)) / F_ref
            rows.append(
                ("ddeint" + (" (vode rtol 1e-10)" if tight else ""), f"n={n}", T_end / n, n, wall, e_peak, e_hist)
            )
            print(rows[-1])
    return rows, F_ref


def orders(rows: list[tuple]) -> tuple[float, float, float]:
    """Observed orders: rods.analytical's history error in rtol and in its mean step (rtol 1e-11..1e-6), and
    ddeint's (as shipped) in Δt over its three finest grids."""
    ours = [r for r in rows if r[0] == "rods.analytical"]
    dde = [r for r in rows if r[0] == "ddeint"]
    rt, eh = np.array([r[2] for r in ours]), np.array([r[6] for r in ours])
    st = np.array([r[3] for r in ours], float)
    fit = (rt >= 1e-11) & (rt <= 1e-6)
    p_tol = np.polyfit(np.log(rt[fit]), np.log(eh[fit]), 1)[0]
    p_step = -np.polyfit(np.log(st[fit]), np.log(eh[fit]), 1)[0]
    p_dde = np.polyfit(np.log([r[2] for r in dde][-3:]), np.log([r[6] for r in dde][-3:]), 1)[0]
    return p_tol, p_step, p_dde


def render(rows: list[tuple], F_ref: float, T_end: float) -> list[str]:
    """analytical-vs-ddeint.md, as lines."""
    p_tol, p_step, p_dde = orders(rows)
    ours_rows = [r for r in rows if r[0] == "rods.analytical"]
    lines = [
        "# Analytical model: convergence and speed against ddeint",
        "",
        f"Paper scene, first touch to {T_end * 1e3:g} ms; reference rods.analytical at rtol = 1e-13 "
        f"(peak force {F_ref:.6f} N). Errors are relative to the peak force; 'history' is the max-norm "
        "error of the force history on a 0.05 µs grid. Wall time: best of three in one process.",
        "",
        "| solver | setting | steps | wall time [s] | peak-force error | history error |",
        "|---|---|---:|---:|---:|---:|",
    ]
    lines += [f"| {r[0]} | {r[1]} | {r[3]} | {r[4]:.4f} | {r[5]:.2e} | {r[6]:.2e} |" for r in rows]
    lines += [
        "",
        f"Observed order (rods.analytical, rtol 1e-11..1e-6): history error ∝ rtol^{p_tol:.2f}, "
        f"∝ (mean step)^{p_step:.2f}. ddeint as shipped (linear history interpolation on a fixed "
        f"grid, vode at its default rtol 1e-6): error ∝ Δt^{p_dde:.2f} over the three finest grids; "
        "its peak-force error stalls near 1e-4, so it cannot reach the 1e-6 that rods.analytical "
        "reaches at rtol = 1e-4.",
        "",
        "## Speed-up at equal or better accuracy",
        "",
        "For each ddeint run, the fastest rods.analytical run whose history error is at most ddeint's:",
        "",
        "| ddeint run | its error | its time [s] | rods.analytical | its error | its time [s] | speed-up |",
        "|---|---:|---:|---|---:|---:|---:|",
    ]
    for d in (r for r in rows if r[0].startswith("ddeint")):
        o = min((o for o in ours_rows if o[6] <= d[6]), key=lambda r: r[4])
        lines.append(
            f"| {d[0]} {d[1]} | {d[6]:.2e} | {d[4]:.3f} | {o[1]} | {o[6]:.2e} | {o[4]:.4f} | {d[4] / o[4]:.0f}x |"
        )
    return lines


def plot(rows: list[tuple], path: Path) -> None:
    """analytical-convergence.png: error against rtol, and accuracy against wall time for both solvers."""
    p_tol = orders(rows)[0]
    ours_rows = [r for r in rows if r[0] == "rods.analytical"]
    rt, eh = [r[2] for r in ours_rows], [r[6] for r in ours_rows]
    plt = pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].loglog(rt, eh, "o-", label="history error")
    ax[0].loglog(rt, [r[5] for r in ours_rows], "s--", label="peak-force error")
    ax[0].loglog(rt, rt, "k:", label="error = rtol")
    ax[0].set(xlabel="rtol", ylabel="relative error", title=f"rods.analytical (order {p_tol:.2f} in rtol)")
    ax[0].legend()
    ax[1].loglog([r[4] for r in ours_rows], eh, "o-", label="rods.analytical (DOP853, method of steps)")
    for name in ("ddeint", "ddeint (vode rtol 1e-10)"):
        rr = [r for r in rows if r[0] == name]
        ax[1].loglog([r[4] for r in rr], [r[6] for r in rr], "s-", label=name)
    ax[1].set(xlabel="wall time [s]", ylabel="history error (rel. to peak force)", title="accuracy against cost")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = _cli.bare_parser(__doc__.splitlines()[0])
    ap.add_argument("--end-time", type=_cli.positive, default=3e-4, help="[s] (default %(default)s)")
    ap.add_argument("--scene", default=str(ROOT / "workflows/scenes/paper.toml"))
    ap.add_argument("--out", default=str(RESULTS), help="folder of the table and the figure (default results/)")
    args = ap.parse_args()
    rows, F_ref = measure(load_scene(args.scene), args.end_time)
    lines = render(rows, F_ref, args.end_time)
    out = Path(args.out)
    out.mkdir(exist_ok=True)
    (out / "analytical-vs-ddeint.md").write_text("\n".join(lines) + "\n")
    plot(rows, out / "analytical-convergence.png")
    print("\n".join(lines))


if __name__ == "__main__":
    _cli.tool(main)
