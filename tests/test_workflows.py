"""Workflow scripts as users call them: exit codes, plans, default folders and files (tiny resolution)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from rods.io import SUMMARY_KEYS, read_history

from .conftest import MPIRUN, PY, ROOT, SCENES, in_process


def run(script: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(ROOT / "workflows" / script), *args], capture_output=True, text=True, cwd=ROOT
    )


def test_analytical_workflow_writes_summary_and_history(tmp_path):
    p = run(
        "analytical.py",
        "--scene",
        str(SCENES / "trial-2-5.toml"),
        "--set",
        "simulation.end_time=5e-4",
        "--out",
        str(tmp_path),
    )
    assert p.returncode == 0, p.stderr
    assert "plan:" in p.stdout
    s = json.loads((tmp_path / "summary.json").read_text())
    assert set(SUMMARY_KEYS) <= set(s) and s["impact_speed"] == 1.848 and s["model"] == "analytical"
    h = read_history(tmp_path / "history.csv")
    assert h["time"][-1] == pytest.approx(5e-4) and {"contact_force", "rod2_mid_velocity", "rod2_mid_strain"} <= set(h)
    assert not list(tmp_path.glob(".*.tmp"))  # atomic writes leave no temporaries


@pytest.mark.parametrize(
    "args",
    [
        ["--set", "impact.speed=-1"],
        ["--set", "impact.speed=nan"],
        ["--set", "rod1.length=250.09"],
        ["--set", "impact.sped=2"],
        ["--set", "effects=['teleport']"],
        ["--set", "impact.speed"],
        ["--scene", "no/such/scene.toml"],
        ["--bogus-flag"],
    ],
)
def test_bad_input_exits_2_and_writes_nothing(tmp_path, args):
    out = tmp_path / "out"
    p = in_process("analytical.py", *args, "--out", str(out), cwd=ROOT)
    assert p.returncode == 2
    assert "error" in p.stderr and "Traceback" not in p.stderr
    assert not out.exists()


def test_malformed_scene_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[impact\nspeed = 2")
    p = run("analytical.py", "--scene", str(bad), "--out", str(tmp_path / "o"))
    assert p.returncode == 2 and "malformed TOML" in p.stderr


# ---------------------------------------------------------------------------------------------
# Every entry point runs as a test, serially and under MPI (after DOLFINx's python/demo/test.py), on a tiny
# scene, from a fresh folder without --out: each writes its default folder under output/ and never results/.
# ---------------------------------------------------------------------------------------------
TINY = ["--set", "fe.axial_size=4e-3", "--set", "fe.radial_size=1e-3", "--set", "simulation.end_time=3e-4"]


@pytest.fixture(scope="module")
def tiny_driver(tmp_path_factory) -> Path:
    """The library's driving global on the tiny scene, run by `global.py --driver` into its default folder."""
    cwd = tmp_path_factory.mktemp("driver")
    p = subprocess.run([str(PY), str(ROOT / "workflows" / "global.py"), *TINY, "--driver"], **_in(cwd))
    assert p.returncode == 0, p.stderr[-2000:]
    assert not (cwd / "results").exists()
    (folder,) = (cwd / "output" / "driver").glob("paper-*")  # the tiny scene's values (--set): their own folder
    return folder


def _in(cwd: Path) -> dict:
    return {"cwd": cwd, "capture_output": True, "text": True, "timeout": 300}


ENTRY_POINTS = {  # name -> (script, arguments, default output folder)
    "analytical": ("analytical.py", ["--set", "simulation.end_time=3e-4"], "output/analytical/paper"),
    "global": ("global.py", TINY, "output/global/paper"),
    "submodel": ("submodel.py", ["--global", "{driver}", "--size", "1e-3"], "output/submodel/h=0.001/paper"),
    "run": ("run.py", [*TINY, "--set", "effects=['wave_response']"], "output/run/paper"),
}


def _entry_point(name: str, ranks: int, driver: Path, cwd: Path) -> None:
    script, args, folder = ENTRY_POINTS[name]
    cmd = [str(PY), str(ROOT / "workflows" / script), *(a.format(driver=driver) for a in args)]
    p = subprocess.run([str(MPIRUN), "-n", str(ranks), *cmd] if ranks > 1 else cmd, **_in(cwd))
    assert p.returncode == 0, p.stderr[-2000:]
    if "--set" in args:  # the scene's values changed: the default folder carries their digest
        (found,) = cwd.glob(folder + "-*")
        folder = found.relative_to(cwd)
    s = json.loads((cwd / folder / "summary.json").read_text())
    assert set(SUMMARY_KEYS) <= set(s) and s["peak_contact_force"] > 0
    # an FE run records its rank count (a study, in its global stage's summary); the analytical model runs on each
    if name != "analytical":
        fe = json.loads((cwd / folder / "global" / "summary.json").read_text()) if name == "run" else s
        assert fe["ranks"] == ranks
    assert any((cwd / folder).rglob("history.csv"))
    assert not (cwd / "results").exists()


@pytest.mark.parametrize("name", list(ENTRY_POINTS))
def test_entry_point_serial(name, tiny_driver, tmp_path):
    _entry_point(name, 1, tiny_driver, tmp_path)


@pytest.mark.mpi
@pytest.mark.parametrize("name", [n for n in ENTRY_POINTS if n != "analytical"])
def test_entry_point_mpi(name, tiny_driver, tmp_path):
    _entry_point(name, 2, tiny_driver, tmp_path)


def test_snakefile_wires_the_library_driver_and_stages():
    """Dry run of the main job and the sweeps: the submodels are driven by `global.py --driver` (the
    library's driver over the contact phase), the comparison writes table3.json, no rule runs a recipe."""
    p = subprocess.run(
        [
            str(PY.parent / "snakemake"),
            "-s",
            "workflows/Snakefile",
            "-n",
            "-p",
            "--nolock",
            "--forceall",
            "--cores",
            "2",
        ]
        + ["paper", "speed_sweep", "mesh_sweep", "dt_sweep"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert p.returncode == 0, p.stderr[-2000:]
    lines = [ln.strip() for ln in p.stdout.splitlines() if str(PY) in ln]  # the shell commands
    drivers = [ln for ln in lines if "global.py" in ln and "--driver" in ln]
    assert len(drivers) == 1 and "--record" not in drivers[0] and "--set" not in drivers[0]
    subs = [ln for ln in lines if "submodel.py" in ln]
    assert all("--global output/paper/driver" in ln for ln in subs)
    levels = [ln for ln in subs if "--phase" not in ln]
    phases = sorted(ln.split("--phase ", 1)[1].split()[0] for ln in subs if "--phase" in ln)
    assert len(levels) == 5  # the five levels; the other four phase members of the first four (the middle is the level)
    assert phases == sorted(["0", "1", "3", "4"] * 4)
    assert any("--level ultra-fine" in ln for ln in levels)
    assert any("compare.py" in ln and "--out results" in ln for ln in lines)
    assert not any("fe.penalty=8" in ln or "record-until" in ln for ln in lines)  # the recipe is the library's
    # a redirected log is a declared `log:` (Snakemake makes its folder; a bare `> output/paper/x.log` failed
    # on a clean clone where no earlier output had made output/paper)
    logs = {ln.split("log:", 1)[1].strip() for ln in p.stdout.splitlines() if ln.strip().startswith("log:")}
    redirected = {ln.split(" > ", 1)[1].split()[0] for ln in lines if " > " in ln and "2>&1" in ln}
    assert redirected and redirected <= logs, sorted(redirected - logs)
