"""The study's recipe, defined once in the library (rods.plan, rods.compare): mesh-free unit tests."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rods import compare, cost, hertz
from rods.analytical import simulate
from rods.plan import (
    CONTACT_MARGIN,
    DRIVER_OVERRIDES,
    MISALIGNMENT_KEYS,
    contact_phase,
    first_contact_end,
    global_drives,
    make_plan,
    most_refined,
    offers,
    submodel_driver,
)
from rods.scene import BAR_ELEMENTS, SUBMODEL_LEVEL_SIZES, SUBMODEL_LEVELS

SHORT_STRIKER = (  # a short steel striker on a long aluminium rod: several contact episodes
    "rod1.length=0.092",
    "rod1.tip_radius=100.0",
    "rod2.length=0.83",
    "rod2.material.youngs_modulus=70e9",
    "rod2.material.density=2700.0",
    "simulation.end_time=1.2e-3",
)


def test_contact_phase_is_the_first_episode_with_margin(scene_with):
    """Repeated impacts: the contact phase ends CONTACT_MARGIN x the *first* episode's end, not the last's."""
    sc = scene_with(*SHORT_STRIKER)
    s = simulate(sc).summary
    episodes = s["contact_episodes"]
    assert len(episodes) >= 3
    assert first_contact_end(s) == episodes[0][1]
    assert contact_phase(s, sc.end_time) == pytest.approx(CONTACT_MARGIN * episodes[0][1], rel=1e-15)
    assert contact_phase(s, sc.end_time) < CONTACT_MARGIN * episodes[-1][1]  # not the last episode's
    p = make_plan(sc.with_overrides("effects=['contact_patch']"), first_contact_end(s))
    assert p.contact_phase == p.global_end_time == contact_phase(s, sc.end_time)
    # no contact: the whole run; a contact ending near the end: capped by the end time
    assert contact_phase({"contact_episodes": []}, 1e-3) == 1e-3
    assert contact_phase({"contact_episodes": [[0.0, 0.9e-3]]}, 1e-3) == 1e-3


def test_submodel_driver_is_the_scene_itself_to_the_contact_phase(scene_with):
    """No special global settings drive a submodel (issue 13): the driver is the scene's own global."""
    sc = scene_with("impact.speed=1.848", "fe.axial_size=2e-3", "fe.contact='penalty'")
    d = submodel_driver(sc, 2.5e-4)
    assert DRIVER_OVERRIDES == () and d.end_time == 2.5e-4
    assert {k: v for k, v in d.values.items() if k != "simulation.end_time"} == {
        k: v for k, v in sc.values.items() if k != "simulation.end_time"
    }
    assert submodel_driver(sc).end_time == sc.end_time
    # an output interval longer than the phase the library chose: the phase's, not a refusal of the user's value
    coarse = sc.with_overrides("simulation.output_interval=1e-3")
    assert submodel_driver(coarse, 2.5e-4).output_interval == 2.5e-4 and d.output_interval == sc.output_interval
    p = make_plan(sc.with_overrides("effects=['contact_patch']"), 2e-4)
    assert p.driver_overrides == DRIVER_OVERRIDES
    assert "submodel driver: the global above, recording the cut until t = 240.0 µs" in p.describe()
    assert global_drives(p)  # the study runs the global once and drives the submodels with it
    assert make_plan(sc, 2e-4).driver_overrides == ()  # wave response only: no submodel, no driver
    assert not global_drives(make_plan(sc, 2e-4))


def _summary(F: float, a: float = 1e-3, speed: float = 1.1) -> dict:
    return {
        "peak_contact_force": F,
        "contact_radius": a,
        "contact_area": math.pi * a * a,
        "peak_contact_pressure": 2e9,
        "contact_duration": 2e-4 + F * 1e-12,
        "midpoint_peak_speed": speed,
        "midpoint_peak_strain": -1e-4,
    }


