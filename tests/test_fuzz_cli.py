"""Fuzz harness: random scenes, overrides and arguments for every entry point, in-process (bounded time:
about 30 s). Whatever comes in, the script ends with exit 0 or exit 2 (bad input: one line on stderr, no
output folder), never an uncaught exception (a traceback). The harness lowers the cost check's budgets
(:data:`SMALL`), also under a drawn --force, so that every run it lets through is small in time and memory: the
users' budgets admit runs of hours and gigabytes (an in-range draw once ran for minutes here, growing by
1 GB/min), which is right for a user and wrong for a test. The budgets themselves are tested in tests/test_cost.py."""

from __future__ import annotations

import contextlib
import importlib
import io
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import _cli
from rods.scene import SCHEMA

from .conftest import SCENES

FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck), database=None)
numbers = st.sampled_from(["0", "-1", "1e-9", "abc", "nan", "inf", "1e300", "2e-5", "1", "3", "''", "[1]", "true"])
values = st.one_of(numbers, st.text(max_size=8), st.floats(allow_nan=True).map(repr), st.integers().map(str))
override = st.tuples(st.sampled_from(sorted(SCHEMA)), values).map(lambda kv: f"{kv[0]}={kv[1]}")
RESULTS: dict[str, list[int]] = {}  # exit codes seen per script (the harness's own check, below)
TINY = ["fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=2e-5"]
# the harness's budgets: about 20 s of stepping and 1.5 GB at most for a run it lets through, and 20 s of estimated
# wall time (a draw of simulation.end_time=1 with a coarse output interval ran the analytical model for minutes)
SMALL = {"STEP_BUDGET": 2e5, "WORK_BUDGET": 2e8, "VALUE_BUDGET": 1e6, "TIME_BUDGET": 20.0,
         "local_memory": lambda: 1.5e9}  # fmt: skip


@pytest.fixture(autouse=True, scope="module")
def small_budgets():
    from rods import cost

    check = cost.check
    with pytest.MonkeyPatch.context() as mp:
        for name, value in SMALL.items():
            mp.setattr(cost, name, value)
        # a drawn --force must not lift them: with simulation.end_time=1 it ran the analytical model for minutes
        mp.setattr(cost, "check", lambda c, force=False, **kw: check(c, False, **kw))
        yield


def call(script: str, argv: list[str]) -> tuple[int, str]:
    """Run workflows/<script>'s guarded main in-process: (exit code, stderr)."""
    main = importlib.import_module(script).main
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            code = _cli.guarded(main)(argv)
        except SystemExit as e:
            code = e.code
    return code, err.getvalue()


def check(script: str, argv: list[str], out: Path) -> None:
    """Exit 0; or 2 for bad input (one line, no folder); or 1 where a guard stopped the run (a designed outcome of
    in-range settings such as a strict fe.energy_growth_limit: one line naming the stop, histories written)."""
    code, err = call(script, argv)
    RESULTS.setdefault(script, []).append(code)
    errors = [line for line in err.splitlines() if line.startswith("error")]
    stopped = code == 1 and len(errors) == 1 and errors[0].startswith("error: run stopped: ")
    assert code in (0, 2) or stopped, (argv, err[-2000:])
    assert "Traceback" not in err
    if code == 2:
        assert len(errors) == 1 and len(errors[0]) < 1000, err[-2000:]
        assert not out.is_dir(), (argv, "an output folder after exit 2")


def _where(kind: str, tmp: Path) -> Path:
    (tmp / "afile").write_text("x")
    return {"fresh": tmp / "out", "file": tmp / "afile", "under a file": tmp / "afile" / "out"}[kind]


outs = st.sampled_from(["fresh", "fresh", "file", "under a file"])


def sets(overrides: list[str]) -> list[str]:
    return [a for o in overrides for a in ("--set", o)]


@FUZZ
@given(overrides=st.lists(override, max_size=3), where=outs, force=st.booleans())
@example(overrides=[], where="fresh", force=False)  # one that runs, whatever the draws (the harness check below)
def fuzz_analytical(overrides, where, force):
    with tempfile.TemporaryDirectory() as d:
        out = _where(where, Path(d))
        extra = ["--force"] if force else []
        check("analytical", [*sets(["simulation.end_time=2e-4", *overrides]), *extra, "--out", str(out)], out)


