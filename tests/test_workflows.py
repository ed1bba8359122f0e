"""Workflow scripts as users call them: exit codes, plans, and files (tiny resolution)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from rods.io import SUMMARY_KEYS, read_history

from .conftest import ROOT, SCENES


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
    p = run("analytical.py", *args, "--out", str(out))
    assert p.returncode == 2
    assert "error" in p.stderr and "Traceback" not in p.stderr
    assert not out.exists()


def test_malformed_scene_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[impact\nspeed = 2")
    p = run("analytical.py", "--scene", str(bad), "--out", str(tmp_path / "o"))
    assert p.returncode == 2 and "malformed TOML" in p.stderr
