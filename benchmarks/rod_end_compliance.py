"""The rod-end correction χ(ν) of the Hertz approach (rods.fe.end_compliance) over Poisson's ratio, with its
discretisation and load-size checks.

    python benchmarks/rod_end_compliance.py [--n 48] [--out results/rod-end-compliance]

For each ν of the table rods.hertz.ROD_END_CHI: χ on the default mesh (n = 48 radial Q2 elements, Hertz radius
a = 0.15 b), on a mesh 2 x finer, and with a = 0.075 b (a << b: the correction must not depend on a).
Writes --out + .md and .json; the .md table is the source of rods.hertz.ROD_END_CHI.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "workflows"))  # _cli: the entry points' one error path
import _cli  # noqa: E402
from rods.fe.end_compliance import end_correction  # noqa: E402
from rods.hertz import ROD_END_NU  # noqa: E402


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=48, help="radial Q2 elements of the default mesh")
    ap.add_argument("--out", default=str(ROOT / "results" / "rod-end-compliance"))
    args = ap.parse_args(argv)
    rows = []
    for ν in ROD_END_NU:
        t0 = time.perf_counter()
        χ = end_correction(ν, n=args.n)
        fine = end_correction(ν, n=2 * args.n)
        small = end_correction(ν, a=0.075, n=2 * args.n)
        rows.append({"nu": ν, "chi": χ, "chi_fine": fine, "chi_small_load": small, "wall": time.perf_counter() - t0})
        print(f"ν = {ν:+.2f}: χ = {χ:.5f}, 2x finer {fine:.5f}, a = 0.075 b {small:.5f}", flush=True)
    out = Path(args.out)
    out.with_suffix(".json").write_text(json.dumps({"n": args.n, "rows": rows}, indent=1) + "\n")
    lines = [
        "# Rod-end correction of the Hertz approach",
        "",
        "`python benchmarks/rod_end_compliance.py` — χ(ν) of rods.fe.end_compliance: a rod's end under a Hertz "
        "pressure is stiffer than the half-space by χ F/(E b) (χ < 0), b the rod radius. Static, axisymmetric, "
        f"Q2; default mesh n = {args.n} radial elements, a = 0.15 b; the finer mesh 2n; the small load a = 0.075 b "
        "on the finer mesh.",
        "",
        "| ν | χ | χ (mesh 2 x finer) | χ (a = 0.075 b) | wall [s] |",
        "|---:|---:|---:|---:|---:|",
    ]
    lines += [
        f"| {r['nu']:+.2f} | {r['chi']:.5f} | {r['chi_fine']:.5f} | {r['chi_small_load']:.5f} | {r['wall']:.1f} |"
        for r in rows
    ]
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    _cli.tool(main)
