"""Accuracy against cost: the Pareto rule, the errors of a synthetic run, the table from its data."""

from __future__ import annotations

import math

import pytest

from rods import hertz
from rods.analytical import simulate
from rods.io import Run, read_data
from rods.paper import accuracy_cost
from tests.conftest import ROOT


def test_pareto_front():
    cost = [1.0, 2.0, 3.0, 4.0, 5.0]
    err = [0.5, 0.6, 0.1, math.nan, 0.1]
    # 2 is beaten by 1 (cheaper, better); 5 ties 3 on error but costs more; NaN is never on the front
    assert accuracy_cost.pareto(cost, err) == [True, False, True, False, False]


def test_errors_of_a_run_with_a_known_patch(scene_with, tmp_path):
    sc = scene_with("simulation.end_time=3e-4")  # the first contact; shorter than the strain window
    r = simulate(sc)
    F = 1.02 * r.summary["peak_contact_force"]
    a_hertz = hertz.at_force(F, *hertz.contact_constants(sc.rod1, sc.rod2))["contact_radius"]
    summary = r.summary | {"model": "fe-axisymmetric", "peak_contact_force": F, "contact_radius": 1.05 * a_hertz}
    d = accuracy_cost.write(sc, [Run("fake", r.history, summary | {"dofs": 10, "wall_time": 5.0})], tmp_path / "ac")
    row = d["rows"][-1]
    assert row["peak_force_error"] == pytest.approx(0.02, rel=1e-5)
    assert row["contact_radius_error"] == pytest.approx(0.05, rel=1e-9)
    assert math.isnan(row["strain_rms"]) and not row["on_front"]["strain_rms"]
    assert [r["label"] for r in d["rows"][:4]] == ["rtol 1e-03", "rtol 1e-05", "rtol 1e-07", "rtol 1e-10"]
    assert {p.suffix for p in tmp_path.iterdir()} == {".json", ".md", ".png"}


def test_a_gpu_run_is_labelled_with_its_device(scene_with, tmp_path, monkeypatch):
    """A run whose time loop ran on a GPU (summary "device") says so in its row and in the text; one without
    a device (before 2026-11-27) or on "CPU" is labelled as given. (The study's analytical rows and reference are
    this one run at every rtol: the labels are tested here, not the tolerances.)"""
    sc = scene_with("simulation.end_time=3e-4")
    r = simulate(sc)
    monkeypatch.setattr(accuracy_cost, "simulate", lambda *_, **__: r)
    base = r.summary | {"model": "fe-3d", "contact_radius": 1e-3, "dofs": 10, "wall_time": 5.0}
    runs = [Run("3d-paper", r.history, base | {"device": "NVIDIA H200"}), Run("old", r.history, base)]
    d = accuracy_cost.write(sc, runs, tmp_path / "ac")
    assert [row["label"] for row in d["rows"][-2:]] == ["3d-paper (GPU: NVIDIA H200)", "old"]
    md = (tmp_path / "ac.md").read_text()
    assert "| 3d-paper (GPU: NVIDIA H200) |" in md and "except rows marked GPU" in md
    accuracy_cost.write(sc, runs[1:], tmp_path / "cpu")  # no GPU row: no word of one
    assert "GPU" not in (tmp_path / "cpu.md").read_text()


def test_table_renders_the_committed_rows():
    """The committed record: accuracy-cost.md's table is the rendering of accuracy-cost.json (the whole file:
    tests/test_results.py)."""
    committed = (ROOT / "results" / "accuracy-cost.md").read_text(encoding="utf-8")
    data = read_data(ROOT / "results" / "accuracy-cost.json")
    lines = accuracy_cost.render_table(data)
    assert len(lines) == 2 + len(data["rows"]) and all(line in committed for line in lines)
