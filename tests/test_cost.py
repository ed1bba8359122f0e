"""The cost estimate (rods.cost): counts that match the built mesh, steps near the model's, and the
entry points refusing, exit 2 with one line and no folder, what would run into the ground (issue class A)."""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import replace

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rods import cost
from rods.preflight import InputError
from rods.scene import SceneError
from rods.study import jobs

from .conftest import SCENES, in_process, run_workflow

TINY = ("fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=1e-4")


def test_estimate_matches_the_built_axisymmetric_model(scene_with):
    """Cells and DOFs exactly (the mesh module's own counting), steps within 20% of the set-up's."""
    from rods.fe.model import ExplicitModel

    sc = scene_with(*TINY)
    c, m = cost.fe_cost(sc), ExplicitModel(sc)
    assert c.cells == m.plan()["cells"] and c.dofs == m.n_global
    assert c.steps == pytest.approx(m.steps, rel=0.2)
    assert c.samples == pytest.approx(1e-4 / sc.output_interval + 1)
    assert cost.check(c) is c  # a tiny run passes


def test_the_fe_records_at_most_one_sample_per_step(scene_with):
    """An output interval below the step: the recorder keeps the step nearest each output time once
    (rods.fe.recorder.output_steps), a row per step (measured: the tiny model to 20 µs every 1 ns wrote 167 rows for
    its 166 steps); the estimate counted 2e4 + 1 samples, and refused the paper scene every 0.1 ns for 1.5e7 samples
    and every 0.1 ps for 6.93 TB of memory (it records 4.8e4 rows)."""
    from rods.fe.model import ExplicitModel
    from rods.fe.recorder import output_steps

    sc = scene_with(*TINY[:2], "simulation.end_time=2e-5", "simulation.output_interval=1e-9")
    c, m = cost.fe_cost(sc), ExplicitModel(sc)
    assert output_steps(sc.end_time, sc.output_interval, m.dt, m.steps).size == m.steps + 1  # what it records
    assert c.samples == c.steps + 1 and c.samples == pytest.approx(m.steps + 1, rel=0.2)
    for interval in ("1e-10", "1e-12"):
        paper = cost.fe_cost(scene_with(f"simulation.output_interval={interval}"))
        assert paper.samples == paper.steps + 1 and cost.check(paper) is paper


def test_a_hemispherical_tip_is_counted_and_its_step_estimated(scene_with):
    """The butterfly cap's cells exactly (rods.fe.layout.mesh_counts) and the step of its distorted rim cells
    (CAP_STEP_FACTOR, 0.69 at 90°) within 15%: before, 1.45x too few steps (19x on the auto mesh with the
    single-block cap)."""
    from rods.fe.model import ExplicitModel

    sc = scene_with(*TINY, "rod1.tip_radius=0.00635", "fe.radial_size=0.5e-3")
    c, m = cost.fe_cost(sc), ExplicitModel(sc)
    assert c.cells == m.plan()["cells"] and c.dofs == m.n_global and c.steps == pytest.approx(m.steps, rel=0.15)


@pytest.mark.parametrize(
    "extra",
    [
        (),
        ("rod1.tip_radius=inf", "rod2.tip_radius=0.035"),
        ("rod1.tip_radius=0.008",),
        ("fe.tip_grading=0.3",),
        ("fe.radial_grading='graded'", "fe.radial_size=0.1e-3"),  # a core and graded columns on both rods
        ("fe.radial_grading='graded'", "fe.radial_size=0.1e-3", "rod1.tip_radius=0.00635"),  # a graded butterfly
        ("fe.radial_size=0.2e-3",),  # 32 across merge into 11 past 25.4 mm (fe.radial_coarsening)
        ("fe.radial_size=0.2e-3", "fe.radial_coarsening='none'"),
    ],
    ids=["paper-tip", "flat-rod1", "8mm-tip", "graded", "radially-graded", "graded-butterfly", "coarsened", "full"],
)
def test_the_axisymmetric_mesh_is_counted_node_by_node(scene_with, extra):
    """The plan's DOFs are the mesh's, 2 per node (rods.fe.layout.mesh_counts: Euler's V = F + E_b/2 + 1 per rod), for
    one-block and butterfly caps, flat or curved, graded along or across or not, coarsened along or not: 2.3 per
    cell before, 5.29e4 planned on the paper mesh against 48,050 built."""
    from rods.fe.mesh import build_mesh

    sc = scene_with(*TINY, *extra)
    rm = build_mesh(sc)
    nodes = rm.mesh.geometry.index_map().size_global
    assert cost.fe_cost(sc).dofs == 2 * nodes
    fine = any(e.startswith("fe.radial_size=0.") for e in extra)  # under a third of the bar's size: merges
    assert any(rm.coarsened) == (fine and "fe.radial_coarsening='none'" not in extra)


@pytest.mark.parametrize(
    "extra",
    [
        *([f"rod1.tip_radius={r}"] for r in (0.035, 0.012, 0.008, 0.0068, 0.00635)),  # rim angles 10.5° to 90°
        ["fe.axial_size=0.5e-3", "fe.radial_size=0.125e-3"],  # finer than auto: a graded block short on the cap
        pytest.param(["fe.axial_size=0.25e-3", "fe.radial_size=0.125e-3"], marks=pytest.mark.slow),  # 7 s
        ["impact.speed=15"],  # a fast rise: a finer tip block, so the cap takes more of its rim column
        ["rod1.diameter=0.03", "rod1.tip_radius=0.05"],  # a thick rod's deep cap (2.4 mm) on a thin one's patch
        ["fe.radial_grading='graded'", "rod1.tip_radius=0.01"],  # graded columns under a curved face
    ],
)
def test_a_curved_tips_step_is_estimated_within_the_measured_band(scene_with, extra):
    """The estimated stable step of an axisymmetric global lies within 0.7 to 1.0 of the set-up's exact one, for tips
    from 35 mm to a hemisphere at the auto mesh and finer, at 15 m/s and on a 30 mm rod: the tip cells from the
    mesher's own geometry (rods.cost._tip_step; measured 0.72 to 0.93 over 48 scenes), a butterfly by its table.
    Before, a table of the paper rods' auto mesh (against the rim angle) read 1.44x the exact step at 15 m/s and
    1.24x on the 30 mm rod (and 1.49x and 1.30x on two random draws): their runs took that many more steps than
    their plans said."""
    from rods.fe.model import ExplicitModel

    sc = scene_with("simulation.end_time=1e-6", *extra)
    m = ExplicitModel(sc)
    estimate = min(cost._step_limits(sc, sc["fe.radial_size"], sc["fe.axial_size"], sc.tip_grading, None))
    butterfly = "rod1.tip_radius=0.00635" in extra  # its table, as before (measured 1.01)
    assert 0.7 <= estimate / min(m.dt_critical, m.dt_switching) <= (1.02 if butterfly else 1.0)


@pytest.mark.parametrize(
    "symmetry, extra",
    [
        ("quarter", TINY[:2]),
        ("half", TINY[:2]),
        ("full", TINY[:2]),
        ("quarter", ("fe.radial_size=0.4e-3",)),  # graded to the tip: cubes there, long cells in the body
        ("quarter", ("fe.radial_size=0.5e-3", "rod1.tip_radius=0.01")),  # a deep cap's thin, sloped rim cells
    ],
    ids=["quarter", "half", "full", "graded", "10mm-tip"],
)
def test_estimate_matches_the_built_3d_model(scene_with, symmetry, extra):
    """3D: cells and DOFs exactly (the O-grid's own counts, rods.fe.mesh3d.section_size), the steps not below the
    set-up's by more than 2% and at most 1.3x them. Before (2026-12-06), the 0.4 mm graded mesh ran 1.09x the steps
    planned (the body's long cells at the O-grid's core corners unseen behind the tip's cubes) and the 10 mm tip
    1.30x (its rim cells, rods.cost._tip_step, unseen); a hexahedron's step is sqrt(2/3) of a square's (the
    estimate was once 0.72 of the paper mesh's)."""
    from rods.fe.model import ExplicitModel

    sc = scene_with(
        *extra, "simulation.end_time=1e-5", "fe.kind=3d", f"fe.symmetry={symmetry}", "rod1.length=0.03",
        "rod2.length=0.04",
    )  # fmt: skip
    c, m = cost.fe_cost(sc), ExplicitModel(sc)
    assert (c.cells, c.dofs) == (m.plan()["cells"], m.n_global)
    assert 0.98 * m.steps <= c.steps <= 1.3 * m.steps


