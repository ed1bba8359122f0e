"""Mesh convergence of the contact: submodel levels and global meshes against Hertz and the analytical force,
with the least-squares observed order, extrapolation and band of :mod:`rods.convergence` (issue 13, item 4).

How to call it (the stage; nothing here runs a model)::

    from rods import hertz
    from rods.paper import convergence
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    records = [  # one dict per run: submodel levels (>= 4 wanted) and global meshes (>= 3 wanted)
        {"model": "submodel", "level": "coarse", "h": 0.25e-3,           # element size at the contact [m]
         "peak_contact_force": 5353.2, "contact_radius": 1.1107e-3,     # [N], [m]
         "contact_area": 3.8753e-6, "peak_contact_pressure": 2.051e9},  # [m^2], [Pa]
        ...,
        {"model": "global", "level": "1 mm", "h": 0.244e-3, ...},
    ]
    data = convergence.write(records, analytical["peak_contact_force"], E_star, R_star, out_dir)
    # -> out_dir/convergence.json (compute's data), convergence.md (render_markdown), convergence.png (plot)
    section = convergence.render_markdown(data)  # the REPORT.md section, from the data or its JSON

Errors, per level [%]: the peak force against the analytical model's peak force; contact radius, area and
peak pressure against Hertz at the model's *own* peak force (paper Eq. 10, :func:`rods.hertz.at_force`), so
they measure how well the mesh resolves the patch, not the force. Against Hertz at the analytical force the
two errors add: a ∝ F^(1/3), so a/a_H(F_an) - 1 ≈ (a/a_H(F) - 1) + (F/F_an - 1)/3 (area 2/3, p0 1/3); where
the force error and the own-force error have opposite signs they cancel, and the data say so ("errors
cancel"). Each error series and each raw value series gets :func:`rods.convergence.estimate` over all
levels and over the three finest (the classic Richardson/GCI, Roache; ASME V&V 20).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rods import hertz, io
from rods.compare import cell, percent
from rods.convergence import FS_GOOD, estimate
from rods.io import write_data
from rods.preflight import InputError
from rods.study.figures import pyplot

__all__ = [
    "KEYS",
    "QUANTITIES",
    "compute",
    "one_driver",
    "one_run_per_size",
    "plot",
    "record",
    "render_markdown",
    "step_vs_scatter",
    "turns_vs_scatter",
    "write",
]

# record key -> (label, unit shown, factor SI -> unit shown, Hertz key or None for the analytical force)
# (the edge-period mean: rods.metrics.edge_period_radius, free of the node-position scatter; NaN where a run has none)
QUANTITIES: dict[str, tuple[str, str, float, str | None]] = {
    "peak_contact_force": ("peak force", "N", 1.0, None),
    "contact_radius": ("contact radius", "mm", 1e3, "contact_radius"),
    "contact_area": ("contact area", "mm²", 1e6, "contact_area"),
    "peak_contact_pressure": ("peak pressure", "GPa", 1e-9, "peak_pressure"),
    "contact_radius_edge_mean": ("contact radius, edge-period mean", "mm", 1e3, "contact_radius"),
    "contact_area_edge_mean": ("contact area, edge-period mean", "mm²", 1e6, "contact_area"),
}
OPTIONAL = ("contact_radius_edge_mean", "contact_area_edge_mean")  # NaN in a record that lacks them
KEYS = ("model", "level", "h", *(q for q in QUANTITIES if q not in OPTIONAL))  # every record has these
PHASE_FAMILY = "submodel (phase mean)"  # each level the mean over its phase members (rods.scene.submodel_phase_size)
MODEL_ORDER = ("submodel", PHASE_FAMILY, "global")  # families listed first, in this order; others follow by name


def _level(r: Mapping[str, Any], F_an: float, E_star: float, R_star: float) -> dict[str, Any]:
    """One level's values [SI], references [SI] and errors [%]: force vs analytical, the rest vs Hertz at the
    level's own force; also vs Hertz at the analytical force (the two errors combined)."""
    F = float(r["peak_contact_force"])
    own, at_an = hertz.at_force(F, E_star, R_star), hertz.at_force(F_an, E_star, R_star)
    values = {q: _num(r.get(q)) for q in QUANTITIES}
    ref = {q: (F_an if hk is None else own[hk]) for q, (_, _, _, hk) in QUANTITIES.items()}
    vs_an = {q: percent(values[q], F_an if hk is None else at_an[hk]) for q, (_, _, _, hk) in QUANTITIES.items()}
    return {
        "level": str(r["level"]),
        "h": float(r["h"]),
        "coarsened": bool(r.get("coarsened", False)),
        "values": values,
        "reference": ref,
        "error_pct": {q: percent(values[q], ref[q]) for q in QUANTITIES},
        "error_vs_analytical_pct": vs_an,
    }


