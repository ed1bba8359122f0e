"""Similarity of the default global FE model.

Linear elastodynamics with Hertz contact has no length scale and no modulus scale of its own: every length of a
scene x λ gives times x λ, forces x λ², speeds and strains unchanged; E and ρ x k (same wave speeds) give forces
x k and times unchanged. The code promises its defaults need no per-scene tuning, so every "auto" (end time,
output interval, mesh sizes, time step) must follow the scene and the FE histories must scale to round-off.
The analytical model's counterpart: tests/test_checks.py::test_a_scene_scaled_in_size_is_judged_alike. About 4 s
on one core.
"""

from __future__ import annotations

import math

import rods.fe  # noqa: F401  (the PyPI wheel's dolfinx shim before dolfinx/petsc4py)

# isort: split

import numpy as np
import pytest

from rods.fe.model import ExplicitModel
from rods.scene import PAPER_SCENE, SUBMODEL_LEVEL_SIZES, load_scene

RISE = 30e-6  # [s] of the paper scene's ~90 µs rise: a third of the force, the rings of the patch closing


def _scene(lam: float = 1.0, k: float = 1.0, end: float | None = None):
    """The paper scene, every length x ``lam``, E, ρ and S_y x ``k``, every time left "auto" (or ``end`` x lam)."""
    base = load_scene(PAPER_SCENE)
    over = ["simulation.end_time='auto'", "simulation.output_interval='auto'"]
    for i, rod in ((1, base.rod1), (2, base.rod2)):
        over += [f"rod{i}.{key}={getattr(rod, key) * lam!r}" for key in ("length", "diameter", "tip_radius")
                 if math.isfinite(getattr(rod, key))]  # fmt: skip
        m = rod.material
        over += [f"rod{i}.material.{key}={getattr(m, key) * k!r}" for key in ("density", "youngs_modulus",
                 "yield_strength")]  # fmt: skip
    over.append(f"station=[{{rod = 1, position = {0.1 * lam!r}, name = 'gauge'}}]")
    if end is not None:
        over.append(f"simulation.end_time={end * lam!r}")
    return load_scene(PAPER_SCENE, over)


@pytest.mark.parametrize("lam", [0.1, 10.0])
def test_auto_defaults_follow_the_scenes_size(lam):
    ref, big = _scene(), _scene(lam)
    for key in ("simulation.end_time", "simulation.output_interval", "fe.axial_size", "fe.radial_size",
                "fe.submodel_length"):  # fmt: skip
        assert big[key] == pytest.approx(lam * ref[key], rel=1e-12), key
    assert big.tip_grading == pytest.approx(ref.tip_grading, rel=1e-12)
    assert big.stiffness_sensitivity == pytest.approx(ref.stiffness_sensitivity, rel=1e-9)


@pytest.mark.parametrize("lam", [1e-3, 0.01, 0.1, 10.0, 28.0])
def test_auto_submodel_levels_follow_the_scenes_size(lam):
    """The submodel ladder is in metres, so "auto" levels follow λ to within its factor 2: the first at most the
    paper's coarse x λ and more than half of it, three halvings (an audit, 2026-12-07: the ladder ended at 1.95 µm,
    and the paper scene x 0.01 took three levels from 7.8 µm, coarser than its 2.7 µm global; x 0.001 was refused
    naming fe.radial_size, a key the user had not set)."""
    levels = _scene(lam).with_overrides("effects=['contact_patch']")["submodel.levels"]
    h = [SUBMODEL_LEVEL_SIZES[lv] for lv in levels]
    assert len(h) == 3 and h[0] / h[1] == h[1] / h[2] == 2.0
    assert 0.5 < h[0] / (lam * SUBMODEL_LEVEL_SIZES["coarse"]) <= 1.0


@pytest.fixture(scope="module")
def reference():
    return ExplicitModel(_scene(end=RISE)).run()


@pytest.mark.parametrize(("lam", "k"), [(0.1, 1.0), (10.0, 1.0), (1.0, 10.0)], ids=["x0.1", "x10", "E,rho x10"])
def test_global_fe_is_similar(reference, lam, k):
    ref, r = reference, ExplicitModel(_scene(lam, k, end=RISE)).run()
    s0, s1 = ref.summary, r.summary
    assert (s1["dofs"], s1["cells"], s1["steps"]) == (s0["dofs"], s0["cells"], s0["steps"])
    assert s1["dt"] == pytest.approx(lam * s0["dt"], rel=1e-6)  # the Lanczos estimate's own tolerance, far below
    scale = {"time": lam, "contact_force": lam**2 * k, "contact_radius": lam, "peak_pressure": k,
             "rod2_mid_velocity": 1.0, "rod2_mid_strain": 1.0, "gauge_velocity": 1.0, "gauge_strain": 1.0,
             "kinetic_energy": lam**3 * k, "strain_energy": lam**3 * k}  # fmt: skip
    for key, factor in scale.items():
        a, b = np.asarray(ref.history[key]), np.asarray(r.history[key]) / factor
        assert a.shape == b.shape, key
        assert np.abs(a - b).max() <= 1e-6 * np.abs(a).max(), key
    assert s0["peak_contact_force"] > 0  # the window holds the contact's rise
