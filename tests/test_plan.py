"""Effects switch the parts of a run on and off."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from rods import plan
from rods.plan import CONTACT_MARGIN, make_plan
from rods.scene import SUBMODEL_LEVELS, SceneError

from .conftest import PAPER


def test_wave_response_alone_runs_no_submodel(scene_with):
    p = make_plan(scene_with("effects=['wave_response']"), contact_end=2e-4)
    assert p.analytical and p.global_model and not p.submodel_levels and not p.fields
    assert p.global_end_time == pytest.approx(1.5e-3)


def test_contact_patch_adds_submodel_and_stops_global_after_contact(scene_with):
    p = make_plan(scene_with("effects=['contact_patch']"), contact_end=2e-4)
    assert p.submodel_levels == ("coarse", "mid", "fine")
    assert p.global_end_time == pytest.approx(CONTACT_MARGIN * 2e-4)
    assert p.contact_phase == p.global_end_time  # the driver records, and the submodels run, that long
    assert not p.fields
    both = make_plan(scene_with("effects=['contact_patch', 'wave_response']"), contact_end=2e-4)
    assert both.global_end_time == pytest.approx(1.5e-3) and both.submodel_levels
    assert both.contact_phase == pytest.approx(CONTACT_MARGIN * 2e-4)  # the driver still stops after contact


def test_fields_only_when_asked(scene_with):
    assert make_plan(scene_with("effects=['fields']")).fields
    assert not make_plan(scene_with()).fields
    assert make_plan(scene_with("fe.field_interval=1e-5")).fields


def test_misalignment_needs_3d_and_unknown_effects_fail(scene_with):
    p = make_plan(scene_with("effects=['misalignment']", "fe.kind=3d", "impact.offset=1e-4"))
    assert p.global_kind == "3d" and not any("centric" in r for r in p.reasons)
    centric = make_plan(scene_with("effects=['misalignment']", "fe.kind=3d"))  # asked, but nothing misaligned
    assert any("impact.offset = impact.tilt = 0: a centric impact" in r for r in centric.reasons)
    with pytest.raises(SceneError, match=r"'misalignment' needs fe.kind = '3d' \(--set fe.kind='3d'"):
        scene_with("effects=['misalignment']")  # the refusal names its remedy
    with pytest.raises(SceneError, match="unknown effect"):
        scene_with("effects=['wave']")
    with pytest.raises(SceneError, match="submodel.levels"):
        scene_with("submodel.levels=['huge']")


@pytest.mark.parametrize("overrides", [[], ["impact.speed=1.0", "rod1.tip_radius=0.05"]])
def test_phase_radius_is_the_analytical_models_contact_radius(overrides):
    """The phase members are placed about Hertz at the analytical peak force: the analytical model's own peak
    contact radius (computed there from its force history), on the paper scene and a slower, blunter one."""
    from rods.analytical import simulate
    from rods.scene import load_scene

    sc = load_scene(PAPER, overrides)
    s = simulate(sc).summary
    assert plan.phase_radius(sc) == pytest.approx(s["contact_radius"], rel=1e-12)
    assert plan.phase_radius(sc, s) == plan.phase_radius(sc)


@pytest.mark.parametrize(
    ("end_time", "extra"),
    [
        (3e-3, ()),
        (1e-3, ("rod1.length=0.05", "rod2.length=0.05")),
        (3e-3, ("rod2.tip_radius=0.035", "impact.speed=0.1")),
    ],
    ids=["paper", "short-rods", "slow-two-tips"],
)
def test_first_contact_summary_ends_the_first_contact_like_the_whole_run(scene_with, end_time, extra):
    """The plan's analytical run over a window of 8 round trips: the first contact's end is the whole run's to the
    last bit (its integration is the same up to the window), on scenes 1-3 ms long (50 round trips of the short
    rods) that it plans without running the whole (a 1 s scene took minutes before the plan: run.py --dry-run,
    global.py --driver)."""
    from rods.analytical import simulate

    sc = scene_with(f"simulation.end_time={end_time!r}", *extra)
    s, whole = plan.first_contact_summary(sc), simulate(sc).summary
    assert plan.first_contact_end(s) == plan.first_contact_end(whole)
    assert s["contact_episodes"][-1][1] < end_time * 0.75  # the window, not the whole run
    sc = sc.with_overrides("effects=['contact_patch']")  # a plan before the run is the plan the study runs
    assert plan.study_plan(sc).as_dict() == plan.study_plan(sc, whole).as_dict()  # effects: not the analytical model's


def test_a_submodel_shares_its_drivers_bodies_impact_and_cut_only(scene_with):
    """check_driven_scene: the speed, a modulus, the cut length and the model kind must be the driver's (its cut
    record carries that scene's motion); the contact law, the output and a yield strength (the yield check's, not
    the motion's: found refused by a probe) may differ."""
    driver = scene_with()
    for own in ("fe.contact=penalty", "simulation.output_interval=1e-6", "rod1.material.yield_strength=3e9",
                "effects=['contact_patch']", "fe.backend=numpy"):  # fmt: skip
        plan.check_driven_scene(scene_with(own), driver)
    plan.check_driven_scene(scene_with("fe.backend=numpy", "fe.operator=matrix-free"), driver)  # how K is applied
    for key, other in (("impact.speed", "1.0"), ("rod2.material.youngs_modulus", "70e9"),
                       ("fe.submodel_length", "0.01"), ("fe.kind", "'3d'")):  # fmt: skip
        with pytest.raises(SceneError, match=f"'{key}'.*driving global"):
            plan.check_driven_scene(scene_with(f"{key}={other}"), driver)


