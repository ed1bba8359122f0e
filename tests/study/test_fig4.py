"""Fig. 4: measures of synthetic FE runs (the analytical histories, perturbed by known amounts)."""

from __future__ import annotations

import copy
import math

import pytest

from rods.analytical import simulate
from rods.io import Run, read_data
from rods.study import fig4
from tests.conftest import ROOT


@pytest.fixture(scope="module")
def analytical(request):
    from rods.scene import load_scene
    from tests.conftest import PAPER

    sc = load_scene(PAPER, ["analytical.rtol=1e-7"])
    r = simulate(sc)
    return sc, Run("analytical", r.history, r.summary | {"scene_values": sc.as_dict()})


def perturbed(run: Run, label: str, force: float = 1.0, strain: float = 0.0, **fe) -> Run:
    """``run`` with the force scaled, a constant strain offset and fe settings changed in its scene."""
    h = dict(run.history) | {"contact_force": run.history["contact_force"] * force}
    h["rod2_mid_strain"] = run.history["rod2_mid_strain"] + strain
    s = copy.deepcopy(run.summary)
    s["peak_contact_force"] *= force
    s["scene_values"]["fe"] |= fe
    return Run(label, h, s | {"model": "fe-axisymmetric", "energy_error": 1e-7})


def test_measures_of_known_perturbations(analytical, tmp_path):
    _, a = analytical
    runs = [perturbed(a, "global", force=1.01, strain=2e-6), perturbed(a, "driver", penalty=8.0, tip_grading=0.25)]
    d = fig4.write(a, runs, tmp_path / "fig4.png", tmp_path / "fig4.md")
    g, drv = d["runs"]
    assert g["force_vs_analytical"] == pytest.approx(0.01, rel=1e-9)
    assert g["strain_rms_difference"] == pytest.approx(2e-6, rel=1e-9)
    assert drv["strain_rms_difference"] == 0.0 and drv["contact_overrides"] == {"penalty": 8.0, "tip_grading": 0.25}
    assert fig4.validation_runs(d) == [g]
    assert read_data(tmp_path / "fig4.json")["runs"][0]["label"] == "global" and (tmp_path / "fig4.png").stat().st_size
    assert f"| global | {1.01 * a.summary['peak_contact_force']:.1f} | +1.00% |" in (tmp_path / "fig4.md").read_text()


def test_window_follows_the_runs_scene(analytical):
    """The window is the analytical run's own Rod 2 (no paper constants): a longer rod, a longer window."""
    _, a = analytical
    b = Run(a.label, a.history, copy.deepcopy(a.summary))
    b.summary["scene_values"]["rod2"]["length"] *= 0.5
    assert fig4.compute(b, [])["strain_window"][1] == pytest.approx(0.5 * fig4.compute(a, [])["strain_window"][1])


def test_force_panel_follows_the_runs_contact(analytical):
    """The force panel shows the first contact and as long after it (FORCE_PANEL_CONTACTS), from the analytical
    run's own contact (it was 400 µs on every scene: a 50 µs contact was a sliver, a 1 ms one cut off); a contact
    that has not ended by the run's end: the whole run."""
    from rods.metrics import FORCE_PANEL_CONTACTS

    _, a = analytical
    duration = a.summary["contact_duration"]  # [s] the paper scene's 204 µs: 409 µs where 400 µs was written
    assert fig4.compute(a, [])["force_panel_end"] == pytest.approx(FORCE_PANEL_CONTACTS * duration)
    short = Run(a.label, a.history, copy.deepcopy(a.summary) | {"contact_duration": 25e-6})
    assert fig4.compute(short, [])["force_panel_end"] == pytest.approx(FORCE_PANEL_CONTACTS * 25e-6)
    open_ = Run(a.label, a.history, copy.deepcopy(a.summary) | {"contact_duration": None})
    assert fig4.compute(open_, [])["force_panel_end"] == pytest.approx(float(a.history["time"][-1]))


def test_table_renders_the_committed_rows():
    """The committed record: fig4.md's table is the rendering of fig4.json (the main job wrote both)."""
    committed = (ROOT / "results" / "fig4.md").read_text()
    data = read_data(ROOT / "results" / "fig4.json")
    assert all(line in committed for line in fig4.render_table(data))


def test_a_run_that_could_not_measure_duration_or_speed_renders(analytical, tmp_path):
    """An FE run whose first contact had not ended and whose midpoint plateaus were missing (null in its summary,
    rods.checks) is drawn and tabulated with '–' (was a TypeError, exit 1 of workflows/fig4.py)."""
    _, a = analytical
    short = perturbed(a, "short run")
    short.summary.update(contact_duration=None, midpoint_peak_speed=None)
    d = fig4.write(a, [short], tmp_path / "fig4.png", tmp_path / "fig4.md")
    assert math.isnan(d["runs"][0]["duration_vs_analytical"]) and (tmp_path / "fig4.png").exists()  # JSON: null
    row = next(line for line in (tmp_path / "fig4.md").read_text().splitlines() if line.startswith("| short run"))
    assert row.count("| – ") == 3  # duration, its difference, the average peak speed


def test_window_ends_with_the_shortest_run(analytical):
    """An analytical run shorter than the FE run (or the reverse): the strain RMS covers the common span only, and
    fig4.md says so. Before, the shorter history was held at its last value (an analytical run to 0.3 ms against an
    FE run to 1.5 ms read 247 µε instead of 10 µε) or the window named 1370 µs where the data ended at 300 µs."""
    _, a = analytical
    keep = a.history["time"] <= 3e-4
    short = Run(a.label, {k: v[keep] for k, v in a.history.items()}, copy.deepcopy(a.summary))
    fe = perturbed(a, "global", strain=2e-6)
    for ref, runs in ((short, [fe]), (a, [perturbed(short, "global", strain=2e-6)])):
        d = fig4.compute(ref, runs)
        assert d["strain_window"][1] == pytest.approx(3e-4, abs=1e-6) and d["strain_periods_end"] > 1.3e-3
        assert d["runs"][0]["strain_rms_difference"] == pytest.approx(2e-6, rel=1e-9)
        assert "over the first 300 µs only (the runs' common end, not the first 5 periods" in fig4.render_md(d, "f.png")
    d = fig4.compute(a, [fe])
    assert "over the first 5 periods 2 L2/c2 (1370 µs)." in fig4.render_md(d, "f.png")


def test_only_whole_runs_are_compared(analytical):
    """check_whole_run: an FE run to the analytical run's end passes; one ending before is refused naming --fe, a
    driving global (it carries its contact phase) told to give the scene's own global."""
    from rods.preflight import InputError

    sc, run = analytical
    fe = perturbed(run, "fe")
    fig4.check_whole_run(fe, sc, "f")
    short = copy.deepcopy(fe)
    short.summary["scene_values"]["simulation"]["end_time"] = 3e-4
    with pytest.raises(InputError, match=r"--fe = .f.: it ends at 0.0003 s, .*simulation.end_time=0.0003"):
        fig4.check_whole_run(short, sc, "f")
    short.summary["contact_phase"] = 2.4e-4
    with pytest.raises(InputError, match="a driving global .*give the scene's own global run"):
        fig4.check_whole_run(short, sc, "f")
    cut = copy.deepcopy(fe)  # its summary's end, its history cut short (damaged from outside)
    keep = cut.history["time"] <= 7.4e-5
    cut.history.update({k: v[keep] for k, v in cut.history.items()})
    with pytest.raises(InputError, match="its history.csv stops at 7.4e-05 s, before its end time 0.0015 s"):
        fig4.check_whole_run(cut, sc, "f")
