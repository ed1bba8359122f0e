"""A study from Python: the plan a scene's effects ask for, run end to end, and its Table 3.

    python demos/study.py
    mpirun -n 2 python demos/study.py

``effects`` in a scene say what it is for; ``rods.plan`` turns them into models: here ``contact_patch`` asks for the
contact radius, area and pressure, which a global mesh does not resolve, so the plan runs the analytical model, the
scene's own global over the contact phase (1.2 x the analytical first contact's end), recording the motion of two
cut planes 14 mm from the tips (``fe.submodel_length``), and submodels of that region driven at the cuts by it
(``submodel.driving = "mixed"``: the global's traction plus a dashpot to its velocity). ``run_study`` runs the plan
into a folder (each stage's summary.json and history.csv, Table 3 and Figs. 5c and 6 under compare/) and returns
the stages' results. Each level's patch is compared with Hertz at the level's *own* peak force (paper Eq. 10),
so the mesh's error is not mixed with the force's. ``workflows/run.py`` is this, with a progress bar.
"""

from __future__ import annotations

from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
from mpi4py import MPI

from rods import cost, plan
from rods.scene import PAPER_SCENE, load_scene
from rods.study import stages
from rods.study.pipeline import run_study, stage_costs

ROOT = Path(__file__).resolve().parents[1]
# the paper's scene, asked for its contact patch on the paper's two coarser submodel levels (0.25 and 0.125 mm)
OVERRIDES = ("effects=['contact_patch']", "submodel.levels=['coarse', 'mid']")


def main(out: Path = ROOT / "output" / "demos" / "study") -> dict:
    comm = MPI.COMM_WORLD
    say = print if comm.rank == 0 else (lambda *a, **k: None)  # one rank prints; every rank computes
    scene = load_scene(PAPER_SCENE, OVERRIDES)
    # the price before anything heavy (what `run.py --dry-run` prints with the plan; run_study logs the plan)
    a = stages.analytical(scene, out / "analytical", comm, write=False)
    costs = cost.calibrated(stage_costs(scene, plan.study_plan(scene, a.summary), comm.size), comm)
    say(f"estimated: {sum(c.wall_time for c in costs):.0f} s on {comm.size} rank(s)")
    study = run_study(scene, out, comm, log=say)
    rows = study.comparison.data["rows"] if comm.rank == 0 else []  # the comparison runs on rank 0
    say("level       h [mm]  force vs analytical  area vs Hertz  p0 vs Hertz  (Hertz at the level's own force)")
    for r in rows:
        if r["role"] == "submodel":
            say(
                f"{r['level']:10s}  {r['h_mm']:6.4g}  {r['d_force_vs_analytical_pct']:+18.3f}%  "
                f"{r['d_area_vs_hertz_pct']:+12.3f}%  {r['d_p0_vs_hertz_pct']:+10.3f}%"
            )
    say(f"status {study.summary['status']}; Table 3 in {out / 'compare' / 'table3.md'}")
    mid = next((r for r in rows if r.get("level") == "mid"), None)
    return comm.bcast({"mid_p0_vs_hertz_pct": mid["d_p0_vs_hertz_pct"] if mid else None}, root=0)


if __name__ == "__main__":
    main()