def test_plan_says_when_no_submodel_level_is_finer_than_the_global(scene_with):
    """ "auto" finds three levels wherever the ladder reaches (it ends at 15 nm: the paper scene at 0.5 µm/s, its
    global 0.49 µm, gets ultra-fine-x16 to x64, 0.98 to 0.24 µm); past its end (1 µm rods at 1 mm/s, a
    global of 0.5 nm) no submodel runs and the plan says so. On the paper scene it says nothing, nor for coarse levels
    given by hand under a coarser global."""
    slow = scene_with("impact.speed=5e-7", "effects=['contact_patch']")
    assert slow["submodel.levels"] == ["ultra-fine-x16", "ultra-fine-x32", "ultra-fine-x64"]
    assert not any("no submodel level" in r for r in make_plan(slow, 2e-4).reasons)
    tiny = scene_with(*(f"rod{n}.diameter=1e-6" for n in (1, 2)), "rod1.length=1e-5", "rod2.length=2e-5",
                      "rod1.tip_radius=3e-6", "impact.speed=1e-3", "effects=['contact_patch']")  # fmt: skip
    assert tiny["submodel.levels"] == [] and tiny.radial_size < SUBMODEL_LEVEL_SIZES[SUBMODEL_LEVELS[-1]]
    assert any("no submodel runs" in r for r in make_plan(tiny, 1e-8).reasons)
    paper = scene_with("effects=['contact_patch']")
    assert not any("no submodel level" in r for r in make_plan(paper, 2e-4).reasons)
    coarse = scene_with("effects=['contact_patch']", "submodel.levels=['coarse']", "fe.radial_size=1e-3")
    assert not any("no submodel level" in r for r in make_plan(coarse, 2e-4).reasons)
    assert any(
        "no submodel level" in r for r in make_plan(coarse.with_overrides("fe.radial_size=0.2e-3"), 2e-4).reasons
    )


def test_most_refined_model_wins(scene_with):
    stages = {
        "submodel/fine": _summary(3.0),
        "analytical": _summary(0.0, speed=1.0),
        "driver": _summary(9.0),  # drives the submodels: offers nothing
        "submodel/coarse": _summary(2.0),
        "global": _summary(1.0, speed=1.2),
    }
    contact = make_plan(scene_with("effects=['contact_patch']"), 2e-4)
    values, sources = most_refined(contact, stages)
    assert values["peak_contact_force"] == 3.0 and sources["contact_radius"] == "submodel/fine"
    assert sources["contact_duration"] == "global"  # a submodel's run is cut at the contact phase
    assert sources["midpoint_peak_speed"] == "analytical" and values["midpoint_peak_speed"] == 1.0
    wave = make_plan(scene_with("effects=['wave_response']"), 2e-4)
    values, sources = most_refined(wave, {k: stages[k] for k in ("analytical", "global")})
    assert sources["midpoint_peak_speed"] == "global" and values["peak_contact_force"] == 1.0
    # no submodel resolves the patch: its radius, area and pressure are the analytical model's Hertz
    assert {sources[k] for k in ("contact_radius", "contact_area", "peak_contact_pressure")} == {"analytical"}
    values, sources = most_refined(wave, {"analytical": stages["analytical"]})
    assert set(sources.values()) == {"analytical"}
    # a misalignment study: the 3D global's centroid, farthest contact node and bending strain, which no centric
    # model has (a fuzz's misalignment study summarised none of them)
    mis = make_plan(scene_with("effects=['misalignment']", "fe.kind='3d'", "impact.offset=2e-3"), 2e-4)
    extra = dict(zip(MISALIGNMENT_KEYS, (1.97e-3, 0.0, 1.1e-3, 2.1e-4), strict=True))
    values, sources = most_refined(mis, {"analytical": stages["analytical"], "global": {**stages["global"], **extra}})
    assert {k: values[k] for k in MISALIGNMENT_KEYS} == extra and {sources[k] for k in MISALIGNMENT_KEYS} == {"global"}
    assert not set(MISALIGNMENT_KEYS) & set(most_refined(wave, {k: stages[k] for k in ("analytical", "global")})[0])
    # by the element size across the contact, not by the stage's name: on 1 mm rods with a 5 mm tip the global's
    # auto mesh (0.025 mm) is finer than the fine submodel level (0.0625 mm), which then is not the answer
    sized = {
        k: {**v, "mesh": {"radial_size": h}}
        for (k, v), h in zip(stages.items(), (6.25e-5, 0, 0, 2.5e-4, 2.5e-5), strict=True)
    }
    values, sources = most_refined(contact, sized)
    assert sources["contact_radius"] == "global" and values["peak_contact_force"] == 1.0
    sized["global"]["mesh"]["radial_size"] = 6.25e-5  # a tie: the submodel
    assert most_refined(contact, sized)[1]["contact_radius"] == "submodel/fine"
    assert offers(contact, "driver") == () and "contact_duration" not in offers(contact, "submodel/fine")
    assert "midpoint_peak_speed" in offers(wave, "global") and "midpoint_peak_speed" not in offers(contact, "global")
    # a fields study's global runs the whole end time too: its midpoint, not the analytical model's (a docs audit)
    fields = make_plan(scene_with("effects=['contact_patch', 'fields']"), 2e-4)
    assert fields.global_end_time == scene_with().end_time and "midpoint_peak_speed" in offers(fields, "global")


