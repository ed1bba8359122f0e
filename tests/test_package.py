"""A normal (non-editable) install of the wheel carries every subpackage and data file and imports them all."""

from __future__ import annotations

import shutil
import subprocess
import sys
import textwrap

from tests.conftest import ROOT

IMPORT_ALL = textwrap.dedent(
    """
    import importlib, pkgutil, sys
    sys.path.insert(0, sys.argv[1])
    import rods
    assert rods.__file__.startswith(sys.argv[1]), rods.__file__   # the wheel's copy, not the source tree
    names = [m.name for m in pkgutil.walk_packages(rods.__path__, "rods.")]
    for name in names:
        importlib.import_module(name)
    from rods import paper_data
    assert paper_data.load().fe_experiment.impact_speed > 0       # package data shipped
    print(" ".join(sorted(names)))
    """
)


UNPACKAGED = (".git", ".venv", "output", "build", "*.egg-info", "__pycache__", ".pytest_cache", ".snakemake")


def test_wheel_installs_and_imports_every_module(tmp_path):
    """Built from a copy of the working tree: setuptools keeps its build/ folder in the tree it builds, and a module
    moved or deleted since an earlier build in the checkout went into the wheel from there (an import error that
    a clean clone does not have)."""
    wheels, target, src = tmp_path / "wheels", tmp_path / "site", tmp_path / "src"
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(*UNPACKAGED))
    build = [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(wheels), "."]
    subprocess.run(build, cwd=src, check=True, capture_output=True)
    (wheel,) = wheels.glob("rods-*.whl")
    pip = [sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(target), str(wheel)]
    subprocess.run(pip, check=True, capture_output=True)
    run = subprocess.run(
        [sys.executable, "-c", IMPORT_ALL, str(target)], cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr
    modules = set(run.stdout.split())
    assert {"rods.fe", "rods.fe.model", "rods.fe.contact", "rods.paper_data", "rods.analytical"} <= modules
