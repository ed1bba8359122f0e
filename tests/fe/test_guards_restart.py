"""Guards stop a broken run with a diagnosis and readable histories; a killed run resumes exactly."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import rods.fe  # noqa: F401
from rods.fe.guards import CornerJacobians, SimulationError
from rods.fe.model import ExplicitModel
from rods.io import read_history

from ..conftest import MPIRUN, PY, ROOT, run_workflow

COARSE = ("fe.axial_size=2e-3", "fe.radial_size=0.5e-3", "simulation.end_time=2e-4")


def test_unstable_step_is_stopped_with_step_time_and_cause(scene_with):
    m = ExplicitModel(scene_with(*COARSE))
    m.dt = 1.2 * m.dt_critical  # bypass the refusal of an unstable fe.dt, as a broken scheme would
    with pytest.raises(SimulationError) as e:
        m.run()
    err = e.value
    assert 0 < err.step < m.steps and err.time == pytest.approx(err.step * m.dt)
    assert "step too large" in str(err) and f"step {err.step}" in str(err)
    h = err.partial.history  # histories up to the failure stay usable
    assert h["time"].size > 0 and np.all(np.isfinite(h["kinetic_energy"]))
    assert err.partial.summary["status"] == "failed"
    # stopped while the rods still touch: no duration (the time up to the stop is none), said so
    assert err.time < 1e-4 and err.partial.summary["contact_duration"] is None
    assert err.partial.summary["warnings"][0].startswith("contact_duration: the first contact had not ended when")


def test_cli_writes_partial_histories_and_exits_1(tmp_path, monkeypatch):
    import importlib

    import _cli

    glob = importlib.import_module("global")
    orig = ExplicitModel._stable_step

    def unstable(self):
        orig(self)
        self.dt = 1.2 * self.dt_critical
        self.steps = int(self.scene.end_time / self.dt)

    monkeypatch.setattr(ExplicitModel, "_stable_step", unstable)
    args = [a for o in COARSE for a in ("--set", o)]
    assert _cli.guarded(glob.main)([*args, "--out", str(tmp_path)]) == 1  # the entry point's error path
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["status"] == "failed" and "likely cause" in s["error"]
    assert read_history(tmp_path / "history.csv")["time"].size > 0


def global_args(out, *extra):
    """global.py's arguments for the killed-run case (2 x 0.5 mm mesh, 0.3 ms) into ``out``."""
    args = [
        a for o in ("fe.axial_size=2e-3", "fe.radial_size=0.5e-3", "simulation.end_time=3e-4") for a in ("--set", o)
    ]
    return [*args, *extra, "--out", str(out)]


def run_global(out, *extra):
    """The command line of :func:`global_args` (a fresh interpreter: the case kills it)."""
    return [sys.executable, str(ROOT / "workflows" / "global.py"), *global_args(out, *extra)]