def test_level_sizes_are_one_table_halving_per_level():
    """One ladder of halvings through the paper's coarse/mid/fine, spanning the element sizes the schema accepts:
    64 mm (a 1 m rod's radius / BAR_ELEMENTS is 62.5 mm) down to 15 nm (fe.radial_size >= 1e-8 m)."""
    paper = ("coarse", "mid", "fine", "extra-fine", "ultra-fine")
    coarse = (*(f"ultra-coarse-x{2**k}" for k in range(6, 0, -1)), "ultra-coarse", "extra-coarse")
    fine = tuple(f"ultra-fine-x{2**k}" for k in range(1, 11))  # below the paper's ladder: small rods' patches
    assert SUBMODEL_LEVELS == tuple(SUBMODEL_LEVEL_SIZES) == (*coarse, *paper, *fine)
    h = list(SUBMODEL_LEVEL_SIZES.values())
    assert SUBMODEL_LEVEL_SIZES["coarse"] == 0.25e-3 and all(a / b == 2.0 for a, b in zip(h, h[1:], strict=False))
    assert h[0] >= 0.5 / BAR_ELEMENTS and 1e-8 <= h[-1] < 2e-8


def test_richardson_takes_the_three_finest_levels_with_constant_ratio():
    sizes = {lv: SUBMODEL_LEVEL_SIZES[lv] for lv in ("fine", "coarse", "extra-fine", "mid")}
    assert compare.richardson_levels(sizes) == (("mid", "fine", "extra-fine"), 2.0)
    assert compare.richardson_levels({k: sizes[k] for k in ("coarse", "mid")}) is None
    assert compare.richardson_levels({"a": 4e-4, "b": 2e-4, "c": 0.5e-4}) is None  # ratios 2 and 4


def test_sigma_r_error_band_and_normalisation():
    """Hertz itself has zero error; an error within ±0.2 a of the edge is ignored; elsewhere it counts
    relative to |σ_r,H(0)| = (1 + 2ν)/2 p0."""
    F, E_star, R_star, nu = 5.5e3, 112e9, 0.035, 0.3  # [N], [Pa], [m], [-]
    H = hertz.at_force(F, E_star, R_star)
    a, p0 = H["contact_radius"], H["peak_pressure"]
    r = np.linspace(0.01, 2.5, 250) * a
    z = np.full_like(r, 1e-6)  # [m] sample depth
    σ = hertz.subsurface_stresses(r, z, a, p0, nu)[0]
    prof = {"r": r, "depth": z, "sigma_r": σ}
    e = compare.sigma_r_error(prof, H, nu)
    assert e["depth"] < 1e-12 and e["gauss_depth"] == pytest.approx(1e-6)
    assert 0 < e["surface"] < 0.05  # 1 µm below the surface: close to the surface closed form
    ref = (1 + 2 * nu) / 2 * p0
    near_edge = np.abs(r - a) < compare.SIGMA_EDGE_BAND * a
    bumped = σ + np.where(near_edge, 0.5 * ref, 0.0)
    assert compare.sigma_r_error({**prof, "sigma_r": bumped}, H, nu)["depth"] < 1e-12
    k = int(np.argmin(np.abs(r - 0.5 * a)))
    bumped = σ.copy()
    bumped[k] += 0.03 * ref
    assert compare.sigma_r_error({**prof, "sigma_r": bumped}, H, nu)["depth"] == pytest.approx(0.03, rel=1e-9)


def test_fe_level_sizes_are_the_scene_table():
    """rods.fe.submodel.LEVEL_SIZES (the FE side's name) is the one table of rods.scene."""
    import rods.fe  # noqa: F401 (loads the wheel's DOLFINx first)
    from rods.fe.submodel import LEVEL_SIZES

    assert LEVEL_SIZES == SUBMODEL_LEVEL_SIZES and tuple(LEVEL_SIZES) == SUBMODEL_LEVELS


