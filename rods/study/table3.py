"""The comparison stage's data (paper Table 3): every model against Hertz at its own force, the analytical
model, experiment and the paper, with a Richardson/GCI estimate over the three finest submodel levels.

:func:`table3` builds the data (the ``table3.json`` contract: SI units in ``analytical``, ``experiment``,
``paper`` and ``richardson``; each row carries the table's columns in its own units, named ``_mm``, ``_GPa``,
``_pct``); :func:`render_csv` and :func:`render_markdown` render that data and nothing else. The paper's
values and the experiment come from :func:`rods.paper_data.load` by named keys.
"""

from __future__ import annotations

import csv
import io as _io
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from rods import compare, hertz, paper_data
from rods.scene import Scene, scene_from_summary

__all__ = ["COLUMNS", "ModelRun", "model_name", "render_csv", "render_markdown", "table3"]

# the columns of results/table3.csv, in order (the rows of table3.json carry exactly these, plus role/level/label)
COLUMNS = (
    "model",
    "h_mm",
    "dofs",
    "wall_s",
    "force_N",
    "radius_mm",
    "area_mm2",
    "p0_GPa",
    "hertz_radius_mm",
    "hertz_area_mm2",
    "hertz_p0_GPa",
    "d_area_vs_hertz_pct",
    "d_p0_vs_hertz_pct",
    "d_force_vs_analytical_pct",
    "d_area_vs_analytical_pct",
    "d_area_vs_exp_pct",
    "d_radius_vs_exp_pct",
    "sigma_r_err_surface_pct",
    "sigma_r_err_depth_pct",
    "max_shear_err_pct",
    "paper_force_N",
    "paper_area_mm2",
)
ROLES = ("global-uniform", "global-driver", "submodel")
# Richardson quantities: summary key -> (label, unit shown, factor SI -> unit shown)
QUANTITIES = {
    "peak_contact_force": ("peak force", "N", 1.0),
    "contact_radius": ("contact radius", "mm", 1e3),
    "contact_area": ("contact area", "mm²", 1e6),
    "peak_contact_pressure": ("peak pressure", "GPa", 1e-9),
}
HERTZ_KEY = {
    "contact_radius": "contact_radius",
    "contact_area": "contact_area",
    "peak_contact_pressure": "peak_pressure",
}


@dataclass(frozen=True)
class ModelRun:
    """One model of the table: its role, its summary and (submodels) its history, whose force and radius
    columns give the plateau radius error."""

    role: str  # one of ROLES
    summary: Mapping[str, Any]
    history: Mapping[str, np.ndarray] | None = None

    @property
    def level(self) -> str | None:
        return self.summary.get("level") if self.role == "submodel" else None


def model_name(run: ModelRun) -> str:
    """The table's model name, from the run's own settings (e.g. "Global (uniform 1 mm)")."""
    s = run.summary
    if run.role == "submodel":  # a graded level (rods.fe.submodel.submodel_grading) says so
        graded = ", graded outside the patch" if any(s.get("mesh", {}).get("graded", ())) else ""
        return f"Submodel {s['level']} (h = {s['element_size'] * 1e3:g} mm{graded})"
    sc = scene_from_summary(s["scene_values"])
    h, g = sc["fe.axial_size"], sc.tip_grading
    mesh = f"uniform {h * 1e3:.3g} mm" if g == 1.0 else f"tips graded to {g * h * 1e3:.3g} mm"
    return f"Global ({mesh}; drives the submodels)" if run.role == "global-driver" else f"Global ({mesh})"


def _paper(data: paper_data.PaperData) -> dict[str, dict[str, float]]:
    out = {"global-uniform": data.table3["global"], "analytical": data.table3["analytical"]}
    out |= {k.removeprefix("submodel_"): v for k, v in data.table3.items() if k.startswith("submodel_")}
    rows = {k: {"force": v.force, "area": v.area} for k, v in out.items()}
    return rows | {"experiment": {"force": math.nan, "area": data.experimental_area}}


