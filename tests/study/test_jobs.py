"""What the workflow's jobs ask a scheduler for (rods.study.jobs): the wall time and memory of each FE rule come from
its run's plan, cover the main job's measured runs with room for a slower node, grow with the run and with a retry,
and reach SLURM through the Snakefile (was: 30 min and 4 GB for every global, a table of minutes per submodel level,
so a 3D sweep point planned at 2 h would be killed at 30 min)."""

from __future__ import annotations

import re
import subprocess

import pytest
import yaml

from rods import io
from rods.scene import load_scene
from rods.study import jobs

from ..conftest import PAPER, PY, ROOT

SNAKEMAKE = PY.parent / "snakemake"
RANKS = 2  # the main job's (workflows/Snakefile PAPER_RANKS)


def _measured() -> dict[str, float]:
    """The main job's measured wall times [s] (results/accuracy-cost.json: its runs on this machine, 2 ranks)."""
    rows = io.read_data(ROOT / "results" / "accuracy-cost.json")["rows"]
    return {r["label"]: r["wall_time"] for r in rows if r["model"] != "analytical" and r.get("device", "CPU") == "CPU"}


def test_the_request_is_the_plan_with_its_margins():
    """runtime = 3 x the plan's wall time + 10 min, mem_mb = 1.5 x its memory (at least 2 GB); a retry asks for
    as many times as much; stages run in turn sum their times and take the largest memory."""
    sc = load_scene(PAPER, [])
    small, large = jobs.global_cost(sc, RANKS), jobs.global_cost(sc.with_overrides("fe.radial_size=0.05e-3"), RANKS)
    r = jobs.request([large])
    assert r["runtime"] == pytest.approx(jobs.RUNTIME_MARGIN * large.wall_time / 60 + jobs.RUNTIME_START, abs=1)
    assert r["mem_mb"] == pytest.approx(max(jobs.MEMORY_MARGIN * large.memory / 1e6, jobs.MEMORY_MIN), abs=1)
    assert jobs.request([large], attempt=2) == {k: pytest.approx(2 * v, abs=2) for k, v in r.items()}
    both = jobs.request([small, large])
    assert both["runtime"] > r["runtime"] and both["mem_mb"] == r["mem_mb"]
    assert jobs.request([]) == {"runtime": round(jobs.RUNTIME_START), "mem_mb": round(jobs.MEMORY_MIN)}


def test_the_requests_cover_the_main_jobs_measured_runs():
    """Each of the main job's FE runs (the globals' meshes, 3D ones too, and the submodel levels, 2 ranks, measured in
    results/accuracy-cost.json) is asked at least twice its measured time (a node half as fast finishes), and the
    submodel levels ask more as they refine."""
    measured = _measured()
    meshes = yaml.safe_load((ROOT / "workflows" / "sweep.yaml").read_text())["paper_global_meshes"]  # the main job's
    sc = load_scene(PAPER, [])
    assert {f"global {name}" for name in meshes} <= set(measured)
    for name, overrides in meshes.items():
        minutes = jobs.request([jobs.global_cost(sc.with_overrides(*overrides), RANKS)])["runtime"]
        assert 60 * minutes >= 2 * measured[f"global {name}"], name
    asked = []
    for level in ("coarse", "mid", "fine", "extra-fine", "ultra-fine"):
        minutes = jobs.request([jobs.submodel_cost(sc, RANKS, level)])["runtime"]
        assert 60 * minutes >= 2 * measured[f"submodel {level}"], level
        asked.append(minutes)
    assert asked == sorted(asked) and asked[-1] > 2 * asked[0]


def test_a_driver_and_a_phase_member_are_planned_as_their_entry_points_plan_them():
    """The driver runs the contact phase only (shorter than the scene's end: cheaper than the full global, though it
    records the cut band); a phase member is a submodel at its own size, about its level's."""
    sc = load_scene(PAPER, [])
    full, driver = jobs.global_cost(sc, RANKS), jobs.global_cost(sc, RANKS, driver=True)
    assert driver.steps < full.steps and driver.what == "the driving global"
    level, member = jobs.submodel_cost(sc, RANKS, "fine"), jobs.submodel_cost(sc, RANKS, "fine", 0)
    assert 0.5 < member.dofs / level.dofs < 2.0 and member.what == "the submodel fine-phase-0"


@pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is not installed beside the interpreter")
def test_the_snakefile_asks_for_each_jobs_plan(tmp_path):
    """A dry run of the mesh sweep in 3D and axisymmetric: each global_fe job's runtime and mem_mb are the request
    for its own scene, so the 3D points ask hours where the axisymmetric ones ask minutes. The coarse level alone (a
    config file in place of sweep.yaml: --config merges its mapping into the yaml's levels, whose 3D fine point needs
    131 GB, refused before the DAG where the jobs run here)."""
    import yaml

    config = yaml.safe_load((ROOT / "workflows" / "sweep.yaml").read_text())
    config |= {"kinds": ["axisymmetric", "3d"], "mesh_levels": {"coarse": [2.0e-3, 0.5e-3]}}
    (tmp_path / "mine.yaml").write_text(yaml.safe_dump(config))
    p = subprocess.run(
        [str(SNAKEMAKE), "-s", "workflows/Snakefile", "--cores", "1", "-n", "--forceall", "mesh_sweep",
         "--configfile", str(tmp_path / "mine.yaml"), "--replace-workflow-config"],
        cwd=ROOT, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert p.returncode == 0, p.stderr[-2000:]
    found = re.findall(r"wildcards: kind=(\w+), level=coarse, dtf=([\d.]+), speed=([\d.]+), key=\w+\n\s+resources: .*"
                       r"runtime=(\d+), mem_mb=(\d+)", p.stdout + p.stderr)  # fmt: skip
    assert {k for k, *_ in found} == {"axisymmetric", "3d"}, (p.stdout + p.stderr)[-3000:]
    for kind, dtf, speed, runtime, mem_mb in found:
        sc = load_scene(ROOT / "workflows" / "scenes" / "paper.toml", [
            f"impact.speed={speed}", f"fe.kind={kind}", "fe.axial_size=0.002", "fe.radial_size=0.0005",
            f"fe.dt_fraction={dtf}"])  # fmt: skip
        assert jobs.request([jobs.global_cost(sc, 1)]) == {"runtime": int(runtime), "mem_mb": int(mem_mb)}
    runtimes = {k: int(r) for k, _, _, r, _ in found}
    assert runtimes["3d"] > 60 > runtimes["axisymmetric"]  # the profile's default 60 min fits neither
