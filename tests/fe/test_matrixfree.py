"""The element kernel (rods.fe.matrixfree, ``fe.operator = "matrix-free"``): K x element by element equals the
assembled product to round-off (axisymmetric with two materials, 3D half model with graded, capped cells), a
model stepped with it gives the PETSc path's histories (kinematic and penalty contact, damped, the CuPy order
of a kinematic step, a driven submodel), and the key's refusals."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from rods.fe import backend, forms, matrixfree
from rods.fe.model import ExplicitModel
from rods.scene import SCHEMA, SceneError, load_scene

from ..conftest import PAPER
from .test_backend import ARRAY_BACKENDS, FAKE, THREE_D, assert_same_histories, on

SMALL = ["rod1.length=0.05", "rod2.length=0.1", "fe.axial_size=2e-3", "fe.radial_size=1e-3"]
TITANIUM = ["rod2.material.youngs_modulus=114e9", "rod2.material.density=4430.0", "rod2.material.poisson_ratio=0.34"]
ROUND_OFF = 1e-13  # K x against the assembled product, relative to its largest entry (measured: 1e-15 to 4e-15)


def kernel(overrides: list[str]) -> tuple[ExplicitModel, matrixfree.ElementStiffness]:
    """The model of the scene with ``overrides`` set up with the element kernel, and the kernel's arrays."""
    m = ExplicitModel(load_scene(PAPER, [*overrides, "fe.backend='numpy'", "fe.operator='matrix-free'"]))
    return m, m.element


@pytest.mark.parametrize("overrides", [[*SMALL, *TITANIUM], [*THREE_D, *TITANIUM]], ids=["axisymmetric", "3d"])
def test_element_product_equals_the_assembled_one(overrides):
    """K x by the kernel and by DOLFINx's assembled CSR matrix agree to round-off for a random x and for a rigid
    axial motion (which K annihilates: both vanish to round-off of K's scale)."""
    m, es = kernel(overrides)
    assert np.unique(es.λ).size == 2  # two materials: the cells' own Lamé parameters are read
    x = np.random.default_rng(1).standard_normal(m.K.shape[0])
    y, y_ref = es.product(x, np), m.K @ x
    assert np.abs(y - y_ref).max() <= ROUND_OFF * np.abs(y_ref).max()
    rigid = np.zeros_like(x)
    rigid[m.axial :: m.bs] = 1e-3  # [m]
    assert np.abs(es.product(rigid, np)).max() <= ROUND_OFF * np.abs(m.K).max() * 1e-3


def test_quadrature_is_the_assembled_forms():
    """The kernel integrates with the Gauss rule FFCx uses: 2 x 2 x 2 points in 3D (the form's metadata), UFL's
    estimate 7 (4 x 4 points) for the axisymmetric Q1 form with its 2πr weight and hoop term."""
    for overrides, degree, points in ((SMALL, 7, 16), (THREE_D, forms.QUADRATURE_DEGREE_3D, 8)):
        m, es = kernel(overrides)
        assert matrixfree.quadrature_degree(forms.stiffness_form(m.V, m.mat, m.kind)) == degree
        assert es.N.shape[0] == points


CASES = {  # 6 µs from the tips touching: the contact closes at once
    "kinematic": [*SMALL, "simulation.end_time=6e-6"],
    "penalty-damped": [*SMALL, "simulation.end_time=6e-6", "fe.contact='penalty'", "fe.bulk_viscosity=0.1"],
    "3d": [*THREE_D[:-1], "simulation.end_time=4e-6"],
}
CUPY = next(p for p in ARRAY_BACKENDS if getattr(p, "values", None) == ("cupy",))  # skipped without a GPU
RUNS = [  # numpy-overlap: the CuPy path's order of a kinematic step (its contact rows from the kernel's K)
    *(pytest.param(c, b, id=f"{c}-{b}") for c in ("kinematic", "3d") for b in ("numpy", "numpy-overlap")),
    pytest.param("penalty-damped", "numpy", id="penalty-damped-numpy"),
    *(pytest.param(c, FAKE, id=f"{c}-{FAKE}") for c in CASES),
    *(pytest.param(c, "cupy", id=f"{c}-cupy", marks=CUPY.marks) for c in CASES),
]


@functools.cache
def reference(case: str):
    """The PETSc path's run of ``case`` (assembled K)."""
    return ExplicitModel(load_scene(PAPER, CASES[case])).run()


@pytest.mark.parametrize(("case", "name"), RUNS)
def test_histories_equal_the_petsc_path(case, name):
    """The model stepped with the element kernel on an array backend: histories equal the PETSc path's to the
    array backends' tolerance (tests/fe/test_backend.py)."""
    ref = reference(case)
    assert ref.history["contact_force"].max() > 0
    m = ExplicitModel(load_scene(PAPER, [*CASES[case], "fe.backend='numpy'", "fe.operator='matrix-free'"]))
    assert isinstance(m.stepper().op, matrixfree.ElementOperator)
    with on(name) as m.backend:
        res = m.run()
    assert res.summary["operator"] == "matrix-free"
    energy = ref.history["kinetic_energy"][0]  # [J]: the scale of a dissipation still at round-off this early
    assert_same_histories(ref.history, res.history, floors={"dissipated_energy": energy})


def test_scene_key_and_refusals():
    assert SCHEMA["fe.operator"][1] == "assembled"
    with pytest.raises(SceneError, match="fe.operator.*fe.backend = 'numpy' or 'cupy'"):
        load_scene(PAPER, ["fe.operator='matrix-free'"])  # the default backend is PETSc's
    with pytest.raises(SceneError, match="fe.operator"):
        load_scene(PAPER, ["fe.operator='ebe'"])
    with pytest.raises(SceneError, match="fe.operator.*serial"):
        backend.select("auto", 2, "matrix-free")  # auto under MPI is the PETSc path
    if not backend.gpu_available():
        assert backend.select("auto", 1, "matrix-free").name == "numpy"


def test_driven_submodel_histories(tmp_path_factory):
    """A submodel driven at its cut (mixed driving, the default) stepped with the element kernel: its histories,
    the cut's external work included, equal the PETSc path's (tests/fe/test_backend.py's driven case)."""
    from rods.fe.cut import CutDriver
    from rods.fe.submodel import submodel_scene

    from ..conftest import recorded_global

    overrides = ["rod1.length=0.1", "rod2.length=0.1", "fe.axial_size=2e-3", "fe.radial_size=1e-3",
                 "simulation.end_time=2e-5", "fe.submodel_length=12e-3"]  # fmt: skip
    sc, _, _, cut = recorded_global(overrides, tmp_path_factory, "global-matrix-free")
    ref = ExplicitModel(submodel_scene(sc, 1e-3))
    ref = ref.run(observers=(CutDriver(ref, cut),))
    m = ExplicitModel(submodel_scene(sc.with_overrides("fe.backend='numpy'", "fe.operator='matrix-free'"), 1e-3))
    assert isinstance(m.stepper().op, matrixfree.ElementOperator)
    res = m.run(observers=(CutDriver(m, cut),))
    assert np.abs(ref.history["external_work"]).max() > 0
    assert_same_histories(ref.history, res.history, floors={"dissipated_energy": ref.history["kinetic_energy"][0]})
