"""The explicit model (rods.fe.model.ExplicitModel), one code path for both kinds: mass, stiffness, stable
step, conservation, summary contract, MPI; then what only one kind has (axisymmetric: validation against
the analytical model, bulk viscosity, ω_max against the dense eigenvalue; 3D: the hexahedral O-grid,
symmetry models, off-axis impacts). Coarse meshes and short rods keep the default subset fast; full-length
cases are ``slow``."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import dolfinx
import numpy as np
import pytest
import ufl

from rods import analytical, hertz, io, metrics
from rods.fe import layout
from rods.fe.explicit import EIGEN_TOL
from rods.fe.layout import BUTTERFLY_ANGLE, butterfly
from rods.fe.mesh import TAGS
from rods.fe.mesh3d import TAGS_3D, Placement, section_counts
from rods.fe.model import ExplicitModel
from rods.scene import SceneError, load_scene

from ..conftest import MPIRUN, PAPER, PY, ROOT, SCENES, run_workflow, set_args

# per kind: a coarse model (axisymmetric: paper rods, 4 mm x 1 mm; 3D: short rods, 4 mm x 1 mm hexahedra, ~22k DOFs)
COARSE = {
    "axisymmetric": ["fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=3e-4"],
    "3d": [
        "fe.kind='3d'",
        "fe.axial_size=4e-3",
        "fe.radial_size=1e-3",
        "rod1.length=0.05",
        "rod2.length=0.1",
        "simulation.end_time=1e-4",
    ],
}
KINDS = list(COARSE)


def coarse(kind: str, *extra: str):
    return load_scene(PAPER, [*COARSE[kind], *extra])


@pytest.fixture(scope="module", params=KINDS)
def model(request) -> ExplicitModel:
    return ExplicitModel(coarse(request.param))


@pytest.fixture(scope="module")
def result(model):
    return model.run()


def _rod_entries(model: ExplicitModel, rod: int, comp: int) -> np.ndarray:
    V, rm = model.V, model.rm
    tags = TAGS_3D if model.kind == "3d" else TAGS
    nodes = dolfinx.fem.locate_dofs_topological(V, rm.mesh.topology.dim, rm.cell_tags.find(tags[f"rod{rod}"]))
    nodes = nodes[nodes < V.dofmap.index_map.size_local]
    return nodes * model.bs + comp


def _volume(model: ExplicitModel, rod: int) -> float:
    """Meshed volume of a rod [m^3] (3D)."""
    dx = ufl.Measure("dx", domain=model.rm.mesh, subdomain_data=model.rm.cell_tags)
    v = dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * dx(TAGS_3D[f"rod{rod}"])))
    return model.comm.allreduce(v)


# ----------------------------------------------------------------------------------------------
# both kinds
# ----------------------------------------------------------------------------------------------
def test_mesh_cells_and_blocks(model):
    """Structured meshes: quadrilaterals n_radial x (n_1 + n_2) axisymmetric, a hexahedral O-grid in 3D
    (n_c² core + 4 n_c n_r ring cells per section); K in bs x bs node blocks, bs = gdim."""
    rm = model.rm
    n_cells = rm.mesh.topology.index_map(rm.mesh.topology.dim).size_global
    if model.kind == "3d":
        assert rm.mesh.topology.cell_type == dolfinx.mesh.CellType.hexahedron
        assert model.bs == 3 and model.axial == 2
        n_c, n_r, _ = section_counts(model.scene.rod2.diameter / 2, model.scene["fe.radial_size"])
        assert n_cells == (n_c * n_c + 4 * n_c * n_r) * sum(rm.n_axial)
    else:
        assert rm.mesh.topology.cell_type == dolfinx.mesh.CellType.quadrilateral
        assert model.bs == 2 and model.axial == 1
        assert n_cells == rm.n_radial * sum(rm.n_axial)
    assert model.K.getBlockSize() == model.bs


def test_lumped_mass_positive_and_totals(model):
    """Row-sum lumped masses are positive (on the axis too) and sum to each rod's mass: Rod 2 a cylinder on
    the section (3D: the polygon of 4 n_core rim nodes placed to hold the circle's area), Rod 1 the cylinder less
    the cap height plus the spherical cap (axisymmetric: meshed with straight chords, rel 1e-4)."""
    sc = model.scene
    assert np.all(model.mass > 0)
    if model.kind == "axisymmetric":
        assert model.axis_r.size > 0 and np.all(model.mass[model.axis_r] > 0)  # row-sum keeps axis nodes
    R = sc.rod2.diameter / 2
    section = math.pi * R**2  # 3D: the polygon of 4 n_core rim nodes at rods.fe.mesh3d.area_radius holds it
    r, h = sc.rod1.tip_radius, sc.rod1.cap_height
    vol = math.pi * R**2 * (sc.rod1.length - h) + math.pi * h**2 * (3 * r - h) / 3
    for comp in range(model.bs):
        m2 = model.mass[_rod_entries(model, 2, comp)].sum()
        assert m2 == pytest.approx(sc.rod2.material.density * section * sc.rod2.length, rel=1e-10)
        m1 = model.mass[_rod_entries(model, 1, comp)].sum()
        if model.kind == "3d":
            assert m1 == pytest.approx(sc.rod1.material.density * _volume(model, 1), rel=1e-10)
        else:
            assert m1 == pytest.approx(sc.rod1.material.density * vol, rel=1e-4)
    if model.kind == "3d":  # on the polygonal section
        assert _volume(model, 1) == pytest.approx(vol * section / (math.pi * R**2), rel=1e-3)


def test_stiffness_kills_rigid_motions(model):
    """K annihilates the rigid translations (axisymmetric: the axial one) and, in 3D, the rotation about z."""
    x, y = model.K.createVecs()
    comps = range(3) if model.kind == "3d" else (model.axial,)
    for comp in comps:
        ones = np.zeros(model.n_local)
        ones[comp :: model.bs] = 1.0
        x.array[:] = ones
        model.K.mult(x, y)
        assert np.abs(y.array).max() <= 1e-10 * model.K.norm(), comp
    if model.kind == "3d":
        coords = model.V.tabulate_dof_coordinates()[: model.n_local // 3]
        rot = np.zeros((len(coords), 3))  # infinitesimal rotation about z: (-y, x, 0)
        rot[:, 0], rot[:, 1] = -coords[:, 1], coords[:, 0]
        x.array[:] = rot.ravel()
        model.K.mult(x, y)
        assert np.abs(y.array).max() <= 1e-9 * model.K.norm() * np.abs(rot).max()


def test_stable_step(model):
    assert 0 < model.dt <= model.scene["fe.dt_fraction"] * model.dt_critical * (1 + 1e-12)
    if model.scene["fe.contact"] == "kinematic":  # no contact stiffness: the bodies' own step (rods.fe.kinematic)
        assert model.dt_critical == model.dt_critical_no_contact
    else:  # the penalty can only stiffen
        assert model.dt_critical <= model.dt_critical_no_contact * (1 + 1e-9)
    lo = 0.3 if model.kind == "3d" else 0.5
    assert lo < model.dt_critical / model.dt_element < 2.0
    assert model.dt_gershgorin <= model.dt_critical * (1 + 1e-9)  # a lower bound (rods.fe.timestep)
    assert model.steps * model.dt >= model.scene.end_time * (1 - 1e-9) > (model.steps - 1) * model.dt


ENERGY_TOL = {"axisymmetric": 1e-5, "3d": 1e-5}  # energy balance error of the coarse runs [-]
MASS_TOL = {"axisymmetric": 3e-3, "3d": 2e-2}  # meshed against nominal Rod-1 mass [-]


def test_conservation_and_contract(model, result):
    s, h = result.summary, result.history
    assert s["model"] == model.model_name and all(k in s for k in io.SUMMARY_KEYS)
    p = h["momentum"]
    assert np.abs(p - p[0]).max() <= 1e-10 * abs(p[0])
    assert s["energy_error"] < ENERGY_TOL[model.kind]
    assert h["contact_force"].max() > 1000  # contact did happen
    E = h["kinetic_energy"] + h["strain_energy"] + h["contact_energy"]
    # at t = 0 only Rod 1 moves: E0 = ½ M1 s1² and p0 = M1 s1 with M1 its lumped axial mass (the recorder's
    # mid-step products against the mass vector), and M1 is the nominal ρ A L1 less the cap (< 0.3%) and, in 3D,
    # the polygonal section's lost area (measured 1.2% at 1 mm elements on the 6.35 mm radius)
    sc = model.scene
    M1 = model.multiplicity * model.mass[_rod_entries(model, 1, model.axial)].sum()
    # (rel 1e-4: the kinematic contact's impulse on the apex pair at step 0 enters the first mid-step product;
    # measured 2e-5 in 3D)
    assert E[0] == pytest.approx(0.5 * M1 * sc.speed**2, rel=1e-4)
    assert p[0] == pytest.approx(M1 * sc.speed, rel=1e-12)
    assert M1 == pytest.approx(sc.rod1.mass, rel=MASS_TOL[model.kind])
    assert s["scene_values"]["impact"]["speed"] == sc.speed
    if model.kind == "axisymmetric":
        assert h["strain_energy"].max() > 0.1 * E[0]
        return
    for key in ("rod2_mid_strain_plus_x", "rod2_mid_strain_minus_x", "contact_centroid_x", "contact_radius_max"):
        assert key in h
    # centric impact: no bending, patch centred on the axis
    assert s["midpoint_peak_bending_strain"] < 1e-9 * abs(s["midpoint_peak_strain"])
    assert abs(s["contact_centroid_x"]) < 1e-12
    # contact radius r = sqrt(area/π) of the active nodal area
    assert s["contact_radius"] == pytest.approx(math.sqrt(s["contact_area_nodal"] / math.pi))


def _run_cli(kind: str, out: Path, extra: list[str], ranks: int = 1) -> subprocess.CompletedProcess:
    return run_workflow("global.py", [*set_args([*COARSE[kind], *extra]), "--out", str(out)], ranks, timeout=300)


# (kind, ranks, overrides): 3D offset so that the cap and the face may sit on different ranks (the pairing is
# searched over the allgathered face)
MPI_CASES = [
    ("axisymmetric", 2, ["simulation.end_time=2.5e-4"]),
    # 3 ranks (an odd partition) oversubscribe 2 cores: 16 s on 2026-11-28's machine, in the slow suite
    pytest.param("axisymmetric", 3, ["simulation.end_time=2.5e-4"], marks=pytest.mark.slow),
    ("3d", 2, ["simulation.end_time=6e-5", "impact.offset=1e-3"]),
    # the penalty law with its contact damping (the dissipation is evaluated identically on every rank), and the bulk
    # viscosity (its K v from the differenced products, rods.fe.explicit)
    # 12 s, in the slow suite
    pytest.param(
        "axisymmetric",
        2,
        ["simulation.end_time=2.5e-4", "fe.contact=penalty", "fe.bulk_viscosity=0.06"],
        marks=pytest.mark.slow,
    ),
]


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which(str(MPIRUN)) is None, reason="no mpirun")
@pytest.mark.parametrize(
    ("kind", "ranks", "extra"), MPI_CASES, ids=["axisymmetric-2", "axisymmetric-3", "3d-2", "penalty-bulk-damped-2"]
)
def test_serial_and_mpi_histories_agree(tmp_path, kind, ranks, extra):
    """Histories of 1 and 2 or 3 ranks agree to rel 1e-9 of each column's largest magnitude (energies, from
    velocity increments with cancellation: 1e-8; contact centroids [m]: absolute against the rod radius)."""
    p1 = _run_cli(kind, tmp_path / "s", extra)
    p2 = _run_cli(kind, tmp_path / "p", extra, ranks=ranks)
    assert p1.returncode == 0, p1.stderr
    assert p2.returncode == 0, p2.stderr
    h1, h2 = io.read_history(tmp_path / "s" / "history.csv"), io.read_history(tmp_path / "p" / "history.csv")
    assert json.loads((tmp_path / "p" / "summary.json").read_text())["ranks"] == ranks
    for k in h1:
        scale = 6.35e-3 if k.startswith("contact_centroid") else max(np.abs(h1[k]).max(), 1e-300)
        tol = 1e-8 if k.endswith("energy") else 1e-9
        assert np.abs(h1[k] - h2[k]).max() <= tol * scale, k


@pytest.mark.parametrize(("kind", "extra", "match"), [
    ("axisymmetric", ["fe.dt=1e-6"], "stable limit"),
    ("3d", ["fe.symmetry='quarter'", "impact.tilt=0.01"], "fe.symmetry"),
])  # fmt: skip
def test_cli_exit_2_on_refused_scene(tmp_path, kind, extra, match):
    """A scene the model refuses (unstable fe.dt; quarter symmetry of a tilted impact): exit 2, no summary."""
    p = subprocess.run(
        [str(PY), "workflows/global.py", *set_args([*COARSE[kind], *extra]), "--out", str(tmp_path / "o")],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert p.returncode == 2 and match in p.stderr
    assert not (tmp_path / "o" / "summary.json").exists()


# ----------------------------------------------------------------------------------------------
# axisymmetric
# ----------------------------------------------------------------------------------------------
def test_requested_dt_above_limit_refused():
    with pytest.raises(SceneError, match="stable limit"):
        ExplicitModel(coarse("axisymmetric", "fe.dt=1e-6"))


HEMISPHERE = ("rod1.tip_radius=0.00635", "fe.radial_size=0.5e-3", "simulation.end_time=1e-6")  # tip = d/2


@pytest.mark.parametrize("tip_radius", [0.00635, 0.0066, 0.035, math.inf])
def test_butterfly_layout_is_on_the_cap_and_convex(tip_radius):
    """The butterfly (rods.fe.layout.butterfly) only above its rim angle; P and E on the sphere, the arcs R - t and
    cap - t long (so the blocks' edges match), every block a convex quadrilateral."""
    rod = load_scene(PAPER, [f"rod2.tip_radius={tip_radius}", "rod1.tip_radius=0.035"]).rod2
    b = butterfly(rod)
    R = rod.diameter / 2
    if math.isinf(tip_radius) or R / tip_radius <= math.sin(BUTTERFLY_ANGLE):
        assert b is None
        return
    p = {k: np.array(v) for k, v in b.points.items()}
    for k in ("A", "P", "E"):
        assert np.linalg.norm(p[k] - p["Oc"]) == pytest.approx(tip_radius, rel=1e-12)
    assert b.arcs == pytest.approx((R - b.t, rod.cap_height - b.t), rel=1e-12)
    for quad in ("APCD", "PEGC", "DCGO"):
        v = [p[k] for k in quad]
        cross = lambda a, b: a[0] * b[1] - a[1] * b[0]  # noqa: E731
        turns = [cross(v[i + 1] - v[i], v[(i + 2) % 4] - v[i + 1]) for i in range(-1, 3)]
        assert all(x > 0 for x in turns) or all(x < 0 for x in turns), quad


def test_hemispherical_tip_keeps_a_usable_step(monkeypatch):
    """A hemispherical tip (radius d/2): one transfinite block puts a 180° corner where the arc meets the
    cylinder, and that element set the step (0.95 ns against 19 ns nominal on the paper's 0.15 mm auto mesh:
    277 402 steps for the contact phase). The butterfly keeps the step within a factor 2 of a flat-ish tip's on
    the same sizes, is all quadrilaterals, and meshes the rod's mass (cylinder + hemisphere, chords: rel 2e-3)."""
    m = ExplicitModel(coarse("axisymmetric", *HEMISPHERE))
    flat = ExplicitModel(coarse("axisymmetric", *HEMISPHERE[1:]))
    assert m.rm.mesh.topology.cell_type == dolfinx.mesh.CellType.quadrilateral
    assert m.dt_critical > 0.5 * flat.dt_critical
    sc = m.scene
    R = sc.rod1.diameter / 2
    vol = math.pi * R**2 * (sc.rod1.length - R) + 2 / 3 * math.pi * R**3
    m1 = m.mass[_rod_entries(m, 1, m.axial)].sum()
    assert m1 == pytest.approx(sc.rod1.material.density * vol, rel=2e-3)
    monkeypatch.setattr(layout, "BUTTERFLY_ANGLE", math.pi / 2)  # the single block, as before
    assert ExplicitModel(coarse("axisymmetric", *HEMISPHERE)).dt_critical < 0.2 * m.dt_critical


def test_bulk_viscosity_dissipates_and_balances():
    r = ExplicitModel(coarse("axisymmetric", "fe.bulk_viscosity=0.06", "simulation.end_time=1.5e-4")).run()
    assert r.summary["energy_error"] < 1e-6
    assert r.history["dissipated_energy"][-1] > 0


def test_summary_against_analytical(model, result):
    if model.kind != "axisymmetric":
        pytest.skip("the 3D coarse model has short rods")
    s = result.summary
    a = analytical.simulate(model.scene)
    # measured on this coarse mesh: +0.38%, -0.14 µs, +0.57%; the duration is the contact's (Rod 1's tip radius
    # doubled or halved moved it by -1.6% and +2.3%, which the old 20 µs bound let pass: a review)
    assert s["peak_contact_force"] == pytest.approx(a.summary["peak_contact_force"], rel=0.01)
    assert abs(s["contact_duration"] - a.summary["contact_duration"]) < 1e-6  # [s]
    assert s["midpoint_peak_strain"] == pytest.approx(a.summary["midpoint_peak_strain"], rel=0.015)
    # the rigid-body velocities at the end, by the analytical model's definition (the contact impulse on the rods'
    # masses): Rod 2's, the impulse itself, within 1% of the 1D model's (this 4 mm mesh: -0.72%; the default mesh
    # -0.06%, equal to the per-rod momentum of the FE's own nodes, a fuzz, 2026-12-07). Rod 1's, v0 less the same
    # impulse over its mass, is a difference of near-equal terms (-6.4% here, -0.52% on the default mesh)
    assert s["rigid_velocity_rod2"] == pytest.approx(a.summary["rigid_velocity_rod2"], rel=0.01)  # [m/s]


def _graded_or_uniform(base: list[str], mode: str) -> tuple[int, dict, np.ndarray]:
    """(DOFs, summary, Rod 2's midpoint velocity) of the paper scene with ``base`` at fe.radial_grading ``mode``."""
    m = ExplicitModel(load_scene(PAPER, [*base, f"fe.radial_grading='{mode}'"]))
    r = m.run()
    return m.n_global, r.summary, r.history["rod2_mid_velocity"]


def test_a_graded_global_answers_as_the_uniform_one():
    """fe.radial_grading "graded" (rods.fe.layout.radial_columns) against "uniform" on the same sizes (short paper
    rods at 1 m/s, 0.125 mm across, 1 mm along; a_P = 0.84 mm, the core 2.6 mm): 31 elements across instead of 52,
    the same first contact: peak force within 0.3% (measured +0.095%), duration within 0.1 µs (0.009 µs), both
    conserving energy (3e-11 and 6e-11 measured), and the midpoint's velocity history within 1.5% of its peak
    (measured over 400 µs: 0.64%, where halving the uniform mesh's radial size moves it by 0.76%)."""
    base = ["rod1.length=0.07", "rod2.length=0.1", "impact.speed=1.0", "fe.axial_size=1e-3",
            "fe.radial_size=0.125e-3", "simulation.end_time=2e-4", "fe.radial_coarsening='none'"]  # fmt: skip
    (n_u, u, v_u), (n_g, g, v_g) = (_graded_or_uniform(base, mode) for mode in ("uniform", "graded"))
    assert v_u.shape == v_g.shape and np.abs(v_g - v_u).max() < 0.015 * np.abs(v_u).max()
    assert g["mesh"]["graded"] == [True, True] and u["mesh"]["graded"] == [False, False] and n_g < 0.7 * n_u
    assert g["mesh"]["core_radius"] >= 3 * 0.84e-3 and g["mesh"]["radial_size"] == pytest.approx(0.125e-3)
    assert g["peak_contact_force"] == pytest.approx(u["peak_contact_force"], rel=3e-3)
    assert abs(g["contact_duration"] - u["contact_duration"]) < 0.1e-6
    assert max(g["energy_error"], u["energy_error"]) < 1e-9


def test_a_coarsened_global_answers_as_the_full_one():
    """fe.radial_coarsening "auto" (rods.fe.layout.coarsening) against "none" on the same sizes (short paper rods at
    1 m/s, 0.125 mm across, 1 mm along: 51 to 53 elements across merge into 17 and 18 from 25.4 mm past the
    tips): the same step (the tip's, to 1e-6), the same first contact: peak force within 0.1%, duration within
    0.1 µs, both conserving energy, and the midpoint's velocity history within 1.5% of its peak, on under 0.65 of
    the DOFs (these rods are short: a third of them keeps the columns). Measured 2026-12-06: the same step to 1e-13,
    force +0.0017%, duration +0.0035 µs, velocity 0.33% (halving the full mesh's size across moves it by 0.76%),
    0.59 of the DOFs."""
    base = ["rod1.length=0.07", "rod2.length=0.1", "impact.speed=1.0", "fe.axial_size=1e-3",
            "fe.radial_size=0.125e-3", "simulation.end_time=2e-4", "fe.radial_grading='uniform'"]  # fmt: skip
    runs = {}
    for mode in ("none", "auto"):
        m = ExplicitModel(load_scene(PAPER, [*base, f"fe.radial_coarsening='{mode}'"]))
        r = m.run()
        runs[mode] = (m.n_global, m.dt, r.summary, r.history["rod2_mid_velocity"])
    (n_f, dt_f, f, v_f), (n_c, dt_c, c, v_c) = runs["none"], runs["auto"]
    assert dt_c == pytest.approx(dt_f, rel=1e-6) and n_c < 0.65 * n_f
    from_ = pytest.approx(0.0254, abs=1e-3)  # [m] the first row boundary past 2 diameters
    assert c["mesh"]["coarsened"] == [{"from": from_, "across": 18}, {"from": from_, "across": 17}]
    assert "coarsened" not in f["mesh"]
    assert v_c.shape == v_f.shape and np.abs(v_c - v_f).max() < 0.015 * np.abs(v_f).max()
    assert c["peak_contact_force"] == pytest.approx(f["peak_contact_force"], rel=1e-3)
    assert abs(c["contact_duration"] - f["contact_duration"]) < 0.1e-6
    assert max(c["energy_error"], f["energy_error"]) < 1e-9


@pytest.mark.slow  # 22 s; the default suite builds the graded butterfly (tests/fe/test_mesh.py) and runs a graded flat
def test_a_graded_butterfly_answers_as_the_uniform_one():
    """A hemispherical Rod 1 (the butterfly cap, rods.fe.layout.graded_butterfly) graded against uniform on the same
    sizes (short paper rods at 0.5 m/s, 0.1 mm across, 1 mm along): the same first contact, peak force within 0.3%
    (measured +0.016%) and duration within 0.2 µs (-0.028 µs), both conserving energy (1e-11), the midpoint's
    velocity history within 1.5% of its peak (0.20%), on under 0.6 of the uniform mesh's DOFs (15.3k against 34.3k)."""
    base = ["rod1.length=0.07", "rod2.length=0.1", "impact.speed=0.5", "fe.axial_size=1e-3", "rod1.tip_radius=0.00635",
            "fe.radial_size=0.1e-3", "simulation.end_time=1.1e-4"]  # fmt: skip
    (n_u, u, v_u), (n_g, g, v_g) = (_graded_or_uniform(base, mode) for mode in ("uniform", "graded"))
    assert g["mesh"]["graded"] == [True, True] and n_g < 0.6 * n_u
    assert v_u.shape == v_g.shape and np.abs(v_g - v_u).max() < 0.015 * np.abs(v_u).max()
    assert g["peak_contact_force"] == pytest.approx(u["peak_contact_force"], rel=3e-3)
    assert abs(g["contact_duration"] - u["contact_duration"]) < 0.2e-6
    assert max(g["energy_error"], u["energy_error"]) < 1e-9


def test_no_fields_unless_asked(tmp_path):
    p = _run_cli("axisymmetric", tmp_path / "none", ["simulation.end_time=2e-5"])
    assert p.returncode == 0, p.stderr
    files = sorted(f.name for f in (tmp_path / "none").iterdir())
    assert files == ["history.csv", "pressure_profile.csv", "summary.json"]
    p = _run_cli("axisymmetric", tmp_path / "fields", ["simulation.end_time=2e-5", "fe.field_interval=1e-5"])
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "fields" / "fields.xdmf").exists()
    # the "fields" effect alone (no fe.field_interval) asks for them too
    effect = ["simulation.end_time=2e-5", "effects=['wave_response', 'fields']"]
    p = _run_cli("axisymmetric", tmp_path / "effect", effect)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "effect" / "fields.xdmf").exists()


