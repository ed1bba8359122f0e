"""Array backends of the explicit loop (rods.fe.backend): the NumPy/SciPy backend runs the PETSc path's scheme
(histories equal to 1e-10 of each column's largest magnitude, serial) on the mesh-free toy impact with damping,
the axisymmetric paper scene (30 µs: the contact closing), a 3D half model of an eccentric impact and a
driven submodel; the CuPy backend runs the same code and the same checks (skipped without CuPy and a CUDA
device), and runs them without a GPU on tests/fake_gpu.py's stand-in device (``fake-gpu``: CuPy's refusal of
implicit host/device conversions on NumPy arrays); the scene key ``fe.backend`` and its refusals."""

from __future__ import annotations

import contextlib
import dataclasses
import re
import shutil
from collections.abc import Iterator
from pathlib import Path

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import numpy as np
import pytest
import scipy.sparse
from mpi4py import MPI

from rods.fe import backend
from rods.fe.cut import CutDriver
from rods.fe.explicit import EIGEN_TOL, CentralDifference, stable_step
from rods.fe.model import ExplicitModel
from rods.fe.observers import march
from rods.fe.recorder import Recorder
from rods.fe.submodel import submodel_scene
from rods.scene import SCHEMA, SceneError, load_scene

from .. import fake_gpu
from ..conftest import MPIRUN, PAPER, benchmark, recorded_global, run_workflow, set_args
from .toy import K_CONTACT, MASS, SPEED, bodies, omega_max, petsc_matrix

TOL = 1e-10  # acceptance: relative to each column's largest magnitude (measured: <= 1.3e-11)
R_ROD = 6.35e-3  # rod radius [m]: the scale of the contact centroid (0 to round-off in a centric impact)
GPU = backend.gpu_available()
FAKE = "fake-gpu"  # the CuPy path on tests/fake_gpu.py's stand-in device: its host/device discipline, no GPU needed
ARRAY_BACKENDS = [
    "numpy",
    FAKE,
    pytest.param(
        "cupy",
        marks=pytest.mark.skipif(
            not GPU, reason="CuPy backend: needs CuPy and a CUDA device (pip install rods[gpu] on a GPU machine)"
        ),
    ),
]
# the models' histories also with the CuPy path's order of a kinematic step (its rates before the product) on
# the host: the NumPy backend with the device's overlap (rods.fe.kinematic, "Overlap")
MODEL_BACKENDS = [*ARRAY_BACKENDS, "numpy-overlap"]
THREE_D = [  # half model, eccentric impact: bilinear pairing, off-axis patch, bending (~11k DOFs)
    "fe.kind='3d'",
    "fe.symmetry='half'",
    "impact.offset=1e-3",
    "fe.axial_size=4e-3",
    "fe.radial_size=1e-3",
    "rod1.length=0.05",
    "rod2.length=0.1",
    "simulation.end_time=6e-5",
]


def assert_same_histories(
    ref: dict[str, np.ndarray], other: dict[str, np.ndarray], tol: float = TOL, floors: dict[str, float] | None = None
) -> None:
    """Each column equal to ``tol`` of its largest magnitude (at least ``floors[column]``: a column that is
    round-off itself, e.g. a dissipation that has not started, against the scale it would have)."""
    assert ref.keys() == other.keys()
    for k, a in ref.items():
        scale = R_ROD if k.startswith("contact_centroid") else max(np.abs(a).max(), 1e-300)
        scale = max(scale, (floors or {}).get(k, 0.0))
        assert np.abs(other[k] - a).max() <= tol * scale, (k, np.abs(other[k] - a).max() / scale)


