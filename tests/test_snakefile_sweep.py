"""Sweeps rerun what changed (issue 15): in a fresh clone (no output/, no Snakemake metadata) the committed record
results/sweep-<name>.csv stands for the points whose key (code, resolved scene, parameters) it holds; a changed
``--config speeds=[...]`` schedules exactly the new points, a code change every point."""

from __future__ import annotations

import os
import re
import shutil
import subprocess

import pytest

from .conftest import PY, ROOT

SNAKEMAKE = PY.parent / "snakemake"
pytestmark = pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is not installed beside the interpreter")


@pytest.fixture(scope="module")
def clone(tmp_path_factory):
    """A clone of the repository with the working tree's tracked files (what a fresh checkout has)."""
    d = tmp_path_factory.mktemp("clone") / "rods"
    subprocess.run(["git", "clone", "-q", str(ROOT), str(d)], check=True)
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    for name in filter(None, files.decode().split("\0")):
        src = ROOT / name
        if src.is_file():
            (d / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, d / name)
    return d


def snakemake(clone, speeds, *args):
    cmd = [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "2", "speed_sweep"]
    env = os.environ | {"PYTHONPATH": str(clone)}  # the clone's code runs (this venv is the repository's)
    p = subprocess.run(
        [*cmd, "--config", f"speeds=[{','.join(speeds)}]", *args], cwd=clone, capture_output=True, text=True, env=env
    )
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    return p.stdout + p.stderr


def scheduled_speeds(clone, speeds) -> set[str]:
    """The speeds of the analytical jobs a dry run schedules."""
    out, rule, found = snakemake(clone, speeds, "-n"), None, set()
    for line in out.splitlines():
        if m := re.match(r"\s*(?:local)?rule (\w+):", line):
            rule = m.group(1)
        elif (m := re.match(r"\s*wildcards: .*?speed=([^,\s]+)", line)) and rule == "analytical":
            found.add(m.group(1))
    return found


@pytest.mark.slow  # ~20 s alone: two real sweep points in a temporary clone, then dry runs
def test_fresh_clone_runs_exactly_the_changed_points(clone):
    snakemake(clone, ["1.0", "2.0"])  # the record: two analytical points (~10 s)
    table = (clone / "results" / "sweep-speed.csv").read_text().splitlines()
    assert len(table) == 3 and table[0].endswith(",key")
    shutil.rmtree(clone / "output")  # as a fresh clone of that record
    assert scheduled_speeds(clone, ["1.0", "2.0"]) == set()
    assert scheduled_speeds(clone, ["1.0", "3.0"]) == {"3.0"}
    with (clone / "rods" / "hertz.py").open("a") as f:  # a code change reruns every point
        f.write("\n# changed\n")
    assert scheduled_speeds(clone, ["1.0", "3.0"]) == {"1.0", "3.0"}
    # the repository's own code imported for the clone's changed one (a venv shared by two clones): refused
    p = subprocess.run([str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "speed_sweep"], cwd=clone,
                       capture_output=True, text=True, env=os.environ | {"PYTHONPATH": str(ROOT)})  # fmt: skip
    assert p.returncode == 2 and "imports other code than" in p.stderr and "PYTHONPATH=$PWD" in p.stderr, p.stderr


@pytest.mark.slow  # ~10 s: one real sweep point in the temporary clone, then a dry run
def test_a_base_scenes_edit_reruns_its_points_under_any_rerun_trigger(clone):
    """A scene that inherits a base file: an edit of the base, which no rule names as an input, gives every point a
    new key; under Snakemake's mtime trigger alone the old runs stood and their numbers were published under the new
    keys (a fuzz, 2026-12-06). The key is in each run's folder now, so a new key is a new run."""
    (clone / "workflows" / "scenes" / "derived.toml").write_text('base = "paper.toml"\nname = "derived"\n')
    base = clone / "workflows" / "scenes" / "paper.toml"
    text = base.read_text()
    cmd = [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "2", "speed_sweep", "--config", "speeds=[1.5]",
           "scene=workflows/scenes/derived.toml"]  # fmt: skip
    env = os.environ | {"PYTHONPATH": str(clone)}  # the clone's code (another test of this module changed it)
    p = subprocess.run(cmd, cwd=clone, capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    try:
        base.write_text(text.replace("youngs_modulus = 204.3e9", "youngs_modulus = 150e9", 1))
        assert base.read_text() != text
        p = subprocess.run(
            [*cmd, "--rerun-triggers", "mtime", "-n"], cwd=clone, capture_output=True, text=True, env=env
        )
        assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
        assert re.search(r"rule analytical:[^\n]*\n(?:[^\n]*\n)*?\s*wildcards: .*speed=1\.5", p.stdout), p.stdout
    finally:
        base.write_text(text)
