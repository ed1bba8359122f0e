"""Traction driving of a submodel (rods.fe.traction): the cut-force operator against the closed-form forces of
a uniform uniaxial stress (each rod its own material), and a traction-driven submodel meshed like its global
reproducing the global's force history with its energy balance closed."""

from __future__ import annotations

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import numpy as np
import pytest

from rods.fe.cut import read_band
from rods.fe.model import ExplicitModel
from rods.fe.submodel import run_submodel, submodel_scene
from rods.fe.traction import cut_force_operator

from ..conftest import recorded_global

# tiny axisymmetric global (0.1 m rods, 2 mm x 1 mm, 12 mm submodel region) with a titanium Rod 2, so that each
# cut's force must come from its own rod's material; kinematic contact (the default)
TITANIUM = ["rod2.material.youngs_modulus=114e9", "rod2.material.density=4430.0", "rod2.material.poisson_ratio=0.34"]
TINY = [
    "simulation.end_time=1e-4",
    "fe.submodel_length=12e-3",
    "rod1.length=0.1",
    "rod2.length=0.1",
    "fe.axial_size=2e-3",
    "fe.radial_size=1e-3",
    "fe.tip_grading=1.0",
    *TITANIUM,
]


TINY_3D = [
    "simulation.end_time=2e-5",
    "fe.submodel_length=12e-3",
    "fe.kind='3d'",
    "fe.symmetry='quarter'",
    "fe.axial_size=4e-3",
    "fe.radial_size=1e-3",
    "fe.tip_grading=1.0",
    "rod1.length=0.048",
    "rod2.length=0.1",
    *TITANIUM,
]


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    return recorded_global(TINY, tmp_path_factory, "global-traction")


@pytest.mark.parametrize("kind", ["axisymmetric", "3d"])
def test_cut_forces_of_a_uniform_uniaxial_stress(tiny, tmp_path_factory, kind):
    """u = ε(−ν x_⊥, z) in each rod (P1-exact): σ = E ε e_z e_z, so each cut carries E ε times its meshed
    area (∫ w ds, assembled independently) along the outward normal (−e_z at Rod 1's cut, +e_z at Rod 2's)
    and no transverse force, to round-off. 3D: the quarter model of tests/fe/test_submodel.py."""
    import dolfinx
    import ufl

    from rods.fe import forms

    sc, _, _, path = tiny if kind == "axisymmetric" else recorded_global(TINY_3D, tmp_path_factory, "global-3d")
    model = ExplicitModel(submodel_scene(sc, 1.5e-3))  # a size nesting with neither global size
    d = read_band(path, model)  # in 3D its sections mapped onto the model's (rods.fe.cut.match_sections)
    T, cut, _ = cut_force_operator(model, d)
    X, ε, gdim = d["nodes"], 1e-4, model.bs  # [m], [-]
    xc = model.V.tabulate_dof_coordinates()[cut]
    msh, tags = model.V.mesh, model.tags
    for k, rod in enumerate(sc.rods, start=1):
        ν, E = rod.material.poisson_ratio, rod.material.youngs_modulus
        U = np.column_stack([*(-ν * ε * X[:, i] for i in range(gdim - 1)), ε * X[:, gdim - 1]])  # [m]
        f = (T @ U.ravel()).reshape(-1, gdim)  # [N]
        ds = ufl.Measure("ds", domain=msh, subdomain_data=model.rm.facet_tags)(tags[f"rod{k}_end"])
        w = forms.measure_weight(ufl.SpatialCoordinate(msh), model.kind)
        area = model.comm.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(w * ds)))  # [m^2]
        on = xc[:, gdim - 1] < 0 if k == 1 else xc[:, gdim - 1] > 0
        expected = (-1 if k == 1 else 1) * E * ε * area  # [N]
        assert f[on, gdim - 1].sum() == pytest.approx(expected, rel=1e-10)
        assert np.abs(f[on, : gdim - 1]).max() < 1e-9 * abs(expected)


def test_traction_driving_reproduces_global(tiny):
    """A traction-driven submodel meshed like the global (same sizes and step) follows the global's contact
    force (measured: peak 0.20%, whole history 0.35% of the peak; the displacement driver: 0.001%, 0.06%: the
    traction is a derivative of the recorded field, the displacement the field itself)."""
    sc, g, res, path = tiny
    sub = run_submodel(sc.with_overrides("submodel.driving='traction'"), path, 1e-3, 2e-3, dt=g.dt, level="like")
    Fg, Fs = res.history["contact_force"], sub.result.history["contact_force"]
    assert sub.summary["driving"] == "traction"
    assert sub.summary["peak_contact_force"] == pytest.approx(res.summary["peak_contact_force"], rel=4e-3)
    assert np.abs(Fg - Fs).max() <= 6e-3 * Fg.max()
    assert sub.summary["cut_work"] < 0.0  # the cut carries the wave's energy out of the region