@contextlib.contextmanager
def on(name: str) -> Iterator[backend.Backend]:
    """Backend ``name`` for the block; "numpy-overlap": the NumPy backend with the device's overlap of a kinematic
    step (rods.fe.kinematic, "Overlap"), so that CI runs the CuPy path's order of operations; :data:`FAKE`: the
    CuPy backend on the stand-in device (tests/fake_gpu.py), importable as CuPy inside the block only."""
    if name == "numpy-overlap":
        yield dataclasses.replace(backend.select("numpy", 1), overlap=True)
    elif name == FAKE:
        with fake_gpu.installed():
            be = backend.select("cupy", 1)
            assert be.on_device and be.device == fake_gpu.NAME.decode()
            yield be
    else:
        yield backend.select(name, 1)


def scene_backend(name: str) -> str:
    """The ``fe.backend`` value of backend ``name``."""
    return "cupy" if name == FAKE else name


def rerun(model: ExplicitModel, name: str, **kw):
    """The same model (mesh, K, stable step) marched on backend ``name``."""
    with on(name) as be:
        model.backend = be
        if name == "numpy-overlap":  # the overlap is engaged (a kinematic, undamped, serial model)
            assert model.stepper().overlap
        try:
            return model.run(**kw)
        finally:
            model.backend = backend.PETSC


# ----------------------------------------------------------------------------------------------
# the stepper, mesh-free
# ----------------------------------------------------------------------------------------------
def toy_run(
    be: backend.Backend, steps: int, β: float, ζ: float = 0.0
) -> tuple[dict[str, np.ndarray], CentralDifference]:
    """The toy impact (tests/fe/toy.py) on backend ``be``, damped (bulk β, contact ζ), every step recorded."""
    K, mass, contact = bodies()
    Kc = K.copy()
    Kc[1:3, 1:3] += K_CONTACT * np.array([[1.0, -1.0], [-1.0, 1.0]])
    dt = 0.5 * stable_step(omega_max(Kc, mass))  # [s]: half the limit with the contact closed
    if ζ:
        contact.set_damping(ζ, 1.0 / mass, dt)
    contact.use(be)
    A = petsc_matrix(K) if be is backend.PETSC else scipy.sparse.csr_matrix(K)
    st = CentralDifference(A, mass, 1.0 / mass, dt, np.array([SPEED, SPEED, 0.0, 0.0]), β, contact, be)
    P = scipy.sparse.csr_matrix(([1.0], ([0], [0])), shape=(2, 4))
    rec = Recorder(contact, (P, [("p0_velocity", "p0_strain")]), mass, np.arange(steps + 1), steps, dt,
                   MPI.COMM_SELF, 1, (), be)  # fmt: skip
    assert march(st, range(steps + 1), [rec], rec.is_out) is None
    return rec.history(), st


@pytest.mark.parametrize("ζ", [0.0, 0.2], ids=["undamped-contact", "damped-contact"])
@pytest.mark.parametrize("name", ARRAY_BACKENDS)
def test_toy_impact_same_on_every_backend(name, ζ):
    """Damped toy impact (contact on and off, dissipation, momentum; also with contact damping): the array
    backend's histories equal the PETSc path's to round-off, and its state restores bit for bit."""
    steps, β = 400, 1e-5
    ref, _ = toy_run(backend.PETSC, steps, β, ζ)
    with on(name) as be:
        hist, st = toy_run(be, steps, β, ζ)
        assert ref["contact_force"].max() > 0 and ref["dissipated_energy"][-1] > 0  # the checks can fail
        assert_same_histories(ref, hist)
        saved = st.state()
        assert isinstance(saved["u"], np.ndarray) and np.array_equal(saved["u"], be.to_host(st.u))
        st2 = CentralDifference(scipy.sparse.csr_matrix(bodies()[0]), MASS * np.ones(4), np.ones(4) / MASS, st.dt,
                                np.zeros(4), β, None, be)  # fmt: skip
        st2.restore(saved)
        assert st2.n == st.n and np.array_equal(be.to_host(st2.v), saved["v"])


# ----------------------------------------------------------------------------------------------
# the models
# ----------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def paper():
    """The axisymmetric paper scene (paper mesh, 51.5k DOFs) over 30 µs on the PETSc path (measured to 0.1 ms:
    largest difference 1.2e-11, in the strain energy)."""
    m = ExplicitModel(load_scene(PAPER, ["simulation.end_time=3e-5"]))
    return m, m.run()


