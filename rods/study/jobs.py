"""What a workflow job asks a batch scheduler for: wall time and memory from the run's own plan (rods.cost).

A SLURM job states its time limit and memory up front and is killed past either; a limit far above the need waits
longer in the queue and holds a node it does not use. So every FE rule of ``workflows/Snakefile`` asks for what its
run's plan estimates, the costs the entry point itself prints before it runs (:func:`global_cost`,
:func:`submodel_cost`, :func:`verification_costs`), through :func:`request`:

* ``runtime`` [min] = (:data:`RUNTIME_MARGIN` x the plan's wall time at the reference rates + :data:`RUNTIME_START`)
  x ``attempt``. The submitting host is not the node, so the plan is not probed there (rods.cost.calibrated); the
  reference rates are this 2-core VM's on an idle day (rods.cost.DOF_STEPS_PER_SECOND), and the same loop ran from
  0.2x to 1.9x of them here (2026-11-29 to 2026-12-07): the margin covers a node a quarter as fast; the start covers the
  interpreter, the forms' JIT compilation on a node with an empty cache and the shared file system. A job the
  scheduler killed for time and retried (Snakemake's ``--retries``) asks for ``attempt`` times as much.
* ``mem_mb`` [MB] = :data:`MEMORY_MARGIN` x the plan's memory (all ranks of the job on one node), at least
  :data:`MEMORY_MIN`, x ``attempt``: the plan's memory model is fitted to measured peak RSS (rods.cost.BYTES_PER_DOF)
  and the margin covers the mesher's and the assembly's transients that the fit does not.

Measured on the main job's jobs (2 ranks, this machine, 2026-12-06): see docs/run-log.md.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from rods import cost, plan
from rods.scene import Scene, cut_record_end
from rods.study import verification

__all__ = ["MEMORY_MARGIN", "MEMORY_MIN", "RUNTIME_MARGIN", "RUNTIME_START", "global_cost", "request",
           "submodel_cost", "verification_costs"]  # fmt: skip

# the plan's wall time x this: a node a quarter as fast as the reference rate [-] (3.0 until the axisymmetric rate
# went from 2.5e7 to 3.5e7 DOF-steps/s in cache, 2026-12-07, so that the requests stay about what they were: 12 min
# for the main job's global as before, 234 min for its ultra-fine submodel, past the cache at 2.8e7, against 212)
RUNTIME_MARGIN = 4.2
RUNTIME_START = 10.0  # [min] start-up beyond the plan: interpreter, JIT compilation, file system, the plan's probe
MEMORY_MARGIN = 1.5  # the plan's memory x this: the mesher's and the assembly's transients [-]
MEMORY_MIN = 2000.0  # [MB] at least this: an interpreter with DOLFINx, PETSc and gmsh per rank is ~190 MB


def global_cost(
    scene: Scene,
    ranks: int,
    *,
    driver: bool = False,
    record_cut: bool = False,
    record_until: float | None = None,
    record_every: int = 1,
    phase: float | None = None,
) -> cost.Cost:
    """The cost of workflows/global.py's run of ``scene`` on ``ranks`` ranks: the driving global of the submodels
    over its contact phase (``driver``: rods.plan.submodel_driver to ``phase`` [s], default rods.plan.driver_phase,
    recording the cut band every step), else the global over the scene's end time, recording the cut band to
    ``record_until`` [s] every ``record_every`` steps where ``record_cut``."""
    if driver and phase is None:
        phase = plan.driver_phase(scene)
    sc = plan.submodel_driver(scene, phase) if driver else scene
    until = cut_record_end(sc, record_until) if driver or record_cut else None
    what = "the driving global" if driver else "the global"
    return cost.fe_cost(sc, ranks, what=what, record_until=until, record_every=record_every, record_flags=record_cut)


def submodel_cost(
    scene: Scene,
    ranks: int,
    level: str,
    phase: int | None = None,
    end_time: float | None = None,
    analytical_summary: Mapping[str, Any] | None = None,
) -> cost.Cost:
    """The cost of workflows/submodel.py's run of submodel ``level`` (member ``phase`` of its phase study) driven by
    ``scene``'s driving global, as planned before the driver has run: its own stable step, to ``end_time`` [s]
    (default the driver's contact phase, rods.plan.submodel_end without the driver's summary). A caller planning
    many members gives the end and the analytical model's summary (rods.plan.planning_summary) once."""
    h = plan.submodel_size(scene, level, phase, analytical_summary)
    end = plan.submodel_end(scene) if end_time is None else end_time
    what = f"the submodel {level}" if phase is None else f"the submodel {level}-phase-{phase}"
    return cost.fe_cost(scene, ranks, what=what, size=h, end_time=end)


def verification_costs(scene: Scene, ranks: int, overrides: Sequence[str] = ()) -> list[cost.Cost]:
    """The costs of workflows/verify.py's matrix on ``scene`` (every case's runs, rods.study.verification)."""
    return [c for name in verification.CASES for c in verification.case_costs(scene, name, overrides, ranks, True)]


def request(costs: Sequence[cost.Cost], attempt: int = 1) -> dict[str, Any]:
    """The scheduler's ``runtime`` [min] and ``mem_mb`` [MB] for one job that runs ``costs`` one after the other
    (module docstring), its ``attempt``-th try."""
    wall = sum(c.wall_time for c in costs)  # [s]
    memory = max((c.memory for c in costs), default=0.0)  # [B] the stages run in turn: the largest
    runtime = (RUNTIME_MARGIN * wall / 60.0 + RUNTIME_START) * attempt
    mem_mb = max(MEMORY_MARGIN * memory / 1e6, MEMORY_MIN) * attempt
    return {"runtime": math.ceil(runtime), "mem_mb": math.ceil(mem_mb)}
