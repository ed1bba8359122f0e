"""workflows/run.py simulates only what the scene's effects ask for (tiny resolution)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from rods.io import read_history

from .conftest import ROOT

TINY = ["--set", "fe.axial_size=4e-3", "--set", "fe.radial_size=1e-3", "--set", "simulation.end_time=3e-4"]


def run(tmp_path, effects: str, *extra: str) -> tuple[subprocess.CompletedProcess, dict]:
    out = tmp_path / "run"
    p = subprocess.run(
        [
            sys.executable,
            str(ROOT / "workflows" / "run.py"),
            *TINY,
            "--set",
            f"effects={effects}",
            *extra,
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert p.returncode == 0, p.stderr[-2000:]
    return p, json.loads((out / "summary.json").read_text())


def test_wave_response_runs_analytical_and_global_only(tmp_path):
    p, s = run(tmp_path, "['wave_response']")
    assert "plan for scene" in p.stdout and "submodel levels: none" in p.stdout
    assert set(s["stages"]) == {"analytical", "global"}
    assert not (tmp_path / "run" / "submodel").exists()
    assert not list((tmp_path / "run").rglob("*.xdmf")) and not (tmp_path / "run" / "global" / "cut.h5").exists()
    assert read_history(tmp_path / "run" / "global" / "history.csv")["time"][-1] == pytest.approx(3e-4, rel=1e-3)
    assert s["sources"]["midpoint_peak_speed"] == "global" and s["plan"]["effects"] == ["wave_response"]


def test_contact_patch_adds_submodel_and_stops_global_early(tmp_path):
    _, s = run(tmp_path, "['contact_patch']", "--set", "submodel.levels=['coarse']")
    assert set(s["stages"]) == {"analytical", "global", "submodel/coarse"}
    t_end = read_history(tmp_path / "run" / "global" / "history.csv")["time"][-1]
    assert t_end == pytest.approx(s["plan"]["global_end_time"], rel=1e-3) and t_end < 3e-4
    assert s["sources"]["contact_radius"] == "submodel/coarse"
    assert s["sources"]["midpoint_peak_speed"] == "analytical"  # no wave response was asked for
    assert not list((tmp_path / "run").rglob("*.xdmf"))


def test_fields_only_when_asked(tmp_path):
    _, s = run(tmp_path, "['fields']", "--set", "fe.field_interval=1e-4")
    assert s["plan"]["fields"] and (tmp_path / "run" / "global" / "fields.xdmf").exists()


def test_unknown_effect_is_exit_2(tmp_path):
    p = subprocess.run(
        [
            sys.executable,
            str(ROOT / "workflows" / "run.py"),
            "--set",
            "effects=['teleport']",
            "--out",
            str(tmp_path / "x"),
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert p.returncode == 2 and "unknown effect" in p.stderr and not (tmp_path / "x").exists()