@pytest.mark.parametrize("factor", [2.0, 10.0, 40.0])
def test_penalty_switching_limit_enters_the_steps(scene_with, factor):
    """Under the penalty law the contact-switching limit sets the step once it is shorter than the bulk limit:
    the estimate follows the built model's steps within 20% from 2 to 40 x E*/h (graded paper tip), and to 0.1%
    where the switching limit sets the step (estimated as the set-up computes it)."""
    from rods.fe.model import ExplicitModel

    sc = scene_with("fe.contact=penalty", f"fe.penalty={factor}", "simulation.end_time=1e-4")
    c, m = cost.fe_cost(sc), ExplicitModel(sc)
    assert c.steps == pytest.approx(m.steps, rel=0.2)
    if factor >= 10:  # the switching limit is the step's
        assert m.dt == pytest.approx(m.dt_switching, rel=1e-9)
        assert c.steps == pytest.approx(m.steps, rel=1e-3)


@pytest.mark.parametrize(
    "extra",
    [(), ("rod1.tip_radius=0.00635", "fe.radial_size=0.5e-3"), ("fe.contact=penalty", "fe.penalty=40.0")],
    ids=["paper", "hemisphere", "penalty"],
)
def test_a_step_far_above_the_stable_limit_is_refused_before_the_set_up(scene_with, extra):
    """fe.dt above DT_REFUSE_FACTOR x the estimated limit is refused by the cost check (before the mesh; was found
    only by the set-up's eigenvalue solve, after a study's analytical stage had written its folder); the estimate
    lies below the set-up's exact limit (so a stable step is never refused) and within 2x of it."""
    from rods.fe.model import ExplicitModel

    sc = scene_with(*TINY, *extra)
    m = ExplicitModel(sc)
    exact = min(m.dt_critical, m.dt_switching)
    estimate = min(cost._step_limits(sc, sc["fe.radial_size"], sc["fe.axial_size"], sc.tip_grading, None))
    assert 0.5 * exact < estimate <= 1.05 * exact, (estimate, exact)
    assert cost.fe_cost(sc.with_overrides(f"fe.dt={0.99 * exact!r}")).steps > 0  # a stable step passes
    with pytest.raises(SceneError, match="'fe.dt'.*must be <= the stable limit, about"):
        cost.fe_cost(sc.with_overrides(f"fe.dt={2.1 * estimate!r}"))
    # between the estimate and the refusal the set-up decides: the plan says so, so a dry run does not pass it
    between = cost.fe_cost(sc.with_overrides(f"fe.dt={1.5 * estimate!r}"))
    assert f"fe.dt = {1.5 * estimate:.3g} s is above the estimated stable limit {estimate:.3g} s" in between.caveat
    assert between.describe().endswith(between.caveat) and cost.fe_cost(sc).caveat == ""
    # just below it: valid, but for the penalty's switching estimate, which can err high (SWITCHING_CAVEAT)
    below = cost.fe_cost(sc.with_overrides(f"fe.dt={0.99 * estimate!r}")).caveat
    assert ("switching limit" in below) if "fe.contact=penalty" in extra else below == ""


def test_a_dry_run_with_a_step_the_set_up_decides_says_so(tmp_path):
    """--dry-run with fe.dt above the estimated limit but below the refusal: exit 0, and its last line says the
    input is valid only as far as the plan can tell (a newcomer's walk, 2026-12-06: "valid", then the run refused
    5e-8 s against the exact 4.11e-8 s)."""
    from .conftest import in_process

    args = ["--set", "fe.dt=5e-8", "--set", "simulation.end_time=2e-5", "--dry-run", "--out", "o"]
    p = in_process("global.py", *args, cwd=tmp_path)
    assert p.returncode == 0, p.stderr[-2000:]
    lines = [ln for ln in p.stdout.strip().splitlines() if not ln.startswith("note: this machine is busy")]
    assert "fe.dt = 5e-08 s is above the estimated stable limit" in lines[-2]
    assert lines[-1].startswith("dry run: the input and the output folder are valid as far as the plan can tell")
    assert not (tmp_path / "o").exists()


@pytest.mark.alone  # a wall time: not beside another test
def test_time_estimate_is_the_measured_order(scene_with):
    """The printed time (rods.cost.calibrated: the probe at the run's own working set) is within a small factor of
    a measured run (the paper's default mesh, 19k DOFs coarsened, 0.1 ms): the time loop's estimate between 1/2x and
    2.5x of the measured loop (2026-12-06: 0.98x and 1.02x serial; 2.2x on 2026-11-27, when a run this short was
    planned at the out-of-cache rate, its mesh sitting in cache), not the 14x over of a bare 1e7 DOF-steps/s per
    rank. The set-up is left out: on a fresh machine it holds the forms' JIT compilation."""
    from rods.fe.model import ExplicitModel

    sc = scene_with("simulation.end_time=1e-4")
    (c,), r = cost.calibrated([cost.fe_cost(sc)]), ExplicitModel(sc).run()
    ratio = (c.wall_time - c.setup_time) / r.summary["wall_time"]
    assert 0.5 < ratio < 2.5, ratio
    assert 0 < c.setup_time < c.wall_time


@pytest.mark.alone  # a wall time: not beside another test
def test_a_3d_time_estimate_is_the_measured_order():
    """The 3D model's loop (a quarter of paper-3d-coarse.toml, 38.8k DOFs, 20 µs in contact, ~200 steps) within 0.5x
    to 2x of its plan at this machine's probe (2026-12-07: 1.07x; 0.94x on 0.1 m rods; to 0.1 ms, past the contact,
    1.57x: its steps are cheaper once the rods part; 2026-12-08 on an Intel Xeon, 2.9-3.1x with the axisymmetric probe
    at the next power of two, 0.93x with the 3D probe at its own size). No test timed 3D before (a mutation audit,
    2026-12-07); this one catches a rate off by 2.5x or more: a 2x error (0.65x here) lies within reach of the
    run-to-run noise of a loop this short (0.94-1.17x over three runs), so the bound leaves it, as the axisymmetric
    test's does."""
    from rods.fe.model import ExplicitModel
    from rods.scene import load_scene

    from .conftest import ROOT

    sc = load_scene(
        ROOT / "workflows" / "scenes" / "paper-3d-coarse.toml", ["fe.symmetry=quarter", "simulation.end_time=2e-5"]
    )
    r = ExplicitModel(sc).run()
    (c,) = cost.calibrated([cost.fe_cost(sc)])
    ratio = (c.wall_time - c.setup_time) / r.summary["wall_time"]
    assert 0.5 < ratio < 2.0, ratio


@pytest.mark.alone  # a wall time: not beside another test
def test_a_memory_bound_run_is_estimated_at_this_machines_rate(scene_with):
    """A mesh too large for a core's cache (the paper scene at 0.25 x 0.125 mm, 398k DOFs, 10 µs, ~900 steps) runs
    at the memory-bound rate: its time loop's estimate at this machine's probe (440,872 rows, the nearest 2^(k/4) to
    its working set's 452k; 524,288 until 2026-12-08) and the out-of-cache rate is within 0.5x to 2.5x of the
    measured loop (2026-12-07, at 524,288 rows: 0.84x and 0.93x;
    at the in-cache rate 0.67x to 0.90x; the reference rates alone erred low 3.4x here at 1.57M DOFs before they were
    re-measured, and the same loop once ran 3x faster on this machine, 2026-11-22: a fixed rate cannot hold). Loop
    against loop: the plan's steps are its own count, above the run's (rods.cost.STEP_COUNT_BIAS)."""
    from rods.fe.model import ExplicitModel

    sc = scene_with("fe.axial_size=0.25e-3", "fe.radial_size=0.125e-3", "simulation.end_time=1e-5")
    r = ExplicitModel(sc).run()
    (c,) = cost.calibrated([cost.fe_cost(sc)])
    ratio = (c.wall_time - c.setup_time) / r.summary["wall_time"]
    assert 0.5 < ratio < 2.5, ratio