@pytest.mark.convergence
@pytest.mark.parametrize("driving", ["traction", "mixed"])
def test_traction_work_closes_the_balance_to_first_order_in_the_step(tiny, driving):
    """The cut forces' work (mixed: the dashpot's too), Δt f_n · (v_{n-½} + v_{n+½})/2, closes the submodel's
    energy balance up to the recorder's O(Δt) energy definition: the error falls as Δt (traction: measured
    5.25e-3, 2.62e-3, 1.31e-3, as for the displacement driver). Impulses on constrained entries (u_r on the
    axis) broke this at a flat 1%."""
    sc, g, _, path = tiny
    sc = sc.with_overrides(f"submodel.driving='{driving}'")
    steps = np.array([1.0, 0.5, 0.25]) * g.dt  # [s]
    errors = [run_submodel(sc, path, 1e-3, 2e-3, dt=dt).summary["energy_error"] for dt in steps]
    order = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert order >= 1.0 - 0.1
    assert errors[0] < 1e-2


def test_mixed_driving_does_not_carry_the_globals_contact_layer(tmp_path_factory):
    """A penalty-free submodel driven from a global with a soft penalty layer (0.5 x E*/h: peak 3355 N, the
    penalty-free global 3969 N). Displacement driving passes the layer's compliance on as approach the
    submodel's stiffer contact must take up (measured 8174 N against 3738 N from the penalty-free global);
    mixed driving passes on only the incoming waves, so both globals give the same submodel (measured 3965.5
    and 3958.1 N, 0.19% apart) and it sits at the penalty-free global's force (0.3%)."""
    sc_k, _, res_k, cut_k = recorded_global(TINY, tmp_path_factory, "global-kinematic")
    soft = [*TINY, "fe.contact='penalty'", "fe.penalty=0.5"]
    sc_p, _, res_p, cut_p = recorded_global(soft, tmp_path_factory, "global-soft-penalty")
    assert res_p.summary["peak_contact_force"] < 0.9 * res_k.summary["peak_contact_force"]

    def peak(sc, cut, driving):
        sub = sc.with_overrides("fe.contact='kinematic'", f"submodel.driving='{driving}'")
        return run_submodel(sub, cut, 1e-3, level="x").summary["peak_contact_force"]

    mixed = peak(sc_k, cut_k, "mixed"), peak(sc_p, cut_p, "mixed")
    assert mixed[1] == pytest.approx(mixed[0], rel=0.005)
    assert mixed[0] == pytest.approx(res_k.summary["peak_contact_force"], rel=0.01)
    shown = peak(sc_p, cut_p, "displacement") / peak(sc_k, cut_k, "displacement")
    assert shown > 1.5  # the displacement driver carries the layer


def test_mixed_driving_meshed_like_the_global_reproduces_it(tiny):
    """Where the submodel moves as the global, the dashpot does nothing: meshed like it, the mixed-driven
    submodel's force follows the global's (measured: peak 0.10%, whole history 0.13% of the peak)."""
    sc, g, res, path = tiny
    sub = run_submodel(sc.with_overrides("submodel.driving='mixed'"), path, 1e-3, 2e-3, dt=g.dt, level="like")
    Fg, Fs = res.history["contact_force"], sub.result.history["contact_force"]
    assert sub.summary["peak_contact_force"] == pytest.approx(res.summary["peak_contact_force"], rel=2e-3)
    assert np.abs(Fg - Fs).max() <= 4e-3 * Fg.max()