def _row(run: ModelRun, ref: Mapping[str, Any], E_star: float, R_star: float, nu: float) -> dict[str, Any]:
    s = run.summary
    F, a, A, p = (s[k] for k in ("peak_contact_force", "contact_radius", "contact_area", "peak_contact_pressure"))
    H = hertz.at_force(F, E_star, R_star)
    an, exp = ref["analytical"], ref["experiment"]
    profile = s.get("sigma_r_profile")  # σ_r at its stored field's own force (rods.compare.stress_field_hertz)
    err = compare.sigma_r_error(profile, compare.stress_field_hertz(s), nu) if profile else {}
    # the largest shear below the patch against Hertz's (a submodel's; null: flat tips, an off-axis impact)
    τ = (s.get("max_shear") or {}).get("max_shear_error")
    key = run.level if run.role == "submodel" else run.role
    none = {"force": math.nan, "area": math.nan}
    pp = ref["paper"].get(key, none) if ref["paper_scene"] else none
    h = s["element_size"] if run.role == "submodel" else s["mesh"]["radial_size"]
    row = {
        "model": model_name(run),
        "h_mm": h * 1e3,
        "dofs": s["dofs"],
        "wall_s": s["wall_time"],
        "force_N": F,
        "radius_mm": a * 1e3,
        "area_mm2": A * 1e6,
        "p0_GPa": p / 1e9,
        "hertz_radius_mm": H["contact_radius"] * 1e3,
        "hertz_area_mm2": H["contact_area"] * 1e6,
        "hertz_p0_GPa": H["peak_pressure"] / 1e9,
        "d_area_vs_hertz_pct": compare.percent(A, H["contact_area"]),
        "d_p0_vs_hertz_pct": compare.percent(p, H["peak_pressure"]),
        "d_force_vs_analytical_pct": compare.percent(F, an["peak_contact_force"]),
        "d_area_vs_analytical_pct": compare.percent(A, an["contact_area"]),
        "d_area_vs_exp_pct": compare.percent(A, exp["contact_area"]),
        "d_radius_vs_exp_pct": compare.percent(a, exp["contact_radius"]),
        "sigma_r_err_surface_pct": 100 * err.get("surface", math.nan),
        "sigma_r_err_depth_pct": 100 * err.get("depth", math.nan),
        "max_shear_err_pct": 100 * _num(τ),
        "paper_force_N": pp["force"],
        "paper_area_mm2": pp["area"] * 1e6,
    }
    label = {"global-uniform": "global", "global-driver": "driver"}.get(run.role, run.level)
    return {"role": run.role, "level": run.level, "label": label, **row}


def _richardson_entry(rr: compare.Richardson, href: float | None) -> dict[str, Any]:
    vs = compare.percent(rr.extrapolated, href) if (href is not None and rr.credible) else math.nan
    return {
        "f1": rr.f1,
        "f2": rr.f2,
        "f3": rr.f3,
        "order": rr.order,
        "extrapolated": rr.extrapolated,
        "gci_fine": rr.gci_fine,
        "error_band": rr.error_band,
        "asymptotic": rr.asymptotic,
        "credible": rr.credible,
        "monotone": rr.monotone,
        "hertz_at_extrapolated": math.nan if href is None else href,
        "vs_hertz_pct": vs,
    }


def _richardson(subs: Sequence[ModelRun], E_star: float, R_star: float) -> dict[str, Any] | None:
    """Richardson/GCI over the three finest levels (rods.compare.richardson_levels); SI units, and the radius
    error against Hertz at the same force averaged over the force plateau [%], whose extrapolation is the
    converged radius error itself (steadier than the peak instant, whose radius jumps as the edge passes a node)."""
    by_level = {r.level: r for r in subs}
    choice = compare.richardson_levels({lv: r.summary["element_size"] for lv, r in by_level.items()})
    if choice is None:
        return None
    levels, ratio = choice
    f3, f2, f1 = (by_level[lv].summary for lv in levels)
    rF = compare.richardson(f1["peak_contact_force"], f2["peak_contact_force"], f3["peak_contact_force"], ratio)
    H_ext = hertz.at_force(rF.extrapolated if rF.credible else f1["peak_contact_force"], E_star, R_star)
    q = {}
    for key in QUANTITIES:
        rr = compare.richardson(f1[key], f2[key], f3[key], ratio)
        q[key] = _richardson_entry(rr, H_ext[HERTZ_KEY[key]] if key in HERTZ_KEY else None)
    e = []
    for lv in reversed(levels):  # fine, mid, coarse
        h = by_level[lv].history
        e.append(100 * compare.plateau_radius_error(h["contact_force"], h["contact_radius"], E_star, R_star)[0])
    rp = compare.richardson(*e, ratio)
    # its Hertz value is 0 by definition, so its extrapolation is the difference from Hertz itself
    q["plateau_radius_error_pct"] = _richardson_entry(rp, None) | {
        "hertz_at_extrapolated": 0.0,
        "vs_hertz_pct": rp.extrapolated if rp.credible else math.nan,  # as every row: nothing at an odd order
    }
    return {"levels": list(levels), "ratio": ratio, "plateau_fraction": compare.PLATEAU, "quantities": q}