@pytest.fixture(scope="module")
def three_d():
    m = ExplicitModel(load_scene(PAPER, THREE_D))
    return m, m.run()


@pytest.mark.parametrize("name", MODEL_BACKENDS)
def test_paper_scene_histories(paper, name):
    model, ref = paper
    assert ref.history["contact_force"].max() > 1000  # the contact closed
    res = rerun(model, name)
    # Rod 2's midpoint is round-off over 30 µs (the wave reaches it at 68 µs): against the scale it would have
    s1 = model.scene.speed  # [m/s]
    floors = {"rod2_mid_velocity": s1, "rod2_mid_strain": s1 / model.scene.rod2.material.wave_speed}
    assert_same_histories(ref.history, res.history, floors=floors)
    assert res.summary["peak_contact_force"] == pytest.approx(ref.summary["peak_contact_force"], rel=TOL)


@pytest.mark.parametrize("name", MODEL_BACKENDS)
def test_3d_histories(three_d, name):
    model, ref = three_d
    assert ref.summary["midpoint_peak_bending_strain"] > 0 and ref.summary["contact_centroid_x"] > 0  # off-axis
    res = rerun(model, name)
    assert_same_histories(ref.history, res.history)
    for k in ("contact_centroid_x", "contact_radius_max", "midpoint_peak_bending_strain"):
        assert res.summary[k] == pytest.approx(ref.summary[k], rel=1e-9), k


@pytest.mark.parametrize("name", MODEL_BACKENDS)
def test_driven_submodel_histories(tmp_path_factory, name):
    """A submodel driven at its cut (CutDriver: prescribed v, external work) by a global run recorded on the same
    backend: the histories equal the PETSc path's, the cut work included."""
    overrides = ["rod1.length=0.1", "rod2.length=0.1", "fe.axial_size=2e-3", "fe.radial_size=1e-3",
                 "simulation.end_time=4e-5", "fe.submodel_length=12e-3"]  # fmt: skip
    sc, _, _, cut = recorded_global(overrides, tmp_path_factory, f"global-{name}")
    sub = ExplicitModel(submodel_scene(sc, 1e-3))
    ref = sub.run(observers=(CutDriver(sub, cut),))
    with on(name) as sub.backend:
        res = sub.run(observers=(CutDriver(sub, cut),))
    assert np.abs(ref.history["external_work"]).max() > 0
    assert_same_histories(ref.history, res.history)


@pytest.mark.parametrize("name", ARRAY_BACKENDS)
def test_model_set_up_on_the_backend(three_d, name):
    """A model set up with ``fe.backend`` = name (K kept as one CSR matrix, never assembled again; on a device
    the step's eigenvalues by Lanczos there): the same stable step as the PETSc path (NumPy: the same SLEPc
    solve, 1e-12; CuPy: its own Lanczos, both upper estimates within EIGEN_TOL of ω_max², so ω within half of
    it), the same Gershgorin bound and the same peak force."""
    ref_model, ref = three_d
    with on(name):
        m = ExplicitModel(load_scene(PAPER, [*THREE_D, f"fe.backend='{scene_backend(name)}'"]))
        assert scipy.sparse.issparse(m.K) and m.K.shape == (m.n_global, m.n_global)
        rel = 1e-12 if name == "numpy" else EIGEN_TOL / 2
        for key in ("ω_max", "ω_max_K"):
            assert getattr(m, key) == pytest.approx(getattr(ref_model, key), rel=rel), key
        assert m.dt_gershgorin == pytest.approx(ref_model.dt_gershgorin, rel=1e-12)
        res = m.run()
    peak = ref.summary["peak_contact_force"]
    assert res.summary["peak_contact_force"] == pytest.approx(peak, rel=max(10 * rel, 1e-9))