def test_the_study_names_a_yield_warning_once_from_its_pressure_source(scene_with):
    """Every stage's summary keeps its yield warning (Hertz's p0 at its own force); the study's status lists it
    once, from the stage its peak pressure comes from, not once per model (five near-copies before)."""
    from mpi4py import MPI

    from rods.study.pipeline import _status
    from rods.study.stages import Stage

    from ..conftest import ROOT

    sc = scene_with("effects=['contact_patch']", "submodel.levels=['coarse', 'mid']")
    p = make_plan(sc, 2e-4)
    done = {}
    for k, p0 in (("analytical", 2691.5), ("driver", 2692.0), ("submodel/coarse", 2691.8), ("submodel/mid", 2691.7)):
        w = f"Hertz peak pressure at rods 1 and 2 at the model's peak force, p0 = {p0} MPa, exceeds 1.1 S_y"
        done[k] = Stage(k, ROOT, sc, {"warnings": [w, f"{k}-own"], "yield_warnings": [w]})
    status = _status(p, done, None, MPI.COMM_SELF, "submodel/mid")
    yields = [w for w in status["warnings"] if "Hertz peak pressure" in w]
    assert yields == [f"submodel/mid: {done['submodel/mid'].summary['yield_warnings'][0]}"]
    assert [w for w in status["warnings"] if w.endswith("-own")] == [f"{k}: {k}-own" for k in done]
    assert len(_status(p, done, None, MPI.COMM_SELF)["warnings"]) == 8  # no source: every stage's


def test_a_fresh_study_forgets_the_stage_summaries_an_earlier_run_left(scene_with, tmp_path):
    """A study started afresh removes its planned FE stages' summary.json first, so a run killed before it
    rewrote them leaves nothing for --restart to keep from the earlier run; other folders stay."""
    from mpi4py import MPI

    from rods.study.pipeline import _forget_stages

    p = make_plan(scene_with("effects=['contact_patch']", "submodel.levels=['coarse', 'mid']"), 2e-4)
    folders = ("analytical", "global", "driver", "submodel/coarse", "submodel/mid", "submodel/fine")
    for f in folders:
        (tmp_path / f).mkdir(parents=True)
        (tmp_path / f / "summary.json").write_text("{}")
    _forget_stages(p, tmp_path, MPI.COMM_SELF, shared=True)
    left = {f for f in folders if (tmp_path / f / "summary.json").exists()}
    assert left == {"analytical", "driver", "submodel/fine"}  # not planned here (shared: no driver folder)


def test_stage_costs_are_the_stages_the_plan_runs(scene_with):
    """rods.study.pipeline.stage_costs: one cost per FE stage run_study runs, and one for the products it makes from
    them. Wave and contact effects: the global records the cut (no second driving global, rods.plan.global_drives),
    then each level, a finer level dearer, then Table 3 and Fig. 4; contact alone: the same stages, the global to the
    contact phase only, Table 3; wave alone: the global to the end, Fig. 4."""
    from rods.study.pipeline import stage_costs

    def costs(effects, levels="['coarse', 'mid']"):
        s = scene_with(f"effects={effects}", f"submodel.levels={levels}")
        return stage_costs(s, make_plan(s, first_contact_end(simulate(s).summary)), 2)

    both, contact, wave = (
        costs("['wave_response', 'contact_patch']"),
        costs("['contact_patch']"),
        costs("['wave_response']"),
    )
    fe = ["the global", "the submodel coarse", "the submodel mid"]
    assert [c.what for c in both] == [*fe, "the comparison and the wave figure"]
    assert [c.what for c in contact] == [*fe, "the comparison"]
    assert [c.what for c in wave] == ["the global", "the wave figure"]
    products = cost.PRODUCT_SECONDS
    assert both[-1].wall_time == products["the comparison"] + products["the wave figure"] and not both[-1].dofs
    assert "cost of the comparison: wall time about" in contact[-1].describe()
    assert both[2].dofs > both[1].dofs and all(c.ranks == 2 for c in both)
    assert contact[0].steps < 0.5 * both[0].steps == 0.5 * wave[0].steps  # the paper scene's 1.5 ms vs ~0.25 ms