def table3(scene: Scene, analytical: Mapping[str, Any], runs: Sequence[ModelRun]) -> dict[str, Any]:
    """The comparison data of ``runs`` (globals in the order given, then submodels coarse to fine) on
    ``scene``, against the analytical model's summary ``analytical`` (table3.json contract, NaN for none).
    The experiment and the paper's columns are Table 3's, for the paper's FE scene only (Table 1's rods at the FE
    trial's speed, rods.paper_data.PaperData.is_fe_scene; else NaN columns): another scene's numbers are not the
    paper's to compare with."""
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    nu = scene.rod1.material.poisson_ratio
    pd = paper_data.load()
    paper_scene = pd.is_fe_scene(scene)
    trial = pd.fe_experiment if paper_scene else None  # Table 3's experiment: Table 2's trial at the FE speed
    a_exp = trial.experimental_radius if trial else math.nan
    ref = {
        "scene": scene.label,
        "impact_speed": scene.speed,
        "analytical": {
            **{
                k: analytical[k]
                for k in ("peak_contact_force", "contact_radius", "contact_area", "peak_contact_pressure")
            },
            # the reference's law (REPORT.md names it; Fig. 4's may differ)
            "contact_law": analytical.get("contact_law"),
        },
        "experiment": {
            "contact_radius": a_exp,
            "contact_area": math.pi * a_exp**2,
            "source": f"Table 2, Spec. {trial.specimen} Trial {trial.trial}" if trial else None,
        },
        "paper": _paper(pd),
        "paper_scene": paper_scene,
    }
    subs = sorted((r for r in runs if r.role == "submodel"), key=lambda r: -r.summary["element_size"])
    ordered = [r for r in runs if r.role != "submodel"] + subs
    rows = [_row(r, ref, E_star, R_star, nu) for r in ordered]
    return ref | {"rows": rows, "richardson": _richardson(subs, E_star, R_star)}


def _num(v: Any) -> float:
    return math.nan if v is None else v


def render_csv(data: Mapping[str, Any]) -> str:
    """results/table3.csv: COLUMNS, floats to 6 significant digits, NaN as nan."""
    buf = _io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(COLUMNS), lineterminator="\r\n")
    w.writeheader()
    for r in data["rows"]:
        row = {k: r.get(k, math.nan) for k in COLUMNS}  # a table3.json from before a column: NaN there
        w.writerow({k: (f"{_num(v):.6g}" if isinstance(_num(v), float) else v) for k, v in row.items()})
    return buf.getvalue()


def _pct(v: Any, d: int) -> str:
    v = _num(v)
    return "–" if math.isnan(v) else f"{v:+.{d}f}%"


def _f(v: Any, d: int = 3) -> str:
    v = _num(v)
    return "–" if isinstance(v, float) and math.isnan(v) else (f"{v:.{d}f}" if isinstance(v, float) else str(v))


def _sigma_r_cell(r: Mapping[str, Any]) -> str:
    """σ_r error at the surface / at the Gauss-point depth; '–' for a model that samples none (the global)."""
    surface, depth = (compare.cell(r[k], ".1f", "%") for k in ("sigma_r_err_surface_pct", "sigma_r_err_depth_pct"))
    return "–" if surface == depth == "–" else f"{surface} / {depth}"


