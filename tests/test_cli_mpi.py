"""A failure on one rank stops every rank with its message; it never hangs in a collective."""

from __future__ import annotations

import select
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from .conftest import MPIRUN, ROOT

# what every script below starts with: the entry points' module on the path, MPI and _cli loaded
PREAMBLE = f"import sys\nsys.path.insert(0, {str(ROOT / 'workflows')!r})\nfrom mpi4py import MPI\nimport _cli\n"


def mpi_script(path, body: str):
    """``path`` written as a script for mpirun: :data:`PREAMBLE`, then ``body`` (dedented); returns ``path``."""
    path.write_text(PREAMBLE + textwrap.dedent(body))
    return path


@pytest.mark.mpi
def test_failure_on_one_rank_aborts_all(tmp_path):
    script = mpi_script(
        tmp_path / "fail_on_rank1.py",
        """
        def main(argv=None):
            if MPI.COMM_WORLD.rank == 1:
                raise RuntimeError("mesh inverted on rank 1")
            MPI.COMM_WORLD.barrier()  # rank 0 waits here forever unless rank 1 aborts the job
            return 0

        _cli.entry(main)
        """,
    )
    p = subprocess.run(
        [str(MPIRUN), "-n", "2", sys.executable, str(script)], capture_output=True, text=True, timeout=60
    )
    assert p.returncode != 0
    assert "error on rank 1: RuntimeError: mesh inverted on rank 1" in p.stderr


@pytest.mark.mpi
def test_a_script_without_mpi_refuses_once_under_mpirun(tmp_path):
    """compare.py (like report.py, paper.py, fig4.py, convergence.py) never loads MPI: under mpirun -n 2 each rank
    printed the same error line; the launcher's rank (PMI_RANK) leaves it to rank 0."""
    p = subprocess.run(
        [str(MPIRUN), "-n", "2", sys.executable, str(ROOT / "workflows" / "compare.py"), "--global", "missing"],
        capture_output=True, text=True, timeout=120, cwd=tmp_path, stdin=subprocess.DEVNULL,
    )  # fmt: skip
    assert p.returncode == 2
    assert len(p.stderr.strip().splitlines()) == 1 and p.stderr.startswith("error:"), p.stderr


@pytest.mark.mpi
def test_analytical_under_mpirun_prints_and_writes_once(tmp_path):
    """mpirun -n 2 workflows/analytical.py: every rank computes (milliseconds), rank 0 alone prints and writes
    (was: the plan, the summary and the files twice)."""
    out = tmp_path / "a"
    p = subprocess.run(
        [str(MPIRUN), "-n", "2", sys.executable, str(ROOT / "workflows" / "analytical.py"), "--out", str(out)],
        capture_output=True, text=True, timeout=120, cwd=tmp_path,
    )  # fmt: skip
    assert p.returncode == 0, p.stderr[-2000:]
    assert p.stdout.count("plan: analytical model") == 1 and p.stdout.count("status: ok") == 1
    assert sorted(f.name for f in out.iterdir()) == ["history.csv", "summary.json"]


@pytest.mark.mpi
def test_a_ctrl_c_in_the_teardown_after_the_run_is_no_error(tmp_path):
    """Ctrl-C (hydra forwards it to every rank) after main returned, in the interpreter's teardown (an atexit
    handler sends it here, as a user's key in the ~0.5 s before exit did): the command exits with main's code, no
    traceback. Before rods' entry (_cli.entry) ignored it there, this printed a KeyboardInterrupt traceback (checked
    with the old `sys.exit(_cli.guarded(main)())`), and a key later in the teardown killed the ranks by SIGINT, which
    mpirun reported as exit 2, the bad-input code."""
    script = mpi_script(
        tmp_path / "late_ctrl_c.py",
        """
        import atexit, os, signal, time

        def late():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.2)

        def main(argv=None):
            atexit.register(late)
            print("status: ok", flush=True)
            return 0

        _cli.entry(main)
        """,
    )
    p = subprocess.run(
        [str(MPIRUN), "-n", "2", sys.executable, str(script)], capture_output=True, text=True, timeout=60
    )
    assert p.returncode == 0, p.stderr[-2000:]
    assert p.stdout.count("status: ok") == 2 and "KeyboardInterrupt" not in p.stderr