@FUZZ
@given(
    overrides=st.lists(override.filter(lambda o: not o.startswith("simulation.end_time")), max_size=2),
    flags=st.lists(
        st.sampled_from(["--record-cut", "--restart", "--record-until", "--record-every", "--driver"]), max_size=2
    ),
    value=numbers,
    where=outs,
)
@example(overrides=[], flags=["--record-cut", "--record-every"], value="3", where="fresh")  # one that runs
# drawn once: in range then, the guard stopped the run at its first record (exit 1); now refused (exit 2)
@example(overrides=["fe.energy_growth_limit=7.117247484842497e-182"], flags=[], value="0", where="fresh")
# a strict limit in range, on the stiffest penalty: runs, or a guard's one-line stop (exit 1), never a traceback
@example(
    overrides=["fe.energy_growth_limit=1e-5", "fe.contact='penalty'", "fe.penalty=1e4"],
    flags=[],
    value="0",
    where="fresh",
)
def fuzz_global(overrides, flags, value, where):
    args = [a for f in flags for a in ((f, value) if f in ("--record-until", "--record-every") else (f,))]
    with tempfile.TemporaryDirectory() as d:
        out = _where(where, Path(d))
        check("global", [*sets([*overrides, *TINY]), *args, "--out", str(out)], out)


@FUZZ
@given(
    folder=st.sampled_from(["missing", "empty", "nosummary", "badsummary"]),
    size=numbers,
    dt=st.one_of(numbers, st.sampled_from(["auto", "global"])),
    level=st.sampled_from(["coarse", "fine", "bogus"]),
    phase=st.one_of(st.none(), st.sampled_from(["0", "4", "5", "-1", "x", "2.5"])),
)
def test_submodel(folder, size, dt, level, phase):
    with tempfile.TemporaryDirectory() as d:
        g = Path(d) / folder
        if folder != "missing":
            g.mkdir()
        if folder in ("nosummary", "badsummary"):
            (g / "cut.h5").write_text("")
        if folder == "badsummary":
            (g / "summary.json").write_text("{")
        out = Path(d) / "out"
        extra = [] if phase is None else ["--phase", phase]
        args = ["--global", str(g), "--size", size, "--dt", dt, "--level", level, *extra, "--out", str(out)]
        check("submodel", args, out)


@FUZZ
@given(paths=st.lists(st.sampled_from(["missing", "empty", "afile", "../.."]), min_size=1, max_size=3))
def test_compare(paths):
    with tempfile.TemporaryDirectory() as d:
        (Path(d) / "empty").mkdir()
        (Path(d) / "afile").write_text("x")
        out = Path(d) / "out"
        args = ["--global", str(Path(d) / paths[0]), *(a for p in paths[1:] for a in ("--submodel", str(Path(d) / p)))]
        check("compare", [*args, "--out", str(out)], out)


@settings(max_examples=10, deadline=None, suppress_health_check=list(HealthCheck), database=None)
@given(
    effects=st.lists(st.sampled_from(["wave_response", "fields", "misalignment", "bogus"]), max_size=2),
    where=outs,
)
@example(effects=["wave_response"], where="fresh")  # one that runs
def fuzz_run(effects, where):
    with tempfile.TemporaryDirectory() as d:
        out = _where(where, Path(d))
        check(
            "run",
            [*sets([*TINY, f"effects={effects!r}"]), "--scene", str(SCENES / "paper.toml"), "--out", str(out)],
            out,
        )


def saw_runs_and_refusals(script: str, fuzz) -> None:
    """Run ``fuzz`` (a hypothesis search of ``script``) and check it both ran and refused (a harness that only ever
    refuses proves nothing). In the case itself: a separate case read the exit codes other cases had left in this
    process, and under pytest-xdist those may have run on the other worker."""
    RESULTS.pop(script, None)
    fuzz()
    assert {0, 2} <= set(RESULTS.get(script, [])), (script, RESULTS.get(script))


def test_analytical():
    saw_runs_and_refusals("analytical", fuzz_analytical)


def test_global():
    saw_runs_and_refusals("global", fuzz_global)


def test_run():
    saw_runs_and_refusals("run", fuzz_run)
