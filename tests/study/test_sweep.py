"""The sweeps' config (rods.study.sweep.check_config): what the Snakefile cannot run is refused at parse time,
one line naming the config key, the entry and its range, exit 2, before any job (was: a dry run passed, a real
run failed inside a rule after other points had run, or a SceneError with Snakemake's stack lines)."""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess

import pytest
import yaml

from rods.study.sweep import ConfigError, check_config

from ..conftest import PY, ROOT

SNAKEMAKE = PY.parent / "snakemake"


@pytest.fixture
def config() -> dict:
    return yaml.safe_load((ROOT / "workflows" / "sweep.yaml").read_text()) | {
        "scene": str(ROOT / "workflows" / "scenes" / "paper.toml")
    }


def test_the_shipped_config_passes(config):
    check_config(config)
    check_config(config | {"speeds": ["1.0", "2.0"], "dt_fractions": ["0.5"]})  # --config gives strings
    check_config(config | {"mpi": None})  # --config mpi= (empty: the venv's mpirun)
    for gpu in (True, False, "true", "False", "auto"):  # YAML booleans; --config gives strings
        check_config(config | {"gpu": gpu})


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"speeds": [-1.0]}, ["'speeds'", "impact.speed", "[1e-09, 100]"]),
        ({"speeds": ["abc"]}, ["'speeds'", "not a number"]),
        ({"speeds": 1.5}, ["'speeds'", "list"]),
        ({"dt_fractions": [0.5, 1.5]}, ["'dt_fractions'", "1.5", "[0.001, 1]"]),
        ({"kinds": ["2d"]}, ["'kinds'", "axisymmetric, 3d"]),
        ({"mesh_levels": {"coarse": [2e-3, 5.0]}}, ["'mesh_levels'", "fe.radial_size"]),
        ({"mesh_levels": {"paper": [1e-3, 2.5e-4]}}, ["'mesh_levels'", "'coarse'"]),
        ({"fe_speed": -3}, ["'fe_speed'", "[1e-09, 100]"]),
        ({"ranks": 0}, ["'ranks'", ">= 1"]),
        ({"paper_levels": ["bogus"]}, ["'paper_levels'", "ultra-fine"]),
        ({"paper_global_meshes": {"x": ["fe.kind=2d"]}}, ["'paper_global_meshes'", "fe.kind"]),
        ({"scene": "nope.toml"}, ["'scene'", "no such scene file", "or your --configfile"]),  # not "--scene"
        ({"sceen": "x"}, ["'sceen'", "unknown key", "did you mean 'scene'?"]),
        ({"spedes": [1.0]}, ["'spedes'", "did you mean 'speeds'?"]),
        ({"mesh_levels": {"coarse": [1e-3]}}, ["'mesh_levels'", "[axial size, radial size]"]),
        ({"mesh_levels": {"coarse": {"a": 1}}}, ["'mesh_levels'", "[axial size, radial size]"]),
        ({"paper_levels": [["fine"]]}, ["'paper_levels'", "submodel levels"]),
        ({"gpu": "maybe"}, ["'gpu'", "auto, true or false"]),
        # found by a bad-input audit (2026-11-29): a string read character by character; a name with a space split
        # every job's command line; a mesh the paper scene refuses, accepted against another sweep scene
        ({"paper_global_meshes": {"paper": "fe.radial_size=0.25e-3"}}, ["'paper_global_meshes'", "KEY=VALUE"]),
        ({"paper_levels": ["coarse", "mid"], "paper_phase_levels": ["fine"]}, ["'paper_phase_levels'", "'fine'"]),
        ({"mesh_levels": {"coarse": [2e-3, 5e-4], "x y": [1e-3, 2.5e-4]}}, ["'mesh_levels'", "'x y'", "folder"]),
        ({"paper_global_meshes": {"a b": ["fe.radial_size=0.25e-3"]}}, ["'paper_global_meshes'", "'a b'"]),
        # a second audit (2026-11-29): a level given twice passed, and the main job's compare stage refused the
        # folder given twice hours later; a point given twice ran twice; no level at all; a typo's remedy was the typo
        ({"paper_levels": ["fine", "fine"], "paper_phase_levels": ["fine"]}, ["'paper_levels'", "'fine'", "once"]),
        ({"paper_phase_levels": ["coarse", "coarse"]}, ["'paper_phase_levels'", "more than once"]),
        ({"speeds": [1.0, "1.0"]}, ["'speeds'", "more than once"]),
        ({"dt_fractions": [0.5, 0.50]}, ["'dt_fractions'", "more than once"]),
        ({"kinds": ["axisymmetric", "axisymmetric"]}, ["'kinds'", "more than once"]),
        ({"paper_levels": [], "paper_phase_levels": []}, ["'paper_levels'", "at least one"]),
        ({"sceen": "x"}, ["--config scene=..."]),
        ({"zzzzzz": "x"}, ["remove it"]),
        # a library audit (2026-12-07): two names, one pair of sizes, ran one point twice into two equal rows
        ({"mesh_levels": {"coarse": [4e-3, 1e-3], "c2": ["4.0e-3", 0.001]}}, ["'mesh_levels'", "'c2'", "same sizes"]),
    ],
)
def test_a_config_the_sweeps_cannot_run_is_named(config, change, words):
    """Each a one-line ConfigError (found by review: a one-entry mesh level, a nested level list escaped as
    IndexError/TypeError tracebacks)."""
    with pytest.raises(ConfigError) as e:
        check_config(config | change)
    for w in words:
        assert w in str(e.value), str(e.value)
    assert "--scene" not in str(e.value)  # an option the sweep's user never gave (a fuzz)


