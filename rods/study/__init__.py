"""Studies: a scene's plan run end to end, each stage one library function with typed results.

* :mod:`rods.study.stages` — the stages: analytical, global FE, the submodels' driver, one submodel level,
  the comparison; each writes ``summary.json`` + ``history.csv`` under its folder and returns a ``Stage``.
* :mod:`rods.study.pipeline` — :func:`rods.study.pipeline.run_study`: the plan (rods.plan) run in order.
* :mod:`rods.study.table3` — the comparison data (``table3.json``) and its markdown/CSV renderings.
* :mod:`rods.study.figures` — Fig. 5c and Fig. 6 from the submodels' summaries.
* :mod:`rods.study.fig4` — Fig. 4 of a scene (its wave response): FE runs over the analytical model, their Rod-2
  midpoint speed and strain and contact force (``fig4.json``, ``.md``, ``.png``).
* :mod:`rods.study.sweep` — one CSV row per run of a parameter sweep.
* :mod:`rods.study.runs` — the runs later stages read, checked as bad input (folder, summary, kind of run, scene),
  and percentage cells.
* :mod:`rods.study.console` — rank 0's log and progress bar for the entry points.
* :mod:`rods.study.jobs` — a stage's cost (rods.cost) and the cluster's request from it (tasks, memory, runtime).
* :mod:`rods.study.verification` — the verification matrix: the global at default settings against the
  analytical model on its scenes (``results/verification.{json,md}``).

The recipe itself (contact phase, the driver's settings, the most-refined rule) is :mod:`rods.plan`; the
comparison math (Richardson level choice, σ_r error band) is :mod:`rods.compare`. Importing this package
loads nothing heavy: the FE stages import DOLFINx when they run.
"""
