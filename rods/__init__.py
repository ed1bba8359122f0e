"""rods: low-speed axial impact of slender rods — analytical, finite-element and closed-form models.

A map of the library (each module's docstring says more):

* :mod:`rods.scene` — the scene schema (rods, materials, tips, impact, simulation, FE settings, effects),
  loading, overrides and validation (bad input raises :class:`rods.scene.SceneError`).
* :mod:`rods.hertz` — closed-form Hertz contact: E*, R* (:func:`rods.hertz.contact_constants`), the
  force-approach law, radius and pressure, Hertz at a model's own force, stresses, the yield check.
* :mod:`rods.analytical` — the paper's analytical model: 1D waves + Hertz as delay differential equations.
* :mod:`rods.metrics` — definitions shared by every model (contact duration, average peak speed, RMS).
* :mod:`rods.compare` — comparison math: Hertz subsurface stresses, Richardson extrapolation and GCI.
* :mod:`rods.plan` — which models a scene's effects ask for.
* :mod:`rods.paper_data` — the paper's published tables, by named keys.
* :mod:`rods.uncertainty` — first-order propagation of input uncertainties.
* :mod:`rods.io` — atomic writes of summaries (JSON) and histories (CSV).
* :mod:`rods.fe` — the explicit FE model (DOLFINx): mesh, forms, contact, the central-difference stepper,
  recorder and observers, the submodel and its cut driver.
* :mod:`rods.paper` — the paper's tables, Fig. 4, the accuracy-against-cost study and REPORT.md, computed
  as JSON-serialisable data and rendered from it.
* :mod:`rods.study` — study recipes: a scene's plan run end to end (analytical, global, submodel chain,
  comparison) with typed, JSON-serialisable stage results.

``rods`` itself imports nothing heavy: DOLFINx is loaded only by :mod:`rods.fe`.
"""