def test_global_entry_point_on_the_stand_in_device(tmp_path, monkeypatch):
    """workflows/global.py with fe.backend = 'cupy' on the stand-in device, writing field frames and checkpoints (the
    observers reading the state on the host through HostView), then resumed with --restart from its last
    checkpoint: the PETSc run's histories to the array backends' tolerance, the device named in the summary, the
    frames and the checkpoint on disk."""
    import importlib

    from rods.io import read_data, read_history

    glob = importlib.import_module("global")
    overrides = ["rod1.length=0.05", "rod2.length=0.1", "fe.axial_size=2e-3", "fe.radial_size=1e-3",
                 "simulation.end_time=6e-5", "fe.field_interval=2e-5", "fe.checkpoint_interval=2e-5"]  # fmt: skip
    ref, dev = tmp_path / "petsc", tmp_path / "cupy"
    assert glob.main([*set_args(overrides), "--out", str(ref)]) == 0
    from rods.fe import checkpoint

    with on(FAKE):
        with monkeypatch.context() as m:  # as if killed after its last checkpoint (a finished run removes it)
            m.setattr(checkpoint, "discard", lambda *a: None)
            assert glob.main([*set_args([*overrides, "fe.backend='cupy'"]), "--out", str(dev)]) == 0
        assert list(dev.glob("checkpoint-*.npz")) and (dev / "fields.bp").is_dir()
        assert glob.main([*set_args([*overrides, "fe.backend='cupy'"]), "--out", str(dev), "--restart"]) == 0
    s = read_data(dev / "summary.json")
    assert (s["backend"], s["device"]) == ("cupy", fake_gpu.NAME.decode())
    assert list(dev.glob("fields-restart-*.bp"))  # the resumed run wrote its frames
    assert_same_histories(read_history(ref / "history.csv"), read_history(dev / "history.csv"))


def test_contact_patch_study_on_the_stand_in_device(tmp_path):
    """workflows/run.py's contact-patch study (analytical, the driving global recording its cut, a submodel level
    driven by it, the comparison) with fe.backend = 'cupy' on the stand-in device: the study's values equal the PETSc
    path's (the driver's and the submodel's steppers, cut driver and records on the device)."""
    import importlib

    from rods.io import read_data

    study = importlib.import_module("run")
    overrides = ["rod1.length=0.05", "rod2.length=0.1", "fe.axial_size=2e-3", "fe.radial_size=1e-3",
                 "simulation.end_time=1e-4", "effects=['contact_patch']", "submodel.levels=['coarse']"]  # fmt: skip
    assert study.main([*set_args(overrides), "--out", str(tmp_path / "petsc")]) == 0
    with on(FAKE):
        assert study.main([*set_args([*overrides, "fe.backend='cupy'"]), "--out", str(tmp_path / "cupy")]) == 0
    ref, dev = (read_data(tmp_path / k / "summary.json") for k in ("petsc", "cupy"))
    assert read_data(tmp_path / "cupy" / "submodel" / "coarse" / "summary.json")["backend"] == "cupy"
    assert dev["sources"]["peak_contact_pressure"] == ref["sources"]["peak_contact_pressure"] == "submodel/coarse"
    for key in ("peak_contact_force", "contact_duration", "contact_radius", "peak_contact_pressure"):
        assert dev[key] == pytest.approx(ref[key], rel=1e-9), key


@pytest.mark.parametrize("contact", ["kinematic", "penalty", "kinematic-damped"])
def test_a_device_step_copies_to_the_host_once(contact):
    """On a device every step copies to the host once (the contact's gaps and rates, or the penalty law's sums:
    the step's only wait, module docstring of rods.fe.kinematic) and launches a bounded number of device
    operations (kernels, products, copies; measured on the stand-in device: kinematic 27, penalty 39, damped 32 a
    step; a step that keeps the energy record's arrays 36-55), counted on tests/fake_gpu.py's device over the
    contact's closing on the paper scene (its penalty steps both open and closed)."""
    extra = {"kinematic": [], "penalty": ["fe.contact='penalty'"], "kinematic-damped": ["fe.bulk_viscosity=0.1"]}
    with on(FAKE):
        m = ExplicitModel(load_scene(PAPER, ["simulation.end_time=3e-5", "fe.backend='cupy'", *extra[contact]]))
        st = m.stepper()
        closed = set()
        for n in range(120):
            fake_gpu.LAUNCHES.clear()
            st.step(keep=n % 40 == 0)
            closed.add(st.contact.force > 0)
            ops = sum(fake_gpu.LAUNCHES.values())
            assert fake_gpu.LAUNCHES.get("copy to host") == 1, (n, fake_gpu.LAUNCHES)
            assert ops <= (60 if n % 40 == 0 else 45), (n, ops, fake_gpu.LAUNCHES)
    assert True in closed  # the contact carried force


