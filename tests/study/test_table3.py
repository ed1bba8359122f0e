"""The comparison stage's data and renderings on synthetic models that follow Hertz (mesh-free)."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from rods import hertz, io, paper_data
from rods.convergence import estimate
from rods.study.table3 import COLUMNS, ModelRun, render_csv, render_markdown, table3

from ..conftest import ROOT

F_EXACT, C, P = 5500.0, 2.5e7, 1.5  # converged force [N], error constant [N/m^p], order [-]
E0, D = 0.004, 3.0e4  # converged plateau radius error [-] and its constant [1/m]


def _hertz_model(scene, F: float, **extra) -> dict:
    """A summary whose contact patch is Hertz at its own force F, σ_r the closed form at its sample depth."""
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    H = hertz.at_force(F, E_star, R_star)
    a, p0 = H["contact_radius"], H["peak_pressure"]
    r = np.linspace(0.02, 2.5, 120) * a
    z = np.full_like(r, 0.2 * extra.get("element_size", 1e-4))
    return {
        "peak_contact_force": F,
        "contact_radius": a,
        "contact_area": H["contact_area"],
        "peak_contact_pressure": p0,
        "dofs": 1000,
        "wall_time": 1.0,
        "hertz_at_own_force": H,
        "sigma_r_profile": {"r": r, "depth": z, "sigma_r": hertz.subsurface_stresses(r, z, a, p0, 0.3)[0]},
        "pressure_profile": {"r": r, "p": hertz.pressure(r, a, p0)},
        "scene_values": scene.as_dict(),
        "mesh": {"radial_size": 0.25e-3},
        **extra,
    }


def _history(scene, e: float) -> dict:
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    F = F_EXACT * np.sin(np.linspace(0.0, np.pi, 301))
    return {"contact_force": F, "contact_radius": (1.0 + e) * hertz.contact_radius(F, E_star, R_star)}


@pytest.fixture
def runs(scene_with):
    sc = scene_with("fe.tip_grading=1.0")  # a uniform global mesh, and a graded driver below
    g = {k: v for k, v in _hertz_model(sc, 5560.0).items() if k not in ("sigma_r_profile", "hertz_at_own_force")}
    out = [ModelRun("global-uniform", g)]
    driver_scene = sc.with_overrides("fe.tip_grading=0.25")
    out.append(ModelRun("global-driver", {**g, "scene_values": driver_scene.as_dict(), "peak_contact_force": 5560.0}))
    for lv in ("fine", "coarse", "mid"):  # any order: the table sorts by element size
        h = {"coarse": 0.25e-3, "mid": 0.125e-3, "fine": 0.0625e-3}[lv]
        s = _hertz_model(sc, F_EXACT + C * h**P, level=lv, element_size=h)
        out.append(ModelRun("submodel", s, _history(sc, E0 + D * h)))
    return sc, out


# the analytical model's contract values the rows are compared with (paper scene magnitudes)
ANALYTICAL = {
    "peak_contact_force": 5555.0,  # [N]
    "contact_radius": 1.09e-3,  # [m]
    "contact_area": 3.74e-6,  # [m^2]
    "peak_contact_pressure": 2.2e9,  # [Pa]
}


def test_models_that_follow_hertz_have_no_hertz_error_and_richardson_finds_the_limit(runs):
    sc, models = runs
    d = table3(sc, ANALYTICAL, models)
    assert [r["model"] for r in d["rows"]] == [
        "Global (uniform 1 mm)",
        "Global (tips graded to 0.25 mm; drives the submodels)",
        "Submodel coarse (h = 0.25 mm)",
        "Submodel mid (h = 0.125 mm)",
        "Submodel fine (h = 0.0625 mm)",
    ]
    for r in d["rows"]:
        assert set(r) == {"role", "level", "label", *COLUMNS}
        assert abs(r["d_area_vs_hertz_pct"]) < 1e-9 and abs(r["d_p0_vs_hertz_pct"]) < 1e-9
        assert r["force_N"] == pytest.approx(r["d_force_vs_analytical_pct"] / 100 * 5555.0 + 5555.0)
    subs = [r for r in d["rows"] if r["role"] == "submodel"]
    assert all(r["sigma_r_err_depth_pct"] < 1e-9 for r in subs)  # σ_r is the closed form at its depth
    assert math.isnan(d["rows"][0]["sigma_r_err_surface_pct"])  # globals sample no σ_r
    assert all(math.isnan(r["max_shear_err_pct"]) for r in d["rows"])  # none sampled the axis here
    paper = paper_data.load()
    assert d["rows"][2]["paper_force_N"] == paper.table3["submodel_coarse"].force
    assert d["experiment"]["contact_radius"] == paper.fe_experiment.experimental_radius
    rich = d["richardson"]
    assert rich["levels"] == ["coarse", "mid", "fine"] and rich["ratio"] == 2.0
    q = rich["quantities"]["peak_contact_force"]
    assert q["order"] == pytest.approx(P, rel=1e-9) and q["extrapolated"] == pytest.approx(F_EXACT, rel=1e-12)
    qa = rich["quantities"]["contact_radius"]
    assert abs(qa["vs_hertz_pct"]) < 1e-3  # Hertz radii extrapolate to Hertz at F_ext (to second order)
    qp = rich["quantities"]["plateau_radius_error_pct"]
    assert qp["order"] == pytest.approx(1.0, rel=1e-6) and qp["extrapolated"] == pytest.approx(100 * E0, rel=1e-6)


def test_an_incredible_order_claims_nothing_against_hertz(runs):
    """Submodel forces that converge at order 3 (outside 0.5-2.1, rods.convergence.P_CREDIBLE): extrapolated by the
    fixed-order fits with the safety factor 3 and not compared with Hertz; the radius, still Hertz at those forces,
    is then judged at the finest level's force. The markdown says why."""
    sc, models = runs
    steep = []
    for m in models:
        if m.role == "submodel":
            h = m.summary["element_size"]
            s = _hertz_model(sc, F_EXACT + 1e8 * h**3, level=m.level, element_size=h)
            m = ModelRun("submodel", s, _history(sc, E0 + 1e9 * h**3))  # the plateau radius error at order 3 too
        steep.append(m)
    d = table3(sc, ANALYTICAL, steep)
    q = d["richardson"]["quantities"]["peak_contact_force"]
    assert q["order"] == pytest.approx(3.0, rel=1e-9) and q["asymptotic"] and not q["credible"]
    fixed = estimate([4.0, 2.0, 1.0], [q["f3"], q["f2"], q["f1"]])  # the fixed-order fits, Fs = 3 (rods.convergence)
    assert fixed.safety_factor == 3.0 and q["extrapolated"] == pytest.approx(fixed.extrapolated, rel=1e-12)
    assert q["gci_fine"] == pytest.approx(fixed.uncertainty / abs(q["f1"]), rel=1e-9)
    assert math.isnan(q["vs_hertz_pct"])
    qp = d["richardson"]["quantities"]["plateau_radius_error_pct"]  # its extrapolation is its error against Hertz
    assert qp["order"] == pytest.approx(3.0, rel=1e-6) and not qp["credible"] and math.isnan(qp["vs_hertz_pct"])
    assert d["richardson"]["quantities"]["contact_radius"]["hertz_at_extrapolated"] == pytest.approx(
        hertz.at_force(q["f1"], *hertz.contact_constants(sc.rod1, sc.rod2))["contact_radius"], rel=1e-12
    )
    md = render_markdown(d)
    assert "not credible" in md
    assert "–%" not in md and "±–" not in md  # a missing value is a bare dash, not a dash with a unit