def test_more_ranks_than_the_machines_cpus_are_refused_where_the_jobs_run_on_it(config):
    """Local execution (the Snakefile passes os.cpu_count()): mpirun -n 1000 on a 2-core machine was planned; a
    cluster executor (None) takes any count."""
    check_config(config | {"ranks": 4}, local_cpus=4)
    with pytest.raises(ConfigError, match=r"'ranks' = 5: .*4 CPUs.*--config ranks=4 or fewer.*profiles/slurm"):
        check_config(config | {"ranks": 5}, local_cpus=4)
    check_config(config | {"ranks": 1000}, local_cpus=None)


def test_the_main_jobs_global_meshes_are_checked_on_the_paper_scene(config, tmp_path):
    """Rule paper_global runs paper_global_meshes on the paper scene whatever the sweeps' scene: an 8 mm radial size
    fits 20 mm rods but not the paper's 12.7 mm ones (it was accepted against a thick sweep scene, then its job exited
    2), and a mesh the paper scene takes passes beside a sweep scene that would refuse it."""
    paper = ROOT / "workflows" / "scenes" / "paper.toml"
    thick = tmp_path / "thick.toml"
    thick.write_text(f'base = "{paper}"\nrod1.diameter = 0.02\nrod2.diameter = 0.02\n')
    thin = tmp_path / "thin.toml"
    thin.write_text(f'base = "{paper}"\nrod1.diameter = 0.0008\nrod2.diameter = 0.0008\n'
                    'rod1.tip_radius = 0.001\nname = "thin"\n')  # fmt: skip
    with pytest.raises(ConfigError, match=r"'paper_global_meshes'.*fe.radial_size.*0.00635"):
        check_config(config | {"scene": str(thick), "paper_global_meshes": {"bad": ["fe.radial_size=0.008"]}})
    meshes = {"coarse": ["fe.radial_size=0.5e-3"]}  # the paper's 12.7 mm rods take it; the thin 0.8 mm ones refuse it
    levels = {"coarse": [2e-4, 1e-4]}
    check_config(config | {"scene": str(thin), "paper_global_meshes": meshes, "mesh_levels": levels})


@pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is not installed beside the interpreter")
def test_snakemake_stops_at_parse_time_with_one_line(tmp_path):
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "speed_sweep",
         "--config", "speeds=[-1.0]"],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and "config 'speeds'" in lines[0], p.stderr[-2000:]
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "mesh_sweep", "--config", "ranks=100000"],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and "config 'ranks' = 100000" in lines[0], p.stderr[-2000:]
    # more ranks than --cores: Snakemake lowers a rule's threads, not its mpirun -n (an audit, 2026-12-07)
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "mesh_sweep", "--config", "ranks=2"],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and "config 'ranks' = 2" in lines[0] and "--cores" in lines[0]
    # a speed point whose analytical run is above its budgets: refused before any job, as an FE point is (it was
    # queued, and refused by its own job: 69 GB of history, an audit, 2026-12-07)
    big = tmp_path / "big.toml"
    big.write_text(f'base = "{ROOT / "workflows" / "scenes" / "paper.toml"}"\n[simulation]\nend_time = 1e-2\n'
                   "output_interval = 1e-10\n")  # fmt: skip
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "speed_sweep", "--config", f"scene={big}",
         "speeds=[1.0]"],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and "the speed sweep's point speed=1.0" in lines[0], p.stderr[-2000:]
    # a point above its entry point's budgets: refused before the DAG (a 95 h point was planned and queued, then
    # refused by its own job, the others' table never written: a fuzz, 2026-12-07)
    tiny = "mesh_levels={coarse: [2.0e-3, 0.5e-3], tiny: [1.0e-4, 2.0e-6]}"
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "mesh_sweep", "--config", tiny],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1, p.stderr[-2000:]
    assert "above the work budget" in lines[0] and "point kind=axisymmetric, level=tiny" in lines[0]
    # from another folder: its paths are the repository's (it said the config "cannot be read ... a UTF-8 YAML file")
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", str(ROOT / "workflows" / "Snakefile"), "--cores", "1", "-n", "speed_sweep"],
        cwd=tmp_path, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and "run snakemake from the repository's root" in lines[0], p.stderr