def test_the_loops_rate_falls_past_the_cache(scene_with):
    """The reference rate per rank is the in-cache one for a working set within IN_CACHE of the cache, the
    out-of-cache one past OUT_OF_CACHE, and falls steadily between; 3D keeps its one rate."""
    rates = [cost.reference_rate("axisymmetric", d) for d in (1e3, 6e4, 1e5, 1.5e5, 2.5e5, 1e7)]
    assert rates[0] == rates[1] == cost.DOF_STEPS_PER_SECOND["axisymmetric"]
    assert rates[-1] == rates[-2] == cost.OUT_OF_CACHE_DOF_STEPS_PER_SECOND["axisymmetric"]
    assert rates == sorted(rates, reverse=True) and rates[1] > rates[2] > rates[3] > rates[4]
    assert {cost.reference_rate("3d", d) for d in (1e3, 1e7)} == {cost.DOF_STEPS_PER_SECOND["3d"]}
    big = cost.fe_cost(scene_with("fe.axial_size=0.25e-3", "fe.radial_size=0.125e-3"))
    share = cost.LOOP_BYTES_PER_DOF["axisymmetric"] * big.dofs / cost.CACHE_BYTES
    assert share > cost.OUT_OF_CACHE  # the paper rods at 398k DOFs: a serial loop past the cache


def test_calibration_scales_the_rate_bound_part_at_each_runs_working_set(scene_with, monkeypatch):
    """On a machine twice the reference's rate a run's rate-bound loop halves, its set-up and per-step fixed cost
    stay, and the plan says which rate it used. Each run is probed at its own working set per rank (a small run in
    cache, as its mesh is, a large one past it), stages of one size once; the analytical model is not probed."""
    probed = []
    monkeypatch.setattr(cost, "machine_speed", lambda rows, kind: probed.append(rows) or (2.0 if rows > 1e5 else 3.0))
    long = cost.fe_cost(scene_with("fe.axial_size=0.25e-3", "fe.radial_size=0.125e-3"))
    short = cost.fe_cost(scene_with(*TINY))
    analytical = cost.analytical_cost(scene_with(*TINY))
    assert long.speed is None and long.probe_rows == 440_872 and short.probe_rows == cost.PROBE_MIN_ROWS
    fast, small, same, untouched = cost.calibrated([long, short, short, analytical])
    assert sorted(probed) == [cost.PROBE_MIN_ROWS, 440_872] and untouched is analytical
    assert fast.memory_bound_time == pytest.approx(long.memory_bound_time / 2)
    assert fast.wall_time - fast.memory_bound_time == pytest.approx(long.wall_time - long.memory_bound_time)
    assert fast.speed == 2.0 and "probed rate 2.00 x the reference's" in fast.describe()
    assert small.speed == same.speed == 3.0
    loop = fast.wall_time - fast.setup_time
    bias = cost.STEP_COUNT_BIAS["axisymmetric"]  # the plan's steps over the run's: the time is the run's steps'
    assert loop == pytest.approx(
        fast.steps / bias * (cost.STEP_OVERHEAD + fast.dofs / (2 * cost.reference_rate("axisymmetric", fast.dofs)))
        + fast.samples * cost.RECORD_ROW_SECONDS
    )
    on_two = cost.fe_cost(scene_with("fe.axial_size=0.25e-3", "fe.radial_size=0.125e-3"), 2)
    assert on_two.probe_rows == 220_436  # each rank's half of the working set
    rows = on_two.samples * cost.RECORD_ROW_SECONDS
    per_step = (on_two.wall_time - on_two.setup_time - on_two.memory_bound_time - rows) / (on_two.steps / bias)
    assert per_step == pytest.approx(cost.MPI_STEP_OVERHEAD)


@given(
    kind=st.sampled_from(["axisymmetric", "3d"]),
    dofs=st.floats(min_value=1.0, max_value=1e9),
    ranks=st.integers(min_value=1, max_value=4096),
)
def test_the_probe_is_sized_to_the_working_set(kind, dofs, ranks):
    """rods.cost.probe_rows: the working set per rank in the probe's rows of the run's own shape (PROBE_ROWS_PER_DOF:
    an axisymmetric DOF's 18-entry row against the probe's, a 3D DOF's 81-entry row against the 3D probe's) on a grid
    of 2^(k/4), within 9% of it (the next power of two put a 38.8k-DOF 3D run's probe past a cache its mesh sat in),
    up to the largest probe, never below the smallest."""
    rows = cost.probe_rows(kind, dofs, ranks)
    need = cost.PROBE_ROWS_PER_DOF[kind] * dofs / ranks
    least, largest = (
        (cost.PROBE_MIN_ROWS_3D, cost.PROBE_ROWS_3D) if kind == "3d" else (cost.PROBE_MIN_ROWS, cost.PROBE_ROWS)
    )
    assert least <= rows <= largest
    step = 2.0 ** (0.5 / cost.PROBE_STEPS_PER_DOUBLING)  # [-] half a grid step: 1.09
    assert rows in (largest, least) or need / step <= rows * (1 + 1e-9) and rows <= need * step + 1
    assert rows == largest or need <= rows * step + 1  # never far under the run's set


@pytest.mark.alone  # a wall time: not beside another test
def test_a_small_runs_probe_is_cheap():
    """The probe at a small run's working set (PROBE_MIN_ROWS) costs its PROBE_MIN_SECONDS of products and a few
    milliseconds more, so every run can be planned at this machine's rate (2026-12-06: 9 ms with its build, best of
    30 products; the largest, 1M rows, ~0.3 s). The minimum is a tenth of a second at most."""
    import time

    assert cost.PROBE_MIN_SECONDS <= 0.1
    t0 = time.perf_counter()
    speed = cost._probe(cost.PROBE_MIN_ROWS)
    assert time.perf_counter() - t0 < cost.PROBE_MIN_SECONDS + 0.1 and speed > 0


def test_the_probe_repeats_its_products_for_its_minimum_time(monkeypatch):
    """rods.cost._probe repeats its products for PROBE_MIN_SECONDS at least (near the cache's edge a product reaches
    its steady rate only after tens of repeats: a plan read 2.14 x its run from 4-6 of them, 2026-12-08)."""
    import time

    monkeypatch.setattr(cost, "PROBE_MIN_SECONDS", 0.2)
    t0 = time.perf_counter()
    cost._probe(cost.PROBE_MIN_ROWS)  # its 30 products and the build: ~10 ms without the minimum (2026-12-08)
    assert time.perf_counter() - t0 >= 0.2


def test_a_3d_run_is_probed_with_its_own_rows(scene_with, monkeypatch):
    """calibrated: an axisymmetric and a 3D run of the same probe rows get separate probes (the 3D one of 81-entry
    rows, rods.cost._probe(rows, "3d")), each scaled by its own; a 3D probe at its smallest is ~8 MB, as the
    axisymmetric one's, not the 32 MB of its 32k rows (past the AMD's 32 MiB cache)."""
    readings = {"axisymmetric": 2.0, "3d": 0.5}
    monkeypatch.setattr(cost, "_probe", lambda rows, kind: readings[kind])
    monkeypatch.setattr(cost, "_probes", {})
    axi, solid = cost.fe_cost(scene_with(*TINY)), cost.fe_cost(scene_with(*TINY, "fe.kind=3d", "fe.symmetry=quarter"))
    solid = dataclasses.replace(solid, probe_rows=axi.probe_rows)  # the same size: only the kind tells them apart
    fast, slow = cost.calibrated([axi, solid])
    assert (fast.speed, slow.speed) == (2.0, 0.5) and set(cost._probes) == {("axisymmetric", axi.probe_rows),
                                                                         ("3d", axi.probe_rows)}  # fmt: skip
    assert cost.probe_rows("3d", 1.0, 1) * cost.PROBE_ROW_BYTES["3d"] < 1e7
    assert cost.probe_rows("axisymmetric", 1.0, 1) * cost.PROBE_ROW_BYTES["axisymmetric"] < 1e7