def test_renderings_come_from_the_data_and_its_json(runs, tmp_path):
    sc, models = runs
    d = table3(sc, ANALYTICAL, models)
    io.write_data(tmp_path / "t.json", d)
    text = (tmp_path / "t.json").read_text()
    back = json.loads(text)  # strict JSON: NaN written as null
    assert "NaN" not in text and back["rows"][0]["sigma_r_err_surface_pct"] is None
    assert render_csv(back) == render_csv(d) and render_markdown(back) == render_markdown(d)
    lines = render_csv(d).splitlines()
    assert lines[0].split(",") == list(COLUMNS) and len(lines) == 1 + len(models)
    md = render_markdown(d)
    assert "| Submodel fine (h = 0.0625 mm) | 5512 |" in md and "levels coarse / mid / fine, ratio 2" in md
    assert "Paper Table 3: global 5549 N / 4.61 mm², coarse 5219 / 4.80" in md


def test_compare_cli_writes_under_output_unless_told(runs, tmp_path):
    """compare.py without --out writes output/compare/<scene> (relative to where it runs), never results/."""
    sc, models = runs
    args = []
    for m in models:
        d = tmp_path / "in" / (m.level or m.role)
        model = f"fe-submodel-{m.level}" if m.role == "submodel" else "fe-axisymmetric"  # what compare.py reads
        s = {k: m.summary.get(k, 0.0) for k in io.SUMMARY_KEYS} | dict(m.summary) | {"model": model}
        io.write_summary(d / "summary.json", s)
        if m.history is not None:
            io.write_history(d / "history.csv", m.history, {})
        flag = {"global-uniform": "--global-uniform", "global-driver": "--global"}.get(m.role, "--submodel")
        args += [flag, str(d)]
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    p = subprocess.run(
        [sys.executable, str(ROOT / "workflows" / "compare.py"), *args], cwd=cwd, capture_output=True, text=True
    )
    assert p.returncode == 0, p.stderr[-2000:]
    assert sorted(f.name for f in (cwd / "output" / "compare" / "paper").iterdir()) == [
        "fig5c-pressure.png",
        "fig5c-profile.png",
        "fig6-sigma-r.png",
        "table3.csv",
        "table3.json",
        "table3.md",
    ]
    assert not (cwd / "results").exists() and "Richardson" in p.stdout


