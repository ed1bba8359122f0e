"""workflows/run.py simulates only what the scene's effects ask for (tiny resolution)."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rods import checks
from rods.io import read_history
from rods.scene import scene_from_summary

from .conftest import ROOT, in_process

TINY = ["--set", "fe.axial_size=4e-3", "--set", "fe.radial_size=1e-3", "--set", "simulation.end_time=3e-4"]


def run(tmp_path, effects: str, *extra: str) -> tuple[subprocess.CompletedProcess, dict]:
    """run.py in this process (tests/conftest.py in_process; a fresh interpreter's case is
    test_restart_keeps_a_copied_study_spelled_otherwise_with_checkpoints_turned_on)."""
    out = tmp_path / "run"
    p = in_process("run.py", *TINY, "--set", f"effects={effects}", *extra, "--out", str(out), cwd=ROOT)
    assert p.returncode == 0, p.stderr[-2000:]
    return p, json.loads((out / "summary.json").read_text())


def test_wave_response_runs_analytical_and_global_only(tmp_path):
    # an earlier study's products in the folder (a fields study's picture, a contact study's Table 3): this study
    # does not write them, so they must not stand beside its own (a fuzz, 2026-12-07)
    (tmp_path / "run" / "compare").mkdir(parents=True)
    for name in ("contact-fields.png", "contact-fields.json", "table3.md", "fig4.md"):
        (tmp_path / "run" / "compare" / name).write_text("an earlier study's")
    p, s = run(tmp_path, "['wave_response']")
    assert "plan for scene" in p.stdout and "submodel levels: none" in p.stdout
    assert set(s["stages"]) == {"analytical", "global", "compare"}
    assert not (tmp_path / "run" / "submodel").exists()
    # the figure a researcher looks at: Fig. 4 of the scene, the global over the analytical model, with its table
    compare = tmp_path / "run" / "compare"
    assert sorted(f.name for f in compare.iterdir()) == ["fig4.json", "fig4.md", "fig4.png"]
    fig4 = json.loads((compare / "fig4.json").read_text())
    assert [r["label"] for r in fig4["runs"]] == ["global"]
    assert fig4["runs"][0]["peak_contact_force"] == s["peak_contact_force"]  # the same run
    assert abs(fig4["runs"][0]["force_vs_analytical"]) < 0.05  # a 4 mm x 1 mm mesh
    assert not list((tmp_path / "run").rglob("*.xdmf")) and not (tmp_path / "run" / "global" / "cut.h5").exists()
    assert read_history(tmp_path / "run" / "global" / "history.csv")["time"][-1] == pytest.approx(3e-4, rel=1e-3)
    assert s["sources"]["midpoint_peak_speed"] == "global" and s["plan"]["effects"] == ["wave_response"]
    # no submodel resolves the patch: its radius, area and pressure are the analytical model's Hertz at its own
    # force, not the global's one element across it; the force and the duration are the global's
    an = json.loads((tmp_path / "run" / "analytical" / "summary.json").read_text())
    for key in ("contact_radius", "contact_area", "peak_contact_pressure"):
        assert s["sources"][key] == "analytical" and s[key] == an[key], key
    assert s["sources"]["peak_contact_force"] == s["sources"]["contact_duration"] == "global"
    # the study's summary names and replays its scene as each stage's does (Scene.identity; a stage's own settings,
    # e.g. a contact-phase global's end time, are in that stage's summary)
    g = json.loads((tmp_path / "run" / "global" / "summary.json").read_text())
    assert s["scene_overrides"] == an["scene_overrides"] == g["scene_overrides"]
    # the scene's own effects given again are no override (paper.toml has them): the label lists what changed
    assert s["scene_overrides"] == [*(o for o in TINY if "=" in o)]
    assert s["stage_settings"] == [] and s["scene"] == g["scene"]
    # the same answer from every entry point: each model's own door, on the study's scene, writes the study's stage
    for script, stage in (("global.py", "global"), ("analytical.py", "analytical")):
        alone = tmp_path / script
        p = in_process(script, *TINY, "--set", "effects=['wave_response']", "--out", str(alone), cwd=ROOT)
        assert p.returncode == 0, p.stderr[-2000:]
        ours, theirs = read_history(alone / "history.csv"), read_history(tmp_path / "run" / stage / "history.csv")
        assert ours.keys() == theirs.keys() and len(ours["time"]) == 1201  # 0.3 ms every 0.25 µs
        for key in ours:
            np.testing.assert_array_equal(ours[key], theirs[key], err_msg=f"{script}: {key}")


PATCH_STUDY = ("['contact_patch']", "--set", "submodel.levels=['coarse']")  # analytical, driver, one level


@pytest.fixture(scope="module")
def patch_study(tmp_path_factory):
    """One finished contact-patch study (its folder and summary): what the study writes is read from it, and the
    restart tests copy it."""
    base = tmp_path_factory.mktemp("patch-study")
    _, summary = run(base, *PATCH_STUDY)
    return base / "run", summary


def test_contact_patch_adds_driver_submodel_and_comparison_and_stops_global_early(patch_study):
    run_dir, s = patch_study
    assert set(s["stages"]) == {"analytical", "global", "driver", "submodel/coarse", "compare"}
    # the scene's own global drives the submodels (no driver settings): one run, recording the cut, not two
    assert s["stages"]["driver"] == s["stages"]["global"] and not (run_dir / "driver").exists()
    assert (run_dir / "global" / "cut.h5").exists()
    phase = s["plan"]["contact_phase"]
    episodes = json.loads((run_dir / "analytical" / "summary.json").read_text())["contact_episodes"]
    assert phase == pytest.approx(1.2 * episodes[0][1], rel=1e-12) and phase < 3e-4
    for stage in ("global", "submodel/coarse"):  # both stop after the contact phase
        t_end = read_history(run_dir / stage / "history.csv")["time"][-1]
        assert t_end == pytest.approx(phase, abs=0.25e-6), stage  # to one output interval
    assert json.loads((run_dir / "global" / "summary.json").read_text())["contact_phase"] == phase
    assert s["sources"]["contact_radius"] == "submodel/coarse"
    assert s["sources"]["midpoint_peak_speed"] == "analytical"  # no wave response was asked for
    # the global stopped at the contact phase, before the midpoint's plateaus: it has no midpoint keys (null, no
    # warning of what it never ran), and the study takes them from the analytical model
    g = json.loads((run_dir / "global" / "summary.json").read_text())
    assert g["midpoint_peak_speed"] is None and not any(w.startswith("midpoint_peak_speed") for w in g["warnings"])
    assert [w.split(":")[0] for w in s["warnings"] if "midpoint_peak_speed" in w] == ["analytical"]  # 0.3 ms
    table = json.loads((run_dir / "compare" / "table3.json").read_text())
    assert [r["role"] for r in table["rows"]] == ["global-driver", "submodel"]  # the global once
    sub = table["rows"][-1]
    assert sub["force_N"] == pytest.approx(s["peak_contact_force"], rel=1e-12)
    assert abs(sub["d_force_vs_analytical_pct"]) < 10  # 0.25 mm submodel driven by a 4 mm global
    assert not list(run_dir.rglob("*.xdmf"))
    # the study's own checks reach its status: the global against the analytical model, the submodel against Hertz
    an, g = (json.loads((run_dir / k / "summary.json").read_text()) for k in ("analytical", "global"))
    assert [w for w in s["warnings"] if w.startswith("study: ")] == [
        f"study: {w}" for w in checks.agreement_warnings(an, g, scene_from_summary(g["scene_values"]))
    ]
    assert [w for w in s["warnings"] if w.startswith("compare: ")] == [
        f"compare: {w}" for w in checks.submodel_warnings(table)
    ]
    # one coarse level (4.4 elements across the patch) misses Hertz's peak pressure by 4.5%: not a signed result
    assert any(w.startswith("compare: peak_contact_pressure: the finest submodel level (coarse") for w in s["warnings"])


# 6 mm rods, a 35 mm tip tilted 0.02 rad: the patch (a = 0.66 mm) lies R1 sin θ = 0.70 mm off Rod 1's axis
TILTED_STUDY = (
    *("--set", "rod1.length=0.05", "--set", "rod2.length=0.05", "--set", "rod1.diameter=6e-3"),
    *("--set", "rod2.diameter=6e-3", "--set", "fe.kind='3d'", "--set", "fe.symmetry='half'"),
    *("--set", "impact.tilt=0.02", "--set", "fe.radial_size=0.4e-3", "--set", "fe.axial_size=1e-3"),
    *("--set", "effects=['contact_patch','misalignment']", "--set", "submodel.levels=['coarse']"),
)


@pytest.mark.slow  # 20 s: a whole tilted 3D study; its pieces (placement, centroid, axis, Fig. 5c) are unit-tested
def test_tilted_3d_study_measures_the_patch_where_the_tilt_puts_it(tmp_path):
    """A tilted impact end to end (global, cut record, 3D submodel, Table 3, Figs. 5c and 6): the patch is found
    R1 sin θ off Rod 1's axis, and the submodel's pressure and σ_r follow Hertz about it (taken about Rod 1's axis,
    as before the contact's axis, the σ_r error is 80%: measured by patching rods.fe.submodel.contact_axis)."""
    out = tmp_path / "run"
    p = in_process("run.py", *TILTED_STUDY, "--out", str(out), cwd=ROOT)
    assert p.returncode == 0, p.stderr[-2000:]
    s = json.loads((out / "summary.json").read_text())
    assert set(s["stages"]) == {"analytical", "global", "driver", "submodel/coarse", "compare"}
    x_touch = -0.035 * np.sin(0.02)  # [m] where the tilted sphere first touches the flat face
    for stage, h in (("global", 0.4e-3), ("submodel/coarse", 0.25e-3)):
        g = json.loads((out / stage / "summary.json").read_text())
        assert g["contact_centroid_x"] == pytest.approx(x_touch, abs=h / 2), stage  # measured -0.644 mm (global)
        assert g["contact_centroid_y"] == 0.0, stage  # the half model's plane of symmetry
    sub = json.loads((out / "compare" / "table3.json").read_text())["rows"][-1]
    assert abs(sub["d_force_vs_analytical_pct"]) < 4  # measured -2.18%: a 0.4 mm global drives it
    assert abs(sub["d_p0_vs_hertz_pct"]) < 3  # measured +0.91%, Hertz at the submodel's own force
    assert sub["sigma_r_err_depth_pct"] < 20  # measured 13.2% (2.6 elements across the patch), 80% about Rod 1's axis
    for name in ("fig5c-pressure.png", "fig5c-profile.png", "fig6-sigma-r.png"):
        assert (out / "compare" / name).stat().st_size > 10_000, name


def copied(study, tmp_path):
    """The finished study copied into tmp_path/run (modification times kept, as cp -p and rsync -a do)."""
    import shutil

    shutil.copytree(study[0], tmp_path / "run")
    return tmp_path / "run"


def test_restart_keeps_the_finished_stages_and_reruns_the_stopped_one(patch_study, tmp_path):
    """run.py --restart: a stage finished for the same scene is kept (not rewritten), a stopped one (an
    interrupt's partial summary) runs again, and the study ends as an uninterrupted one did; a stage of other
    settings is never kept."""
    run_dir, s1 = copied(patch_study, tmp_path), patch_study[1]
    g, sub = run_dir / "global" / "summary.json", run_dir / "submodel" / "coarse" / "summary.json"
    partial = json.loads(sub.read_text()) | {"status": "interrupted"}
    sub.write_text(json.dumps(partial))  # as Ctrl-C in the submodel leaves it
    stamp = g.stat().st_mtime_ns
    p, s2 = run(tmp_path, *PATCH_STUDY, "--restart")
    assert f"global: finished in {run_dir / 'global'} for this scene, kept" in p.stdout
    assert g.stat().st_mtime_ns == stamp and json.loads(sub.read_text())["status"] != "interrupted"
    for key in ("peak_contact_force", "contact_radius", "contact_duration", "status", "warnings", "sources"):
        assert s2[key] == s1[key], key


def test_restart_with_other_settings_is_refused(patch_study, tmp_path):
    """run.py --restart with other settings (a coarser axial mesh) into a study's folder is refused before anything
    runs, one line naming the key and both values, as global.py's and submodel.py's restarts are: it reran and
    overwrote every finished stage, silently (a fuzz, 2026-12-07). A level added (submodel.levels) or checkpoints
    turned on are a restart's own choices (the test above and the one below)."""
    run_dir = copied(patch_study, tmp_path)
    g = run_dir / "global" / "summary.json"
    stamp = g.stat().st_mtime_ns
    args = (*TINY, "--set", f"effects={PATCH_STUDY[0]}", *PATCH_STUDY[1:], "--set", "fe.axial_size=5e-3")
    p = in_process("run.py", *args, "--out", str(run_dir), "--restart", cwd=ROOT)
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1, p.stderr[-2000:]
    assert "ran another scene (fe.axial_size = 0.004 there, 0.005 here)" in p.stderr and "without --restart" in p.stderr
    assert g.stat().st_mtime_ns == stamp


def test_restart_keeps_a_copied_study_spelled_otherwise_with_checkpoints_turned_on(patch_study, tmp_path):
    """A finished study copied elsewhere, its --out given relative, restarted with fe.checkpoint_interval now on:
    every FE stage is kept, and said so. The cut record is known by the id its recording wrote, not by its path
    (a copied folder reran its submodels before; an --out spelled otherwise did once), and checkpoints do not
    change a stage's result (adding them reran the finished stages before)."""
    run_dir = copied(patch_study, tmp_path)
    sub = run_dir / "submodel" / "coarse" / "summary.json"
    stamp = sub.stat().st_mtime_ns
    args = [sys.executable, str(ROOT / "workflows" / "run.py"), *TINY, "--set", f"effects={PATCH_STUDY[0]}",
            *PATCH_STUDY[1:], "--set", "fe.checkpoint_interval=1e-4", "--out", "run", "--restart"]  # fmt: skip
    env = {**__import__("os").environ, "PYTHONPATH": str(ROOT)}
    p = subprocess.run(args, capture_output=True, text=True, cwd=tmp_path, env=env)
    assert p.returncode == 0, p.stderr[-2000:]
    assert sub.stat().st_mtime_ns == stamp
    for stage in ("global", "submodel/coarse"):
        assert f"{stage}: finished in {Path('run') / stage} for this scene, kept" in p.stdout, stage


@pytest.mark.slow  # 13 s: a regression case of the restart's cut-record id; the restart itself is in the default suite
def test_restart_reruns_a_submodel_level_driven_by_an_earlier_cut_record(patch_study, tmp_path):
    """A fresh run that rewrote the global (its cut.h5) and was killed before reaching a submodel level leaves
    that level's earlier summary in the folder: the restart keeps the global, not the level (another record
    drove it; it was kept as "finished for this scene")."""
    import h5py

    run_dir = copied(patch_study, tmp_path)
    with h5py.File(run_dir / "global" / "cut.h5", "r+") as f:
        f.attrs["record_id"] = "another recording"  # as the fresh run's global rewrote it
    p, _ = run(tmp_path, *PATCH_STUDY, "--restart")
    assert "global: finished" in p.stdout and "submodel/coarse: finished" not in p.stdout
    p, _ = run(tmp_path, *PATCH_STUDY, "--restart")
    assert "submodel/coarse: finished" in p.stdout  # the level the restart ran is kept by the next one


def test_wave_and_contact_run_one_global_that_records_the_cut_over_the_contact_phase_only(tmp_path):
    import h5py

    p, s = run(tmp_path, "['wave_response', 'contact_patch']", "--set", "submodel.levels=['coarse']")
    run_dir, phase = tmp_path / "run", s["plan"]["contact_phase"]
    assert p.stdout.count("cost of the global") == 1 and "cost of the driving global" not in p.stdout
    assert s["stages"]["driver"] == s["stages"]["global"] and not (run_dir / "driver").exists()
    assert read_history(run_dir / "global" / "history.csv")["time"][-1] == pytest.approx(3e-4, rel=1e-3)
    with h5py.File(run_dir / "global" / "cut.h5") as f:
        times = f["times"][:]
    dt = times[1] - times[0]
    assert phase <= times[-1] < phase + dt + 1e-15  # the record covers the contact phase, one step past, no more
    t_sub = read_history(run_dir / "submodel" / "coarse" / "history.csv")["time"][-1]
    assert t_sub == pytest.approx(phase, abs=0.25e-6)
    assert s["sources"]["midpoint_peak_speed"] == "global" and s["sources"]["contact_radius"] == "submodel/coarse"
    # its plateaus are its own (0.3 ms: two of five), not a driver's stopped at the contact phase (a fuzz draw found
    # "a driving global runs the contact phase only (to 259.6 µs)" on such a study, its end the scene's)
    mid = [w for w in s["warnings"] if w.startswith("global: midpoint_peak_speed")]
    assert mid and "only 2 of 5 plateaus within end_time" in mid[0] and "driving global" not in mid[0]
    # and fig4.py takes that global as the study's compare stage did (it refused it as a driver, by the key its
    # summary shares with one: a fuzz, 2026-12-06)
    fig = tmp_path / "fig4"
    args = [
        "--analytical",
        str(run_dir / "analytical"),
        "--fe",
        f"global={run_dir / 'global'}",
        "--png",
        str(fig / "f.png"),
    ]
    p = in_process("fig4.py", *args, "--md", str(fig / "f.md"), cwd=ROOT)
    assert p.returncode == 0, p.stderr[-2000:]
    ours, study = (json.loads(f.read_text())["runs"][0] for f in (fig / "f.json", run_dir / "compare" / "fig4.json"))
    assert ours["peak_contact_force"] == study["peak_contact_force"]  # the study's own measures (the strain RMS
    assert ours["strain_rms_difference"] == pytest.approx(study["strain_rms_difference"], rel=1e-8)  # from CSV here)


def test_dry_run_prints_the_plan_and_costs_and_writes_nothing(tmp_path):
    out = tmp_path / "x"
    p = subprocess.run(
        [sys.executable, str(ROOT / "workflows" / "run.py"), "--set", "effects=['contact_patch']", "--dry-run",
         "--out", str(out)],
        capture_output=True, text=True, cwd=ROOT,
    )  # fmt: skip
    assert p.returncode == 0, p.stderr
    assert "submodel levels: coarse, mid, fine" in p.stdout and "cost of the submodel fine" in p.stdout
    assert "\ncost of the comparison: wall time about " in p.stdout  # Table 3 and its figures, after the stages
    assert "\ncost in all: wall time about " in p.stdout  # the stages' sum under their costs
    assert "dry run" in p.stdout and not out.exists()
    for script in ("analytical.py", "global.py"):  # the single-model doors too
        p = in_process(script, "--dry-run", "--out", str(out), cwd=ROOT)
        assert p.returncode == 0 and "cost of" in p.stdout and "dry run" in p.stdout, (script, p.stderr)
        assert p.stdout.startswith("plan: ") and not out.exists()  # what would run, then what it costs
        assert "cost in all" not in p.stdout  # one stage: its cost is the whole
    p = in_process("global.py", "--driver", "--dry-run", "--out", str(out), cwd=ROOT)
    assert "plan: the driving global (axisymmetric" in p.stdout and "t_end = 0.000244" in p.stdout  # the contact phase


def test_fields_only_when_asked(tmp_path):
    """effects = ["fields"] alone (no fe.field_interval) writes the series at the default interval: ten frames a
    round trip of Rod 1 (the shorter: 97.7 µs, a frame every 9.77 µs) over the 0.3 ms run, plus the final state where
    it is a step or more past the last; the wave-response run (test above) writes none."""
    from rods.scene import FIELD_FRAMES_PER_ROUND_TRIP, scene_from_summary

    _, s = run(tmp_path, "['fields']")
    xdmf = tmp_path / "run" / "global" / "fields.xdmf"
    assert s["plan"]["fields"] and xdmf.exists()
    interval = scene_from_summary(s["scene_values"]).rod1.round_trip_time / FIELD_FRAMES_PER_ROUND_TRIP  # [s]
    assert interval == pytest.approx(9.764e-6, rel=1e-3)
    times = [float(t) for t in re.findall(r'<Time Value="([^"]+)"', xdmf.read_text())]
    requested = [t for t in times if abs(t / interval - round(t / interval)) < 1e-6]
    assert len(requested) == int(3e-4 / interval) + 1 and len(times) - len(requested) <= 1
    # and the picture of them people would rather look at: the contact region at the peak-pressure frame
    compare = Path(s["stages"]["compare"])
    picture = json.loads((compare / "contact-fields.json").read_text())
    assert (compare / "contact-fields.png").stat().st_size > 20_000 and picture["time"] in times
    assert picture["peak_contact_pressure"] > 0 and picture["scene"] == s["scene"]
    assert picture["field_interval"] == pytest.approx(interval)  # the effect's default (fe.field_interval is 0)


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