def test_the_probe_is_measured_again_when_it_ages(monkeypatch):
    """One process planning runs for longer than rods.cost.PROBE_MAX_AGE (a benchmark over many scenes) measures the
    machine again instead of planning the later runs at its first probe's rate (2026-11-29: 0.54 x a 169 s run's
    time, the rate having dropped since); within the age it reuses the probe, and `refresh` overrides both ways."""
    readings, clock = iter([1.0, 0.4, 0.7, 0.9]), [0.0]
    monkeypatch.setattr(cost, "_probe", lambda rows, kind: next(readings))
    monkeypatch.setattr(cost, "_probes", {})
    monkeypatch.setattr(cost, "_clock", lambda: clock[0])
    assert cost.probe_is_stale() and cost.machine_speed() == 1.0
    clock[0] = 0.9 * cost.PROBE_MAX_AGE
    assert not cost.probe_is_stale() and cost.machine_speed() == 1.0  # reused
    clock[0] = 1.1 * cost.PROBE_MAX_AGE
    assert cost.probe_is_stale() and cost.machine_speed() == 0.4  # measured again
    assert cost.machine_speed(refresh=True) == 0.7  # a rank told to measure does
    clock[0] = 10 * cost.PROBE_MAX_AGE
    assert cost.machine_speed(refresh=False) == 0.7  # a rank told not to does not
    assert cost.machine_speed(rows=cost.PROBE_ROWS // 2) == 0.9  # another size has its own probe


@pytest.mark.mpi
def test_every_rank_plans_at_rank_0s_probe(tmp_path):
    """Under mpirun -n 2 a long run's plan is calibrated by both ranks' probe at once, the slower taken by both: the
    dry run prints one calibrated estimate and exits 0 on both ranks (a rate per rank could refuse on one rank and
    not the other)."""
    r = run_workflow(
        "global.py",
        ["--scene", str(SCENES / "paper.toml"), "--set", "fe.axial_size=0.25e-3", "--set", "fe.radial_size=0.125e-3",
         "--dry-run", "--out", str(tmp_path / "g")],
        ranks=2,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert r.stdout.count("x the reference's)") == 1, r.stdout
    assert not (tmp_path / "g").exists()


@pytest.mark.alone  # a wall time: not beside another test
def test_checkpoints_are_counted_in_the_time_estimate(tmp_path, scene_with):
    """A checkpoint every step (an interval below Δt) costs what its writes measure: the estimate's extra over the
    same run without checkpoints is within 0.1x to 5x of the measured extra (2026-11-24: 2.8 ms per checkpoint
    of the 52.9k-DOF paper mesh, serial; the estimate 3.0 ms), not nothing. The writes go to disk, whose speed the
    plan does not probe: on 2026-11-28's machine one `make test` measured 12 ms per checkpoint (0.23x), the same
    case run by itself again 0.25x or more."""
    from rods.fe.model import ExplicitModel

    runs = {}
    for ci in (0.0, 1e-9):
        sc = scene_with("simulation.end_time=1e-5", f"fe.checkpoint_interval={ci}")
        runs[ci] = (cost.fe_cost(sc), ExplicitModel(sc).run(tmp_path / str(ci)).summary["wall_time"])
    estimated = runs[1e-9][0].wall_time - runs[0.0][0].wall_time  # [s]
    measured = runs[1e-9][1] - runs[0.0][1]  # [s]
    assert estimated > 0.0 and 0.1 < estimated / measured < 5.0, (estimated, measured)


def test_budgets_and_force(scene_with):
    """--force lifts the step budget, never the memory check."""
    long = cost.fe_cost(scene_with("fe.dt=1e-12"))
    assert long.steps == pytest.approx(1.5e9)
    with pytest.raises(InputError, match="step budget"):
        cost.check(long)
    assert cost.check(long, force=True) is long
    huge = cost.fe_cost(scene_with("fe.axial_size=1e-7"))
    for force in (False, True):
        with pytest.raises(InputError, match="more memory than available"):
            cost.check(huge, force=force)


def test_a_memory_refusal_names_what_the_memory_goes_to(scene_with, monkeypatch):
    """The parts above a fifth of the memory, largest first, each with what lowers it: a cut record's refusal named
    a larger output interval, which changed nothing (a fuzz, 2026-12-06)."""
    sc = scene_with()
    recording = cost.fe_cost(sc, record_until=sc.end_time)
    assert recording.memory_parts.startswith("the cut record") and "output_interval" not in recording.memory_parts
    assert cost.fe_cost(sc).memory_parts.startswith("the ranks' interpreters and libraries")  # 170 MB vs 16 MB
    fine = cost.fe_cost(scene_with("fe.axial_size=2e-5", "fe.radial_size=2e-5"))
    assert fine.memory_parts.startswith("the mesh") and fine.memory_parts.endswith("coarser sizes")
    monkeypatch.setattr(cost, "local_memory", lambda: 0.5 * recording.memory)
    with pytest.raises(InputError, match="the cut record .* GB: coarser sizes") as e:
        cost.check(recording)
    assert "simulation.output_interval" not in str(e.value)
    # the --record-* options are named only where the user has them (global.py --record-cut): a driver and a study
    # record their contact phase every step (a corner audit: run.py refused for 25 GB was told --record-every)
    assert "--record-every" not in recording.memory_parts
    assert "--record-every" in cost.fe_cost(sc, record_until=sc.end_time, record_flags=True).memory_parts
    driver = jobs.global_cost(sc, 1, driver=True, phase=2e-4)
    assert (
        "--record-every" not in driver.memory_parts
        and "--record-every" in jobs.global_cost(sc, 1, record_cut=True).memory_parts
    )


def test_an_end_time_below_one_step_is_refused_before_the_set_up(scene_with):
    """As the set-up would refuse it (rods.fe.timestep), but before: a dry run passed a 1 ps end time. A given
    fe.dt is known exactly (its remedy a smaller fe.dt, not finer sizes); an estimated step only where it is
    surely below (the estimate is 0.68-1.05 x the exact step): the set-up decides the margin."""
    tiny = ("simulation.end_time=1e-12", "simulation.output_interval=1e-12")
    with pytest.raises(SceneError, match=r"one time step, about .* \(a longer end time, or finer sizes"):
        cost.fe_cost(scene_with(*tiny))
    given = ("fe.dt=3e-8", "simulation.end_time=1e-8", "simulation.output_interval=1e-8")
    with pytest.raises(SceneError, match=r"fe.dt = 3e-08 s on this mesh \(a longer end time, or a smaller fe.dt\)"):
        cost.fe_cost(scene_with(*given))
    near = cost.fe_cost(scene_with("simulation.end_time=3e-8", "simulation.output_interval=1e-8"))
    assert near.steps == 2  # within the estimate's margin of the exact 3.3e-8 s step: planned, the set-up decides


@pytest.fixture
def fake_driver(tmp_path, scene_with):
    """A folder that passes submodel.py's input checks (summary.json of a driver, a cut.h5 with its times and
    recording scene only)."""
    import h5py

    d = tmp_path / "driver"
    d.mkdir()
    s = {"scene_values": scene_with().as_dict(), "dt": 3e-8, "contact_phase": 1.2e-4, "status": "ok"}
    (d / "summary.json").write_text(json.dumps(s))
    with h5py.File(d / "cut.h5", "w") as f:
        f["times"] = [0.0, 1.2e-4]
        f.attrs["scene_values"] = json.dumps(s["scene_values"])
    return d


def _stations(tmp_path, n: int):
    lines = [f'base = "{SCENES / "paper.toml"}"']
    for i in range(1, n + 1):
        lines += ["[[station]]", "rod = 2", f"position = {i * 1e-4!r}", f'name = "s{i}"']
    (tmp_path / "stations.toml").write_text("\n".join(lines) + "\n")
    return str(tmp_path / "stations.toml")


THIN_LONG = ["--set", "rod1.diameter=1e-6", "--set", "rod2.diameter=1e-6", "--set", "simulation.end_time=1.0",
             "--set", "simulation.output_interval=1e-3"]  # fmt: skip
CASES = {  # (script, arguments) that would exhaust memory or run for days
    "output_interval 1e-12": ("analytical.py", ["--set", "simulation.output_interval=1e-12"]),
    "dt 1e-15": ("global.py", ["--set", "fe.dt=1e-15"]),
    "dt 1e-12": ("global.py", ["--set", "fe.dt=1e-12"]),
    "axial_size 1e-7": ("global.py", ["--set", "fe.axial_size=1e-7"]),
    "run axial_size 1e-7": ("run.py", ["--set", "fe.axial_size=1e-7"]),
    "driver radial 1e-6": ("global.py", ["--driver", "--set", "fe.radial_size=1e-6"]),
    "submodel size 1e-8": ("submodel.py", ["--global", "{driver}", "--size=1e-8"]),
    "5000 stations": ("analytical.py", ["--scene", "{stations}"]),
    # thin rods: the contact is so stiff against them that the explicit solver needs ~1e10 steps over 1 s at 1 µm (1 nm
    # rods, refused by the schema since 2026-11-29, once ran an hour, growing to 18 GB, in the fuzz test)
    "1 µm rods for 1 s": ("analytical.py", [*THIN_LONG]),
    "run 1 µm rods for 1 s": ("run.py", [*THIN_LONG]),
}


@pytest.mark.parametrize("case", list(CASES))
def test_entry_points_refuse_what_would_run_into_the_ground(tmp_path, fake_driver, case):
    script, args = CASES[case]
    args = [a.format(driver=fake_driver, stations=_stations(tmp_path, 5000) if "{stations}" in a else "") for a in args]
    out = tmp_path / "out"
    p = in_process(script, *args, "--out", str(out), cwd=tmp_path)  # the shell's own start: test_cli_errors
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and len(lines[0]) < 1000, p.stderr[-2000:]
    assert "budget" in lines[0] or "memory" in lines[0]
    assert not out.exists()


@pytest.mark.parametrize("d", [1e-4, pytest.param(5e-5, marks=pytest.mark.slow)])  # 8 s: the growth, in make test-slow
def test_analytical_steps_follow_the_contacts_stiffness_against_thin_rods(scene_with, d):
    """Thin rods (diameter d [m]) under the paper's 35 mm tip: the explicit DOP853's steps grow as d^(-4/3) (the
    contact's rate against the rods' impedance, rods.cost.analytical_steps). The estimate takes the whole run as
    stiff, so it errs high where the contact is a part of it (2.6x at 1e-4 s here), never low by more than 15%
    (measured 0.94-1.06 at 2e-4 s); the paper rods' few hundred steps are not overestimated into seconds."""
    from rods.analytical import simulate

    s = scene_with(f"rod1.diameter={d!r}", f"rod2.diameter={d!r}", "simulation.end_time=2e-4")
    taken = len(simulate(s).model._history.t_lo)
    assert 0.85 * taken < cost.analytical_cost(s).steps < 3.0 * taken
    assert cost.analytical_cost(scene_with()).wall_time < 1.0


def test_time_budget_refuses_a_day_long_analytical_run(scene_with):
    """The analytical model has neither steps nor DOFs: its estimated wall time is budgeted (a day). 1 s of
    simulated time on 50 mm rods (~102 000 wave passes, about 4 min estimated, 1.7 min measured) passes; a budget
    below the estimate refuses it, naming the time, and --force lifts that."""
    short = cost.analytical_cost(scene_with("simulation.end_time=1", "simulation.output_interval=1e-3",
                                            "rod1.length=0.05", "rod2.length=0.05"))  # fmt: skip
    assert 100.0 < short.wall_time < cost.TIME_BUDGET
    assert cost.check(short) is short
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cost, "TIME_BUDGET", 0.5 * short.wall_time)
        with pytest.raises(InputError, match="time budget"):
            cost.check(short)
        assert cost.check(short, force=True) is short


@pytest.mark.parametrize("grading", ["uniform", "graded"])
@pytest.mark.parametrize("tip", [0.035, 0.010, 0.0075, 0.00676, 0.00635])
def test_a_submodels_steps_follow_its_curved_tip(scene_with, tip, grading):
    """A submodel (0.25 mm, rods.fe.submodel.submodel_scene, uniform or graded across) on tips from the paper's
    35 mm (rim angle 10°) to a hemisphere: the estimate not below the built model's steps by more than 2% and at
    most 1.35x them (the tip cells' own geometry, rods.cost._tip_step, errs low on deep graded caps: 1.26x at 6.76
    mm; a butterfly by SUBMODEL_CAP_STEP_FACTOR, GRADED_SUBMODEL_CAP_STEP_FACTOR). Before the curvature counted, a
    10 mm tip ran 1.3x, a 7.5 mm one 2.1x and a 6.76 mm one (69.9°, just below the butterfly cap) 3.4x the steps
    estimated."""
    from rods.fe.model import ExplicitModel
    from rods.fe.submodel import submodel_scene

    sc = scene_with(f"rod1.tip_radius={tip}", "simulation.end_time=1e-5", f"fe.radial_grading='{grading}'")
    c = cost.fe_cost(sc, size=0.25e-3, end_time=1e-5)
    m = ExplicitModel(submodel_scene(sc, 0.25e-3, end_time=1e-5))
    assert 0.98 * m.steps <= c.steps <= 1.35 * m.steps


def test_a_gpu_run_is_estimated_at_the_gpu_rates(scene_with):
    """fe.backend = "cupy": the plan's time is the GPU's (set-up on that machine's CPU + steps x the measured
    step line), minutes for the paper's 3D mesh where the CPU estimate is hours; "auto" without a GPU (this
    machine) is the CPU's."""
    paper_3d = ("fe.kind=3d", "fe.axial_size=1e-3", "fe.radial_size=0.25e-3", "fe.symmetry=full")
    cpu, gpu = (cost.fe_cost(scene_with(*paper_3d, f"fe.backend={b}")) for b in ("petsc", "cupy"))
    assert gpu.dofs == cpu.dofs and gpu.steps == cpu.steps
    steps = gpu.steps / cost.STEP_COUNT_BIAS["3d"]  # the steps the run will take, centrally
    loop = steps * (cost.GPU_STEP_OVERHEAD + gpu.dofs / cost.GPU_DOF_STEPS_PER_SECOND)
    loop += gpu.samples * cost.RECORD_ROW_SECONDS  # the recorder's rows, on the host
    assert gpu.setup_time == pytest.approx(gpu.dofs * cost.GPU_SETUP_SECONDS_PER_DOF["3d"])
    assert gpu.wall_time == pytest.approx(gpu.setup_time + loop)
    assert 60.0 < gpu.wall_time < 1200.0 < 3600.0 < cpu.wall_time  # [s] minutes against hours
    from rods.fe.backend import gpu_available

    if not gpu_available():
        assert cost.fe_cost(scene_with(*paper_3d, "fe.backend=auto")).wall_time == pytest.approx(cpu.wall_time)


def test_the_matrix_free_loop_is_planned_at_its_own_rate_not_the_probes(scene_with):
    """fe.operator = "matrix-free" on the CPU: the element kernel's gathers and small products are not the sparse
    product the machine probe times, so its loop is planned at its measured rate, unscaled, with no probe (an options
    fuzz, 2026-12-06: 42.9k DOFs planned 66.6 s at 7.8e5 x the probe's 2.91, ran 151 s; now 193 s planned; 48k DOFs,
    101 s planned, 109 s run)."""
    sc = scene_with("fe.backend='numpy'", "fe.operator='matrix-free'", "simulation.end_time=6e-5")
    c = cost.fe_cost(sc)
    run_steps = c.steps / cost.STEP_COUNT_BIAS["axisymmetric"]  # the time is the steps the run will take
    loop = run_steps * (cost.STEP_OVERHEAD + c.dofs / cost.MATRIX_FREE_CPU_DOF_STEPS_PER_SECOND["axisymmetric"])
    loop += c.samples * cost.RECORD_ROW_SECONDS
    assert c.probe_rows == 0 and c.memory_bound_time == 0.0
    assert c.wall_time == pytest.approx(c.setup_time + loop)
    assert cost.calibrated([c])[0].wall_time == c.wall_time  # no probe scales it
    assembled = cost.fe_cost(scene_with("fe.backend='numpy'", "simulation.end_time=6e-5"))
    assert assembled.probe_rows > 0 and c.wall_time > 5 * assembled.wall_time  # 6-25x the CSR product's


def test_a_study_level_above_the_machine_names_submodel_levels(scene_with, monkeypatch):
    """A 3D scene's contact_patch study: "auto" picks the levels, not the user, so a level refused for memory (or a
    budget) names submodel.levels first in its remedy (found on paper-3d-coarse, 2026-11-27: fine, 5.4e7 DOFs and
    118 GB, was refused with "coarser sizes" only)."""
    from rods import plan
    from rods.study.pipeline import stage_costs

    sc = scene_with("fe.kind='3d'", "fe.axial_size=4e-3", "fe.radial_size=1e-3", "fe.tip_grading=0.25",
                    "effects=['contact_patch']")  # fmt: skip
    costs = {c.what: c for c in stage_costs(sc, plan.make_plan(sc), 1)}
    fine = costs["the submodel fine"]
    assert fine.remedy.startswith("submodel.levels without 'fine'") and costs["the global"].remedy == ""
    monkeypatch.setattr(cost, "local_memory", lambda: 0.5 * fine.memory)
    with pytest.raises(InputError, match=r"more memory .*; submodel.levels without 'fine' \(the plan's: coarse, mid"):
        cost.check(fine)
    monkeypatch.setattr(cost, "STEP_BUDGET", 0.5 * fine.steps)
    monkeypatch.setattr(cost, "local_memory", lambda: 2.0 * fine.memory)
    with pytest.raises(InputError, match=r"step budget .*\); submodel.levels without 'fine'"):
        cost.check(fine)


THICK_ONTO_THIN = (  # a 37 mm steel rod, 226 mm tip, onto an 8.6 mm glass rod at 0.427 m/s (submodel draw 61208)
    "rod1.diameter=0.03714", "rod1.length=0.3498", "rod1.tip_radius=0.2258", "rod2.material.youngs_modulus=7e10",
    "rod2.material.density=2500.0", "rod2.material.poisson_ratio=0.22", "rod2.diameter=0.008647",
    "rod2.length=0.6216", "rod2.tip_radius=inf", "impact.speed=0.427", "effects=['contact_patch']",
)  # fmt: skip


def test_a_uniform_study_names_grading_where_it_saves_most_of_a_level(scene_with):
    """ "auto" keeps a study's submodels uniform where grading saves less than half across at the levels' start
    (rods.fe.submodel.submodel_grading); below it a uniform level quadruples, so a level that grading brings to at
    most GRADED_SHARE of its time names fe.radial_grading='graded' in its remedy (the plan's total, a refusal) with
    both DOF counts, each as the mesher would count it; a graded study, or one the user set uniform, names none."""
    from rods import plan
    from rods.fe.layout import GRADED_SHARE
    from rods.study.pipeline import stage_costs

    def levels(*overrides):
        sc = scene_with(*THICK_ONTO_THIN, *overrides)
        return sc, {c.what: c for c in stage_costs(sc, plan.make_plan(sc), 1) if c.what.startswith("the submodel")}

    sc, uniform = levels()
    assert list(uniform) == [f"the submodel {lv}" for lv in ("mid", "fine", "extra-fine")]
    _, graded = levels("fe.radial_grading='graded'")
    for what, c in uniform.items():
        g = graded[what]
        assert g.wall_time <= GRADED_SHARE * c.wall_time  # here every level: 17.7k / 122k DOFs at mid
        said = f"or fe.radial_grading='graded' (the global and the submodels graded outside the patch: {g.dofs:.3g} "
        assert said + f"DOFs at this level, not {c.dofs:.3g}" in c.remedy and g.remedy.count("radial_grading") == 0
    assert graded["the submodel extra-fine"].dofs < 0.1 * uniform["the submodel extra-fine"].dofs
    line = cost.total(list(uniform.values()))
    assert "of it the submodel extra-fine" in line and "or fe.radial_grading='graded'" in line
    _, own = levels("fe.radial_grading='uniform'")
    assert all("radial_grading" not in c.remedy for c in own.values())
    # the paper scene: its coarse level's grading leaves more than half of its time, its fine level's less
    sc = scene_with("effects=['contact_patch']")
    paper = {c.what: c for c in stage_costs(sc, plan.make_plan(sc), 1)}
    assert "radial_grading" not in paper["the submodel coarse"].remedy
    assert "radial_grading" in paper["the submodel fine"].remedy


@pytest.mark.parametrize("ξ", [0.0, 0.3, 0.99])
def test_bulk_viscosity_shortens_the_estimated_step_as_the_scheme_does(scene_with, ξ):
    """The estimate's damped factor is the integrator's (rods.fe.explicit.stable_step), and the steps estimated
    for the paper scene's driver at ξ follow the set-up's within the undamped estimate's own 20%."""
    from rods.fe.explicit import stable_step
    from rods.fe.model import ExplicitModel

    sc = scene_with(f"fe.bulk_viscosity={ξ!r}", "simulation.end_time=2e-6", *TINY[:2])
    assert cost.damped_step_factor(sc) == pytest.approx(stable_step(1.0, ξ) / stable_step(1.0), rel=1e-15)
    assert cost.fe_cost(sc).steps == pytest.approx(ExplicitModel(sc).steps, rel=0.2)


def test_afford_refuses_memory_before_probing_and_prints_the_calibrated_plan(scene_with, monkeypatch, capsys):
    """workflows/_cli.afford: a run above the free memory is refused (exit 2 at the entry points) before the
    machine probe (no 0.2 GB product for a run that cannot start); a long run that fits is printed at the probed
    rate."""
    import argparse

    import _cli  # workflows/ (tests/conftest.py puts it on the path)

    def no_probe(rows: int = cost.PROBE_ROWS, kind: str = "axisymmetric") -> float:
        raise AssertionError("probed before the memory check")

    monkeypatch.setattr(cost, "machine_speed", no_probe)
    args = argparse.Namespace(force=True, dry_run=False)
    huge = cost.fe_cost(scene_with("fe.axial_size=1e-7"))
    assert huge.probe_rows > 0
    with pytest.raises(InputError, match="more memory than available"):  # the entry points' exit 2
        _cli.afford(args, huge)
    monkeypatch.setattr(cost, "machine_speed", lambda rows=cost.PROBE_ROWS, kind="axisymmetric": 0.5)
    long = cost.fe_cost(scene_with("fe.axial_size=0.25e-3", "fe.radial_size=0.125e-3"))
    _cli.afford(args, long)
    assert "probed rate 0.50 x the reference's" in capsys.readouterr().out


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    tip=st.one_of(st.just("inf"), st.floats(min_value=1e-3, max_value=2.0)),  # [m] at least the rod radius
    diameter=st.floats(min_value=2e-3, max_value=40e-3),  # [m]
    axial=st.floats(min_value=5e-5, max_value=5e-3),  # [m]
    ratio=st.floats(min_value=0.1, max_value=2.0),  # radial / axial size [-]
    grading=st.one_of(st.just("'auto'"), st.floats(min_value=0.05, max_value=1.0)),
)
def test_any_axisymmetric_mesh_gets_a_finite_estimate_or_a_refusal(scene_with, tip, diameter, axial, ratio, grading):
    """Whatever tip, rod and mesh sizes a scene holds, the estimate (with the tip cells' own geometry) is finite and
    positive, or a SceneError naming a key: never a crash."""
    flat = tip == "inf"  # then Rod 2's tip is the curved one (two flats have no Hertz contact)
    tips = (
        ("rod1.tip_radius=inf", "rod2.tip_radius=0.035")
        if flat
        else (f"rod1.tip_radius={max(tip, diameter / 2 * 1.0001)!r}",)
    )
    try:
        sc = scene_with(
            *tips, f"rod1.diameter={diameter!r}", f"fe.axial_size={axial!r}", f"fe.radial_size={axial * ratio!r}",
            f"fe.tip_grading={grading}", "simulation.end_time=1e-5",
        )  # fmt: skip
        c = cost.fe_cost(sc)
    except SceneError as e:
        assert e.key
        return
    assert 0 < c.wall_time < math.inf and c.steps >= 1 and 0 < c.memory_bound_time <= c.wall_time
    assert 0 < cost._tip_step(sc, sc["fe.radial_size"], sc["fe.axial_size"], sc.tip_grading) <= math.inf


