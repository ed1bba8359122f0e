"""REPORT.md from the stage JSON only: tables as the stages render them, prose that follows the data."""

from __future__ import annotations

import subprocess
import sys

from rods.io import read_data, write_data
from rods.paper import accuracy_cost, report
from rods.study import fig4
from tests.conftest import ROOT


def render(stages: dict) -> str:
    return report.render(
        report.ReportData(
            stages["table2.json"], stages["table3.json"], stages["fig4.json"], stages["accuracy-cost.json"],
            stages["contact-study.json"],
        )
    )  # fmt: skip


def test_cli_reads_only_json_and_defaults_to_the_folder_of_out(results):
    """The folder holds no markdown and no CSV: the report needs none."""
    out = results / "REPORT.md"
    p = subprocess.run(
        [
            sys.executable,
            "workflows/report.py",
            "--out",
            str(out),
            "--contact-study",
            str(results / "contact-study.json"),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stderr
    text = out.read_text()
    assert "\n".join(fig4.render_table(report.read(results).fig4)) in text
    assert "\n".join(accuracy_cost.render_table(report.read(results).accuracy_cost)) in text
    row = report.read(results, results / "contact-study.json").contact_study["rows"][0]  # the contact study
    assert f"{row['scene']}, kinematic: {row['duration_vs_analytical'] * 1e6:+.2f} µs" in text


def test_stages_of_another_scene_or_a_table_without_its_global_are_refused(results):
    """A fuzz (2026-12-06): a 1 m/s fig4.json among the paper's stages rendered as the paper's ("as the paper
    found"), and a compare.py table written without --global-uniform crashed the report (StopIteration, exit 1).
    Both are bad input now: exit 2, one line naming --results and the files."""
    fig4_data = read_data(results / "fig4.json")
    write_data(results / "fig4.json", {**fig4_data, "impact_speed": 1.0})
    cmd = [sys.executable, "workflows/report.py", "--out", str(results / "REPORT.md")]
    p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1, p.stderr
    assert "different impact speeds (table3.json 2.197 m/s, fig4.json 1 m/s" in lines[0] and "--results" in lines[0]
    write_data(results / "fig4.json", fig4_data)
    t3 = read_data(results / "table3.json")
    write_data(results / "table3.json", {**t3, "rows": [r for r in t3["rows"] if r["role"] != "global-uniform"]})
    p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    assert p.returncode == 2 and "no 'global-uniform' row" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert not (results / "REPORT.md").exists()


def test_paper_numbers_in_the_prose_follow_the_data(stages):
    before = render(stages)
    before_phrases = (
        "5219 -> 5368 -> 5492 N, -5.8% to -0.9%", "paper: +0.1%)", "(the paper's global model: area +24%",
        "Table 3's analytical 5,543 N", "(the paper: -4.9% to -1.7%)", "-1.25% from the paper's 1.105",
    )  # fmt: skip
    assert all(p in before for p in before_phrases)
    paper = stages["table3.json"]["paper"]
    paper["fine"]["force"] = 5543.0  # as the analytical force: 0.0%
    paper["global-uniform"]["area"] = paper["analytical"]["area"] * 1.5
    paper["global-uniform"]["force"] = paper["analytical"]["force"] * 1.01
    t2 = stages["table2.json"]
    t2["paper_analytical_force"] = 5000.0
    next(r for r in t2["trials"] if r["name"] == "trial-2-4")["paper_radius"] = 1.143e-3  # = experiment
    next(r for r in t2["trials"] if r["name"] == t2["fe_trial"])["paper_peak_speed"] = 1.2
    after = render(stages)
    after_phrases = (
        "5219 -> 5368 -> 5543 N, -5.8% to +0.0%", "paper: +1.0%)", "(the paper's global model: area +50%",
        "Table 3's analytical 5,000 N", "(the paper: -3.2% to +0.0%)", "-9.06% from the paper's 1.200",
    )  # fmt: skip
    assert [p for p in after_phrases if p not in after] == []
    assert not any(p in after for p in before_phrases)


def test_measured_numbers_follow_the_data(stages):
    stages["fig4.json"]["runs"][0]["duration_vs_analytical"] = 3.5e-6
    stages["contact-study.json"]["rows"][0]["duration_vs_analytical"] = -7.5e-6
    sub = [r for r in stages["table3.json"]["rows"] if r["role"] == "submodel"][-1]
    sub["d_area_vs_hertz_pct"] = 0.42
    stages["table3.json"]["richardson"]["quantities"]["plateau_radius_error_pct"]["vs_hertz_pct"] = 0.33
    text = render(stages)
    assert "global, paper mesh: +3.50 µs" in text and "kinematic: -7.50 µs" in text
    assert "midpoint strain (RMS difference at most" in text  # the record: within 10 µε
    for r in stages["fig4.json"]["runs"]:
        r["strain_rms_difference"] = 13.9e-6
    assert "the midpoint strain differs by up to 13.9 µε RMS" in render(stages)
    assert "the area is +0.42%" in text and "gives 0.33%" in text


def test_richardson_sentence_when_nothing_extrapolates(stages, tmp_path):
    q = stages["table3.json"]["richardson"]["quantities"]
    q["plateau_radius_error_pct"]["extrapolated"] = float("nan")
    q["contact_radius"]["order"] = float("nan")
    text = render(stages)
    assert "does not apply (observed order none: non-monotone)" in text
    write_data(tmp_path / "t3.json", stages["table3.json"])  # NaN survives as null and back
    assert "does not apply" in report._richardson_text(read_data(tmp_path / "t3.json")["richardson"])


def test_no_richardson_when_the_comparison_has_none(stages, tmp_path):
    stages["table3.json"]["richardson"] = None
    write_data(tmp_path / "t3.json", stages["table3.json"])
    stages["table3.json"] = read_data(tmp_path / "t3.json")
    assert "Richardson" not in render(stages)


def test_verification_section_follows_the_matrix(stages):
    """The verification paragraph counts the cases that meet every target and names each miss."""
    import json

    from tests.conftest import ROOT

    v = json.loads((ROOT / "results" / "verification.json").read_text())
    data = report.ReportData(
        stages["table2.json"], stages["table3.json"], stages["fig4.json"], stages["accuracy-cost.json"],
        stages["contact-study.json"], verification=v,
    )  # fmt: skip
    for r in v["rows"]:
        r["passes"] = {"peak_force": True, "duration": True, "energy": True}
    v["rows"][0]["passes"]["duration"] = False
    v["rows"][0]["duration_difference"] = 4.25e-6
    v["rows"][0]["duration_gap_is_model_form"] = False
    text = report.render(data)
    n = len(v["rows"])
    assert f"{n - 1} of {n} cases meet every target" in text
    assert f"{v['rows'][0]['description']}: Δ duration +4.25 µs" in text
    assert "does not attribute the duration misses" in text  # no mesh check in the row
    v["rows"][0].update(
        duration_gap_is_model_form=True, duration_mesh_change=-0.09e-6, mesh_check=2.0, strain_lag=-2.6e-6
    )
    text = report.render(data)
    assert "1 of these duration gaps are the analytical model's form" in text
    assert "at most 0.09 µs on a mesh 2 x finer" in text and "leads by -2.6 to -2.6 µs" in text
    for r in v["rows"]:  # a matrix without the paper's law as a second reference: no paragraph on it
        r.pop("paper_law", None)
    assert "Against the paper's law" not in report.render(data)
    for k, r in enumerate(v["rows"]):  # the second reference: every case 3 µs off but one within 0.3 µs
        ok = k == 1
        r["strain_rms"], r["contact_law"] = 3e-6, "hertz-rod"
        r["paper_law"] = {"duration_difference": 0.3e-6 if ok else 3.5e-6, "peak_force_pct": 0.05,
                          "strain_lag": -2.5e-6, "strain_rms": 12e-6,
                          "passes": {"peak_force": True, "duration": ok, "energy": True}}  # fmt: skip
    text = report.render(data)
    assert 'The reference is the default `analytical.contact = "hertz-rod"`' in text
    assert f"meet every target in 1 of {n} cases: durations up to 3.50 µs apart" in text
    assert "(with the correction: within 4.25 µs)" in text
    assert "strain RMS 12.0 to 12.0 µε (with the correction: 3.0 to 3.0 µε)" in text
    assert "verification" not in render(stages).lower()  # no matrix, no section


def test_driver_sentence_follows_the_driver_study(stages):
    """The cut-driving sentence quotes the finest level of the driver study and names the driving whose worst
    error over both globals is smallest (or, with one global, the closer one)."""
    rows = []
    for level, scale in (("coarse", 2.0), ("fine", 1.0)):
        for g, s, d, e in (
            ("kinematic", "kinematic", "displacement", 0.0004),
            ("kinematic", "kinematic", "mixed", 0.0005),
            ("penalty", "kinematic", "displacement", 0.06),
            ("penalty", "kinematic", "mixed", -0.0004),
        ):
            rows.append(
                {"global": g, "submodel": s, "driving": d, "level": level, "peak_force_vs_analytical": e * scale}
            )
    ds = {"rows": rows}
    t = report.driver_text(ds)
    assert "fine level" in t and "displacement +0.04%, mixed +0.05%" in t
    assert "displacement +6.00%, mixed -0.04%" in t and "mixed driving is the closest (0.05% at most)" in t
    one = {"rows": [r for r in rows if r["global"] == "kinematic"]}
    assert "displacement driving is the closer" in report.driver_text(one)
    assert report.driver_text(None) == "" and "driver-study" not in render(stages)


def test_fig4_strain_text_quotes_the_other_contact_law():
    """The Fig. 4 text quotes the same FE strain against the analytical model with the contact law that Fig. 4's
    reference does not use, from the verification matrix's paper row, and says which law the reference has."""
    import copy
    import json

    from tests.conftest import ROOT

    f4 = json.loads((ROOT / "results" / "fig4.json").read_text())
    row = {"case": "paper", "contact_law": "hertz-rod", "strain_rms": 3.17e-6, "strain_lag": 0.12e-6,
           "paper_law": {"contact_law": "hertz", "strain_rms": 13.9e-6, "strain_lag": -2.57e-6}}  # fmt: skip
    plain = "\n".join(report.fig4_section(f4, None))
    assert "half-space" not in plain
    f4["analytical"]["contact_law"] = "hertz"  # the paper's model (Table 2's trial run)
    text = "\n".join(report.fig4_section(f4, None, {"rows": [row]}))
    assert "The reference is the paper's model" in text
    # the verification's paper case, named as such: not Fig. 4's mesh (an audit: "the same FE strain" read as one run)
    assert (
        '(`analytical.contact = "hertz-rod"`) the verification\'s paper case (the global at its default mesh, not '
        "this figure's) differs by 3.2 µε RMS, lag +0.12 µs" in text
    )
    rod = copy.deepcopy(f4)
    rod["analytical"]["contact_law"] = "hertz-rod"
    text = "\n".join(report.fig4_section(rod, None, {"rows": [row]}))
    assert 'The reference carries the rods\' end correction (`analytical.contact = "hertz-rod"`)' in text
    assert "not this figure's) differs by 13.9 µε RMS, lag -2.57 µs" in text


def test_edge_scatter_sentence_quotes_each_levels_band():
    """The convergence section quotes, per level, the band of the radius, area and peak-pressure errors over the
    sizes around it (benchmarks/edge_scatter.py), and says the non-monotone radius is that scatter."""
    rows = [
        {"level": lv, "h": h, "errors": {"radius_peak": e, "radius_loading_mean": e / 2, "area": 2 * e,
                                          "peak_pressure": p}}
        for lv, h, e, p in (("mid", 1.2e-4, -0.002, -0.017), ("mid", 1.25e-4, 0.0037, -0.0155),
                            ("fine", 6e-5, -0.0018, -0.0083), ("fine", 5.8e-5, 0.0105, -0.0074))
    ]  # fmt: skip
    text = report.edge_scatter_text({"levels": ["mid", "fine"], "spread": [0.93, 1.0, 1.07], "rows": rows})
    assert "mid: radius -0.20% to +0.37%, area -0.40% to +0.74%, peak pressure -1.70% to -1.55%" in text
    assert "fine: radius -0.18% to +1.05%" in text and "from 0.93 to 1.07 x a level's" in text
    assert "non-monotone radius and area" in text


def test_phase_mean_paragraph_follows_the_phase_family():
    """The paragraph quotes the phase family's series and says whether the last step is within the members'
    scatter, from the convergence data; absent without phase members."""
    from rods.paper import convergence
    from tests.paper.test_convergence import E_STAR, F_AN, R_STAR, H, phase_members
    from tests.paper.test_convergence import phase_study as conv

    mono = report.phase_mean_text(conv(0.002))
    assert "+1.000% / +0.500% / +0.200%" in mono and "monotone over the three finest levels" in mono
    turn = report.phase_mean_text(conv(0.0051))
    assert "not strictly monotone" in turn and "stopped changing" in turn
    jump = report.phase_mean_text(conv(0.008))
    assert "more than the members' scatter explains" in jump
    plain = convergence.compute([r for r in phase_members("fine", H[2], F_AN, [0.0] * 5) if r["phase"] is None],
                                F_AN, E_STAR, R_STAR)  # fmt: skip
    assert convergence.PHASE_FAMILY not in plain["models"]


def test_edge_mean_paragraph_says_when_the_trend_itself_turns():
    """The edge-period paragraph quotes the submodel series and, where the phase means turn by more than the
    members' scatter, says the approach itself is non-monotone; not where they are monotone."""
    from tests.paper.test_convergence import phase_study as conv

    smooth = report.edge_mean_text(conv(0.002))
    assert "area +1.020% / +0.520% / +0.220%" in smooth and "monotone over the three finest" in smooth
    assert "turn by more than" not in smooth
    assert "turn by more than the members' scatter" in report.edge_mean_text(conv(0.008))


def test_a_gci_narrower_than_the_edge_scatter_is_said_to_be_bounded_by_it():
    """The Richardson sentence quotes the edge scatter where it is wider than the GCI band (a GCI of ±0.04 points
    beside a scatter of ±0.1 at the fine level: an audit, 2026-12-07); none where the scatter is within it."""
    scatter = {"rows": [{"level": "fine", "errors": {"radius_loading_mean": e}} for e in (-0.0019, 0.0002, -0.0005)]}
    wide = report._beside_scatter(scatter, ["fine", "extra-fine"], "radius_loading_mean", 0.04)
    assert "from -0.19% to +0.02%" in wide and "±0.10 points, wider than the GCI's" in wide
    assert report._beside_scatter(scatter, ["fine"], "radius_loading_mean", 0.2) == ""
    assert report._beside_scatter(None, ["fine"], "radius_loading_mean", 0.04) == ""


def test_the_verification_sentence_names_the_cases_that_warn():
    """ "6 of 6 meet every target" is read with the cases' warnings (yield, an unreliable average speed)."""
    rows = [
        {"description": "paper", "warnings": []},
        {"description": "4 m/s", "warnings": ["analytical: Hertz peak pressure at rods 1 and 2 ...",
                                              "global: Hertz peak pressure at rods 1 and 2 ..."]},
        {"description": "equal rods", "warnings": ["global: midpoint_peak_speed: the first contact ..."]},
    ]  # fmt: skip
    text = report._warned_text(rows)
    assert "4 m/s: yield (p0 above 1.1 S_y); equal rods: midpoint_peak_speed." in text and "paper" not in text
    assert report._warned_text(rows[:1]) == ""