def test_a_sweep_row_carries_its_runs_status_and_what_its_warnings_name(tmp_path):
    """A sweep table shows each run's status and the keys its warnings name: a 5 m/s point past yield and a
    coarse-patch point read like clean rows before (a probe, 2026-11-25); and its scene label, which names the
    point's settings (the mesh and step sweeps' sizes were only in the path, a fuzz, 2026-12-07)."""
    import csv
    import json

    from rods.study.sweep import write_sweep_table

    runs = {
        "ok": {"model": "analytical", "scene": "paper with impact.speed=1.0", "impact_speed": 1.0, "status": "ok"},
        "hot": {
            "model": "analytical",
            "impact_speed": 5.0,
            "status": "warnings",
            "warnings": [
                "Hertz peak pressure at rods 1 and 2 at the model's peak force, p0 = 2930.6 MPa, exceeds 1.1 S_y",
                "contact_radius: 1.2 elements across the 1.09 mm contact radius (h = 0.912 mm): not resolved",
            ],
        },
    }
    points = []
    for name, s in runs.items():
        (tmp_path / name).mkdir()
        (tmp_path / name / "summary.json").write_text(json.dumps(s))
        points.append((tmp_path / name / "summary.json", name))
    write_sweep_table(tmp_path / "t.csv", points)
    rows = {r["key"]: r for r in csv.DictReader((tmp_path / "t.csv").open())}
    assert (rows["ok"]["status"], rows["ok"]["warnings"]) == ("ok", "")
    assert rows["ok"]["scene"] == "paper with impact.speed=1.0"
    assert (rows["hot"]["status"], rows["hot"]["warnings"]) == ("warnings", "yield; contact_radius")


def test_a_sweep_tables_header_names_the_units_and_its_record_reads_back(tmp_path):
    """Every number column's header carries its SI unit, ``name [unit]`` as in the histories (a sweep table's
    had none, 2026-12-07); a record read back, with units or from before them, gives the rows by bare name, and a
    table written from that record is the same table."""
    import json

    from rods.study.sweep import FIELD_UNITS, FIELDS, read_record, write_sweep_table

    s = {"model": "fe-axisymmetric", "impact_speed": 2.197, "peak_contact_force": 5562.4, "contact_duration": 2.04e-4,
         "dofs": 13636, "status": "ok"}  # fmt: skip
    (tmp_path / "summary.json").write_text(json.dumps(s))
    write_sweep_table(tmp_path / "t.csv", [(tmp_path / "summary.json", "k1")])
    header = (tmp_path / "t.csv").read_text().splitlines()[0].split(",")
    assert "peak_contact_force [N]" in header and "contact_duration [s]" in header and "impact_speed [m/s]" in header
    assert {h.split(" [")[0] for h in header if " [" not in h} == {
        "path",
        "model",
        "scene",
        "status",
        "warnings",
        "key",
    }
    assert set(FIELD_UNITS) | {"model", "scene", "status", "warnings"} == set(FIELDS)
    record = read_record(tmp_path / "t.csv")
    assert record["k1"]["peak_contact_force"] == "5562.4" and record["k1"]["dofs"] == "13636"
    write_sweep_table(tmp_path / "again.csv", [(tmp_path / "absent.json", "k1")], record)  # from the record alone
    assert (tmp_path / "again.csv").read_bytes() == (tmp_path / "t.csv").read_bytes()
    old = (tmp_path / "t.csv").read_text().replace(" [N]", "").replace(" [s]", "").replace(" [m/s]", "")
    (tmp_path / "old.csv").write_text(old.replace(" [-]", ""))
    assert read_record(tmp_path / "old.csv") == record