def test_the_total_names_the_stage_that_is_most_of_a_study(scene_with):
    """cost.total: the wall time of several stages in all, and a submodel level above half of it named with how to
    leave it out (a small patch puts the auto levels down to ultra-fine, each about 8 x the one above it); a stage no
    setting chose (the global) is not named; one stage gets no line."""
    from rods import plan
    from rods.study.pipeline import stage_costs

    sc = scene_with("effects=['contact_patch']", "impact.speed=0.3", "rod1.tip_radius=0.01")
    p = plan.study_plan(sc)
    costs = stage_costs(sc, p, 2)
    finest = max(costs, key=lambda c: c.wall_time)
    wall = sum(c.wall_time for c in costs)
    line = cost.total(costs)
    assert finest.what == f"the submodel {p.submodel_levels[-1]}" and finest.wall_time > 0.5 * wall
    assert line.startswith(f"cost in all: wall time about {cost._duration(wall)} on 2 rank(s), ")
    assert f"{finest.wall_time / wall:.0%} of it {finest.what} (to leave it out: submodel.levels without" in line
    assert len(costs) >= 3 and "of it" not in cost.total([replace(c, wall_time=1.0) for c in costs])  # none > half
    cheap = [c for c in costs if c is not finest]
    assert "of it" not in cost.total([*cheap, replace(finest, remedy="")])  # no setting to name
    assert cost.total(costs[:1]) is None


