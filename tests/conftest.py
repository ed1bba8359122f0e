"""Shared fixtures: the paper scene and a helper to build variants of it."""

from __future__ import annotations

import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "workflows" / "scenes"
PAPER = SCENES / "paper.toml"
PY = Path(sys.executable)  # the interpreter running the tests (.venv/bin/python under make test)
# the mpich wheel's launcher beside the interpreter; another install's (conda, a container) on PATH
MPIRUN = PY.parent / "mpirun" if (PY.parent / "mpirun").exists() else Path(shutil.which("mpirun") or "mpirun")
sys.path.insert(0, str(ROOT / "workflows"))


def pytest_collection_modifyitems(config, items):  # noqa: ARG001
    """A case marked ``mpi`` or ``alone`` sits in a file that spells the mark (``pytest.mark.mpi``): `make test`
    collects its one-at-a-time part from the files a grep for the marks finds (Makefile, MARKED)."""
    import re

    spelled: dict[Path, bool] = {}
    for item in items:
        if item.get_closest_marker("mpi") or item.get_closest_marker("alone"):
            path = Path(item.path)
            if path not in spelled:
                spelled[path] = re.search(r"mark\.(mpi|alone)", path.read_text(encoding="utf-8")) is not None
            if not spelled[path]:
                raise pytest.UsageError(
                    f"{item.nodeid}: marked mpi or alone without 'pytest.mark.mpi'/'.alone' in its file"
                )


def benchmark(name: str):
    """benchmarks/<name>.py loaded as a module (the benchmarks are scripts, not a package)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    return bench


@pytest.fixture(scope="session")
def paper_dict() -> dict:
    return tomllib.loads((SCENES / "paper.toml").read_text())


@pytest.fixture
def scene_with(paper_dict):
    """``scene_with("impact.speed=1.0", ...)``: the paper scene with overrides, validated."""
    from rods.scene import scene_from_dict

    def make(*overrides: str):
        return scene_from_dict(paper_dict, overrides, source="paper.toml")

    return make


def recorded_global(overrides: list[str], tmp_path_factory, name: str = "global"):
    """Run the paper scene with ``overrides`` as a global model recording its cut band (submodel tests):
    returns (scene, model, result, path of cut.h5)."""
    from rods.fe.cut import CutRecorder
    from rods.fe.model import ExplicitModel
    from rods.scene import load_scene

    sc = load_scene(PAPER, overrides)
    g = ExplicitModel(sc)
    rec = CutRecorder(g)
    res = g.run(observers=(rec,))
    path = tmp_path_factory.mktemp(name) / "cut.h5"
    rec.write(path)
    return sc, g, res, path


def set_args(overrides: list[str]) -> list[str]:
    """``--set KEY=VALUE`` arguments for scene overrides."""
    return [a for o in overrides for a in ("--set", o)]


def in_process(script: str, *args: str, cwd: Path) -> subprocess.CompletedProcess:
    """Run ``workflows/<script>``'s main through the entry points' one error path (``_cli.guarded``, as its
    ``__main__`` does) in this process, from ``cwd``: the exit code, stdout and stderr a subprocess would give,
    without an interpreter's start and imports (about 1 s each on 2026-11-28's machine, which the ~60 refusal
    cases paid). What only a fresh interpreter shows (an import's warning on stderr) is left to one subprocess
    case per script (tests/test_cli_errors.py)."""
    import contextlib
    import importlib
    import io
    import os

    import _cli

    main = importlib.import_module(Path(script).stem).main
    out, err, here = io.StringIO(), io.StringIO(), Path.cwd()
    try:
        os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = _cli.guarded(main)(list(args))
            except SystemExit as e:  # argparse's and _cli.fail's exit
                code = e.code if isinstance(e.code, int) else int(e.code is not None)
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess([script, *args], code, out.getvalue(), err.getvalue())


def run_workflow(
    script: str, args: list[str], ranks: int = 1, timeout: float = 600, fresh: bool = False
) -> subprocess.CompletedProcess:
    """Run ``workflows/<script>`` with ``args`` from the repository root: under mpirun when ranks > 1; serially in
    this process (:func:`in_process`: the same main and error path, without an interpreter's start and imports, 2-4 s
    each) unless ``fresh`` asks for a new interpreter. Every entry point also runs as a subprocess, serially and
    under mpirun, in tests/test_workflows.py."""
    if ranks == 1 and not fresh:
        return in_process(script, *args, cwd=ROOT)
    cmd = [str(PY), f"workflows/{script}", *args]
    if ranks > 1:
        cmd = [str(MPIRUN), "-n", str(ranks), *cmd]
    return subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=timeout)