def test_no_experiment_at_another_impact_speed(runs):
    """Table 3's experiment is the trial at the paper's FE speed: a 1.848 m/s study has none to compare with."""
    sc, models = runs
    an = {"peak_contact_force": 4e3, "contact_radius": 1e-3, "contact_area": 3.1e-6, "peak_contact_pressure": 2e9}
    d = table3(sc.with_overrides("impact.speed=1.848"), an, models)
    assert d["experiment"]["source"] is None and all(math.isnan(r["d_area_vs_exp_pct"]) for r in d["rows"])
    md = render_markdown(d)
    assert "No experiment for this scene" in md
    assert render_markdown(json.loads(json.dumps(d).replace("NaN", "null"))) == md


def test_the_papers_columns_only_for_the_papers_scene(runs):
    """At the paper's speed but on other rods (a titanium Rod 2), neither the experiment nor the paper's Table 3
    numbers are set beside the results: they belong to Table 1's rods."""
    sc, models = runs
    an = {"peak_contact_force": 4e3, "contact_radius": 1e-3, "contact_area": 3.1e-6, "peak_contact_pressure": 2e9}
    assert table3(sc, an, models)["paper_scene"]  # the fixture is the paper's scene: its columns are there
    assert not math.isnan(table3(sc, an, models)["rows"][-1]["paper_force_N"])
    d = table3(sc.with_overrides("rod2.material.youngs_modulus=114e9", "rod2.material.density=4430.0"), an, models)
    assert not d["paper_scene"] and d["experiment"]["source"] is None
    assert all(math.isnan(r["paper_force_N"]) and math.isnan(r["d_area_vs_exp_pct"]) for r in d["rows"])
    md = render_markdown(d)
    assert "Paper columns: only for the paper's scene" in md and "Paper Table 3: global" not in md


def test_an_order_outside_the_credible_range_is_marked_in_its_row(runs):
    """A Richardson row whose observed order is not credible (a probe's p0 at p = 0.13: its 'extrapolation' +14%
    from Hertz) says so in the row, not only in the legend; a credible one stays unmarked."""
    sc, models = runs
    data = table3(sc, ANALYTICAL, models)
    q = data["richardson"]["quantities"]
    q["peak_contact_pressure"] |= {"order": 0.13, "credible": False}
    q["contact_area"] |= {"order": 1.6, "credible": True}
    rows = {line.split(" |")[0]: line for line in render_markdown(data).splitlines() if line.startswith("| ")}
    assert "| 0.13 (not credible) |" in rows["| peak pressure [GPa]"]
    assert "| 1.60 |" in rows["| contact area [mm²]"] and "not credible" not in rows["| contact area [mm²]"]