def test_lanczos_on_the_host_matches_krylov_schur():
    """The device's eigenvalue route (rods.fe.timestep.largest_eigenvalue_on with the operator M^-1/2 (K + K_c)
    M^-1/2 on a backend's arrays) run with SciPy on a penalty-contact model: ω_max with and without the
    contact as SLEPc's to EIGEN_TOL/2 (both upper estimates of ω_max² within EIGEN_TOL), and the contact's
    full-engagement stiffness enters the operator."""
    from rods.fe.timestep import _scaled, largest_eigenvalue_on

    m = ExplicitModel(load_scene(PAPER, [*THREE_D, "fe.backend='numpy'", "fe.contact='penalty'"]))
    be = backend.select("numpy", 1)
    ω = [np.sqrt(largest_eigenvalue_on(be, _scaled(m, c, m.K), m.n_local)) for c in (False, True)]
    assert ω[0] == pytest.approx(m.ω_max_K, rel=EIGEN_TOL / 2)
    assert ω[1] == pytest.approx(m.ω_max, rel=EIGEN_TOL / 2)
    x = 1.0 + np.sin(np.arange(m.n_local))
    assert np.abs(_scaled(m, True, m.K)(x) - _scaled(m, False, m.K)(x)).max() > 0  # K_c enters the operator


# ----------------------------------------------------------------------------------------------
# the scene key
# ----------------------------------------------------------------------------------------------
def test_scene_key_default_and_refusals():
    assert SCHEMA["fe.backend"][1] == "petsc"
    assert backend.select("petsc", 4) is backend.PETSC
    with pytest.raises(SceneError, match="fe.backend"):
        load_scene(PAPER, ["fe.backend='torch'"])
    for name in ("numpy", "cupy"):
        with pytest.raises(SceneError, match="fe.backend.*serial only"):
            backend.select(name, 2)
    assert backend.select("auto", 2) is backend.PETSC  # MPI: the PETSc path
    with on(FAKE):  # where CuPy sees a device, "auto" runs there serially (the element kernel too), PETSc under MPI
        assert backend.select("auto", 1).name == backend.select("auto", 1, "matrix-free").name == "cupy"
        assert backend.select("auto", 2) is backend.PETSC
    if not GPU:
        assert backend.select("auto", 1) is backend.PETSC
    try:
        import cupy  # noqa: F401
    except ImportError:
        with pytest.raises(SceneError, match=r"pip install rods\[gpu\]"):
            backend.select("cupy", 1)


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which(str(MPIRUN)) is None, reason="no mpirun")
def test_array_backend_refused_under_mpi(tmp_path: Path):
    """fe.backend = 'numpy' on 2 ranks: exit 2 naming the key, before any mesh is built."""
    p = run_workflow("global.py", [*set_args(["fe.backend='numpy'"]), "--out", str(tmp_path / "o")], ranks=2)
    assert p.returncode == 2 and "fe.backend" in p.stderr and "serial only" in p.stderr


