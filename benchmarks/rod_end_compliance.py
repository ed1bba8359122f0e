"""The rod-end correction χ(ν, b/R, a/b) of the Hertz approach (rods.fe.end_compliance) over Poisson's ratio, the
cap's depth and the patch's size, with its discretisation check.

    python benchmarks/rod_end_compliance.py [--refine 2] [--out results/rod-end-compliance]

For each ν of rods.hertz.ROD_END_NU, each b/R of ROD_END_S (0: flat, 1: a hemisphere) and each a/b of
ROD_END_ALPHA: χ on the default mesh (elements a/24 at the apex); at ν = 0.3 and the smallest patch, the mesh 2 x
finer. Writes --out + .md and .json; the .json's "table" is rods.hertz.ROD_END_CHI ([ν][b/R][a/b]).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "workflows"))  # _cli: the entry points' one error path
import _cli  # noqa: E402
from rods import io  # noqa: E402
from rods.fe.end_compliance import end_correction  # noqa: E402
from rods.hertz import ROD_END_ALPHA, ROD_END_NU, ROD_END_S  # noqa: E402

CHECK_NU = 0.3  # [-] the mesh check's Poisson ratio


def main(argv: list[str] | None = None) -> int:
    ap = _cli.bare_parser(__doc__.splitlines()[0])
    ap.add_argument("--refine", type=_cli.positive, default=2.0, help="mesh refinement (elements ∝ 1/refine)")
    ap.add_argument("--out", default=str(ROOT / "results" / "rod-end-compliance"), help="tables: OUT.json, OUT.md")
    args = ap.parse_args(argv)
    _cli.output_file(args.out)  # before the solves
    t0 = time.perf_counter()
    table = [[[end_correction(ν, s, α, args.refine) for α in ROD_END_ALPHA] for s in ROD_END_S] for ν in ROD_END_NU]
    wall = time.perf_counter() - t0
    for ν, plane in zip(ROD_END_NU, table, strict=True):
        print(f"ν = {ν:+.2f}: " + "; ".join(" ".join(f"{χ:.5f}" for χ in row) for row in plane), flush=True)
    α0, i = ROD_END_ALPHA[0], ROD_END_NU.index(CHECK_NU)
    check = [
        {"s": s, "chi": table[i][j][0], "chi_fine": end_correction(CHECK_NU, s, α0, 2 * args.refine)}
        for j, s in enumerate(ROD_END_S)
    ]
    data = {
        "refine": args.refine,
        "nu": list(ROD_END_NU),
        "s": list(ROD_END_S),
        "alpha": list(ROD_END_ALPHA),
        "table": table,
        "mesh_check": check,
        "wall_time": wall,
    }
    io.write_data(Path(args.out + ".json"), data)
    io.atomic_write_text(Path(args.out + ".md"), render(data))
    return 0


def render(data: dict) -> str:
    """The .md of one run's data."""
    alphas = data["alpha"]
    lines = [
        "# Rod-end correction of the Hertz approach",
        "",
        "`python benchmarks/rod_end_compliance.py` — χ(ν, b/R, a/b) of rods.fe.end_compliance: a rod's end under a "
        "Hertz pressure of radius a differs from the half-space by χ F/(E b) (b the rod radius, R the tip's; χ < 0: "
        "stiffer), measured from the end of the 1D bar of the rod's mass (rods.scene.Rod.bar_offset). Static, "
        f"axisymmetric, P2 triangles refined to a/{12 * data['refine']:g} at the apex; "
        f"{len(data['nu']) * len(data['s']) * len(alphas)} solves in {data['wall_time']:.0f} s. The table is "
        "rods.hertz.ROD_END_CHI.",
        "",
        "| ν | b/R | " + " | ".join(f"a = {α:g} b" for α in alphas) + " |",
        "|---:|---:|" + "---:|" * len(alphas),
    ]
    for ν, plane in zip(data["nu"], data["table"], strict=True):
        for s, row in zip(data["s"], plane, strict=True):
            lines.append(f"| {ν:+.2f} | {s:g} | " + " | ".join(f"{χ:.5f}" for χ in row) + " |")
    lines += [
        "",
        f"Mesh check at ν = 0.3, a = {alphas[0]:g} b, the mesh 2 x finer:",
        "",
        "| b/R | χ | χ (mesh 2 x finer) | difference |",
        "|---:|---:|---:|---:|",
    ]
    lines += [
        f"| {c['s']:g} | {c['chi']:.5f} | {c['chi_fine']:.5f} | {c['chi_fine'] - c['chi']:+.5f} |"
        for c in data["mesh_check"]
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    _cli.tool(main)
