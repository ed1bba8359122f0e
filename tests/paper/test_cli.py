"""The four thin CLIs, called in-process as the Snakefile calls them (the bands are skipped: seconds)."""

from __future__ import annotations

import importlib

import pytest

from rods.io import read_data
from rods.paper import table2


@pytest.fixture(scope="module")
def job(tmp_path_factory):
    """workflows/paper.py --out DIR (its tables default to DIR, never to results/)."""
    out = tmp_path_factory.mktemp("paper")
    mp = pytest.MonkeyPatch()
    mp.setattr(
        table2, "_bands", lambda scene: {q: {"nominal": 1.0, "uncertainty": 0.0} for q in ("radius", "peak_speed")}
    )
    assert importlib.import_module("paper").main(["--out", str(out)]) == 0
    mp.undo()
    return out


def test_paper_writes_its_stage_under_out(job):
    names = {p.name for p in job.iterdir()}
    assert {"table2.json", "table2.csv", "table2.md", "table2.png", "fig4-analytical.png", "analytical"} <= names
    s = read_data(job / "analytical" / "trial-1-3" / "summary.json")
    assert s["scene_values"]["rod2"]["length"] == 0.70099  # later stages rebuild the scene from the run


def test_fig4_and_accuracy_cost_clis(job, tmp_path, monkeypatch):
    """Both read the runs they are given, and refuse (exit 2) what is not a run of their scene: an analytical run
    of another trial as an FE run, a missing folder (skipped with a note before 2026-11-24)."""
    from rods.preflight import InputError
    from rods.scene import load_scene
    from rods.study import stages

    from ..conftest import SCENES

    a, g = job / "analytical", tmp_path / "global"
    tiny = ("fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=3e-4")
    stages.global_model(load_scene(SCENES / "trial-1-3.toml", tiny), g, None)
    fig4 = importlib.import_module("fig4")
    out = ["--png", str(tmp_path / "f.png"), "--md", str(tmp_path / "f.md")]
    with pytest.raises(InputError, match="--fe.*it ends at 0.0003 s, before the --analytical run's end"):
        fig4.main(["--analytical", str(a / "trial-1-3"), "--fe", f"coarse={g}", *out])  # its plateaus: not all
    short = tmp_path / "analytical"  # the analytical model over the global's 0.3 ms: the two compare
    stages.analytical(load_scene(SCENES / "trial-1-3.toml", ("simulation.end_time=3e-4",)), short)
    assert fig4.main(["--analytical", str(short), "--fe", f"coarse={g}", *out]) == 0
    assert read_data(tmp_path / "f.json")["runs"][0]["label"] == "coarse"
    with pytest.raises(InputError, match="--fe.*model 'analytical'"):
        fig4.main(["--analytical", str(a / "trial-1-3"), "--fe", f"other trial={a / 'trial-2-4'}", *out])
    ac = importlib.import_module("accuracy_cost")
    runs = ["--scene", str(SCENES / "trial-1-3.toml"), "--run", f"trial={a / 'trial-1-3'}", "--run", f"coarse={g}"]
    assert ac.main([*runs, "--set", "simulation.end_time=3e-4", "--out", str(tmp_path / "ac")]) == 0
    assert {r["label"] for r in read_data(tmp_path / "ac.json")["rows"]} >= {"trial", "coarse"}
    # without --out: the scene's own folder, not the paper's tables (the default was output/paper/ for every scene)
    monkeypatch.chdir(tmp_path)
    assert ac.main([*runs, "--set", "simulation.end_time=3e-4"]) == 0
    (own,) = (tmp_path / "output" / "accuracy-cost").glob("trial-1-3-*/accuracy-cost.json")
    assert [r["label"] for r in read_data(own)["rows"]] == [r["label"] for r in read_data(tmp_path / "ac.json")["rows"]]
    with pytest.raises(InputError, match="--run.*no such folder"):
        ac.main([*runs, "--run", f"missing={tmp_path / 'none'}", "--out", str(tmp_path / "ac2")])


def test_later_stages_read_real_submodel_runs(tmp_path):
    """global.py --driver and submodel.py, then compare.py, convergence.py and accuracy_cost.py on their folders
    with --scene, as the Snakefile chains them. A submodel's own scene_values are the cut region's (rods 14 mm
    long: no scene of the schema), so its bodies and impact are checked against its driving global's scene
    (driver_scene_values); all three refused every submodel of the paper's rods before (exit 2, "rod1.length =
    0.014 ... unreadable summary.json")."""
    from rods.preflight import InputError

    from ..conftest import SCENES

    tiny = [a for o in ("fe.axial_size=4e-3", "fe.radial_size=1e-3") for a in ("--set", o)]
    scene = ["--scene", str(SCENES / "paper.toml"), *tiny]
    drv, sub = tmp_path / "driver", tmp_path / "coarse"
    assert importlib.import_module("global").main([*scene, "--driver", "--out", str(drv)]) == 0
    assert importlib.import_module("submodel").main(["--global", str(drv), "--size", "1e-3", "--out", str(sub)]) == 0
    assert read_data(sub / "summary.json")["driver_scene_values"]["rod1"]["length"] == 0.25009
    compare = importlib.import_module("compare")
    assert compare.main([*scene, "--global", str(drv), "--submodel", str(sub), "--out", str(tmp_path / "t3")]) == 0
    t3 = read_data(tmp_path / "t3" / "table3.json")
    assert {r["role"] for r in t3["rows"]} >= {"submodel"}
    # a 1 mm level across a ~1.1 mm patch: compare.py says what a study's "compare:" check says of it (it printed no
    # status at all, where run.py warned of the same runs)
    from rods import checks

    assert t3["status"] == "warnings" and t3["warnings"] == checks.submodel_warnings(t3)
    assert "Warning: " in (tmp_path / "t3" / "table3.md").read_text()
    assert importlib.import_module("convergence").main([*scene, "--run", str(sub), "--out", str(tmp_path / "cv")]) == 0
    ac = importlib.import_module("accuracy_cost")
    assert ac.main([*scene, "--run", f"coarse={sub}", "--out", str(tmp_path / "ac")]) == 0
    with pytest.raises(InputError, match="--run.*impact.speed = 2.197 there, 2.0 in this one"):  # another scene's
        importlib.import_module("convergence").main([*scene, "--set", "impact.speed=2.0", "--run", str(sub)])
    # a global that ends before its first contact does (its Table 3 row read -20% with exit 0), a stopped run
    import json
    import shutil

    for name, change, match in (
        ("short", {"contact_duration": None}, "--global.*first contact has not ended"),
        ("stopped", {"status": "interrupted"}, "--global.*a stopped run"),
    ):
        shutil.copytree(drv, tmp_path / name)
        s = read_data(drv / "summary.json") | change
        (tmp_path / name / "summary.json").write_text(json.dumps(s))
        with pytest.raises(InputError, match=match):
            compare.main(
                [*scene, "--global", str(tmp_path / name), "--submodel", str(sub), "--out", str(tmp_path / "y")]
            )
        assert not (tmp_path / "y").exists()