def _written(folder) -> int:
    """Bytes of every file under ``folder``."""
    from pathlib import Path

    return sum(f.stat().st_size for f in Path(folder).rglob("*") if f.is_file())


@pytest.mark.parametrize(
    "extra, flags",
    [
        (("fe.field_interval=5e-6", "fe.checkpoint_interval=2e-5"), ()),  # frames and checkpoints
        ((), ("--record-cut",)),  # the submodels' cut record
    ],
    ids=["fields-checkpoints", "cut-record"],
)
def test_planned_files_bound_what_a_run_writes(tmp_path, scene_with, extra, flags, monkeypatch):
    """Cost.file_bytes, what rods.cost.check_disk holds against the free disk, is what the run writes, erring high
    by the cut band's fifth row and the step estimate's margin (measured on the coarse paper mesh: frames and
    checkpoints 1.03x, the cut record 1.05x the files written): never below it (a disk the plan passed would fill),
    and within 1.3x (a plan that refuses what fits is a wrong plan too)."""
    args = (*TINY[:2], "simulation.end_time=4e-5", *extra)
    sc = scene_with(*args)
    until = sc.end_time if flags else None
    planned = cost.fe_cost(sc, record_until=until).file_bytes
    out = tmp_path / "run"
    from rods.fe import checkpoint

    # the last checkpoint kept (a finished run removes it): the disk held it while the run went on
    monkeypatch.setattr(checkpoint, "discard", lambda *a: None)
    p = run_workflow("global.py", [*(a for o in args for a in ("--set", o)), *flags, "--out", str(out)])
    assert p.returncode == 0, p.stderr[-2000:]
    written = _written(out)
    if extra:  # the plan counts two checkpoints on disk while the newer replaces the older: the last, once more
        written += max(f.stat().st_size for f in out.glob("checkpoint-*.npz"))
    else:
        assert (out / "cut.h5").stat().st_size > 0.5 * written  # the record is what this case sizes
    assert written <= planned <= 1.3 * written


