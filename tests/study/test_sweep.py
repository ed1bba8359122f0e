"""The sweeps' config (rods.study.sweep.check_config): what the Snakefile cannot run is refused at parse time,
one line naming the config key, the entry and its range, exit 2, before any job (was: a dry run passed, a real
run failed inside a rule after other points had run, or a SceneError with Snakemake's stack lines)."""

from __future__ import annotations

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


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"speeds": [-1.0]}, ["'speeds'", "impact.speed", "(0, 100]"]),
        ({"speeds": ["abc"]}, ["'speeds'", "not a number"]),
        ({"speeds": 1.5}, ["'speeds'", "list"]),
        ({"dt_fractions": [0.5, 1.5]}, ["'dt_fractions'", "1.5", "(0, 1]"]),
        ({"kinds": ["2d"]}, ["'kinds'", "axisymmetric, 3d"]),
        ({"mesh_levels": {"coarse": [2e-3, 5.0]}}, ["'mesh_levels'", "fe.radial_size"]),
        ({"mesh_levels": {"paper": [1e-3, 2.5e-4]}}, ["'mesh_levels'", "'coarse'"]),
        ({"fe_speed": -3}, ["'fe_speed'", "(0, 100]"]),
        ({"ranks": 0}, ["'ranks'", ">= 1"]),
        ({"paper_levels": ["bogus"]}, ["'paper_levels'", "ultra-fine"]),
        ({"paper_global_meshes": {"x": ["fe.kind=2d"]}}, ["'paper_global_meshes'", "fe.kind"]),
        ({"scene": "nope.toml"}, ["'scene'", "no such scene file"]),
        ({"sceen": "x"}, ["'sceen'", "unknown key"]),
        ({"mesh_levels": {"coarse": [1e-3]}}, ["'mesh_levels'", "[axial size, radial size]"]),
        ({"mesh_levels": {"coarse": {"a": 1}}}, ["'mesh_levels'", "[axial size, radial size]"]),
        ({"paper_levels": [["fine"]]}, ["'paper_levels'", "submodel levels"]),
    ],
)
def test_a_config_the_sweeps_cannot_run_is_named(config, change, words):
    """Each a one-line ConfigError (found by review: a one-entry mesh level, a nested level list escaped as
    IndexError/TypeError tracebacks)."""
    with pytest.raises(ConfigError) as e:
        check_config(config | change)
    for w in words:
        assert w in str(e.value), str(e.value)


@pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is not installed beside the interpreter")
def test_snakemake_stops_at_parse_time_with_one_line(tmp_path):
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "speed_sweep",
         "--config", "speeds=[-1.0]"],
        cwd=ROOT, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and "config 'speeds'" in lines[0], p.stderr[-2000:]
