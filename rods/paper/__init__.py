"""The paper job's tables, figures and report: each stage computes its result as data, writes it as JSON,
and renders its markdown and figures from that data.

* :mod:`rods.paper.table2` — Table 2: the analytical model on the six trials against the paper and the
  experiment, with uncertainty bands (``table2.json``, ``.csv``, ``.md``, ``.png``, ``fig4-analytical.png``).
* :mod:`rods.paper.accuracy_cost` — every model's error against its cost, Pareto fronts
  (``accuracy-cost.json``, ``.md``, ``.png``).
* :mod:`rods.paper.report` — ``REPORT.md`` rendered only from the stages' JSON files (``table2.json``,
  ``table3.json``, ``fig4.json``, ``accuracy-cost.json``, ``contact-study.json``; where they exist
  ``convergence.json``, ``verification.json``, ``contact-fields.json``, ``driver-study.json``,
  ``edge-scatter.json``). Fig. 4 is any scene's wave
  response figure, :mod:`rods.study.fig4`, which the paper job draws for its own runs.

The runs later stages read (checked as bad input) are :mod:`rods.study.runs` (here as ``rods.paper.data`` before
2026-12-07). The paper's published numbers enter only through :func:`rods.paper_data.load`, by named keys.
"""