def test_a_run_whose_files_overflow_the_disk_is_refused_before_anything_is_written(tmp_path, monkeypatch, scene_with):
    """rods.cost.check_disk at the entry points (workflows/_cli.afford): the files planned against the free space of
    --out's file system, refused with exit 2 and one line naming --out, the sizes and the remedy, nothing written,
    and --force does not lift it (it lifts budgets, not the disk's room); where they fit, the run goes on."""
    overrides = ("fe.field_interval=1e-5", "simulation.end_time=4e-5", *TINY[:2])
    frames = [a for o in overrides for a in ("--set", o)]
    out = tmp_path / "deep" / "run"
    planned = cost.fe_cost(scene_with(*overrides)).file_bytes  # [B]
    monkeypatch.setattr(cost, "available_disk", lambda folder: 0.5 * planned)
    for force in ([], ["--force"]):
        p = in_process("global.py", *frames, *force, "--out", str(out), cwd=tmp_path)
        lines = p.stderr.strip().splitlines()
        assert p.returncode == 2 and len(lines) == 1, p.stderr[-2000:]
        assert lines[0].startswith("error: --out = ") and "GB of files" in lines[0] and "field frames" in lines[0]
        assert "a larger fe.field_interval" in lines[0]
        assert not (tmp_path / "deep").exists()
    monkeypatch.setattr(cost, "available_disk", lambda folder: 2.0 * planned)
    assert in_process("global.py", *frames, "--out", str(out), cwd=tmp_path).returncode == 0
    monkeypatch.setattr(cost, "available_disk", lambda folder: 0.0)
    for script in ("analytical.py", "run.py"):  # every entry point holds its files to the disk
        p = in_process(script, "--out", str(tmp_path / script), cwd=tmp_path)
        assert p.returncode == 2 and "--out" in p.stderr and "GB of files" in p.stderr, p.stderr[-2000:]


@pytest.mark.parametrize(
    "extra, named",
    [
        ((), "fe.symmetry = 'quarter'"),
        (("fe.symmetry=half",), "fe.symmetry = 'quarter'"),
        (("impact.tilt=0.01",), "fe.symmetry = 'half'"),
        (("fe.symmetry=quarter",), None),
        (("fe.kind=axisymmetric",), None),
    ],
)
def test_a_refused_3d_run_names_its_symmetric_twin(scene_with, extra, named):
    """A 3D model refused for its size names the symmetric model the impact allows among the remedies (a quarter of
    the DOFs for a centric impact, half for one misaligned in a plane); found by a fuzz (2026-12-06), where a full
    model's refusal named coarser sizes only and its quarter model ran in half the time."""
    sc = scene_with("fe.kind=3d", "fe.radial_size=0.05e-3", *extra)
    c = cost.fe_cost(sc)
    assert (named in c.cheaper) if named else c.cheaper == ""
    if named:
        with pytest.raises(InputError, match=named.replace("'", ".")):  # 404 GB on the full model
            cost.check(c)


def test_a_busy_machine_is_said_beside_the_estimate():
    """The plan's time is an idle machine's: where the load leaves this run's ranks no free cores, the plan says so
    (a fuzz measured 3-11 x the estimate on 2 ranks at load 3.4-6.9 on 2 cores); with their cores free, nothing."""
    assert cost.busy_note(2, load=0.3, cores=2) == "" and cost.busy_note(1, load=0.9, cores=2) == ""
    note = cost.busy_note(2, load=5.9, cores=2)
    assert note.startswith("note: this machine is busy (load average 5.9 on 2 cores") and "several times" in note
    assert cost.busy_note(2, load=1.0, cores=16) == ""


def test_a_step_near_the_penalty_switching_estimate_is_valid_only_as_far_as_the_plan_can_tell(scene_with):
    """The switching limit's estimate read 4% above the set-up's exact one (a fuzz: 1.12e-8 s passed the dry run as
    "valid", the set-up refused it): a given fe.dt within cost.SWITCHING_CAVEAT of it carries the plan's caveat; one
    well below it does not."""
    sc = scene_with("fe.contact='penalty'", "simulation.end_time=2e-5")
    switching = cost._step_limits(sc, *cost._fe_mesh(sc, None, None)[0], None)[1]  # [s] the plan's estimate
    near = cost.fe_cost(sc.with_overrides(f"fe.dt={0.98 * switching!r}"))
    assert "switching limit" in near.caveat and "refuses a step above it" in near.caveat
    assert cost.fe_cost(sc.with_overrides(f"fe.dt={0.5 * switching!r}")).caveat == ""


def test_a_long_full_3d_plan_names_its_quarter_twin(scene_with):
    """A centric full 3D plan of hours named fe.symmetry = 'quarter' (a quarter of the DOFs) only when refused for
    memory (a helper's audit, 2026-12-07); a plan above CHEAPER_NOTE names it, a short or a quarter one does not."""
    from rods.study import jobs

    full = jobs.global_cost(scene_with("fe.kind=3d"), 1)
    assert full.wall_time > cost.CHEAPER_NOTE and "for less: fe.symmetry = 'quarter'" in full.describe()
    quarter = jobs.global_cost(scene_with("fe.kind=3d", "fe.symmetry=quarter"), 1)
    assert "for less" not in quarter.describe()
    coarse = jobs.global_cost(scene_with("fe.kind=3d", "fe.radial_size=1e-3", "fe.axial_size=4e-3"), 1)
    assert coarse.wall_time < cost.CHEAPER_NOTE and "for less" not in coarse.describe()