def _band(band: Any) -> str:
    return "–" if math.isnan(_num(band)) else f"±{_f(band, 2)} points"


def _model_rows(data: Mapping[str, Any]) -> list[str]:
    L = [
        "| model | F [N] | area [mm²] | a [mm] | p0 [GPa] | Hertz a [mm] | Hertz area [mm²] | Hertz p0 [GPa] "
        "| Δarea vs Hertz | Δp0 vs Hertz | ΔF vs anal. | Δarea vs anal. | Δarea vs exp. | σ_r err (surf / depth) "
        "| Δτ_max vs Hertz | paper F [N] | paper area [mm²] | DOFs | wall [s] |",
        "|" + "---|" * 19,
    ]
    for r in data["rows"]:
        L.append(
            f"| {r['model']} | {r['force_N']:.0f} | {r['area_mm2']:.3f} | {r['radius_mm']:.4f} | {r['p0_GPa']:.3f} "
            f"| {_f(r['hertz_radius_mm'], 4)} | {_f(r['hertz_area_mm2'])} | {_f(r['hertz_p0_GPa'])} "
            f"| {_pct(r['d_area_vs_hertz_pct'], 2)} | {_pct(r['d_p0_vs_hertz_pct'], 2)} "
            f"| {_pct(r['d_force_vs_analytical_pct'], 2)} "
            f"| {_pct(r['d_area_vs_analytical_pct'], 1)} | {_pct(r['d_area_vs_exp_pct'], 1)} "
            f"| {_sigma_r_cell(r)} | {_pct(r.get('max_shear_err_pct'), 2)} "
            f"| {_f(r['paper_force_N'], 0)} | {_f(r['paper_area_mm2'], 2)} | {r['dofs']} | {r['wall_s']:.1f} |"
        )
    an, exp, pa = data["analytical"], data["experiment"], data["paper"]
    paper = (
        f"{pa['analytical']['force']:.0f} | {pa['analytical']['area'] * 1e6:.2f} / {pa['experiment']['area'] * 1e6:.2f}"
        if data.get("paper_scene", True)  # a table3.json from before the key: the main job's, the paper's scene
        else "– | –"
    )
    L.append(
        f"| Analytical / Experimental | {an['peak_contact_force']:.0f} | {an['contact_area'] * 1e6:.3f} / "
        f"{_f(_num(exp['contact_area']) * 1e6)} | {an['contact_radius'] * 1e3:.4f} / "
        f"{_f(_num(exp['contact_radius']) * 1e3)} | "
        f"{an['peak_contact_pressure'] / 1e9:.3f} | | | | | | | | | | | {paper} | | |"
    )
    return L


def _order(q: dict[str, Any]) -> str:
    """The observed-order cell: p, marked where it lies outside the credible range (its extrapolation is then
    no estimate of the converged value: the row says so, not only the legend)."""
    text = _f(q["order"], 2)
    return f"{text} (not credible)" if q.get("credible") is False and math.isfinite(_num(q["order"])) else text