@pytest.mark.slow  # ~80 s of the default suite's 5 min 19 s; the main job checks the same scene (make verify, Fig. 4)
def test_paper_scene_validation():
    """The paper scene at default settings (1 mm along, "auto" 0.273 mm across, kinematic contact) against the
    analytical model at its default law (Hertz less the rods' end correction) and the paper's law (~25 s).

    Measured (main job 2026-11-23, results/verification.md): against the default, peak force +0.05%, contact
    duration -0.02 µs, midpoint strain 2.8 µε RMS unaligned over five periods, lag +0.10 µs; energy error 8e-10.
    Against the paper's half-space law: duration -1.48 µs, strain 13.7 µε RMS, of which most is a lead: the FE
    pulse runs 2.6 µs ahead, because that law counts the rods' far field twice and its contact spring is too soft
    at first contact.
    """
    sc = load_scene(PAPER)
    fe = ExplicitModel(sc).run()
    s = fe.summary
    assert s["energy_error"] < 1e-6
    window = metrics.strain_window(sc.rod2)
    an = analytical.simulate(sc)  # the default law
    paper = analytical.simulate(sc.with_overrides(analytical.PAPER_LAW))
    assert (an.summary["contact_law"], paper.summary["contact_law"]) == ("hertz-rod", "hertz")
    lags = {}
    for name, a, rms, duration in ((
        "default", an, 5e-6, 0.5e-6), ("paper", paper, 15e-6, 2e-6)):  # fmt: skip
        strains = (fe.history["time"], fe.history["rod2_mid_strain"], a.history["time"], a.history["rod2_mid_strain"])
        assert s["peak_contact_force"] == pytest.approx(a.summary["peak_contact_force"], rel=0.005), name
        assert abs(s["contact_duration"] - a.summary["contact_duration"]) < duration, name
        assert metrics.rms_difference(*strains, window) < rms, name
        lags[name] = metrics.time_lag(*strains, window, max_lag=10e-6)
    assert abs(lags["default"][0]) < 0.5e-6
    assert -4e-6 < lags["paper"][0] < -1e-6 and lags["paper"][1] < 10e-6  # the FE leads the paper's law
    h = hertz.at_force(s["peak_contact_force"], *hertz.contact_constants(sc.rod1, sc.rod2))
    # the global mesh puts ~4 elements across the patch: measured 2026-12-07 radius -0.19%, peak pressure -4.8% from
    # Hertz at its own force (a band of 0.8-1.5 had let a radius taken at the next node, +26% area, pass: an audit)
    assert abs(s["contact_radius"] / h["contact_radius"] - 1) < 0.03
    assert abs(s["peak_contact_pressure"] / h["peak_pressure"] - 1) < 0.08