@pytest.mark.mpi
def test_files_beyond_any_disk_are_refused_once_by_every_rank(tmp_path):
    """rods.cost.check_disk under mpirun: rank 0 looks at the disk and every rank takes its figure, so both refuse
    (exit 2, one line, nothing written), never one rank alone in a collective. Field frames every 40 ns for 1 s of
    the paper scene plan ~10^14 B, more than any disk."""
    out = tmp_path / "run"
    sets = ["fe.field_interval=4e-8", "simulation.end_time=1.0", "simulation.output_interval=1e-6"]
    args = [a for s in sets for a in ("--set", s)]
    cmd = [str(MPIRUN), "-n", "2", sys.executable, str(ROOT / "workflows" / "global.py"), *args, "--out", str(out)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1, p.stderr[-2000:]
    assert lines[0].startswith("error: --out = ") and "GB of files" in lines[0] and "GB are free" in lines[0]
    assert not out.exists()


@pytest.mark.mpi
@pytest.mark.parametrize("script", ["global.py", "analytical.py"])
def test_memory_short_on_one_rank_is_refused_by_every_rank(tmp_path, script):
    """One rank's node with less free memory (rods.cost.local_memory 1 MB on rank 1): every rank refuses (exit 2,
    one line, nothing written). Each rank read its own /proc/meminfo: rank 1 refused alone and rank 0 waited in the
    next collective, both spinning until killed, SIGTERM too (an audit, 2026-12-07)."""
    wrapper = mpi_script(
        tmp_path / "short_on_rank1.py",
        f"""
        import runpy
        import rods.cost
        if MPI.COMM_WORLD.rank == 1:
            rods.cost.local_memory = lambda: 1e6
        sys.argv = [{str(ROOT / "workflows" / script)!r}, *sys.argv[1:]]
        runpy.run_path(sys.argv[0], run_name="__main__")
        """,
    )
    out = tmp_path / "run"
    cmd = [str(MPIRUN), "-n", "2", sys.executable, str(wrapper), "--out", str(out)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120, stdin=subprocess.DEVNULL)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1, p.stderr[-2000:]
    assert "needs more memory than available (0.001 GB)" in lines[0], lines[0]
    assert not out.exists()


@pytest.mark.mpi
def test_a_signal_ends_a_rank_stuck_in_a_collective(tmp_path):
    """Rank 1 leaves (as one rank's refusal did), rank 0 waits in a barrier for ever: SIGTERM to mpirun still ends
    the job, one line, exit 130, within rods.interrupt.STUCK_GRACE (2 s here), the folder released. Python's
    handler never runs in a rank blocked in MPI: SIGTERM did nothing, only SIGKILL ended such a hang (an audit,
    2026-12-07)."""
    script = mpi_script(
        tmp_path / "stuck_on_rank0.py",
        f"""
        from rods import interrupt

        interrupt.STUCK_GRACE = 2.0

        def main(argv=None):
            from pathlib import Path
            _cli.hold(Path({str(tmp_path / "run")!r}), MPI.COMM_WORLD)
            if MPI.COMM_WORLD.rank == 0:
                print("started", flush=True)
            if MPI.COMM_WORLD.rank == 1:
                raise SystemExit(2)  # leaves without the others, as a refusal on one rank did
            MPI.COMM_WORLD.barrier()  # for ever
            return 0

        _cli.entry(main)
        """,
    )
    p = subprocess.Popen(
        [str(MPIRUN), "-n", "2", sys.executable, str(script)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, stdin=subprocess.DEVNULL,
    )  # fmt: skip
    try:
        assert select.select([p.stdout], [], [], 60)[0], "the ranks did not start within 60 s"
        assert p.stdout.readline().strip() == "started"
        time.sleep(2.0)  # both ranks in main, rank 0 in the barrier
        t0 = time.monotonic()
        p.send_signal(signal.SIGTERM)
        out, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 130, err[-2000:]
    assert time.monotonic() - t0 < 30
    assert "error on rank 0: interrupted, but this process did not return from a call within 2 s" in err
    assert not (tmp_path / "run").exists()  # the watcher released the folder (made for the run, empty) first


@pytest.mark.mpi
@pytest.mark.parametrize("who", ["rank 1", "every rank"])
def test_a_refusal_after_the_folder_is_held_never_hangs(tmp_path, who):
    """An input refused after the folder is held (a checkpoint's, a cut record's): refused by every rank alike, one
    line, exit 2; by one rank alone (its node's view of a file), that rank aborts the others, exit 2, its line. Rank
    0 waited for ever in its next collective while rank 1 had exited 2 (an audit, 2026-12-07)."""
    script = mpi_script(
        tmp_path / "refuse_after_hold.py",
        f"""
        from pathlib import Path
        from rods.preflight import InputError

        def main(argv=None):
            comm = MPI.COMM_WORLD
            _cli.hold(Path({str(tmp_path / "run")!r}), comm)
            if {who!r} == "every rank" or comm.rank == 1:
                raise InputError("--restart", "x", "a checkpoint of another scene", "run afresh")
            comm.barrier()  # for ever without the agreement
            return 0

        _cli.entry(main)
        """,
    )
    cmd = [str(MPIRUN), "-n", "2", sys.executable, str(script)]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL)
    assert p.returncode == 2, p.stderr[-2000:]
    errors = [ln for ln in p.stderr.splitlines() if ln.startswith("error")]
    expected = "error: " if who == "every rank" else "error on rank 1: "
    assert len(errors) == 1 and errors[0].startswith(expected + "--restart = 'x': a checkpoint"), p.stderr
    if who == "every rank":
        assert not (tmp_path / "run").exists()  # released and removed, as it was made for the run


@pytest.mark.mpi
def test_a_scene_refused_on_one_rank_alone_never_hangs(tmp_path):
    """One rank's view of the scene file refused (a stale network copy): that rank aborts the others, exit 2, its
    line. `_cli.load` exited 2 on that rank alone and the other waited for ever in its next collective, SIGTERM
    then ending it 20 s later (a review, 2026-12-07)."""
    wrapper = mpi_script(
        tmp_path / "scene_refused_on_rank1.py",
        f"""
        import runpy
        import rods.scene
        if MPI.COMM_WORLD.rank == 1:
            def unreadable(*args, **kwargs):
                raise rods.scene.SceneError("scene", "paper.toml", "must be readable on every rank")
            _cli.load_scene = unreadable
        sys.argv = [{str(ROOT / "workflows" / "global.py")!r}, *sys.argv[1:]]
        runpy.run_path(sys.argv[0], run_name="__main__")
        """,
    )
    out = tmp_path / "run"
    cmd = [str(MPIRUN), "-n", "2", sys.executable, str(wrapper), "--out", str(out)]
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=60, stdin=subprocess.DEVNULL)
    assert p.returncode == 2, p.stderr[-2000:]
    assert time.monotonic() - t0 < 30
    assert "must be readable on every rank" in p.stderr
    assert not out.exists()