def test_killed_run_resumes_from_its_checkpoint_with_the_same_histories(tmp_path):
    """SIGKILL after a checkpoint in the contact (t >= 0.1 ms of its 0.20 ms on this mesh): --restart resumes
    the contact's state too and ends with the uninterrupted run's histories, also at another checkpoint interval
    (it saves the state, it never changes it: rods.scene.RESULT_NEUTRAL)."""
    ref, cut = tmp_path / "ref", tmp_path / "cut"
    assert run_workflow("global.py", global_args(ref)).returncode == 0  # the uninterrupted run, in this process
    p = subprocess.Popen(
        run_global(cut, "--set", "fe.checkpoint_interval=5e-5"),
        cwd=ROOT,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    t0 = time.time()
    while not (cut / "checkpoint.json").exists() or json.loads((cut / "checkpoint.json").read_text())["time"] < 1e-4:
        assert p.poll() is None, "run ended before it could be killed"
        assert time.time() - t0 < 120
        time.sleep(0.05)
    p.send_signal(signal.SIGKILL)
    p.wait()
    assert not (cut / "summary.json").exists()  # killed mid-way: no (half-)written results
    r = subprocess.run(
        run_global(cut, "--set", "fe.checkpoint_interval=7e-5", "--restart"), capture_output=True, text=True, cwd=ROOT
    )
    assert r.returncode == 0, r.stderr[-2000:]
    assert "restart from the checkpoint of step" in r.stderr
    # finished: its checkpoint resumes nothing, so it is gone (a fuzz: a later --restart reran from it, "ok")
    assert not (cut / "checkpoint.json").exists() and not list(cut.glob("checkpoint-*.npz"))
    a, b = read_history(ref / "history.csv"), read_history(cut / "history.csv")
    assert set(a) == set(b)
    for key in a:
        np.testing.assert_allclose(b[key], a[key], rtol=1e-12, atol=1e-14 * np.abs(a[key]).max(), err_msg=key)
    sa, sb = (json.loads((d / "summary.json").read_text()) for d in (ref, cut))
    assert sb["peak_contact_force"] == sa["peak_contact_force"] and sb["contact_duration"] == sa["contact_duration"]


@pytest.mark.parametrize("kind", ["axisymmetric", "3d"])
def test_inverted_cells_are_found_and_rigid_motion_is_not(scene_with, kind):
    extra = ("fe.kind=3d", "fe.symmetry=quarter", "rod1.length=0.05", "rod2.length=0.05") if kind == "3d" else ()
    m = ExplicitModel(scene_with("fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=2e-5", *extra))
    u = np.zeros(m.n_local)
    u[m.rod1_z] = 1.0  # 1 m of rigid translation: nothing is distorted
    assert m.inverted_cells(u) == 0
    u[:] = 0.0
    u[m.rod1_z[m.rod1_z.size // 2]] = 0.05  # one interior node pushed 5 cm through its 4 mm neighbours
    assert m.inverted_cells(u) > 0
    with pytest.raises(SimulationError, match="mesh inverted"):
        from rods.fe.guards import Guard

        Guard(m.dt, m.dt_critical).check_inverted(7, 7 * m.dt, m.inverted_cells(u))


def test_checkpoint_interval_below_the_step_checkpoints_every_step(scene_with, tmp_path, monkeypatch):
    """fe.checkpoint_interval under Δt (in range: any positive interval) checkpoints every step, not a division
    by zero (found by tests/test_fuzz_cli.py with 1e-9 s); the finished run's last checkpoint is removed."""
    from rods.fe import checkpoint

    saved, save = [], checkpoint.save
    monkeypatch.setattr(checkpoint, "save", lambda out, step, *a, **k: saved.append(step) or save(out, step, *a, **k))
    m = ExplicitModel(scene_with(*COARSE[:2], "simulation.end_time=2e-6", "fe.checkpoint_interval=1e-9"))
    res = m.run(out=tmp_path)
    assert res.summary["steps"] == m.steps and saved == list(range(1, m.steps))  # every step before the last
    assert not list(tmp_path.glob("*checkpoint*"))


def test_inverted_cells_counted_on_a_device_as_on_the_host(scene_with):
    """CornerJacobians' device path (serial: no ghost update; cells, coordinates and signs moved once by use())
    counts what the host path counts, on a state that inverts some cells. Run on the stand-in device
    (tests/fake_gpu.py: the CuPy backend's code, refusing implicit host/device conversions as CuPy does)."""
    from rods.fe import backend

    from .. import fake_gpu

    m = ExplicitModel(scene_with("fe.kind=3d", "fe.symmetry=quarter", "fe.axial_size=4e-3", "fe.radial_size=1e-3",
                                 "rod1.length=0.03", "rod2.length=0.03", "simulation.end_time=2e-5"))  # fmt: skip
    msh = m.rm.mesh
    corners = CornerJacobians(m.V, m.n_local, msh.topology.index_map(msh.topology.dim).size_local)
    u = np.random.default_rng(1).normal(size=m.n_local) * 3e-4  # [m] about a third of the 1 mm elements
    on_host = corners.count(u)
    with fake_gpu.installed():
        be = backend.select("cupy", 1)
        corners.use(be)
        assert corners._device is not None  # the count runs on the device's arrays
        assert on_host > 0 and corners.count(be.asarray(u)) == on_host


def test_checkpoints_append_what_is_new_and_a_restart_reads_what_its_checkpoint_counts(tmp_path):
    """Each checkpoint rewrote every history row and force so far (5917 checkpoints: 8.55 GB for a 5 MB run); the
    growing arrays are appended to a log now, one record a save, a checkpoint's .npz counting and checking its bytes.
    A kill after an append but before its checkpoint's manifest leaves the earlier checkpoint whole; a log changed
    is refused as damaged, naming it; a restart's first checkpoint starts a log of its own and removes the old."""
    from mpi4py import MPI

    from rods.fe import checkpoint

    comm, force = MPI.COMM_SELF, np.arange(10_000, dtype=float)  # [N] a per-step trace
    rows = np.arange(1000.0)  # [-] a history column
    tail, sizes = None, []
    for step in (999, 1999, 2999):
        state = {"force": checkpoint.Appended(force[: step + 1]), "rows": checkpoint.Appended(rows[: step // 3])}
        tail = checkpoint.save(tmp_path, step, step * 1e-9, {**state, "u": np.ones(4)}, comm, "key", tail=tail)
        sizes.append((tmp_path / tail.log).stat().st_size)
    assert tail.log == "checkpoint-log-999-r0.bin" and tail.lengths == {"force": 3000, "rows": 999}
    # one record a save: its new entries and two .npy headers (a record per key cost ~256 B of headers each time)
    assert 8 * (1000 + 333) < sizes[1] - sizes[0] < 8 * (1000 + 333) + 300
    checkpoint._append(tmp_path, 3999, 0, {"force": force[:5000]}, tail)  # the next checkpoint's, then a kill
    state = checkpoint.load(tmp_path, comm, "key")
    np.testing.assert_array_equal(state["force"], force[:3000])
    np.testing.assert_array_equal(state["rows"], rows[:999])
    assert not any(k.startswith("@") for k in state)
    # a restart's first checkpoint: a new log, the old removed with its checkpoint
    after = {"force": checkpoint.Appended(force[:4000]), "rows": checkpoint.Appended(rows[:1000])}
    checkpoint.save(tmp_path, 3999, 4e-6, after, comm, "key")
    assert sorted(p.name for p in tmp_path.glob(checkpoint.LOG_GLOB)) == ["checkpoint-log-3999-r0.bin"]
    np.testing.assert_array_equal(checkpoint.load(tmp_path, comm, "key")["force"], force[:4000])
    with open(tmp_path / "checkpoint-log-3999-r0.bin", "r+b") as f:  # a byte the checkpoint counts, changed
        f.seek(f.seek(0, 2) - 8)
        f.write(np.float64(-1.0).tobytes())
    with pytest.raises(checkpoint.CheckpointError, match="checkpoint-log-3999-r0.bin"):
        checkpoint.load(tmp_path, comm, "key")
    checkpoint.discard(tmp_path, comm)
    assert not list(tmp_path.glob("checkpoint*"))


def test_a_finished_or_fresh_run_leaves_no_checkpoint_file_a_kill_left_and_a_lost_log_starts_anew(tmp_path):
    """A kill between a save's steps left an older step's states or a save's temporary files, which a finished run
    kept (21 of 55 killed-and-resumed runs in a fuzz): discard removes them all. A log removed under a run (another
    run's discard) is started anew, whole, not written past its end as a sparse file."""
    from mpi4py import MPI

    from rods.fe import checkpoint

    for name in ("checkpoint-891-r0.npz", "checkpoint-891-r1.npz", ".checkpoint-778-r0.npz.tmp",
                 ".checkpoint.json.x1y2.tmp", "checkpoint-log-5-r0.bin"):  # fmt: skip
        (tmp_path / name).write_bytes(b"x")
    checkpoint.discard(tmp_path, MPI.COMM_SELF)
    assert not list(tmp_path.iterdir())
    force = np.arange(100.0)
    tail = checkpoint.save(tmp_path, 9, 1e-8, {"force": checkpoint.Appended(force[:10])}, MPI.COMM_SELF, "k")
    (tmp_path / tail.log).unlink()
    tail = checkpoint.save(
        tmp_path, 19, 2e-8, {"force": checkpoint.Appended(force[:20])}, MPI.COMM_SELF, "k", tail=tail
    )
    assert tail.log == "checkpoint-log-19-r0.bin"
    np.testing.assert_array_equal(checkpoint.load(tmp_path, MPI.COMM_SELF, "k")["force"], force[:20])


@pytest.mark.mpi
def test_one_rank_losing_its_log_starts_every_ranks_log_anew(tmp_path):
    """Rank 1's log removed under a 2-rank run: rank 1 alone started a new log, which rank 0 then removed as an
    earlier one's, and every later checkpoint was damaged (a review, 2026-12-07); now every rank starts anew."""
    code = f"""
import numpy as np
from mpi4py import MPI
from pathlib import Path
from rods.fe import checkpoint
comm, out, force = MPI.COMM_WORLD, Path({str(tmp_path)!r}), np.arange(100.0) + MPI.COMM_WORLD.rank
tail = checkpoint.save(out, 9, 1e-8, {{"force": checkpoint.Appended(force[:10])}}, comm, "k")
comm.Barrier()
if comm.rank == 1:
    (out / tail.log).unlink()
comm.Barrier()
checkpoint.save(out, 19, 2e-8, {{"force": checkpoint.Appended(force[:20])}}, comm, "k", tail=tail)
np.testing.assert_array_equal(checkpoint.load(out, comm, "k")["force"], force[:20])
print("ok", comm.rank)
"""
    p = subprocess.run([str(MPIRUN), "-n", "2", str(PY), "-c", code], cwd=ROOT, capture_output=True, text=True,
                       timeout=120)  # fmt: skip
    assert p.returncode == 0 and p.stdout.count("ok") == 2, p.stdout + p.stderr[-2000:]
    assert sorted(f.name for f in tmp_path.glob("checkpoint-log-*")) == [
        "checkpoint-log-19-r0.bin", "checkpoint-log-19-r1.bin"
    ]  # fmt: skip


def test_a_run_killed_while_writing_its_results_keeps_its_checkpoint(tmp_path, monkeypatch):
    """A kill after the last step, before the result files, had left neither checkpoint nor results (the model
    removed its checkpoint as it finished; a fuzz: 3 of 3 kills at the last step): the stage removes it after writing
    them, so a --restart rewrites the results from the last checkpoint."""
    from rods import io

    from ..conftest import in_process

    args = ["--set", "fe.axial_size=4e-3", "--set", "fe.radial_size=1.5e-3", "--set", "simulation.end_time=1e-4",
            "--set", "fe.checkpoint_interval=2e-5", "--out", str(tmp_path / "g")]  # fmt: skip
    real = io.write_summary

    def killed(path, summary):  # the run ends here, as under a SIGKILL
        raise RuntimeError("killed")

    monkeypatch.setattr(io, "write_summary", killed)
    assert in_process("global.py", *args, cwd=tmp_path).returncode == 1
    assert (tmp_path / "g" / "checkpoint.json").exists() and not (tmp_path / "g" / "summary.json").exists()
    monkeypatch.setattr(io, "write_summary", real)
    p = in_process("global.py", *args, "--restart", cwd=tmp_path)
    assert p.returncode == 0, p.stderr[-2000:]
    assert (tmp_path / "g" / "summary.json").exists() and not list((tmp_path / "g").glob("checkpoint*"))