def test_a_sweep_point_is_one_key_however_its_numbers_are_spelled():
    """--config's "4.0e-3" arrives as text and is the yaml's 0.004: one point, not a rerun (a probe, 2026-11-25);
    another value or a word is another point."""
    from rods.study.sweep import point_key

    same = point_key("c", "s", sweep="dt", sizes=[0.004, 0.001], dtf=0.5, kind="axisymmetric")
    assert point_key("c", "s", sweep="dt", sizes=["4.0e-3", "1e-3"], dtf="0.5", kind="axisymmetric") == same
    assert point_key("c", "s", sweep="dt", sizes=[0.004, 0.001], dtf=0.9, kind="axisymmetric") != same
    assert point_key("c", "s", sweep="dt", sizes=[0.004, 0.001], dtf=0.5, kind="3d") != same


@pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is not installed beside the interpreter")
def test_the_gpu_run_joins_the_accuracy_cost_study_only_when_asked(tmp_path):
    """gpu=true: the dry run of the accuracy-cost rule plans the paper's 3D mesh on the GPU (rule
    paper_global_gpu, fe.backend=cupy) and passes it as a run; gpu=false: no such job."""

    def plan(gpu: str) -> str:
        p = subprocess.run(
            [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "-p", "--forceall",
             "paper_accuracy_cost", "--config", f"gpu={gpu}"],
            cwd=ROOT, capture_output=True, text=True, timeout=300,
        )  # fmt: skip
        assert p.returncode == 0, p.stderr[-2000:]
        return p.stdout + p.stderr

    on, off = plan("true"), plan("false")
    assert "rule paper_global_gpu" in on and "fe.backend=cupy" in on and "global 3d-paper=output/paper/gpu/" in on
    assert "paper_global_gpu" not in off and "output/paper/gpu/" not in off