def _per_node_operators(model, d, tol=1e-6):
    """W and T built as before the colouring (2026-11-24): one interpolation per band node for W, one traction
    projection and interpolation per band node and component for T; the reference the coloured build must meet."""
    import dolfinx
    import scipy.sparse
    import ufl

    from rods.fe import forms
    from rods.fe.cut import band_space, cut_space
    from rods.fe.traction import _BandTraction

    Vb, node_of_dof = band_space(d, model.comm)
    V0, nodes0, cut_cells, cut_nodes = cut_space(model)
    n_nodes, bs = d["nodes"].shape[0], model.bs
    own = np.arange(Vb.dofmap.index_map.size_local)
    dof_of_node = np.full(n_nodes, -1, dtype=np.int64)
    dof_of_node[node_of_dof[own]] = own
    data = dolfinx.fem.create_interpolation_data(V0, Vb, cut_cells, padding=1e-10)
    fb, g = dolfinx.fem.Function(Vb), dolfinx.fem.Function(V0)
    W = np.zeros((nodes0.size, n_nodes))
    for j in range(n_nodes):
        fb.x.array[:] = 0.0
        if dof_of_node[j] >= 0:
            fb.x.array[dof_of_node[j]] = 1.0
        fb.x.scatter_forward()
        g.x.array[:] = 0.0
        g.interpolate_nonmatching(fb, cut_cells, data, tol=tol)
        W[:, j] = g.x.array[nodes0]
    Vb_vec = dolfinx.fem.functionspace(Vb.mesh, ("Lagrange", 1, (bs,)))
    traction = _BandTraction(Vb_vec, model.scene, model.kind, model.axial)
    gv = dolfinx.fem.Function(model.V)
    data_v = dolfinx.fem.create_interpolation_data(model.V, Vb_vec, cut_cells, padding=1e-10)
    ds = ufl.Measure("ds", domain=model.V.mesh, subdomain_data=model.rm.facet_tags)(
        (model.tags["rod1_end"], model.tags["rod2_end"])
    )
    area = model._assemble_owned(forms.tributary_area_form(model.V, ds, model.kind))[cut_nodes * bs + model.axial]
    entries = cut_nodes[:, None] * bs + np.arange(bs)[None, :]
    T = np.zeros((entries.size, n_nodes * bs))
    for j in range(n_nodes):
        for c in range(bs):
            traction.u.x.array[:] = 0.0
            if dof_of_node[j] >= 0:
                traction.u.x.array[dof_of_node[j] * bs + c] = 1.0
            traction.u.x.scatter_forward()
            gv.x.array[:] = 0.0
            gv.interpolate_nonmatching(traction.evaluate(), cut_cells, data_v, tol=tol)
            T[:, j * bs + c] = (gv.x.array[entries] * area[:, None]).ravel()
    return scipy.sparse.csr_matrix(W), scipy.sparse.csr_matrix(T)


@pytest.mark.parametrize("kind", ["axisymmetric", pytest.param("3d", marks=pytest.mark.slow)])  # 3D: 7-10 s
def test_coloured_cut_operators_equal_the_per_node_ones(tiny, tmp_path_factory, kind):
    """W (cut displacements) and T (cut forces), built one colour of band nodes at a time, equal the per-node
    build to round-off (1e-12 of their largest entry) on a submodel whose cut nests with neither global size."""
    from rods.fe.cut import CutDriver

    sc, _, _, path = tiny if kind == "axisymmetric" else recorded_global(TINY_3D, tmp_path_factory, "global-3d")
    model = ExplicitModel(submodel_scene(sc, 1.5e-3))
    d = read_band(path, model)
    W_ref, T_ref = _per_node_operators(model, d)
    W = CutDriver(model, path).W
    T, _, _ = cut_force_operator(model, d)
    assert W.shape == W_ref.shape and T.shape == T_ref.shape
    assert abs(W - W_ref).max() <= 1e-12 * abs(W_ref).max()
    assert abs(T - T_ref).max() <= 1e-12 * abs(T_ref).max()
    assert W.nnz > 0 and T.nnz > 0


def test_an_interrupted_submodel_resumes_to_the_same_histories(tiny, tmp_path):
    """A mixed-driven submodel (kinematic contact: the contact's memory, the dashpot's last velocity, the cut's
    work and the peak field are all state) stopped halfway by a stop request (Ctrl-C) resumes from its checkpoint
    to the uninterrupted run's histories, cut work and σ_r at peak force, to 1e-12."""
    import signal

    from rods import interrupt
    from rods.fe.guards import Interrupted

    sc, _, _, path = tiny
    sc = sc.with_overrides("fe.checkpoint_interval=1e-5")
    whole = run_submodel(sc, path, 1e-3, 2e-3, level="like")  # no folder: no checkpoints

    def stop(step: int, total: int, elapsed: float) -> None:  # noqa: ARG001
        if 0 < step < total:
            interrupt._state["signal"] = signal.SIGINT  # as the handler records Ctrl-C during the loop

    with pytest.raises(Interrupted):
        run_submodel(sc, path, 1e-3, 2e-3, progress=stop, level="like", out=tmp_path)
    interrupt.reset()
    assert (tmp_path / "checkpoint.json").exists()
    resumed = run_submodel(sc, path, 1e-3, 2e-3, level="like", out=tmp_path, restart=True)
    assert resumed.result.history.keys() == whole.result.history.keys()
    for k, v in whole.result.history.items():
        np.testing.assert_allclose(resumed.result.history[k], v, rtol=1e-12, atol=1e-12 * np.abs(v).max(), err_msg=k)
    assert resumed.summary["cut_work"] == pytest.approx(whole.summary["cut_work"], rel=1e-12)
    np.testing.assert_allclose(resumed.sigma_r["sigma_r"], whole.sigma_r["sigma_r"], rtol=1e-12)