@pytest.mark.parametrize("name", ["numpy", FAKE])
def test_gpu_benchmark_runs_on_the_cpu(tmp_path, monkeypatch, capsys, name):
    """benchmarks/gpu_throughput.py with --backend numpy (with the device's overlap, so the A/B column is
    measured), and with --backend cupy on the stand-in device (its device name, copy rate, timings and end-to-end
    run on the CuPy path's code: a slip there would cost a lent GPU's minutes), on its tiny mesh: the table, the
    end-to-end run and the comparison with the PETSc path (equal histories) are written to --out, the run's
    outputs to --run-out."""
    bench = benchmark("gpu_throughput")
    numpy_backend = backend._numpy
    monkeypatch.setattr(backend, "_numpy", lambda: dataclasses.replace(numpy_backend(), overlap=True))
    out = tmp_path / "gpu.md"
    args = ["--backend", scene_backend(name), "--meshes", "tiny", "--steps", "10", "--run", "tiny",
            "--compare", "tiny", "--end-time", "1e-5", "--copy-mib", "8", "--out", str(out),
            "--run-out", str(tmp_path / "r")]  # fmt: skip
    with on(name):
        assert bench.main(args) == 0
    text = out.read_text()
    assert "| tiny |" in text and "End to end, `tiny`" in text
    assert "tiny: step 101/101" in capsys.readouterr().out  # the end-to-end runs' progress lines
    row = next(line for line in text.splitlines() if line.startswith("| tiny |"))
    assert float(row.split("|")[-2]) > 0.0  # the step without the overlap was timed (the A/B)
    diff = float(text.split("largest history difference ")[1].split(" ")[0])
    assert diff <= TOL
    assert (tmp_path / "r" / f"tiny-{scene_backend(name)}" / "history.csv").exists()
    if name == FAKE:
        assert fake_gpu.NAME.decode() in text  # the device the figures come from


def test_master_reaction_as_a_sparse_product_equals_the_bincount():
    """Wᵀ t as the device's sparse product (rods.fe.contact.transpose_matrix: CuPy's bincount waits for the
    device) equals the bincount sum, repeated masters of one slave included, to round-off."""
    from rods.fe.contact import _transpose, transpose_matrix

    rng = np.random.default_rng(3)
    ns, nw, nm = 40, 4, 25
    J, W, t = rng.integers(0, nm, size=(ns, nw)), rng.random((ns, nw)), rng.normal(size=ns) * 1e3  # [N]
    J[0, 1] = J[0, 0]  # a master twice in one slave's row
    expected = _transpose(np, J, W, t, nm)
    product = _transpose(np, J, W, t, nm, transpose_matrix(J, W, nm))
    np.testing.assert_allclose(product, expected, rtol=1e-14, atol=1e-11)


def test_petsc_path_multiplies_plain_aij_equal_to_the_assembled_block_matrix(paper):
    """The PETSc operator holds K as AIJ without inode routines (rods.fe.backend.plain_aij: DOLFINx's serial BAIJ
    product ran ~3x slower here), and its product equals the block matrix's to round-off."""
    model, _ = paper
    K = model._assemble_stiffness()
    assert K.getType() == "seqbaij"  # what DOLFINx gives serially: the case the conversion is for
    x = K.createVecRight()
    x.setArray(np.random.default_rng(0).standard_normal(x.getLocalSize()))
    y_block = K.createVecLeft()
    K.mult(x, y_block)
    A = backend.plain_aij(K)
    assert A.getType() == "seqaij"
    y = A.createVecLeft()
    A.mult(x, y)
    scale = np.abs(y_block.getArray()).max()
    assert np.abs(y.getArray() - y_block.getArray()).max() <= 1e-13 * scale
    op = model.stepper().op
    assert op.A.getType() == "seqaij" and isinstance(op, backend.PetscOperator)