@pytest.mark.skipif(
    importlib.util.find_spec("snakemake_executor_plugin_slurm") is None,
    reason="the SLURM executor plugin is an extra (pip install -e '.[cluster]')",
)
def test_a_cluster_executor_takes_more_ranks_than_the_submitting_machines_cpus():
    """Under the SLURM profile the ranks run on the cluster's nodes: ranks=8 on a 2-CPU submit host was refused
    (the Snakefile read workflow.local_exec before Snakemake had its executor, True under any executor); the same
    ranks on the local profile still are."""
    cpus = os.cpu_count() or 1
    base = [str(SNAKEMAKE), "-s", "workflows/Snakefile", "-n", "dt_sweep", "--config", f"ranks={cpus + 1}"]
    slurm = subprocess.run(
        [*base[:3], "--workflow-profile", "workflows/profiles/slurm", *base[3:]],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert slurm.returncode == 0 and "global_fe" in slurm.stdout + slurm.stderr, slurm.stderr[-2000:]
    local = subprocess.run(
        [*base[:3], "--workflow-profile", "workflows/profiles/local", *base[3:]],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert local.returncode == 2 and f"config 'ranks' = {cpus + 1}" in local.stderr, local.stderr[-2000:]


def test_a_config_file_snakemake_would_misread_is_refused_with_its_line(tmp_path):
    """The Snakefile reads its config files as YAML first: Snakemake's own error for a broken one named neither line
    nor column (exit 1), and a key given twice kept the last silently (a fuzz, 2026-12-07)."""
    from rods.study.sweep import check_config_file

    check_config_file(ROOT / "workflows" / "sweep.yaml")
    cases = {
        "broken.yaml": ("scene: x\nspeeds: [1.0\n", r"not valid YAML at line 3, column 1"),
        "twice.yaml": ("ranks: 1\nkinds: [axisymmetric]\nranks: 2\n", r"'ranks' = None: given twice .* \(line 3\)"),
        "list.yaml": ("- 1\n- 2\n", "must be a YAML mapping"),
        "latin1.yaml": (b"scene: \xe9\n", "cannot be read"),
    }
    for name, (text, words) in cases.items():
        path = tmp_path / name
        path.write_bytes(text if isinstance(text, bytes) else text.encode())
        with pytest.raises(ConfigError, match=words):
            check_config_file(path)


@pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is not installed beside the interpreter")
def test_a_point_in_two_sweeps_runs_once():
    """The mesh sweep's coarse level at step fraction 0.8 is the step sweep's 0.8 on the coarse mesh: one run, which
    both tables read (the sweep's name in the key ran it twice: two 144-min SLURM jobs for paper-3d, a fuzz,
    2026-12-07). sweep.yaml: 3 levels and 3 fractions, 5 runs."""
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "--forceall", "mesh_sweep", "dt_sweep"],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert p.returncode == 0, p.stderr[-2000:]
    counts = dict(re.findall(r"^(\w+)\s+(\d+)$", p.stdout + p.stderr, re.M))
    assert counts["global_fe"] == "5", (p.stdout + p.stderr)[-2000:]


def test_a_config_file_of_ones_own_that_drops_a_key_is_told_to_copy_sweep_yaml(config):
    """A --configfile with --replace-workflow-config replaces sweep.yaml whole: a key left out (the main job's too)
    is refused with one remedy (its message had the config file's name twice)."""
    with pytest.raises(ConfigError) as e:
        check_config({k: v for k, v in config.items() if k != "fe_speed"})
    text = str(e.value)
    assert "'fe_speed' = None: missing" in text and "copy workflows/sweep.yaml and edit the copy" in text
    assert text.count("sweep.yaml") == 2  # the replaced file, the one to copy


def test_a_number_is_one_folder_however_it_is_spelled():
    """2, 2.0 and "2.0" (--config gives strings) are one point (its key) and one folder (a run under speed-2.0/ was run
    again under speed-2/: an audit, 2026-12-07)."""
    from rods.study.sweep import folder_text, point_key

    assert folder_text(2) == folder_text(2.0) == folder_text("2.0") == folder_text("2") == "2.0"
    assert folder_text("4.0e-3") == folder_text(0.004) == "0.004"
    assert point_key("c", "s", speed=2) == point_key("c", "s", speed=folder_text("2"))


def test_a_trigger_rewritten_by_another_config_reassembles_the_table(tmp_path):
    """rods.study.sweep.sync_keys: the published record holds config A's keys, the trigger (written at parse time by
    config B's refused or dry invocation) holds B's and is older than the record: touched, so the table reassembles
    under any rerun trigger; where the record is the config's, the trigger is left alone (no rerun)."""
    import time

    from rods.study.sweep import sync_keys

    record, keys = tmp_path / "sweep-speed.csv", tmp_path / "speed.keys"
    record.write_text(f"peak_contact_force [N],key\n1.0,{'a' * 16}\n")  # A's published table
    b = [("b/summary.json", "b" * 16)]
    sync_keys(keys, b, record)  # B's invocation: the trigger B's
    os.utime(keys, (time.time() - 60, time.time() - 60))  # ... then A's table published after it
    old = keys.stat().st_mtime
    sync_keys(keys, b, record)
    assert keys.stat().st_mtime > record.stat().st_mtime > old and keys.read_text() == f"{'b' * 16} b/summary.json\n"
    record.write_text(f"peak_contact_force [N],key\n1.0,{'b' * 16}\n")  # B's table published: nothing to redo
    os.utime(keys, (time.time() - 60, time.time() - 60))
    old = keys.stat().st_mtime
    sync_keys(keys, b, record)
    assert keys.stat().st_mtime == old


def test_a_sweep_points_scene_and_plan_are_its_parameters(config):
    """rods.study.sweep.point_overrides/point_cost (the Snakefile's rules run and plan through them): an FE point's
    scene has its mesh level's sizes, kind, step fraction and speed, whichever way --config spells the numbers; an
    analytical point's only its speed, and its plan is the analytical model's."""
    from rods import cost
    from rods.scene import load_scene
    from rods.study.sweep import point_cost, point_overrides

    fe = dict(kind="axisymmetric", level="fine", dtf="0.5", speed="3.0")
    sc = load_scene(config["scene"], point_overrides(config | {"mesh_levels": {"fine": ["5e-4", 1.25e-4]}}, fe))
    keys = ("fe.axial_size", "fe.radial_size", "fe.dt_fraction", "impact.speed", "fe.kind")
    assert [sc[k] for k in keys] == [5e-4, 1.25e-4, 0.5, 3.0, "axisymmetric"]
    assert point_overrides(config, dict(speed="1.0")) == ["impact.speed=1.0"]
    analytical = point_cost(config, dict(speed="1.0"))
    assert analytical == cost.analytical_cost(load_scene(config["scene"], ["impact.speed=1.0"]))
    fine, coarse = point_cost(config, fe), point_cost(config, fe | dict(level="coarse"))
    assert fine.wall_time > 8 * coarse.wall_time  # 16x the elements, a step a quarter as long