def test_first_contact_summary_runs_the_whole_scene_when_the_contact_outlasts_the_window(scene_with, monkeypatch):
    """A first contact still open at the window's end (a window of 0.2 round trips here): the whole run decides."""
    from rods.analytical import simulate

    monkeypatch.setattr(plan, "FIRST_CONTACT_ROUND_TRIPS", 0.2)
    sc = scene_with("simulation.end_time=1e-3")
    assert plan.first_contact_summary(sc)["contact_episodes"] == simulate(sc).summary["contact_episodes"]


def test_a_submodel_ends_at_the_contact_phase_its_driver_recorded(scene_with):
    """One rule for the study's submodel stages and workflows/submodel.py: the driver summary's recorded contact
    phase when there is one (not recomputed from a scene that may differ in its outputs), else the scene's driver
    phase; never past the scene's end. A size overriding the level labels the run by it."""
    from rods.fe.submodel import submodel_label

    sc = scene_with()
    assert plan.submodel_end(sc) == plan.driver_phase(sc) == pytest.approx(CONTACT_MARGIN * 203.6e-6, rel=0.01)
    assert plan.submodel_end(sc, {"contact_phase": 1e-4}) == 1e-4
    assert plan.submodel_end(sc, {"contact_phase": None}) == plan.driver_phase(sc)
    assert plan.submodel_end(scene_with("simulation.end_time=5e-5"), {"contact_phase": 1e-4}) == 5e-5
    assert (submodel_label("fine"), submodel_label("fine", 3e-5)) == ("fine", "h=3e-05")


def test_a_plans_analytical_run_records_a_bounded_history(scene_with, monkeypatch):
    """A plan runs the analytical model before any stage's cost check: at a 1e-10 s output interval (1.5e7 samples,
    2 GB) it records at most PLAN_SAMPLES samples over the same end time, and it never records a finer history
    than the scene's; above the free memory it is refused (exit 2) instead of run."""
    from rods import analytical, cost
    from rods.preflight import InputError

    seen = []
    monkeypatch.setattr(analytical, "simulate", lambda sc: seen.append(sc) or SimpleNamespace(summary={}))
    plan.planning_summary(scene_with("simulation.output_interval=1e-10"))
    plan.planning_summary(scene_with())
    fine, plain = seen
    assert fine.end_time == plain.end_time
    assert fine.end_time / fine.output_interval == pytest.approx(plan.PLAN_SAMPLES)
    assert plain.output_interval == scene_with().output_interval  # the paper's 6001 samples: as the scene says
    monkeypatch.setattr(cost, "local_memory", lambda: 1e6)  # [B]
    with pytest.raises(InputError, match="analytical model"):
        plan.planning_summary(scene_with())


def test_levels_no_submodel_would_use_are_refused(scene_with):
    """A bad-input audit (2026-11-29): run.py with submodel.levels and no contact effect ran without them, silently;
    levels all coarser than the global mesh ran submodels that resolve less than their driver. Both refused;
    'auto' and useful levels pass, and where even the ladder's finest is not finer, the plan says so instead."""
    plan.check_levels(scene_with())  # auto, waves
    plan.check_levels(scene_with("effects=['contact_patch']", "submodel.levels=['coarse', 'fine']"))
    with pytest.raises(SceneError, match=r"'submodel.levels' = \['fine'\]: given, but effects = \['wave_response'\]"):
        plan.check_levels(scene_with("submodel.levels=['fine']"))
    with pytest.raises(SceneError, match=r"no level finer than the global mesh .*0.2728 mm.*levels from coarse on"):
        plan.check_levels(scene_with("effects=['contact_patch']", "submodel.levels=['ultra-coarse', 'extra-coarse']"))
    last = SUBMODEL_LEVELS[-1]  # 15 nm: the ladder spans the radial sizes the schema accepts, down to 1e-8 m
    fine_global = scene_with("effects=['contact_patch']", "fe.radial_size=1e-8", f"submodel.levels=['{last}']")
    plan.check_levels(fine_global)  # no level of the ladder is finer: refusing would leave no remedy
    assert "add cost, not resolution" in " ".join(plan.make_plan(fine_global).reasons)
