"""3D submodel (fe.kind = "3d", quarter symmetry): cut recording on hexahedra, driving, non-nested
sections (the finer circle bulges past the band's polygon), σ_r at the hexahedron Gauss points, CLI, MPI."""

from __future__ import annotations

import json
import math
import shutil

import dolfinx_solver  # noqa: F401  (must precede dolfinx/petsc4py)

# isort: split
import dolfinx
import numpy as np
import pytest

from rods import io
from rods.fe.mesh3d import section_counts
from rods.fe.model import ExplicitModel
from rods.fe.submodel import MAX_EXTRAPOLATION, CutDriver, run_submodel, submodel_scene
from rods.scene import load_scene

from .conftest import MPIRUN, PAPER, recorded_global, run_workflow, set_args

# tiny quarter model: 48 + 100 mm rods, 4 mm along x 1 mm across (~6k DOFs), 12 mm submodel region (3 global
# axial elements, so a submodel meshed like the global nests along z). Penalty fixed: global and submodel are
# compared at equal ε = penalty factor x E*/h_tip (fe.penalty for the global, submodel.penalty for the submodel).
TINY = [
    "fe.kind='3d'",
    "fe.symmetry='quarter'",
    "fe.penalty=1.0",
    "submodel.penalty=1.0",
    "fe.axial_size=4e-3",
    "fe.radial_size=1e-3",
    "rod1.length=0.048",
    "rod2.length=0.1",
    "simulation.end_time=1e-4",
    "fe.submodel_length=12e-3",
]
L_S = 12e-3  # [m]
H_NN = 0.7e-3  # non-nested submodel size [m]: divides neither 4 mm, 1 mm nor L_s


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    return recorded_global(TINY, tmp_path_factory, "global3d")


def test_cut_file_contents_3d(tiny):
    import h5py

    sc, g, _, path = tiny
    with h5py.File(path) as f:
        n_rec, n_nodes, gdim = f["u"].shape
        assert gdim == 3 and f.attrs["cell_type"] == "hexahedron" and f["cells"].shape[1] == 8
        assert n_rec == g.steps + 1 and f.attrs["kind"] == "3d"
        X, U = f["nodes"][()], f["u"][()]
    z = X[:, 2]
    assert np.all(np.minimum(np.abs(z + L_S), np.abs(z - L_S)) <= 8e-3 + 1e-12)  # ±2 axial elements
    assert X[:, :2].min() >= -1e-15  # quarter model: x, y >= 0
    assert np.abs(U[0]).max() == 0.0
    # the symmetry planes are in the band, and their normal displacement stays exactly zero
    on_x, on_y = np.abs(X[:, 0]) < 1e-12, np.abs(X[:, 1]) < 1e-12
    assert on_x.sum() > 0 and on_y.sum() > 0
    assert np.abs(U[:, on_x, 0]).max() == 0.0 and np.abs(U[:, on_y, 1]).max() == 0.0
    assert np.abs(U[-1, :, 2]).max() > 1e-6  # the wave has passed the cut [m]


def test_submodel_scene_keeps_kind_and_symmetry(tiny):
    sc, _, _, _ = tiny
    m = ExplicitModel(submodel_scene(sc, 1e-3, 4e-3, end_time=1e-6))
    assert m.kind == "3d" and m.rm.symmetry == "quarter" and m.multiplicity == 4
    # the cut planes are the rods' flat far ends at z = ∓L_s (the cap blend vanishes there)
    x = m.V.tabulate_dof_coordinates()
    for tag, z in (("rod1_end", -L_S), ("rod2_end", L_S)):
        nodes = dolfinx.fem.locate_dofs_topological(m.V, 2, m.rm.facet_tags.find(m.tags[tag]))
        assert nodes.size > 0 and np.allclose(x[nodes, 2], z, rtol=0, atol=1e-15)
    assert m.rm.n_axial == (3, 3)


