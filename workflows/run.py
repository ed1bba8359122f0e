"""Run what a scene asks for: its effects decide the models (rods/plan.py), the plan is printed first.

    python workflows/run.py --scene workflows/scenes/paper.toml --set 'effects=["contact_patch"]' --out DIR
    mpirun -n 2 python workflows/run.py --scene ... --out DIR

Stages, each the same script a user would call by hand, in process:
  DIR/analytical/      always (milliseconds; every model's reference, and the contact end for the plan)
  DIR/global/          the global FE model, to the planned end time; records the cut when a submodel follows
  DIR/submodel/LEVEL/  one per planned level (contact_patch, subsurface_stress)
DIR/summary.json holds the plan, the stage folders and the contract keys, each taken from the most
refined model that computed it (contact quantities: finest submodel > global > analytical; wave
quantities: global > analytical).
"""

from __future__ import annotations

import importlib
import json
import sys
import time
from collections.abc import Sequence

import rods.fe  # noqa: F401  (loads the wheel's dolfinx_solver first where installed)

# isort: split
from mpi4py import MPI

import _cli
from rods import io
from rods.analytical import simulate
from rods.plan import make_plan

CONTACT_KEYS = ("peak_contact_force", "contact_radius", "contact_area", "peak_contact_pressure", "contact_duration")
WAVE_KEYS = ("midpoint_peak_speed", "midpoint_peak_strain")


def main(argv: Sequence[str] | None = None) -> int:
    t0 = time.perf_counter()
    comm = MPI.COMM_WORLD
    root = comm.rank == 0
    args = _cli.parser(__doc__.splitlines()[0]).parse_args(argv)
    scene = _cli.load(args)
    out = _cli.out_dir(args, "run", scene)
    passthrough = ["--scene", args.scene, *(a for o in args.overrides for a in ("--set", o))]

    # analytical model (every rank computes it: it is cheap and the plan needs its contact end)
    ana = simulate(scene)
    episodes = ana.summary["contact_episodes"]
    plan = make_plan(scene, contact_end=episodes[-1][1] if episodes else None)
    if root:
        print(f"plan for scene '{scene.name}' -> {out}\n{plan.describe()}", flush=True)
        io.write_history(out / "analytical" / "history.csv", ana.history, ana.units)
        io.write_summary(out / "analytical" / "summary.json", ana.summary)
    stages = {"analytical": str(out / "analytical")}
    sources = {k: "analytical" for k in (*CONTACT_KEYS, *WAVE_KEYS)}
    values = {k: ana.summary[k] for k in (*CONTACT_KEYS, *WAVE_KEYS)}

    def take(stage: str, keys: Sequence[str]) -> None:
        s = json.loads((out / stage / "summary.json").read_text()) if root else {}
        s = comm.bcast(s, root=0)
        for k in keys:
            values[k], sources[k] = s[k], stage

    if plan.global_model:
        g_args = [*passthrough, "--set", f"simulation.end_time={plan.global_end_time!r}", "--out", str(out / "global")]
        if plan.submodel_levels:
            g_args.append("--record-cut")
        importlib.import_module("global").main(g_args)
        stages["global"] = str(out / "global")
        take("global", (*CONTACT_KEYS, *WAVE_KEYS) if "wave_response" in plan.effects else CONTACT_KEYS)
    for level in plan.submodel_levels:
        importlib.import_module("submodel").main(
            ["--global", str(out / "global"), "--level", level, "--out", str(out / "submodel" / level)]
        )
        stages[f"submodel/{level}"] = str(out / "submodel" / level)
        take(f"submodel/{level}", CONTACT_KEYS[:-1])  # the submodel's contact duration is cut at its end time

    if root:
        summary = {
            "model": "workflow",
            "scene": scene.name,
            "impact_speed": scene.speed,
            **values,
            "wall_time": time.perf_counter() - t0,
            "sources": sources,
            "plan": plan.as_dict(),
            "stages": stages,
            "scene_values": scene.as_dict(),
        }
        io.write_summary(out / "summary.json", summary)
        print(json.dumps({k: summary[k] for k in ("plan", "sources")}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(_cli.guarded(main)())