def test_a_graded_submodel_level_is_named_so():
    """A level graded outside the patch (rods.fe.submodel.submodel_grading; its summary's mesh.graded) says so in
    its row's name; a uniform one, the paper's, does not."""
    from rods.study.table3 import model_name

    base = {"level": "fine", "element_size": 0.0625e-3}
    graded = ModelRun("submodel", {**base, "mesh": {"graded": [True, True]}}, {})
    uniform = ModelRun("submodel", {**base, "mesh": {"graded": [False, False]}}, {})
    assert model_name(graded) == "Submodel fine (h = 0.0625 mm, graded outside the patch)"
    assert model_name(uniform) == "Submodel fine (h = 0.0625 mm)"


@pytest.mark.parametrize("force", [50.0, 5560.0, 5e5])  # [N] patches of 0.24, 1.09 and 5.1 mm on the paper's tip
def test_the_pressure_figures_show_the_patch_whatever_its_size(scene_with, tmp_path, monkeypatch, force):
    """Fig. 5c's profile and disc and Fig. 6's σ_r reach PICTURE_PATCHES Hertz radii at the run's own force (they
    showed 2.5 and 3 mm, the paper's patch, on every scene: a 5 mm patch was cut, a 0.2 mm one a corner of the plot)."""
    import matplotlib.axes

    from rods.metrics import PICTURE_PATCHES
    from rods.study import figures

    sc = scene_with()
    s = _hertz_model(sc, force)
    s["pressure_profile"] = {k: v * 4.0 if k == "r" else v for k, v in s["pressure_profile"].items()}  # to 10 a
    s["pressure_profile"]["p"] = hertz.pressure(s["pressure_profile"]["r"], s["contact_radius"], 1e9)
    limits = []
    original = matplotlib.axes.Axes.set_xlim
    monkeypatch.setattr(matplotlib.axes.Axes, "set_xlim", lambda ax, *a, **k: limits.append(a) or original(ax, *a, **k))
    figures.fig5c(tmp_path, s, *hertz.contact_constants(sc.rod1, sc.rod2))
    assert limits[0] == (0, pytest.approx(PICTURE_PATCHES * s["contact_radius"] * 1e3, rel=1e-9))  # the profile
    assert (tmp_path / "fig5c-profile.png").stat().st_size and (tmp_path / "fig5c-pressure.png").stat().st_size
    # Fig. 6 (σ_r near the surface) alike, from the finest level's Hertz radius at its own force
    limits.clear()
    figures.fig6(tmp_path, [s | {"level": "fine", "element_size": 6.25e-5}], 0.3)
    assert limits[0] == (0, pytest.approx(PICTURE_PATCHES * s["hertz_at_own_force"]["contact_radius"] * 1e3))


def test_fig5c_disc_is_drawn_by_matplotlib_where_vtk_cannot_render(scene_with, tmp_path, monkeypatch, capsys):
    """A headless machine without EGL still gets Fig. 5c's disc (matplotlib), and says why on stderr."""
    from rods import io
    from rods.study import figures

    def no_gl():
        raise RuntimeError("no EGL device")

    monkeypatch.setattr(io, "offscreen_pyvista", no_gl)
    sc = scene_with()
    figures.fig5c(tmp_path, _hertz_model(sc, 5560.0), *hertz.contact_constants(sc.rod1, sc.rod2))
    assert (tmp_path / "fig5c-pressure.png").stat().st_size > 10_000
    assert "matplotlib fallback" in capsys.readouterr().err