def test_driving_reproduces_global_3d(tiny):
    """Submodel meshed like the global model (1 mm across, 4 mm along, same step) reproduces its contact force.

    The nodes coincide except for the cap mapping, which blends over the whole rod (48 mm globally, 12 mm in
    the submodel): measured 2.4e-4 in peak force, 3.9e-4 in the history (axisymmetric analogue 1.8e-4)."""
    sc, g, res, path = tiny
    sub = run_submodel(sc, path, 1e-3, 4e-3, dt=g.dt, level="global-like")
    Fg, Fs = res.history["contact_force"], sub.result.history["contact_force"]
    assert sub.summary["dofs"] < g.n_global / 3
    assert sub.summary["peak_contact_force"] == pytest.approx(res.summary["peak_contact_force"], rel=1e-3)
    assert np.abs(Fg - Fs).max() <= 1e-3 * Fg.max()
    assert sub.summary["contact_radius"] == pytest.approx(res.summary["contact_radius"], rel=1e-3)


@pytest.fixture(scope="module")
def non_nested_driver(tiny):
    sc, _, _, path = tiny
    return CutDriver(ExplicitModel(submodel_scene(sc, H_NN, end_time=5e-5)), path)


def test_non_nested_cut_interpolation_3d(tiny, non_nested_driver):
    """h = 0.7 mm: the cut nodes fall inside global cells, on the symmetry planes, and (on the circle,
    12 against 8 arc cells per quadrant) up to 0.027 mm outside the band's polygonal section."""
    import h5py

    d = non_nested_driver
    with h5py.File(tiny[3]) as f:
        X, U, T = f["nodes"][()], f["u"][()], f["times"][()]
    # interpolation reproduces linear fields, extrapolated circle nodes included (isoparametric Q1)
    assert np.abs(d.W @ X - d.cut_x).max() <= 1e-12 * L_S
    r = np.hypot(d.cut_x[:, 0], d.cut_x[:, 1])
    R = 6.35e-3
    rows = np.unique(d.W.tocoo().row[d.W.tocoo().data < -1e-12])  # extrapolated: only on the circle
    assert rows.size > 0 and np.allclose(r[rows], R, rtol=1e-9)
    assert -MAX_EXTRAPOLATION < d.w_min < -1e-3
    # symmetry planes: zero normal displacement at all times; on the axis: the recorded displacement
    t = 0.3 * T[300] + 0.7 * T[301]
    u = d.displacement(t)
    assert np.abs(u[np.abs(d.cut_x[:, 0]) < 1e-12, 0]).max() <= 1e-15 * np.abs(u).max()
    assert np.abs(u[np.abs(d.cut_x[:, 1]) < 1e-12, 1]).max() <= 1e-15 * np.abs(u).max()
    on_axis = np.flatnonzero(r < 1e-12)
    assert on_axis.size == 2  # one per rod
    for i in on_axis:
        j = np.flatnonzero(np.linalg.norm(X - d.cut_x[i], axis=1) < 1e-12)
        assert j.size == 1
        assert np.allclose(u[i], 0.3 * U[300, j[0]] + 0.7 * U[301, j[0]], rtol=1e-12, atol=1e-18)


def test_non_nested_submodel_3d(tiny):
    """The 0.7 mm submodel at the global's penalty stiffness: the Hertz patch (a = 1.8 mm) spans ~2 global
    cells, so the finer tip changes the force (measured -4.8% peak, contact duration -0.5%)."""
    sc, g, res, path = tiny
    h_tip = L_S / math.ceil(L_S / H_NN)  # 18 elements of 0.667 mm along L_s
    sub = run_submodel(sc.with_overrides(f"submodel.penalty={h_tip / 4e-3!r}"), path, H_NN, level="non-nested")
    s = sub.summary
    assert s["penalty"] == pytest.approx(g.ε_pen, rel=1e-9)
    assert s["peak_contact_force"] == pytest.approx(res.summary["peak_contact_force"], rel=0.06)
    assert s["contact_duration"] == pytest.approx(res.summary["contact_duration"], rel=0.01)
    # σ_r: one row of 4 Gauss points per Rod-1 tip cell, compressive under the contact centre
    σ = sub.sigma_r
    n_c, n_r, _ = section_counts(sc.rod1.diameter / 2, H_NN)
    assert σ["r"].size == 4 * (n_c**2 + 4 * n_c * n_r) // 4 and np.all(np.isfinite(σ["sigma_r"]))  # quarter
    assert np.all(σ["sigma_r"][σ["r"] < 0.5e-3] < 0)