def _richardson_rows(rich: Mapping[str, Any]) -> list[str]:
    c, m, f = rich["levels"]
    L = [
        "",
        f"## Richardson extrapolation and GCI (levels {c} / {m} / {f}, ratio {rich['ratio']:g})",
        "",
        f"| quantity | {c} (f3) | {m} (f2) | {f} (f1) | observed order p | extrapolated | GCI_fine "
        "| Hertz at extrapolated force | extrapolated vs Hertz |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for key, (label, unit, k) in QUANTITIES.items():
        q = rich["quantities"][key]
        href = _num(q["hertz_at_extrapolated"]) * k
        ext = _num(q["extrapolated"]) * k
        L.append(
            f"| {label} [{unit}] | {q['f3'] * k:.5g} | {q['f2'] * k:.5g} | {q['f1'] * k:.5g} | {_order(q)} "
            f"| {_f(ext, 4)} | {compare.cell(q['gci_fine'], '.2f', '%', scale=100)} | {_f(href, 4)} "
            f"| {_pct(q['vs_hertz_pct'], 2)} |"
        )
    q = rich["quantities"]["plateau_radius_error_pct"]
    L.append(
        f"| radius vs Hertz at the same force, plateau mean [%] | {q['f3']:+.3f} | {q['f2']:+.3f} | {q['f1']:+.3f} "
        f"| {_order(q)} | {_f(q['extrapolated'], 3)} | {_band(q['error_band'])} | 0 "
        f"| {_pct(q['vs_hertz_pct'], 2)} |"
    )
    return [
        *L,
        "",
        f"Plateau mean: a(t)/a_H(F(t)) − 1 averaged over the samples with F ≥ {rich['plateau_fraction']:g} F_max; its "
        "extrapolation is the converged radius error itself.",
        "",
        "p = ln((f3 − f2)/(f2 − f1))/ln r, f_ext = f1 + (f1 − f2)/(r^p − 1), GCI_fine = 1.25 |(f1 − f2)/f1|/(r^p − 1) "
        "(Roache; ASME V&V 20); an order outside 0.5-2.1 is not credible (rods.convergence): the extrapolation and "
        "GCI are then the fixed-order fits' (f0 + α h or f0 + α h², whichever fits closer; 3 in place of 1.25; "
        "Eça & Hoekstra) and the extrapolation is not compared with Hertz. '–': no extrapolation: non-monotone (no "
        "order), or p <= 0 (the differences grow under refinement: the levels are not in the asymptotic range).",
    ]


def render_markdown(data: Mapping[str, Any]) -> str:
    """results/table3.md from the data of :func:`table3` (or its JSON)."""
    an, exp, pa = data["analytical"], data["experiment"], data["paper"]
    named = [(k, v) for k, v in pa.items() if k not in ("analytical", "experiment")]
    paper = ", ".join(
        f"{'global' if k == 'global-uniform' else k} {v['force']:.0f}{' N' if i == 0 else ''} / "
        f"{v['area'] * 1e6:.2f}{' mm²' if i == 0 else ''}"
        for i, (k, v) in enumerate(named)
    )
    L = ["# Table 3 reproduced: contact force and area, global model and submodel levels", ""]
    L.append(
        f"Scene `{data['scene']}` (s1 = {data['impact_speed']} m/s). Analytical model: "
        f"F = {an['peak_contact_force']:.1f} N, a = {an['contact_radius'] * 1e3:.4f} mm, "
        f"area = {an['contact_area'] * 1e6:.3f} mm², p0 = {an['peak_contact_pressure'] / 1e9:.3f} GPa. "
        + (
            f"Experiment ({exp['source']}): a = {exp['contact_radius'] * 1e3:.3f} mm, area π a² = "
            f"{exp['contact_area'] * 1e6:.3f} mm² (Table 3 prints {pa['experiment']['area'] * 1e6:.2f} mm²). "
            if exp["source"]
            else "No experiment for this scene (Table 3's is Table 1's rods at its speed). "
        )
        + "Hertz columns: closed form at the model's own peak force."
    )
    L += ["", *_model_rows(data)]
    L += [
        "",
        "σ_r err: max |σ_r,FE − σ_r,Hertz| / |σ_r,Hertz(0)| over the Gauss points nearest the surface with "
        f"|r − a| > {compare.SIGMA_EDGE_BAND:g} a (away from the contact edge); closed form at the surface (Johnson "
        "Eq. 3.41) and at the Gauss-point depth (Johnson Eq. 3.44). Δτ_max: the largest shear |σ_z − σ_r|/2 along "
        "the axis (the site of first yield) against Hertz's at the same Gauss points (Johnson Eq. 3.44; 0.31 p0 at "
        "0.48 a for ν = 0.3). Δ: relative differences. "
        + (
            f"Paper Table 3: {paper}."
            if data.get("paper_scene", True)
            else "Paper columns: only for the paper's scene (Table 1's rods at the FE trial's speed); not this one."
        ),
    ]
    if data.get("richardson"):
        L += _richardson_rows(data["richardson"])
    if data.get("warnings"):  # the finest level's checks (rods.study.stages.comparison)
        L += ["", *(f"Warning: {w}" for w in data["warnings"])]
    return "\n".join(L) + "\n"