def test_omega_max_matches_dense_eigenvalue():
    """SLEPc's ω_max² is an upper estimate of the largest eigenvalue of the dense M^-½ (K + K_c) M^-½ (small
    mesh), above it by at most the Ritz pair's tolerance (rods.fe.explicit.EIGEN_TOL)."""
    m = ExplicitModel(
        load_scene(PAPER, ["rod1.length=0.03", "rod2.length=0.03", "fe.axial_size=3e-3", "fe.radial_size=1.6e-3"])
    )
    K = m.K.convert("dense").getDenseArray().copy()
    n = m.n_local
    Kc = np.zeros((n, n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = 1.0
        m.contact.apply_stiffness(e, Kc[:, j])
    D = np.sqrt(m.inv_mass)
    λ = np.linalg.eigvalsh(D[:, None] * (K + Kc) * D[None, :]).max()
    assert λ * (1 - 1e-12) <= m.ω_max**2 <= λ * (1 + EIGEN_TOL)
    assert np.allclose(Kc, Kc.T)


# ----------------------------------------------------------------------------------------------
# 3D
# ----------------------------------------------------------------------------------------------
def tiny(*extra: str):
    return coarse("3d", *extra)


def _axisymmetric_vs_3d(extra: list[str], symmetry: str = "quarter") -> tuple[dict, dict, float]:
    """(summary 3D, summary axisymmetric, RMS of the midpoint-strain difference over the run). The 3D
    model is a quarter model by default (it reproduces the full model: test_symmetry_models_reproduce_full)."""
    r3 = ExplicitModel(load_scene(PAPER, ["fe.kind='3d'", f"fe.symmetry='{symmetry}'", *extra])).run()
    ra = ExplicitModel(load_scene(PAPER, extra)).run()
    t = r3.history["time"]
    rms = metrics.rms_difference(
        t, r3.history["rod2_mid_strain"], ra.history["time"], ra.history["rod2_mid_strain"], (0.0, t[-1])
    )
    return r3.summary, ra.summary, rms


@pytest.mark.slow  # 12 s; the 3D model's symmetry, offset, tilt and conservation cases are in the default suite
def test_centric_3d_matches_axisymmetric_to_peak():
    """Cheap version of the issue's criterion: paper rods, 4 x 1 mm meshes, up to just past the peak
    force (120 µs). Peak force within 1% (measured 0.70%); midpoint strain RMS within 10 µε (measured
    6.8 µε: the wave front at the midpoint follows the contact stiffness of the coarse tips, which the
    2D node lattice of the 3D cap and the rings of the axisymmetric one resolve differently). Peak time
    within 10 µs: the force plateau is flat to ~0.1% from 70 to 130 µs, so its argmax wanders (measured
    6.4 µs with the kinematic contact)."""
    s3, sa, rms = _axisymmetric_vs_3d(["fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=1.2e-4"])
    assert s3["peak_contact_force"] == pytest.approx(sa["peak_contact_force"], rel=0.01)
    assert rms < 10e-6
    assert s3["peak_force_time"] == pytest.approx(sa["peak_force_time"], abs=10e-6)
    # the 3D tip's nodes are not in rings: its pressure profile names each node's x, y (rows of one r differ)
    p3, pa = s3["pressure_profile"], sa["pressure_profile"]
    assert list(pa) == ["r", "p"] and list(p3) == ["r", "x", "y", "p"]
    assert np.allclose(np.hypot(p3["x"], p3["y"]), p3["r"]) and np.all(np.diff(p3["r"]) >= 0)


@pytest.mark.slow
def test_centric_3d_matches_axisymmetric_paper_rods():
    """Issue #4's comparison on the paper rods over 5 Rod-2 periods at 2 x 0.5 mm (quarter 3D model).

    Measured 2026-11-23 (tips graded by default): peak force -0.24%, midpoint strain RMS 3.57 µε (1.7% of
    the 215 µε peak; the 3D strain trails by 0.34 µs, aligned 3.21 µε); the penalty law gives 3.23 µε. Issue
    #4's 3 µε was met (2.8 µε, recorded under earlier defaults; which change moved it was not bisected); both
    laws now exceed it by about as much."""
    sc = load_scene(PAPER)
    end = 5 * sc.rod2.round_trip_time
    s3, sa, rms = _axisymmetric_vs_3d(["fe.axial_size=2e-3", "fe.radial_size=0.5e-3", f"simulation.end_time={end}"])
    assert s3["peak_contact_force"] == pytest.approx(sa["peak_contact_force"], rel=0.005)
    assert rms < 4e-6


@pytest.fixture(scope="module")
def full_short():
    return ExplicitModel(tiny("simulation.end_time=6e-5", "fe.dt=9e-8")).run()  # one step for all models


@pytest.mark.parametrize("symmetry", ["half", "quarter"])
def test_symmetry_models_reproduce_full(full_short, symmetry):
    r = ExplicitModel(tiny("simulation.end_time=6e-5", "fe.dt=9e-8", f"fe.symmetry='{symmetry}'")).run()
    s, f = r.summary, full_short.summary
    assert s["symmetry"] == symmetry
    assert s["dofs"] < f["dofs"] / (1.7 if symmetry == "half" else 3.0)
    assert s["peak_contact_force"] == pytest.approx(f["peak_contact_force"], rel=1e-6)
    for key in ("contact_force", "rod2_mid_strain", "rod2_mid_strain_minus_x", "kinetic_energy", "momentum"):
        scale = np.abs(full_short.history[key]).max()
        assert np.abs(r.history[key] - full_short.history[key]).max() <= 1e-6 * scale, key
    assert s["contact_area_nodal"] == pytest.approx(f["contact_area_nodal"], rel=1e-9)


def test_symmetry_contradictions_refused():
    with pytest.raises(SceneError, match="quarter symmetry needs"):
        ExplicitModel(tiny("fe.symmetry='quarter'", "impact.offset=1e-3"))


def test_offset_impact(model, result):
    """Eccentric impact (e = 2 mm, half model): momentum exact, patch follows the offset, Rod 2 bends."""
    if model.kind != "3d":
        pytest.skip("off-axis impacts need the 3D model")
    e = 2e-3
    r = ExplicitModel(tiny(f"impact.offset={e}", "fe.symmetry='half'")).run()
    centric = result  # the full 3D model
    s, h = r.summary, r.history
    p = h["momentum"]
    assert np.abs(p - p[0]).max() <= 1e-10 * abs(p[0])
    assert s["energy_error"] < 1e-6
    assert s["contact_centroid_x"] == pytest.approx(e, abs=0.3e-3)  # sphere on a flat: contact under the apex
    assert s["contact_centroid_y"] == 0.0
    bend = s["midpoint_peak_bending_strain"]
    assert bend > 0.1 * abs(s["midpoint_peak_strain"])  # plus_x != minus_x
    # the +x side (under the impact) is compressed more than the -x side, on average over the run: the first
    # flexural arrival on these short rods (20-30 µs) is dispersive and briefly compresses -x more (measured)
    assert np.mean(h["rod2_mid_strain_plus_x"] - h["rod2_mid_strain_minus_x"]) < 0
    # same axial momentum transfer, a little softer than centric (measured -2.9% on this mesh; the old rel=0.1 took
    # either sign: a review)
    assert -0.06 < s["peak_contact_force"] / centric.summary["peak_contact_force"] - 1 < -0.01


def test_tilt_impact():
    """Tilted Rod 1 (θ = 0.02 rad about y): the sphere touches at x ≈ -r1 sin θ; bending appears."""
    θ = 0.02
    r = ExplicitModel(tiny(f"impact.tilt={θ}", "fe.symmetry='half'")).run()
    s = r.summary
    x_touch = -r.summary["scene_values"]["rod1"]["tip_radius"] * math.sin(θ)
    assert s["contact_centroid_x"] == pytest.approx(x_touch, abs=0.35e-3)
    assert s["midpoint_peak_bending_strain"] > 0.02 * abs(s["midpoint_peak_strain"])
    assert abs(s["rod1_placement_dz"]) < 2e-5  # rotation about the apex, then the gap closed
    p = r.history["momentum"]
    assert np.abs(p - p[0]).max() <= 1e-10 * abs(p[0])


def _brute_force_contact(R1: float, R2: float, e: float, θ: float, half_width: float) -> tuple[float, float]:
    """The first contact of the placed tips found by search: Rod 1's tip profile (x-z plane, body at z < 0) placed
    by rods.fe.mesh3d.Placement, its point of least gap to Rod 2's tip (body at z > 0): the distances of that
    point from Rod 1's axis (its reference x) and from Rod 2's (its placed x)."""
    x = np.linspace(-half_width, half_width, 400_001)  # [m] 50 nm apart on a 20 mm face

    def cap(r: float, ρ: np.ndarray) -> np.ndarray:
        return np.zeros_like(ρ) if math.isinf(r) else r - np.sqrt(np.maximum(r * r - ρ * ρ, 0.0))

    ref = np.stack([x, np.zeros_like(x), -cap(R1, np.abs(x))], axis=1)
    placed = Placement(θ, e, 0.0).apply(ref)
    i = int(np.argmin(cap(R2, np.abs(placed[:, 0])) - placed[:, 2]))
    return abs(x[i]), abs(placed[i, 0])


@pytest.mark.parametrize(
    "R1, R2, e, θ",
    [
        (0.035, math.inf, 0.0, 0.05),  # the paper's tips tilted: x = -R1 sin θ
        (0.035, math.inf, 3e-3, 0.05),  # tilt and offset partly cancel
        (0.035, 0.035, 2e-3, 0.03),  # two spheres
        (0.02, 0.05, 0.0, 0.08),
        (math.inf, 0.035, 1e-3, 0.04),  # a flat, tilted Rod 1 on a curved Rod 2
    ],
)
def test_first_contact_offsets_match_the_placed_mesh_geometry(R1, R2, e, θ):
    """rods.scene.first_contact_offsets (the scene check that refuses an edge impact before any set-up) against a
    search over the tips placed as the 3D mesh places them: to 2 µm (the search's grid, 50 nm, and the flat tip's
    ill-conditioned minimum)."""
    from rods.scene import first_contact_offsets

    d1, d2 = first_contact_offsets(R1, R2, e, θ)
    b1, b2 = _brute_force_contact(R1, R2, e, θ, 10e-3)
    assert d1 == pytest.approx(b1, abs=2e-6) and d2 == pytest.approx(b2, abs=2e-6)


def test_an_edge_impact_is_refused_with_the_scene():
    """An offset or tilt that puts the first contact beyond a tip face is bad input, refused by the scene (before,
    an offset beyond Rod 2's face passed and failed after the analytical model, in the 3D set-up; one short of it
    ran an edge impact)."""
    with pytest.raises(SceneError, match="impact.offset.*off Rod 2's axis, beyond its tip face"):
        tiny("impact.offset=0.02")
    with pytest.raises(SceneError, match="impact.offset.*off Rod 2's axis"):
        tiny("impact.offset=6.5e-3")  # the cap's apex just past the flat face's rim (6.35 mm)
    with pytest.raises(SceneError, match="impact.tilt.*off Rod 1's axis"):
        tiny("rod1.tip_radius=1.0", "impact.tilt=0.01")  # a 1 m cap's rim is 6.35 mrad from its axis
    assert tiny("impact.offset=5e-3")["impact.offset"] == 5e-3  # on the face: a misaligned impact


def test_scene_files():
    sc = load_scene(SCENES / "paper-3d.toml")
    assert sc["fe.kind"] == "3d" and sc["fe.axial_size"] == 1e-3 and sc["fe.radial_size"] == 0.25e-3
    n_c, n_r, _ = section_counts(sc.rod1.diameter / 2, sc["fe.radial_size"])
    cells = (n_c * n_c + 4 * n_c * n_r) * (math.ceil(sc.rod1.length / 1e-3) + math.ceil(sc.rod2.length / 1e-3))
    assert 1.8e6 < cells < 2.6e6  # "about 2 million hexahedra"
    coarse_3d = load_scene(SCENES / "paper-3d-coarse.toml")
    assert coarse_3d["fe.kind"] == "3d" and coarse_3d.speed == sc.speed and coarse_3d.end_time == sc.end_time


@pytest.mark.slow
@pytest.mark.mpi
@pytest.mark.skipif(shutil.which(str(MPIRUN)) is None, reason="no mpirun")
def test_paper_3d_coarse_scene_vs_analytical(tmp_path):
    """workflows/scenes/paper-3d-coarse.toml on 2 ranks: peak force within 3% of the analytical model."""
    scene = SCENES / "paper-3d-coarse.toml"
    p = subprocess.run(
        [str(MPIRUN), "-n", "2", str(PY), "workflows/global.py", "--scene", str(scene), "--out", str(tmp_path)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert p.returncode == 0, p.stderr
    s = json.loads((tmp_path / "summary.json").read_text())
    a = analytical.simulate(load_scene(scene)).summary
    assert s["peak_contact_force"] == pytest.approx(a["peak_contact_force"], rel=0.03)
    assert abs(s["contact_duration"] - a["contact_duration"]) < 20e-6
    assert s["energy_error"] < 1e-2


@pytest.mark.slow  # ~40 s: two graded globals
def test_a_hemispherical_striker_converges_to_the_analytical_model_with_its_cap():
    """Short paper rods (70 / 100 mm), Rod 1 hemispherical (6.35 mm) at 0.5 m/s: the contact lasts about four of
    Rod 1's round trips, so its mass matters, and its cap holds 2.1 mm less than its 70 mm (rods.scene.Rod.bar_length,
    3% of its mass). The analytical model's default law counts the cap (the bars of the rods' mass, the cap's end
    compliance from the rods.hertz table). The FE's peak force on 0.1 x 1 mm and on 0.05 x 0.5 mm (radial x axial,
    graded) falls towards it, and the first-order extrapolation 2 F_fine - F_coarse lies within 0.5% of it
    (measured: 744.55, 739.33 N, 734.1 N against 736.39 N, -0.31%; a third mesh, 0.025 x 0.25 mm, 736.77 N, gives
    an observed order 1.03), where the paper's bars of length L with the flat end's χ (the model before) give
    746.72 N, 1.7% above the extrapolation."""
    base = ["rod1.length=0.07", "rod2.length=0.1", "impact.speed=0.5", "rod1.tip_radius=0.00635",
            "fe.radial_grading='graded'", "simulation.end_time=1.1e-4"]  # fmt: skip
    s = load_scene(PAPER, base)
    coarse, fine = (
        ExplicitModel(s.with_overrides(f"fe.radial_size={h * 0.1e-3!r}", f"fe.axial_size={h * 1e-3!r}"))
        .run()
        .summary["peak_contact_force"]
        for h in (1.0, 0.5)
    )
    a = analytical.simulate(s).summary
    assert a["contact_law"] == "hertz-rod"
    flat = sum(hertz.rod_end_compliance(replace(r, tip_radius=math.inf), 1e-3) for r in s.rods)  # the flat end's χ
    before = analytical.WaveModel(s.rod1, s.rod2, s.speed, rtol=s["analytical.rtol"], compliance=flat).run(s.end_time)
    F, limit = a["peak_contact_force"], 2 * fine - coarse
    assert abs(fine - F) < abs(coarse - F)
    assert abs(limit / F - 1) < 5e-3 and abs(limit / before.peak()[1] - 1) > 1e-2


def test_the_time_loop_runs_on_one_blas_thread_and_gives_the_threads_back():
    """rods.fe.model.LOOP_BLAS_THREADS: inside the loop every BLAS library the process loaded (NumPy's and SciPy's
    OpenBLAS here) runs one thread, where the kinematic contact's dense LCP solves ran ~300x slower on oversubscribed
    threads under mpirun (a 3D submodel: 23 s against 0.05 s in 232 factorisations); after the run, the caller's
    setting again."""
    from threadpoolctl import threadpool_info, threadpool_limits

    seen = []

    class BlasThreads:
        def after_step(self, step, t, state):  # noqa: ARG002
            if step == 1:
                seen.extend(i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas")

    def threads() -> list[int]:
        return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

    with threadpool_limits(limits=2, user_api="blas"):  # a caller's own setting (this machine's 2 cores)
        before = threads()
        ExplicitModel(coarse("axisymmetric", "simulation.end_time=2e-6")).run(observers=[BlasThreads()])
        after = threads()
    assert seen and set(seen) == {1} and len(seen) == len(before)
    assert after == before and max(before) > 1  # restored: the caller's setting