@pytest.mark.parametrize("kind", ["axisymmetric", "3d"])
def test_surface_gauss_stress_linear_field(kind):
    """u = (a r e_r, b z): σ_rr = 2(λ + μ) a + λ b at every Gauss point, for both kinds (one code path);
    the kept points are the layer nearest the tip, (½ - ½/√3) h_tip deep up to the cap's bending."""
    from rods.fe.submodel import surface_gauss_stress

    extra = TINY if kind == "3d" else [s for s in TINY if "kind" not in s and "symmetry" not in s]
    m = ExplicitModel(submodel_scene(load_scene(PAPER, extra), 1e-3, 4e-3, end_time=1e-6))
    a, b = 1e-4, -3e-4  # [-]
    x = m.V.tabulate_dof_coordinates()[: m.n_local // m.bs]
    u = np.zeros((x.shape[0], m.bs))
    u[:, : m.bs - 1] = a * x[:, : m.bs - 1]  # radial: a (x, y) in 3D, a r axisymmetric
    u[:, -1] = b * x[:, m.bs - 1]
    out = surface_gauss_stress(m, u.ravel())
    λ, μ = m.scene.rod1.material.lame
    assert out["r"].size > 0
    assert np.allclose(out["sigma_r"], 2 * (λ + μ) * a + λ * b, rtol=1e-9)
    assert np.all(np.diff(out["r"]) >= 0)
    g = 0.5 - 0.5 / math.sqrt(3.0)  # the far layer would be 0.79 h_tip deep
    assert np.all((out["depth"] > 0.9 * g * 4e-3) & (out["depth"] < 1.02 * g * 4e-3))


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which(str(MPIRUN)) is None, reason="no mpirun")
def test_serial_and_mpi_submodel_3d_agree(tmp_path):
    """CLI end to end in 3D: global --record-cut, then the non-nested submodel on 1 and 2 ranks."""
    g = tmp_path / "g"
    p = run_workflow("global.py", [*set_args(TINY), "--record-cut", "--out", str(g)])
    assert p.returncode == 0, p.stderr
    args = ["--global", str(g), "--size", str(H_NN), "--end-time", "6e-5"]
    p1 = run_workflow("submodel.py", [*args, "--out", str(tmp_path / "s")])
    p2 = run_workflow("submodel.py", [*args, "--out", str(tmp_path / "p")], ranks=2)
    assert p1.returncode == 0, p1.stderr
    assert p2.returncode == 0, p2.stderr
    h1, h2 = io.read_history(tmp_path / "s" / "history.csv"), io.read_history(tmp_path / "p" / "history.csv")
    F1, F2 = h1["contact_force"], h2["contact_force"]
    assert F1.max() > 1000 and np.abs(F1 - F2).max() <= 1e-9 * F1.max()
    s1, s2 = (json.loads((tmp_path / d / "summary.json").read_text()) for d in ("s", "p"))
    assert s2["ranks"] == 2 and s1["cut_nodes"] == s2["cut_nodes"]
    σ1, σ2 = (io.read_history(tmp_path / d / "sigma_r.csv") for d in ("s", "p"))
    assert σ1["r"].size > 0 and np.allclose(σ1["sigma_r"], σ2["sigma_r"], rtol=1e-8, atol=1.0)