def test_the_plans_time_counts_the_steps_the_run_will_take(scene_with):
    """The estimated stable step errs low by design (a stable given fe.dt is never refused), so the plan's step count
    runs 1.10-1.34 x the run's on 20 drawn axisymmetric globals and 1.11-1.13 on the verification matrix (2026-12-07);
    the per-step costs are per step run, so the time takes the steps the run will take: the plan's over that bias
    where the stable estimate sets the step (3D globals ran 1.0-1.2 x fewer steps than planned, eleven runs,
    2026-12-07; the axisymmetric submodels 1.09-1.16, 16 levels of five studies: each its own bias; 3D submodels
    unmeasured: none), its own count where a given step or the penalty's switching limit (estimated as the set-up
    computes it) does: a bias on those read their time 1.15 x low."""
    assert 1.10 <= cost.STEP_COUNT_BIAS["axisymmetric"] <= 1.2 and 1.0 <= cost.STEP_COUNT_BIAS["3d"] <= 1.2
    assert 1.09 <= cost.SUBMODEL_STEP_COUNT_BIAS["axisymmetric"] <= 1.16 and "3d" not in cost.SUBMODEL_STEP_COUNT_BIAS
    bias, sub_bias = cost.STEP_COUNT_BIAS["axisymmetric"], cost.SUBMODEL_STEP_COUNT_BIAS["axisymmetric"]

    def run_steps(sc):  # the plan's count, and the count its time takes
        c = cost.fe_cost(sc)
        loop = cost._fe_time(sc, 1, 1.0, c.dofs, cut=False)[2]  # the rate-bound time of one step
        return c.steps, c.memory_bound_time / loop

    sc = scene_with("simulation.end_time=3e-4")
    planned, timed = run_steps(sc)
    assert timed == pytest.approx(planned / bias, rel=1e-9)
    dt = 0.5 * sc.end_time / planned  # [s] about half the plan's step, given: the run's exactly
    given = sc.with_overrides(f"fe.dt={dt!r}")
    assert run_steps(given)[1] == pytest.approx(run_steps(given)[0], rel=1e-9) == math.ceil(sc.end_time / dt)
    stiff = scene_with("simulation.end_time=3e-4", "fe.contact=penalty", "fe.penalty=40.0")  # the switching limit
    assert run_steps(stiff)[1] == pytest.approx(run_steps(stiff)[0], rel=1e-9)
    (h_r, h, g), region, _, _ = cost._fe_mesh(sc, 0.2e-3, None)
    assert cost._march_step(sc, h_r, h, g, 0.2e-3, "auto", region)[2] == pytest.approx(sub_bias)  # a submodel's
    assert cost._march_step(sc, h_r, h, g, 0.2e-3, 1e-9, region)[2] == 1.0


# the penalty pair's switching limit, estimated against the set-up's exact one: a thin flat rod under a graded one
# (the graded rod's coarse nodes over the thin rod's fine face: the equal-mesh estimate read 1.52 x), a butterfly
# pair, the paper scene, and 3D quarter models with a flat and a strongly curved tip (1.66 x before) and a thin slave
# over a thick master's core (1.16 x without the O-grids' cell areas)
THIN_UNDER_GRADED = (
    "rod1.diameter=0.0088", "rod1.tip_radius=0.022", "rod1.length=0.05", "rod2.diameter=0.0039", "rod2.length=0.05",
    "rod2.material.youngs_modulus=1.14e11", "rod2.material.density=4430.0", "rod2.material.poisson_ratio=0.34",
    "impact.speed=0.515",
)  # fmt: skip
QUARTER_3D = (
    "fe.kind=3d", "fe.symmetry=quarter", "rod1.length=0.04", "rod2.length=0.04", "fe.radial_size=0.0005",
    "fe.axial_size=0.002",
)  # fmt: skip


@pytest.mark.parametrize(
    "extra, low, high",
    [
        ((), 0.999, 1.001),
        (THIN_UNDER_GRADED, 0.999, 1.001),
        (("rod1.tip_radius=0.0066", "rod2.tip_radius=0.007", "fe.radial_grading=graded"), 0.99, 1.001),
        (QUARTER_3D, 0.97, 1.03),
        ((*QUARTER_3D, "rod1.tip_radius=0.007"), 0.9, 1.03),
        ((*QUARTER_3D, "rod1.diameter=0.006"), 0.9, 1.05),
    ],
    ids=["paper", "thin-under-graded", "butterflies", "3d-quarter", "3d-deep-cap", "3d-thin-slave"],
)
def test_the_switching_estimate_is_the_set_ups_limit(scene_with, extra, low, high):
    """The plan's switching limit (rods.cost._switching_step, from the faces as the mesher lays them) against the
    set-up's (rods.fe.contact.PenaltyContact.pair_frequency over the built mesh): 0.966-1.003 x on 39 axisymmetric
    scenes, 0.93-1.03 x on fourteen 3D quarter models (2026-12-08); a curved 3D tip's estimate errs low (safe)."""
    from rods.fe.model import ExplicitModel

    sc = scene_with(*extra, "fe.contact=penalty", "simulation.end_time=1e-6")
    (h_r, h, g), region, _, _ = cost._fe_mesh(sc, None, None)
    estimate = cost._step_limits(sc, h_r, h, g, None, region)[1]
    assert low <= estimate / ExplicitModel(sc).dt_switching <= high


def _planned_and_used(scene_file, overrides, tmp_path):
    """A 2-rank global's planned memory (rods.study.jobs.global_cost, what workflows/global.py prints) and the
    ranks' summed peak RSS its summary records (rods.cost.peak_memory) [B]: each run in its own interpreters, whose
    peak is the run's alone."""
    from rods.scene import load_scene
    from rods.study import jobs

    out = tmp_path / str(len(list(tmp_path.iterdir())))
    sets = [a for o in overrides for a in ("--set", o)]
    p = run_workflow("global.py", ["--scene", str(scene_file), *sets, "--out", str(out)], ranks=2, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    planned = jobs.global_cost(load_scene(scene_file, overrides), 2).memory
    return planned, json.loads((out / "summary.json").read_text())["peak_memory"]


@pytest.mark.mpi
@pytest.mark.parametrize(
    "scene_file, small, large",
    [
        pytest.param(  # the paper mesh coarsened (19.3k DOFs) and 0.25 x 0.125 mm (398k): ~14 s
            "paper.toml", [], ["fe.axial_size=0.25e-3", "fe.radial_size=0.125e-3"], id="axisymmetric"
        ),
        pytest.param(  # quarter 3D at 3 x 0.7 mm (112k DOFs) and 2 x 0.5 mm (267k): ~25 s
            "paper-3d-coarse.toml",
            ["fe.symmetry=quarter", "fe.axial_size=3e-3", "fe.radial_size=0.7e-3"],
            ["fe.symmetry=quarter", "fe.axial_size=2e-3", "fe.radial_size=0.5e-3"],
            id="3d",
            marks=pytest.mark.slow,
        ),
    ],
)
def test_the_planned_memory_is_what_a_run_uses(scene_file, small, large, tmp_path):
    """The plan's memory (rods.cost.BASE_MEMORY + BYTES_PER_DOF per DOF + histories), which refuses a run that
    would not fit, against the peak RSS the run's summary records: each within 0.7x to 1.4x, and the growth from a
    small to a large mesh (the per-DOF part) within 0.5x to 2x of the plan's (2026-12-07, 2 ranks: axisymmetric
    0.397/0.385 GB planned/used at 19.3k DOFs, 0.739/0.790 GB at 398k, 1069 B per DOF used against 902 planned; 3D
    0.672/0.725 GB at 112k, 1.08/1.09 GB at 267k, 2.39 kB per DOF against 2.63 kB). No test held the memory model
    to a measurement before; a base or a per-DOF figure off by 2x fails here."""
    from .conftest import ROOT

    runs = [_planned_and_used(ROOT / "workflows" / "scenes" / scene_file, [*o, "simulation.end_time=2e-6"], tmp_path)
            for o in (small, large)]  # fmt: skip
    for planned, used in runs:
        assert 0.7 < used / planned < 1.4, (planned, used)
    (p0, u0), (p1, u1) = runs
    assert 0.5 < (u1 - u0) / (p1 - p0) < 2.0, runs