@pytest.mark.parametrize("index", [np.int32, np.int64])
def test_product_is_scipys_product_to_the_bit(index):
    """backend.product: SciPy's CSR kernel called without its checks gives A @ x bit for bit (the contact's gap
    operator and the recorder's probe map on every step), and anything it does not take (a dense or CSC matrix,
    an integer or complex vector) goes to A @ x unchanged."""
    rng = np.random.default_rng(7)
    A = scipy.sparse.random(40, 3000, density=0.003, format="csr", random_state=rng)
    A.indices, A.indptr = A.indices.astype(index), A.indptr.astype(index)
    x = rng.normal(size=3000)
    y = backend.product(A, x)
    assert y.dtype == np.float64 and np.array_equal(y, A @ x)
    strided = rng.normal(size=6000)[::2]  # a view, not contiguous
    assert np.array_equal(backend.product(A, strided), A @ strided)
    X = rng.normal(size=(3000, 2))  # a block of vectors: A @ X, not the vector kernel
    for other, v in ((A.toarray(), x), (A.tocsc(), x), (A, np.arange(3000)), (A, x + 1j * x), (A, X)):
        np.testing.assert_array_equal(backend.product(other, v), other @ v)


@pytest.mark.parametrize(
    ("attribute", "value", "words"),
    [
        ("version", "0.10.0", ("DOLFINx = '0.10.0'", "rods needs DOLFINx 0.11.x")),
        ("version", "0.12.1", ("DOLFINx = '0.12.1'", "rods needs DOLFINx 0.11.x")),
        ("scalar", np.complex128, ("PETSc scalar type = 'complex128'", "real float64")),
        ("scalar", np.float32, ("PETSc scalar type = 'float32'", "real float64")),
        ("slepc4py", None, ("slepc4py = 'not importable'", "eigenvalue solve needs SLEPc")),
    ],
)
def test_a_stack_the_models_cannot_run_on_is_refused_before_the_set_up(monkeypatch, tmp_path, attribute, value, words):
    """Another DOLFINx series, a complex / single-precision PETSc or no slepc4py: the backend's selection (every FE
    entry point and ExplicitModel ask it first) refuses with one line naming what it found and the remedy; the entry
    point exits 2 before its plan, nothing written. This install passes (the rest of this file runs on it)."""
    import dolfinx
    from petsc4py import PETSc

    from rods.preflight import InputError

    from ..conftest import in_process
    from ..test_cli_errors import refused

    backend.select("petsc", 1)  # the pinned stack passes
    if attribute == "version":
        monkeypatch.setattr(dolfinx, "__version__", value)
    elif attribute == "scalar":
        monkeypatch.setattr(PETSc, "ScalarType", value)
    else:  # an environment without slepc4py
        import importlib.util

        find = importlib.util.find_spec
        monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == attribute else find(name, *a))
    with pytest.raises(InputError, match="ensure-venv"):
        backend.select("petsc", 1)
    with pytest.raises(InputError, match=re.escape(words[0])):
        ExplicitModel(load_scene(PAPER, ["simulation.end_time=1e-6"]), MPI.COMM_SELF)
    line = refused(in_process("global.py", "--out", str(tmp_path / "g"), cwd=tmp_path), *words)
    assert "dolfinx-real-mode" in line and not (tmp_path / "g").exists()


def test_a_form_cache_that_cannot_be_made_is_refused_before_the_plan(monkeypatch, tmp_path):
    """A read-only HOME (a cluster node): DOLFINx's form cache ~/.cache/fenics could not be made, and the set-up
    failed with a PermissionError after the plan; now exit 2 naming XDG_CACHE_HOME, nothing written. An existing
    cache, or one that can be made, passes."""
    import os

    import dolfinx.jit

    from ..conftest import in_process
    from ..test_cli_errors import refused

    home = tmp_path / "home"
    home.mkdir()
    options = dict(dolfinx.jit.get_options(), cache_dir=home / ".cache" / "fenics")
    monkeypatch.setattr(dolfinx.jit, "get_options", lambda *a, **k: options)
    backend.select("petsc", 1)  # can be made
    access = os.access
    monkeypatch.setattr(os, "access", lambda p, mode: False if str(p) == str(home) else access(p, mode))  # read-only
    line = refused(in_process("global.py", "--out", str(tmp_path / "g"), cwd=tmp_path), "form cache", "XDG_CACHE_HOME")
    assert str(home) in line and not (tmp_path / "g").exists()