def test_the_tip_pressure_map_revolves_an_axisymmetric_profile_and_mirrors_a_symmetry_model():
    """rods.study.figures.tip_pressure: p(r) revolved every 2° with the axis node once; a 3D quarter model's nodes
    mirrored about x = 0 and y = 0 and a half model's about y = 0 (rods.fe.mesh3d.QUADRANTS), a node on a
    symmetry plane once; a full model's nodes as they lie."""
    from rods.study.figures import tip_pressure

    x, y, p = tip_pressure({"pressure_profile": {"r": [0.0, 1e-3, 2e-3], "p": [3.0, 2.0, 0.0]}})
    assert x.size == 1 + 2 * 180 and np.allclose(np.hypot(x, y), np.r_[0.0, np.repeat([1e-3, 2e-3], 180)])
    assert p[0] == 3.0 and set(p[1:181]) == {2.0}
    quarter = {"x": [0.0, 1e-3, 0.0, 1e-3], "y": [0.0, 0.0, 1e-3, 1e-3], "p": [4.0, 3.0, 2.0, 1.0]}
    prof = quarter | {"r": np.hypot(quarter["x"], quarter["y"]).tolist()}
    x, y, p = tip_pressure({"pressure_profile": prof, "symmetry": "quarter"})
    assert x.size == 9  # the axis node once, the plane nodes twice, the corner node four times
    assert dict(zip(zip(x.round(6), y.round(6), strict=True), p, strict=True))[(-0.001, -0.001)] == 1.0
    x, y, p = tip_pressure({"pressure_profile": prof, "symmetry": "half"})
    assert x.size == 6 and y.min() == -1e-3 and x.min() == 0.0
    assert tip_pressure({"pressure_profile": prof, "symmetry": "full"})[0].size == 4


def test_fig5c_of_a_tilted_3d_run_is_centred_on_its_patch(scene_with, tmp_path, monkeypatch):
    """A 3D run's Fig. 5c: p against the distance from the run's contact centroid (a tilted impact's patch lies
    R1 sin θ off Rod 1's axis, from which the profile's r runs: against that r the Hertz comparison was off by the
    offset), the map drawn around it."""
    import matplotlib.axes

    from rods.study import figures

    sc = scene_with()
    s = _hertz_model(sc, 5560.0)
    a, p0 = s["contact_radius"], s["hertz_at_own_force"]["peak_pressure"]
    xc = -0.35e-3  # [m] the patch's centre, off Rod 1's axis
    g = np.linspace(-3 * a, 3 * a, 41)
    X, Y = np.meshgrid(g + xc, g[g >= 0])  # a half model's nodes, y >= 0
    P = hertz.pressure(np.hypot(X - xc, Y), a, p0)
    s["pressure_profile"] = {"r": np.hypot(X, Y).ravel(), "x": X.ravel(), "y": Y.ravel(), "p": P.ravel()}
    s |= {"symmetry": "half", "contact_centroid_x": xc, "contact_centroid_y": 0.0}
    lines = []
    original = matplotlib.axes.Axes.plot
    monkeypatch.setattr(matplotlib.axes.Axes, "plot", lambda ax, *a_, **k: lines.append(a_) or original(ax, *a_, **k))
    figures.fig5c(tmp_path, s, *hertz.contact_constants(sc.rod1, sc.rod2))
    r_fe, p_fe = np.asarray(lines[0][0]) / 1e3, np.asarray(lines[0][1]) * 1e9  # [m], [Pa]
    assert np.allclose(p_fe, hertz.pressure(r_fe, a, p0), atol=1e-6 * p0)  # on Hertz's curve about the centroid
    assert (tmp_path / "fig5c-pressure.png").stat().st_size > 10_000


def test_a_submodels_largest_shear_below_the_patch_is_its_own_column(runs):
    """Δτ_max: a submodel's max_shear_error (rods.compare.max_shear_error) as a percentage in its row, the table and
    its CSV; '–' for a row without one (a global; a table3.json from before the column renders and writes NaN)."""
    sc, models = runs
    fine = models[2]
    models[2] = ModelRun("submodel", {**fine.summary, "max_shear": {"max_shear_error": 0.0054}}, fine.history)
    d = table3(sc, ANALYTICAL, models)
    (row,) = [r for r in d["rows"] if r["level"] == "fine"]
    assert row["max_shear_err_pct"] == pytest.approx(0.54)
    md = render_markdown(d)
    assert "| Δτ_max vs Hertz |" in md and "| +0.54% |" in md
    old = {**d, "rows": [{k: v for k, v in r.items() if k != "max_shear_err_pct"} for r in d["rows"]]}
    assert "| +0.54% |" not in render_markdown(old) and render_csv(old).count("nan") >= len(d["rows"])
