"""The convergence stage on synthetic levels whose errors are known in closed form (Hertz at the model's own
force, a power law in h), and on the committed submodel record."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rods import compare, hertz
from rods.io import read_data
from rods.paper import convergence

E_STAR, R_STAR = 1.1e11, 0.035  # [Pa], [m]
F_AN = 5555.0  # analytical peak force [N]
H = (0.4e-3, 0.2e-3, 0.1e-3, 0.05e-3, 0.025e-3)  # [m]
NAMES = ("coarse", "mid", "fine", "extra-fine", "ultra-fine")


def record(model, level, h, F, e_a=0.0, e_p=0.0):
    """A level at force F [N] whose radius and peak pressure are Hertz at F times (1 + e); area π a²."""
    Hz = hertz.at_force(F, E_STAR, R_STAR)
    a = Hz["contact_radius"] * (1 + e_a)
    return {
        "model": model,
        "level": level,
        "h": h,
        "peak_contact_force": F,
        "contact_radius": a,
        "contact_area": math.pi * a * a,
        "peak_contact_pressure": Hz["peak_pressure"] * (1 + e_p),
        "contact_radius_edge_mean": a,  # the edge-period mean: here the radius itself
        "contact_area_edge_mean": math.pi * a * a,
    }


def power_records(model="submodel", n=5, p=1.5):
    """Force low by 20 (h/h1)^p %, radius high by 10 (h/h1)^p %, pressure low by 5 (h/h1)^p %."""
    out = []
    for name, h in zip(NAMES[:n], H[:n], strict=True):
        x = (h / H[n - 1]) ** p
        out.append(record(model, name, h, F_AN * (1 - 0.002 * x), e_a=0.001 * x, e_p=-0.0005 * x))
    return out


def test_errors_against_own_force_and_analytical_force():
    """Hertz at the model's own force: zero error for an exact Hertz patch; against the analytical force the
    radius is off by (F/F_an)^(1/3) - 1, the area by (F/F_an)^(2/3) - 1 (Johnson Eq. 4.22)."""
    F = 1.03 * F_AN
    d = convergence.compute([record("global", "g", 1e-3, F)], F_AN, E_STAR, R_STAR)
    lv = d["models"]["global"]["levels"][0]
    assert lv["error_pct"]["peak_contact_force"] == pytest.approx(3.0)
    for q in ("contact_radius", "contact_area", "peak_contact_pressure"):
        assert lv["error_pct"][q] == pytest.approx(0.0, abs=1e-12)
    assert lv["error_vs_analytical_pct"]["contact_radius"] == pytest.approx(100 * (1.03 ** (1 / 3) - 1))
    assert lv["error_vs_analytical_pct"]["contact_area"] == pytest.approx(100 * (1.03 ** (2 / 3) - 1))
    assert d["models"]["global"]["estimates"] is None
    assert any("only 1 level," in f for f in d["models"]["global"]["flags"])


def test_power_law_errors_recovered_and_cancellation_flagged():
    d = convergence.compute(power_records(), F_AN, E_STAR, R_STAR)
    fam = d["models"]["submodel"]
    x = (np.array(H) / H[-1]) ** 1.5
    assert [lv["error_pct"]["peak_contact_force"] for lv in fam["levels"]] == pytest.approx(-0.2 * x)
    assert [lv["error_pct"]["contact_radius"] for lv in fam["levels"]] == pytest.approx(0.1 * x)
    for q in convergence.QUANTITIES:
        e = fam["estimates"][q]["error_pct"]
        assert e["branch"] == "observed order" and e["monotone"] and e["monotone_last3"]
        if q in ("contact_area", "contact_area_edge_mean"):  # (1 + e_a)² - 1 = 2 e_a + e_a²: a power law only
            # to first order; e0 within
            # a tenth of the finest level's error (0.2%)
            assert e["order"] == pytest.approx(1.5, abs=0.1) and e["extrapolated"] == pytest.approx(0.0, abs=0.02)
        else:
            assert e["order"] == pytest.approx(1.5, abs=1e-4) and e["extrapolated"] == pytest.approx(0.0, abs=1e-6)
    assert fam["monotone_last3"]
    # force low, radius and area high against Hertz at their own force: they cancel at every level;
    # the pressure error has the force's sign: it does not. At the finest level the radius error falls below
    # convergence.CANCEL_MIN (0.1%), so the area error (twice it) is the one named at every level
    cancel = [f for f in fam["flags"] if "errors cancel" in f]
    assert len(cancel) == 5 and all("contact area" in f and "peak pressure" not in f for f in cancel)
    assert not any("non-monotone" in f for f in fam["flags"])


def test_non_monotone_level_named_in_flags_and_report():
    recs = power_records(n=4)
    a = recs[1]["contact_radius"] * 1.05  # the mid level's radius jumps above the coarse one
    recs[1] = recs[1] | {"contact_radius": a, "contact_area": math.pi * a * a}
    d = convergence.compute(recs, F_AN, E_STAR, R_STAR)
    e = d["models"]["submodel"]["estimates"]["contact_radius"]["error_pct"]
    assert not e["monotone"] and e["nonmonotone_levels"] == ["mid"] and e["monotone_last3"]
    assert math.isnan(e["extrapolated"])
    md = convergence.render_markdown(d)
    assert "submodel contact radius error and value: non-monotone at mid" in md
    assert "| no (mid) / yes |" in md


def test_three_finest_are_richardson_on_the_committed_record(stages):
    """The committed submodel levels (table3.json, rounded to 6 digits): the three-finest estimate of the force
    is Richardson/GCI, the record's order, and the radius's turn at mid is reported."""
    t3 = stages["table3.json"]
    an = t3["analytical"]
    R_star = R_STAR  # only R*/E* enters a_H: take E* from the analytical contact radius (Johnson Eq. 4.22)
    E_star = 3 * an["peak_contact_force"] * R_star / (4 * an["contact_radius"] ** 3)
    recs = [
        {
            "model": "submodel",
            "level": r["level"],
            "h": r["h_mm"] * 1e-3,
            "peak_contact_force": r["force_N"],
            "contact_radius": r["radius_mm"] * 1e-3,
            "contact_area": r["area_mm2"] * 1e-6,
            "peak_contact_pressure": r["p0_GPa"] * 1e9,
        }
        for r in t3["rows"]
        if r["role"] == "submodel"
    ]
    d = convergence.compute(recs, an["peak_contact_force"], E_star, R_star)
    est = d["models"]["submodel"]["estimates"]
    rich = t3["richardson"]["quantities"]["peak_contact_force"]  # from the unrounded forces
    F = [r["peak_contact_force"] for r in recs]
    rr = compare.richardson(F[3], F[2], F[1], 2.0)
    assert rr.order == pytest.approx(rich["order"], abs=0.01)
    assert est["peak_contact_force"]["value_last3"]["order"] == pytest.approx(rr.order, rel=1e-8)
    assert est["peak_contact_force"]["value_last3"]["uncertainty"] == pytest.approx(rr.error_band, rel=1e-8)
    assert est["contact_radius"]["error_pct"]["nonmonotone_levels"] == ["mid"]
    # 4.09% -> 2.90% -> 0.64%: monotone over the three finest, but the steps grow: no extrapolation claimed
    assert est["contact_radius"]["error_pct_last3"]["branch"] == "diverging"
    flags = d["models"]["submodel"]["flags"]
    assert any("contact radius error: the differences grow" in f and "three finest" in f for f in flags)
    assert "converging there (p > 0): no (contact radius, contact area" in convergence.render_markdown(d)
    area = [lv["error_pct"]["contact_area"] for lv in d["models"]["submodel"]["levels"]]
    assert area == pytest.approx([r["d_area_vs_hertz_pct"] for r in t3["rows"] if r["role"] == "submodel"], rel=1e-4)


def test_write_three_files_and_json_renders_the_same(tmp_path):
    recs = power_records() + power_records("global", n=3, p=1.0)
    d = convergence.write(recs, F_AN, E_STAR, R_STAR, tmp_path / "out")
    files = {p.name: p for p in (tmp_path / "out").iterdir()}
    assert set(files) == {"convergence.json", "convergence.md", "convergence.png"}
    assert (
        files["convergence.png"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        and files["convergence.png"].stat().st_size > 10_000
    )
    assert list(d["models"]) == ["submodel", "global"]
    assert convergence.render_markdown(read_data(files["convergence.json"])) == files["convergence.md"].read_text()
    # three global meshes: the all-level fit is the three-level Richardson/GCI
    g = d["models"]["global"]["estimates"]["peak_contact_force"]
    f = g["value"]["f"]
    rr = compare.richardson(f[2], f[1], f[0], 2.0)
    assert g["value"]["uncertainty"] == pytest.approx(rr.error_band, rel=1e-8)


def test_record_without_a_key():
    r = power_records(n=3)
    del r[0]["contact_area"]
    with pytest.raises(KeyError, match="contact_area"):
        convergence.compute(r, F_AN, E_STAR, R_STAR)


def test_for_scene_measures_against_the_scenes_own_references(tmp_path):
    """The recipe for a scene: E*, R* of its rods and the analytical model's peak force. Levels built as Hertz
    at exactly that force from those constants have zero error on every quantity."""
    from rods.analytical import simulate
    from rods.scene import load_scene

    from ..conftest import PAPER

    sc = load_scene(PAPER, ["impact.speed=1.0", "simulation.end_time=3e-4"])
    F = simulate(sc).summary["peak_contact_force"]  # [N]
    E, R = hertz.contact_constants(sc.rod1, sc.rod2)
    runs = []
    for name, h in zip(NAMES[:3], H[:3], strict=True):
        Hz = hertz.at_force(F, E, R)
        s = {"level": name, "element_size": h, "peak_contact_force": F, "peak_contact_pressure": Hz["peak_pressure"]}
        s |= {"contact_radius": Hz["contact_radius"], "contact_area": Hz["contact_area"]}
        runs.append((name, s))
    d = convergence.for_scene(sc, runs, tmp_path)
    for lv in d["models"]["submodel"]["levels"]:
        assert max(abs(e) for e in lv["error_pct"].values()) < 1e-9
    assert (tmp_path / "convergence.md").is_file()


def test_3d_globals_are_their_own_family():
    """A 3D global mesh is not a level of the axisymmetric series: records carry the kind in the family name."""
    base = {"peak_contact_force": 5555.0, "contact_radius": 1e-3, "contact_area": 3.1e-6, "peak_contact_pressure": 2e9}
    ax = convergence.record({**base, "scene_values": {"fe": {"kind": "axisymmetric", "radial_size": 0.25e-3}}})
    three = convergence.record({**base, "scene_values": {"fe": {"kind": "3d", "radial_size": 1e-3}}}, "global 3d-c")
    assert (ax["model"], ax["level"]) == ("global", "0.25 mm")
    assert (three["model"], three["level"], three["h"]) == ("global 3d", "global 3d-c", 1e-3)


def test_a_family_mixing_coarsened_and_full_far_fields_says_so():
    """A global family whose finer meshes merge their elements across away from the tips (fe.radial_coarsening,
    recorded as the summary's mesh.coarsened) and whose coarsest does not (its elements too wide to merge): the
    flags and the report name both sets, as the main job's global coarse / paper / fine do; a family merged on every
    level, or on none, carries no such note. The record reads the flag from a run's summary."""
    base = {"peak_contact_force": 5555.0, "contact_radius": 1e-3, "contact_area": 3.1e-6, "peak_contact_pressure": 2e9}
    fe = {"scene_values": {"fe": {"kind": "axisymmetric", "radial_size": 0.25e-3}}}
    merged = {"mesh": {"coarsened": [{"from": 0.026, "across": 8}, {"from": 0.026, "across": 8}]}}
    assert (
        convergence.record({**base, **fe, **merged})["coarsened"]
        and not convergence.record({**base, **fe})["coarsened"]
    )
    recs = power_records("global", n=3)
    for coarsened, words in (((False, True, True), "global: mid, fine merged across 3:1"), ((True,) * 3, None),
                             ((False,) * 3, None)):  # fmt: skip
        d = convergence.compute([r | {"coarsened": c} for r, c in zip(recs, coarsened, strict=True)], F_AN, E_STAR,
                                R_STAR)  # fmt: skip
        notes = [f for f in d["models"]["global"]["flags"] if "merged across" in f]
        if words is None:
            assert notes == []
        else:
            assert len(notes) == 1 and notes[0].startswith(words) and "coarse not" in notes[0]
            assert words in convergence.render_markdown(d)


def test_a_two_level_family_renders_from_its_json(tmp_path):
    """Two levels get no estimate; the record read back (null -> NaN, rods.io.read_data) still renders."""
    d = convergence.write(power_records() + power_records("global 3d", n=2), F_AN, E_STAR, R_STAR, tmp_path)
    assert d["models"]["global 3d"]["estimates"] is None
    text = convergence.render_markdown(read_data(tmp_path / "convergence.json"))
    assert "### global 3d (2 levels)" in text and text == (tmp_path / "convergence.md").read_text()


def phase_members(level, h, F, e_area_members, e_p=-0.001):
    """Phase members of one level at force F [N]: areas off Hertz at F by e (the edge scatter), radius √(area/π)."""
    out = []
    for k, e in enumerate(e_area_members):
        r = record("submodel", level, h * (1.02 - 0.01 * k), F, e_a=math.sqrt(1 + e) - 1, e_p=e_p)
        out.append(r | {"phase": None if k == len(e_area_members) // 2 else k})  # the middle one: the level's own
    return out


def test_phase_family_is_the_mean_of_the_members_and_the_plain_family_keeps_the_own_runs():
    """Per level the phase family's values are the members' means at the level's own size; the plain submodel
    family sees the own runs only; the range and standard error are the members' errors'."""
    scat = {"coarse": (-0.02, 0.01, 0.03, -0.01, 0.0), "mid": (-0.01, 0.005, 0.012, -0.006, 0.0)}
    recs = [r for lv, e in scat.items() for r in phase_members(lv, H[NAMES.index(lv)], F_AN, e)]
    recs += phase_members("fine", H[2], F_AN, (-0.004, 0.002, 0.005, -0.003, 0.0))
    d = convergence.compute(recs, F_AN, E_STAR, R_STAR)
    plain, fam = d["models"]["submodel"], d["models"][convergence.PHASE_FAMILY]
    assert [lv["h"] for lv in plain["levels"]] == [lv["h"] for lv in fam["levels"]] == list(H[:3])
    assert [lv["error_pct"]["contact_area"] for lv in plain["levels"]] == pytest.approx([3.0, 1.2, 0.5])
    for lv, e in zip(fam["levels"], (*scat.values(), (-0.004, 0.002, 0.005, -0.003, 0.0)), strict=True):
        assert lv["members"] == 5
        assert lv["error_pct"]["contact_area"] == pytest.approx(100 * np.mean(e), abs=1e-9)
        assert lv["spread_pct"]["contact_area"] == pytest.approx([100 * min(e), 100 * max(e)])
        assert lv["standard_error_pct"]["contact_area"] == pytest.approx(100 * np.std(e, ddof=1) / math.sqrt(5))
        assert lv["error_pct"]["peak_contact_pressure"] == pytest.approx(-0.1)


def phase_study(fine_mean):
    """Three levels of five phase members each, ±0.03 points about area errors of 1.0, 0.5 and ``fine_mean``
    (fractions), through :func:`convergence.compute`."""
    recs = []
    for name, h, mean in zip(NAMES, H, (0.01, 0.005, fine_mean), strict=False):
        recs += phase_members(name, h, F_AN, [mean + x for x in (0.0003, -0.0003, 0.0002, -0.0002, 0.0)])
    return convergence.compute(recs, F_AN, E_STAR, R_STAR)


def test_phase_family_turn_is_weighed_against_the_members_scatter():
    """A turn smaller than twice the combined standard error of the two means is called scatter; a larger one is
    not. Members ±0.03 points about means of 1.0, 0.5 and then 0.51 or 0.8 %."""

    def flags(fine_mean):
        return phase_study(fine_mean)["models"][convergence.PHASE_FAMILY]["flags"]

    small = [f for f in flags(0.0051) if f.startswith("submodel (phase mean) contact area error")]
    assert len(small) == 1 and "at mid the smaller step is 0.010 points" in small[0]
    assert "within the members' scatter" in small[0]
    large = [f for f in flags(0.008) if f.startswith("submodel (phase mean) contact area error")]
    assert len(large) == 1 and "larger than the members' scatter" in large[0]


def test_a_single_mesh_turn_is_weighed_against_one_meshs_scatter_over_its_phase_members():
    """The plain family's levels are single meshes (the middle member, offset 0): a turn there is judged against
    the two meshes' standard deviations over their phase members, not the means' standard errors, and a level
    without members (no scatter) is left out. Members spread ±0.3 points; own runs 1.0, 0.5, 0.51 or 0.8 %."""

    def plain_flag(fine_mean, spread=0.003):
        recs = []
        for name, h, mean in zip(NAMES, H, (0.01, 0.005, fine_mean), strict=False):
            recs += phase_members(name, h, F_AN, [mean + x for x in (spread, -spread, 0.7 * spread, -0.7 * spread, 0)])
        d = convergence.compute(recs, F_AN, E_STAR, R_STAR)
        fine = d["models"]["submodel"]["levels"][2]
        sd = d["models"][convergence.PHASE_FAMILY]["levels"][2]["standard_deviation_pct"]["contact_area"]
        assert fine["snapshot_sd_pct"]["contact_area"] == pytest.approx(sd)
        flags = [f for f in d["models"]["submodel"]["flags"] if f.startswith("submodel contact area error")]
        return flags[0] if flags else ""

    small = plain_flag(0.0051)
    assert "at mid the smaller step is 0.010 points" in small
    assert "under 2 x that, within a single mesh's scatter" in small
    assert "larger than a single mesh's scatter" in plain_flag(0.0051, spread=0.00001)
    levels = [{"level": n, "error_pct": {"a": e}} for n, e in zip(NAMES, (1.0, 0.5, 0.51), strict=False)]
    assert convergence.turns_vs_scatter(levels, "a", ["mid"]) == []  # no members: no scatter claimed


def test_a_two_level_family_whose_error_grows_says_so_and_a_small_offset_is_no_cancelling():
    """Two levels (the 3D globals): an error that grows from the coarser to the finer is said, not left to "no
    convergence estimate" (+11.0% -> +12.9% radius: an audit, 2026-12-07); a force error that moves a large own-force
    error by less than a tenth of it is no "errors cancel" (-0.49% against +11.01% -> +10.83% had been said to)."""
    recs = [
        record("global 3d", "3d-coarse", 1e-3, F_AN * (1 - 0.0049), e_a=0.110),
        record("global 3d", "3d-medium", 0.7e-3, F_AN * (1 - 0.0015), e_a=0.129),
    ]
    flags = convergence.compute(recs, F_AN, E_STAR, R_STAR)["models"]["global 3d"]["flags"]
    assert any(f.startswith("global 3d contact radius error grows under refinement (+11.00% at") for f in flags)
    assert not any("errors cancel" in f for f in flags), flags
    swapped = list(reversed([dict(r, h=h) for r, h in zip(recs, (0.7e-3, 1e-3), strict=True)]))  # error shrinks
    shrinking = convergence.compute(swapped, F_AN, E_STAR, R_STAR)["models"]["global 3d"]["flags"]
    assert not any("grows under refinement" in f and "contact radius" in f for f in shrinking)