def _phase_means(records: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """One :data:`PHASE_FAMILY` record per submodel level with two or more phase members (the level's own run,
    without a ``phase``, is the middle member): the members' mean values at the level's own size (else the
    geometric mean of the members'), and the members themselves under ``members``."""
    by_level: dict[str, list[Mapping[str, Any]]] = {}
    for r in records:
        if r["model"] == "submodel":
            by_level.setdefault(str(r["level"]), []).append(r)
    out = []
    for level, ms in by_level.items():
        if len(ms) < 2 or all(m.get("phase") is None for m in ms):
            continue
        own = [m for m in ms if m.get("phase") is None]
        h = float(own[0]["h"]) if own else math.exp(np.mean([math.log(float(m["h"])) for m in ms]))
        mean = {q: float(np.mean([float(m[q]) for m in ms])) for q in QUANTITIES}
        out.append({"model": PHASE_FAMILY, "level": level, "h": h, **mean, "members": list(ms)})
    return out


def _member_scatter(r: Mapping[str, Any], F_an: float, E_star: float, R_star: float) -> dict[str, Any]:
    """The phase members of a :data:`PHASE_FAMILY` record: their sizes [m], and per quantity the error [%]
    range (min, max) and the standard error of the mean, s/sqrt(n) [%] (stratified members: an upper bound)."""
    errs = [_level(m, F_an, E_star, R_star)["error_pct"] for m in r["members"]]
    n = len(errs)
    sd = {q: float(np.std([e[q] for e in errs], ddof=1)) for q in QUANTITIES}  # one member's scatter [%]
    return {
        "members": n,
        "member_h": sorted((float(m["h"]) for m in r["members"]), reverse=True),
        "spread_pct": {q: [min(e[q] for e in errs), max(e[q] for e in errs)] for q in QUANTITIES},
        "standard_error_pct": {q: sd[q] / math.sqrt(n) for q in QUANTITIES},
        "standard_deviation_pct": sd,
    }


def _estimates(levels: Sequence[Mapping[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per quantity: the error [%] and the raw value, each over all levels and over the three finest (a quantity
    that some level lacks, NaN, is left out)."""
    names, h = [lv["level"] for lv in levels], [lv["h"] for lv in levels]
    out = {}
    for q in QUANTITIES:
        series = {"error_pct": [lv["error_pct"][q] for lv in levels], "value": [lv["values"][q] for lv in levels]}
        if not np.isfinite(series["value"]).all():
            continue
        out[q] = {}
        for kind, f in series.items():
            out[q][kind] = estimate(h, f, names).as_dict()
            out[q][f"{kind}_last3"] = estimate(h[-3:], f[-3:], names[-3:]).as_dict()
    return out


# [%] both errors at least this large, and the force's offsetting the own-force error by at least this much (its
# error against Hertz at the analytical force that much smaller), before "errors cancel" is said (else it is noise:
# -9.64% against -9.61% had been said to cancel, an audit, 2026-12-07)
CANCEL_MIN = 0.1
CANCEL_SHARE = 0.1  # [-] ... and by this share of the own-force error (3D: +11.01% against +10.83% is no cancelling)


def _flags(model: str, levels: Sequence[Mapping[str, Any]], est: Mapping[str, Any] | None) -> list[str]:
    """Plain-language findings: where errors cancel (opposite signs, both >= CANCEL_MIN, and the error against Hertz
    at the analytical force smaller by CANCEL_MIN points), where a series turns or a two-level family's error grows."""
    flags = []
    for lv in levels:
        eF = lv["error_pct"]["peak_contact_force"]
        opp = [
            q
            for q in QUANTITIES
            if q != "peak_contact_force"
            and eF * lv["error_pct"][q] < 0
            and min(abs(eF), abs(lv["error_pct"][q])) >= CANCEL_MIN
            and abs(lv["error_pct"][q]) - abs(lv["error_vs_analytical_pct"][q])
            >= max(CANCEL_MIN, CANCEL_SHARE * abs(lv["error_pct"][q]))
        ]
        if opp:
            parts = ", ".join(
                f"{QUANTITIES[q][0]} {lv['error_pct'][q]:+.2f}% vs Hertz at its own force "
                f"({lv['error_vs_analytical_pct'][q]:+.2f}% vs Hertz at the analytical force)"
                for q in opp
            )
            name = lv["level"] if lv["level"].startswith(model) else f"{model} {lv['level']}"  # not "global global"
            flags.append(f"{name}: errors cancel: force {eF:+.2f}% vs analytical, {parts}")
    flags += _mixed_far_fields(model, levels)
    if est is None:
        n = len(levels)
        return [
            *flags,
            *_grows(model, levels),
            f"{model}: only {n} level{'s' if n != 1 else ''}, no convergence estimate (three or more needed)",
        ]
    for q, (label, *_) in QUANTITIES.items():
        if q not in est:
            continue
        e, v = est[q]["error_pct"], est[q]["value"]
        bad = [(w, x) for w, x in (("error", e), ("value", v)) if not x["monotone"]]
        if len(bad) == 2 and e["nonmonotone_levels"] == v["nonmonotone_levels"]:
            bad = [("error and value", e)]
        for what, x in bad:
            last3 = "monotone" if x["monotone_last3"] else "not monotone either"
            at = ", ".join(x["nonmonotone_levels"])
            scatter = _turns_text(turns_vs_scatter(levels, q, x["nonmonotone_levels"])) if what != "value" else ""
            flags.append(f"{model} {label} {what}: non-monotone at {at}; over the three finest levels {last3}{scatter}")
        spans = (("all levels", e), ("the three finest levels", est[q]["error_pct_last3"]))
        for span, x in spans[: 1 if len(levels) == 3 else 2]:
            if x["branch"] == "diverging":
                flags.append(
                    f"{model} {label} error: the differences grow under refinement over {span} (p = {x['order']:.2f}): "
                    "not in the asymptotic range, no extrapolation"
                )
    return flags


def _grows(model: str, levels: Sequence[Mapping[str, Any]]) -> list[str]:
    """A family of two levels whose error of a quantity grows from the coarser to the finer by CANCEL_MIN points or
    more: said, not left to "no convergence estimate" (the 3D globals' radius +11.0% -> +12.9%, area +23.2% ->
    +27.5% from 1 mm to 0.7 mm: an audit, 2026-12-07)."""
    if len(levels) != 2:
        return []
    a, b = levels
    return [
        f"{model} {label} error grows under refinement ({a['error_pct'][q]:+.2f}% at {a['level']}, "
        f"{b['error_pct'][q]:+.2f}% at {b['level']}): no convergence shown"
        for q, (label, *_) in QUANTITIES.items()
        if math.isfinite(a["error_pct"][q])
        and math.isfinite(b["error_pct"][q])
        and abs(b["error_pct"][q]) - abs(a["error_pct"][q]) >= CANCEL_MIN
    ]


def _mixed_far_fields(model: str, levels: Sequence[Mapping[str, Any]]) -> list[str]:
    """A family whose meshes merge their elements across away from the tips (``fe.radial_coarsening``,
    rods.fe.layout.coarsening) on some levels and not on others is no one systematic refinement: the merge's own
    small error (the paper scene's global: +0.047% on the peak force, 2026-12-06) is in some levels' errors only."""
    merged = [lv["level"] for lv in levels if lv.get("coarsened")]
    if not merged or len(merged) == len(levels):
        return []
    full = ", ".join(lv["level"] for lv in levels if not lv.get("coarsened"))
    return [
        f"{model}: {', '.join(merged)} merged across 3:1 away from the tips (fe.radial_coarsening), {full} not "
        "(its elements too wide to merge within the bar's size): not one systematic refinement, so an order fitted "
        "over them mixes the two far fields"
    ]


SCATTER_SIGMAS = 2.0  # a step under this many combined standard errors (deviations) is the scatter [-]


def _scatter(lv: Mapping[str, Any]) -> tuple[Mapping[str, float], str] | None:
    """A level's scatter per quantity [%] and what it is: a phase mean's standard error ("members"), or, for a
    single-mesh level run with phase members, one member's standard deviation ("snapshot"); None for neither."""
    if "standard_error_pct" in lv:
        return lv["standard_error_pct"], "members"
    if "snapshot_sd_pct" in lv:
        return lv["snapshot_sd_pct"], "snapshot"
    return None


def step_vs_scatter(a: Mapping[str, Any], b: Mapping[str, Any], q: str) -> dict[str, Any]:
    """The step of quantity ``q`` between two levels [points], their combined scatter [points] (:func:`_scatter`:
    the phase means' standard errors, or single meshes' standard deviations) and whether the step is within
    :data:`SCATTER_SIGMAS` of it (scatter) or a trend."""
    (sa, basis), (sb, _) = _scatter(a), _scatter(b)
    step = abs(b["error_pct"][q] - a["error_pct"][q])
    s = math.hypot(sa[q], sb[q])
    return {"step": step, "standard_error": s, "within_scatter": step < SCATTER_SIGMAS * s, "basis": basis}


def turns_vs_scatter(levels: Sequence[Mapping[str, Any]], q: str, turns: Sequence[str]) -> list[dict[str, Any]]:
    """At each interior level in ``turns``: the smaller of its two steps of quantity ``q`` [points], the two levels'
    combined scatter [points] and whether the step is within :data:`SCATTER_SIGMAS` of it (:func:`step_vs_scatter`);
    a turn whose step joins a level without a scatter (no phase members) is left out."""
    names = [lv["level"] for lv in levels]
    e = [lv["error_pct"][q] for lv in levels]
    out = []
    for t in turns:
        j = names.index(t)
        if not 0 < j < len(levels) - 1:
            continue
        k = j - 1 if abs(e[j] - e[j - 1]) < abs(e[j + 1] - e[j]) else j + 1  # the smaller step's other end
        if _scatter(levels[j]) is None or _scatter(levels[k]) is None:
            continue
        out.append({"level": t, **step_vs_scatter(levels[j], levels[k], q)})
    return out


def _turns_text(turns: Sequence[Mapping[str, Any]]) -> str:
    """The flag's tail for :func:`turns_vs_scatter`'s entries."""
    what = {
        "members": ("a standard error", "the members' scatter"),
        "snapshot": ("the two meshes' combined standard deviation over their phase members", "a single mesh's scatter"),
    }
    parts = []
    for t in turns:
        measure, scatter = what[t.get("basis", "members")]
        within = f"under {SCATTER_SIGMAS:g} x that, within {scatter}"
        verdict = within if t["within_scatter"] else f"{SCATTER_SIGMAS:g} x that or more, larger than {scatter}"
        parts.append(
            f"at {t['level']} the smaller step is {t['step']:.3f} points against {measure} of "
            f"{t['standard_error']:.3f}: {verdict}"
        )
    return ("; " + "; ".join(parts)) if parts else ""


def _snapshot_scatter(levels: dict[str, list[dict[str, Any]]]) -> None:
    """Give each single-mesh submodel level whose phase members ran (family :data:`PHASE_FAMILY`) one member's
    standard deviation, ``snapshot_sd_pct``: the scatter of a single mesh's value, against which its turns are
    judged."""
    phase = {lv["level"]: lv for lv in levels.get(PHASE_FAMILY, [])}
    for lv in levels.get("submodel", []):
        if lv["level"] in phase and "standard_deviation_pct" in phase[lv["level"]]:
            lv["snapshot_sd_pct"] = phase[lv["level"]]["standard_deviation_pct"]


def compute(
    records: Sequence[Mapping[str, Any]], analytical_force: float, E_star: float, R_star: float
) -> dict[str, Any]:
    """The convergence data (convergence.json): per model family, its levels coarse to fine, the estimates of
    :func:`_estimates` (None below three levels) and the flags. ``analytical_force`` [N], E* [Pa], R* [m]."""
    for r in records:
        missing = [k for k in KEYS if k not in r]
        if missing:
            raise KeyError(f"convergence record {dict(r)!r} lacks {missing}")
    records = [r for r in records if r.get("phase") is None] + _phase_means(records)
    families = sorted({str(r["model"]) for r in records}, key=_rank)
    models, by_family = {}, {}
    for m in families:
        recs = sorted((r for r in records if r["model"] == m), key=lambda r: -float(r["h"]))
        by_family[m] = [_level(r, analytical_force, E_star, R_star) for r in recs]
        for lv, r in zip(by_family[m], recs, strict=True):
            if "members" in r:
                lv.update(_member_scatter(r, analytical_force, E_star, R_star))
    _snapshot_scatter(by_family)
    for m, levels in by_family.items():
        est = _estimates(levels) if len(levels) >= 3 else None
        models[m] = {"levels": levels, "estimates": est, "flags": _flags(m, levels, est)}
        if est is not None:
            models[m]["monotone_last3"] = all(e["error_pct"]["monotone_last3"] for e in est.values())
    return {
        "reference": {
            "analytical_force": analytical_force,
            "E_star": E_star,
            "R_star": R_star,
            "hertz_at_analytical_force": hertz.at_force(analytical_force, E_star, R_star),
        },
        "quantities": {q: {"label": v[0], "unit": v[1], "factor": v[2]} for q, v in QUANTITIES.items()},
        "models": models,
    }


def _rank(m: str) -> tuple[int, str]:
    return (MODEL_ORDER.index(m) if m in MODEL_ORDER else len(MODEL_ORDER), m)


def _num(v: Any) -> float:
    return math.nan if v is None else float(v)


def _mono(e: Mapping[str, Any]) -> str:
    turns = ", ".join(e["nonmonotone_levels"])
    return f"{'yes' if e['monotone'] else f'no ({turns})'} / {'yes' if e['monotone_last3'] else 'no'}"


def _last3(t: Mapping[str, Any], k: float, digits: str) -> str:
    """The three-finest estimate in one cell: p, extrapolated ± U (Richardson/GCI), or why there is none."""
    if math.isfinite(_num(t["extrapolated"])):
        return (
            f"p = {cell(t['order'], '.2f')}: {cell(_num(t['extrapolated']) * k, digits)} ± "
            f"{cell(_num(t['uncertainty']) * k, '.3g')} ({t['branch']}, Fs = {t['safety_factor']:g})"
        )
    return f"p = {cell(t['order'], '.2f')}: {t['branch']}, no extrapolation"


def _error_rows(fam: Mapping[str, Any]) -> list[str]:
    levels, est = fam["levels"], fam["estimates"]
    head = " | ".join(f"{lv['level']} (h = {lv['h'] * 1e3:.4g} mm)" for lv in levels)
    L = [
        f"| error [%] | {head} | p (all) | e0 (all) | U (all) | branch | monotone (all / 3 finest) "
        "| 3 finest (Richardson/GCI) |",
        "|---|" + "---|" * (len(levels) + 6),
    ]
    for q, (label, *_rest, hk) in QUANTITIES.items():
        vs = "analytical force" if hk is None else "Hertz at own force"
        cells = " | ".join(cell(lv["error_pct"][q], "+.3f") for lv in levels)
        if est is None or q not in est:
            L.append(f"| {label} vs {vs} | {cells} | | | | | | |")
            continue
        a, t = est[q]["error_pct"], est[q]["error_pct_last3"]
        L.append(
            f"| {label} vs {vs} | {cells} | {cell(a['order'], '.2f')} | {cell(a['extrapolated'], '+.3f')} "
            f"| ±{cell(a['uncertainty'], '.3f')} | {a['branch']} | {_mono(a)} "
            f"| {_last3(t, 1.0, '+.3f')} |"
        )
    return L


def _value_rows(fam: Mapping[str, Any]) -> list[str]:
    L = [
        "| value | finest | p (all) | extrapolated ± U (all) | U/\\|f1\\| (all) | 3 finest (Richardson/GCI) "
        "| GCI_fine (3 finest) |",
        "|---|---|---|---|---|---|---|",
    ]
    for q, (label, unit, k, _) in QUANTITIES.items():
        if q not in fam["estimates"]:
            continue
        a, t = fam["estimates"][q]["value"], fam["estimates"][q]["value_last3"]
        L.append(
            f"| {label} [{unit}] | {a['f'][-1] * k:.5g} | {cell(a['order'], '.2f')} "
            f"| {cell(_num(a['extrapolated']) * k, '.5g')} ± {cell(_num(a['uncertainty']) * k, '.3g')} "
            f"| {cell(100 * _num(a['relative_uncertainty']), '.2f')}% | {_last3(t, k, '.5g')} | {_gci(t)} |"
        )
    return L


def _member_rows(fam: Mapping[str, Any]) -> list[str]:
    """The phase members behind each level's mean: sizes, and per quantity the error range and standard error."""
    L = [
        "| level | members | h of the members [mm] | "
        + " | ".join(f"{QUANTITIES[q][0]}: range (SE) [%]" for q in QUANTITIES)
        + " |",
        "|---|---|---|" + "---|" * len(QUANTITIES),
    ]
    for lv in fam["levels"]:
        hs = ", ".join(f"{h * 1e3:.4g}" for h in lv["member_h"])
        cells = " | ".join(
            f"{cell(lv['spread_pct'][q][0], '+.3f')} .. {cell(lv['spread_pct'][q][1], '+.3f')} "
            f"({cell(lv['standard_error_pct'][q], '.3f')})"
            for q in QUANTITIES
        )
        L.append(f"| {lv['level']} | {lv['members']} | {hs} | {cells} |")
    return L


def _gci(t: Mapping[str, Any]) -> str:
    """U/|f1| of the three finest where it is Roache's GCI (credible order, Fs = 1.25), else '–'."""
    ok = t["branch"] == "observed order" and t["safety_factor"] == FS_GOOD
    return f"{100 * _num(t['relative_uncertainty']):.2f}%" if ok else "–"


METHOD = (
    "Errors: the peak force against the analytical model's; contact radius, area and peak pressure against "
    "Hertz at the model's own peak force (paper Eq. 10). Fit e(h) = e0 + α h^p to all levels by least squares "
    "(Eça & Hoekstra, J. Comput. Phys. 262, 2014), e0 the extrapolated error; U the band of the finest level, "
    "Fs = 1.25 for a credible order (0.5 ≤ p < 2.1, fit scatter below the data range), else 3 with a "
    "fixed-order fit; '–' and branch non-monotone or diverging: no order and no extrapolation claimed, "
    "U = 3 × the data range. On the three finest levels the same fit is Richardson's with Roache's GCI "
    "(ASME V&V 20). Monotone: every successive difference of one sign; a named level is where the "
    "sequence turns."
)


def render_markdown(data: Mapping[str, Any]) -> str:
    """The convergence section (convergence.md; a section of REPORT.md) from :func:`compute`'s data or its JSON."""
    ref = data["reference"]
    L = [
        "## Mesh convergence against Hertz and the analytical force",
        "",
        f"Analytical peak force F_an = {ref['analytical_force']:.1f} N (Hertz there: a = "
        f"{_num(ref['hertz_at_analytical_force']['contact_radius']) * 1e3:.4f} mm, p0 = "
        f"{_num(ref['hertz_at_analytical_force']['peak_pressure']) / 1e9:.3f} GPa). {METHOD}",
    ]
    for m, fam in data["models"].items():
        if not isinstance(fam["estimates"], Mapping):  # too few levels; JSON's null reads back as NaN
            fam = {**fam, "estimates": None}
        n = len(fam["levels"])
        L += ["", f"### {m} ({n} levels)", "", *_error_rows(fam)]
        if fam["estimates"] is not None:
            L += ["", *_value_rows(fam)]
            ok = "yes" if fam["monotone_last3"] else "no"
            branch = {QUANTITIES[q][0]: e["error_pct_last3"]["branch"] for q, e in fam["estimates"].items()}
            grow = [q for q, b in branch.items() if b == "diverging"]
            swing = [q for q, b in branch.items() if b == "non-monotone"]  # no order at all: not "converging"
            why = [f"{', '.join(grow)}: the differences grow"] if grow else []
            why += [f"{', '.join(swing)}: non-monotone, no order"] if swing else []
            conv = "yes" if not why else f"no ({'; '.join(why)})"
            L += ["", f"Every error monotone over the three finest levels: {ok}; converging there (p > 0): {conv}."]
        if all("members" in lv for lv in fam["levels"]):
            L += ["", *_member_rows(fam)]
        # the findings as this code words them from the data (a JSON written by older code keeps its own words)
        flags = _flags(m, fam["levels"], fam["estimates"])
        if flags:
            L += ["", *(f"* {s}." for s in flags)]
        else:
            L += ["", "* No level is non-monotone and no errors cancel."]
    return "\n".join(L) + "\n"


def _fit_line(e: Mapping[str, Any], hh: np.ndarray) -> np.ndarray | None:
    """e0 + α (h/h1)^p of an observed-order estimate at sizes hh [m]; None for the other branches."""
    if e["branch"] != "observed order":
        return None
    return _num(e["extrapolated"]) + _num(e["alpha"]) * (hh / e["h"][-1]) ** _num(e["order"])


def _positive(x: Sequence[float], y: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.asarray(x, dtype=float), np.abs(np.asarray(y, dtype=float))
    keep = np.isfinite(y) & (y > 0)
    return x[keep], y[keep]


PLOT_COLUMNS = 3  # quantities a row of the figure: each has its error panel above its |e - e0| panel


def plot(data: Mapping[str, Any], path: str | Path) -> None:
    """Log-log, per quantity: |error| [%] against h with the least-squares fit |e0 + α h^p| (upper panel), and the
    discretisation error |e - e0| with α h^p, a line of slope p (lower panel; where no family has a fit, the panel
    says why instead); one colour per model family, h ticks at the levels' sizes."""
    plt = pyplot()
    rows = 2 * -(-len(QUANTITIES) // PLOT_COLUMNS)
    fig, grid = plt.subplots(rows, PLOT_COLUMNS, figsize=(5.2 * PLOT_COLUMNS, 3.4 * rows), squeeze=False)
    panels = [
        (grid[2 * (j // PLOT_COLUMNS), j % PLOT_COLUMNS], grid[2 * (j // PLOT_COLUMNS) + 1, j % PLOT_COLUMNS])
        for j in range(len(QUANTITIES))
    ]
    for a in grid.flat[2 * len(QUANTITIES) :]:
        a.set_axis_off()
    notes: list[list[tuple[str, str]]] = [[] for _ in QUANTITIES]
    for c, (m, fam) in enumerate(data["models"].items()):
        colour, h = f"C{c}", np.array([lv["h"] for lv in fam["levels"]])
        hh = np.geomspace(h.min(), h.max(), 60)
        for j, q in enumerate(QUANTITIES):
            top, bottom = panels[j]
            err = [lv["error_pct"][q] for lv in fam["levels"]]
            top.loglog(*_positive(h * 1e3, err), "o-", color=colour, lw=0.8, label=m)
            e = fam["estimates"][q]["error_pct"] if fam["estimates"] and q in fam["estimates"] else None
            line = _fit_line(e, hh) if e else None
            if line is None:
                notes[j].append((f"{m}: {e['branch'] if e else 'under 3 levels'}, no fit", colour))
                continue
            top.loglog(*_positive(hh * 1e3, line), "--", color=colour, lw=1, label=f"{m} fit")
            e0, p = _num(e["extrapolated"]), _num(e["order"])
            bottom.loglog(*_positive(h * 1e3, np.asarray(err) - e0), "o", color=colour)
            bottom.loglog(*_positive(hh * 1e3, line - e0), "--", color=colour, lw=1, label=f"{m}: p = {p:.2f}")
    sizes = sorted({lv["h"] * 1e3 for fam in data["models"].values() for lv in fam["levels"]})
    for (top, bottom), (label, *_rest, hk), note in zip(panels, QUANTITIES.values(), notes, strict=True):
        _dress(top, bottom, f"{label}\nvs {'analytical' if hk is None else 'Hertz at own force'}", sizes, note)
    fig.suptitle("Mesh convergence of the contact (least-squares fit e0 + α h^p over all levels)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _dress(top: Any, bottom: Any, title: str, sizes: Sequence[float], notes: Sequence[tuple[str, str]]) -> None:
    """A quantity's two panels: title, labels, h ticks at the levels' ``sizes`` [mm] (minor log labels crowded a
    sub-decade axis), the error axis kept on the data, the families without a fit listed on the lower panel."""
    from matplotlib.ticker import FixedLocator, NullFormatter, NullLocator

    ys = [y for line in top.get_lines() if line.get_marker() == "o" for y in line.get_ydata()]
    if ys:  # where a fitted error crosses zero its |.| dips: keep the axis on the data
        top.set_ylim(bottom=min(ys) / 3)
    top.set(title=title, ylabel="|error| [%]")
    bottom.set(xlabel="element size at the contact h [mm]", ylabel="|e − e0| [%]")
    for a in (top, bottom):
        a.grid(alpha=0.3, which="both")
        if a.has_data():
            a.legend(fontsize=7)
            a.xaxis.set_major_locator(FixedLocator(sizes))
            a.xaxis.set_major_formatter(lambda x, _pos: f"{x:.3g}")
            a.xaxis.set_minor_locator(NullLocator())
            a.xaxis.set_minor_formatter(NullFormatter())
            a.tick_params(axis="x", labelrotation=45, labelsize=7)
    if not bottom.has_data():  # no family fitted this quantity: the reasons instead of empty axes
        bottom.set(xticks=[], yticks=[], xlabel="", ylabel="")
    for k, (text, colour) in enumerate(notes):
        bottom.text(0.03, 0.95 - 0.09 * k, text, color=colour, fontsize=8, transform=bottom.transAxes, va="top")


FILES = ("convergence.json", "convergence.md", "convergence.png")  # what write puts in its folder


def write(
    records: Sequence[Mapping[str, Any]], analytical_force: float, E_star: float, R_star: float, out_dir: str | Path
) -> dict[str, Any]:
    """The stage: ``out_dir``/convergence.json (:func:`compute`), convergence.md (:func:`render_markdown`),
    convergence.png (:func:`plot`). Returns the data."""
    data = compute(records, analytical_force, E_star, R_star)
    json_file, md_file, png_file = (Path(out_dir) / name for name in FILES)
    write_data(json_file, data)
    io.atomic_write_text(md_file, render_markdown(data))
    plot(data, png_file)
    return data


def for_scene(scene: Any, runs: Sequence[tuple[str, Mapping[str, Any]]], out_dir: str | Path) -> dict[str, Any]:
    """The stage for ``scene`` (rods.scene.Scene): its (label, summary) runs against Hertz with the scene's
    E*, R* (rods.hertz.contact_constants) and the analytical model's peak force, written by :func:`write`."""
    from rods import hertz
    from rods.analytical import simulate

    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    F_an = simulate(scene).summary["peak_contact_force"]
    return write([record(s, label) for label, s in runs], F_an, E_star, R_star, out_dir)


def one_run_per_size(
    runs: Sequence[tuple[str, Mapping[str, Any]]], folders: Sequence[Any], flag: str = "--run"
) -> None:
    """Each family's element sizes distinct among ``runs`` ((label, summary), from ``folders``), else bad input naming
    both runs: they are the fit's abscissae (three runs of one level with another --dt, driving or contact law failed
    the fit, two passed as two sizes: a fuzz, 2026-12-06). A phase member is its level's, averaged apart."""
    seen: dict[tuple[str, float], Any] = {}
    for (label, summary), folder in zip(runs, folders, strict=True):
        r = record(summary, label)
        if r["phase"] is not None:
            continue
        key = (r["model"], r["h"])
        if key in seen:
            why = f"the same {r['model']} element size ({r['h'] * 1e3:.4g} mm) as {seen[key]}: one run per size"
            raise InputError(flag, folder, why, "give one run per mesh size (runs of one size: accuracy_cost.py)")
        seen[key] = folder


def one_driver(runs: Sequence[tuple[str, Mapping[str, Any]]], folders: Sequence[Any], flag: str = "--run") -> None:
    """The submodel levels among ``runs`` ((label, summary), from ``folders``) driven by one cut record (their
    ``cut_record``), else bad input naming both: levels of two drivers differ by their drivers too, so their fit is
    no refinement's (a fuzz, 2026-12-06: compare.py refused the mix, convergence.py fitted an order over it)."""
    first: tuple[str, Any] | None = None
    for (_, summary), folder in zip(runs, folders, strict=True):
        cut = summary.get("cut_record")
        if cut is None:  # a global, or a submodel of a version that did not record its driver
            continue
        if first is None:
            first = (cut, folder)
        elif cut != first[0]:
            why = f"driven by another global's cut record than {first[1]} ({cut} against {first[0]})"
            raise InputError(flag, folder, why, "give the submodel levels of one driving global")


def record(summary: Mapping[str, Any], label: str = "") -> dict[str, Any]:
    """One record of :func:`compute` from a run's summary.json: a submodel level (its uniform element size) or
    a global mesh (h = fe.radial_size, the element width across the contact face, which sets how finely the
    patch radius is resolved; the tip is graded to it by default), in the family of its kind ("global" for the
    axisymmetric model, "global 3d" for the 3D one)."""
    sub = "element_size" in summary and summary.get("level") is not None
    if sub:
        model, level, h = "submodel", str(summary["level"]), float(summary["element_size"])
    else:  # one family per model kind: a 3D global is not a finer axisymmetric one
        fe = summary["scene_values"]["fe"]
        model = "global" if fe.get("kind", "axisymmetric") == "axisymmetric" else f"global {fe['kind']}"
        h = float(fe["radial_size"])
        level = label or f"{h * 1e3:g} mm"
    keys = ("peak_contact_force", "contact_radius", "contact_area", "peak_contact_pressure")
    edge = {q: _num(summary.get(q)) for q in OPTIONAL}
    phase = summary.get("phase", {}).get("member") if sub else None  # a phase member (rods.scene.submodel_phase_size)
    coarsened = bool(summary.get("mesh", {}).get("coarsened"))  # merged across away from the tips (rods.fe.layout)
    return {"model": model, "level": level, "h": h, "phase": phase, "coarsened": coarsened,
            **{k: float(summary[k]) for k in keys}, **edge}  # fmt: skip
