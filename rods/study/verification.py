"""Verification matrix: the global FE model at default settings against the analytical model, scene by scene.

One recipe, run by ``workflows/verify.py`` (``make verify``) and the slow test: each case is the paper scene
with a few overrides (:data:`CASES`), run through the analytical model and the global FE model at the
scene's defaults (no per-case tuning). Per case the matrix reports

* peak contact force, FE against analytical [%] — target :data:`TARGETS` ``peak_force``;
* first contact duration, FE minus analytical [s] (rods.metrics.contact_duration) — target ``duration_transits``
  of the thinner rod's diameter transit d/c (rods.checks.agree_duration: 1.99 µs on the paper's rods, issue 13's
  2 µs; in the scene's own time scale, so a scene scaled in size is judged alike);
* Rod-2 midpoint average peak speed, FE against analytical [%] (rods.metrics.midpoint_peak_speed);
* midpoint strain RMS difference over the strain window [-] (rods.metrics.strain_window, rms_difference), and
  the lag of the FE's strain behind the analytical one that minimises it [s] (rods.metrics.time_lag);
* the FE energy-balance error [-] — target ``energy``;
* the mesh check: the same global on a mesh refined by :data:`MESH_CHECK` in both directions (:func:`finer`),
  run over the contact phase only (rods.plan.contact_phase: the duration and the peak force are settled
  there, so it costs about as much as the default run), and the change Δ of peak force and duration from it
  to the default mesh. The default mesh's own error is e = Δ 2^p/(2^p - 1) for an order p (Richardson), so a
  gap to the analytical model over :data:`MODEL_FORM_RATIO` = 8 times Δ is the reference's model form (1D bars,
  quasi-static Hertz between half-spaces), not the FE's discretisation, for any order p >= log2(8/7) = 0.19;
  so is a gap that the refinement widens (Δ of the opposite sign: a monotone sequence's limit lies further out
  still) (:func:`gap_is_model_form`).
  A coarser check would mislead: on the paper scene (measured before the analytical bars held the caps' mass) a
  2 x coarser mesh (2 tip elements across the patch radius) lasted 1.22 µs longer, where the default and a 2 x
  finer mesh agreed to 0.02 µs (202.74, 202.76 µs); two equal 0.35 m rods converged slowly (2/1/0.5 mm: 160.96,
  161.08, 161.17 µs) against the paper's law's 165.18 µs (161.21 µs with the rods' end correction). The committed
  ``results/verification.json`` (2026-11-30) has the paper scene's check at -0.13 µs (FE 203.49 µs) and the equal
  rods' FE 161.55 µs against the analytical 161.52 µs;
* wall time of the FE run (set-up + time loop) [s].

A case *passes* when every targeted column is inside its target. The targets are issue 13's acceptance
figures; the matrix reports what the defaults give, it does not tune them.

The reference is the analytical model at the scene's default contact law, ``analytical.contact = "hertz-rod"``
(rods.analytical): Hertz's half-space approach less the rods' end correction χ F/(E b), the far field that the
1D bars already carry (χ of ν, the cap's depth and the patch's size from a static elasticity solve,
rods.fe.end_compliance, not from these runs), on bars of the rods' mass (rods.scene.Rod.bar_length). A second
table compares the same FE runs with the paper's law (:data:`rods.analytical.PAPER_LAW`), which counts that far
field twice, so its contact is too compliant and lasts longer.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from rods import checks, io, metrics, plan
from rods.analytical import PAPER_LAW
from rods.compare import cell, difference, measured, percent
from rods.scene import PAPER_SCENE, Scene, SceneError, load_scene, override, parse_override

__all__ = [
    "CASES",
    "MESH_CHECK",
    "NOT_ENDED",
    "TARGETS",
    "case_description",
    "case_row",
    "duration_words",
    "finer",
    "gap_is_model_form",
    "passes",
    "render_markdown",
    "run_matrix",
]

# case name -> (what it checks, scene overrides of the paper scene)
CASES: dict[str, tuple[str, tuple[str, ...]]] = {
    "paper": ("the paper scene, 2.197 m/s", ()),
    "speed-1.0": ("paper rods at 1.0 m/s", ("impact.speed=1.0",)),
    "speed-4.0": ("paper rods at 4.0 m/s", ("impact.speed=4.0",)),
    "titanium-rod2": (
        "titanium Rod 2 (E = 114 GPa, ρ = 4430 kg/m³, ν = 0.34) at 2.5 m/s",
        (
            "impact.speed=2.5",
            "rod2.material.youngs_modulus=114e9",
            "rod2.material.density=4430.0",
            "rod2.material.poisson_ratio=0.34",
        ),
    ),
    "tip-20mm": ("Rod 1 with a 20 mm tip radius", ("rod1.tip_radius=0.020",)),
    "equal-0.35m": ("two equal 0.35 m rods, flat Rod 2", ("rod1.length=0.35", "rod2.length=0.35")),
}
# the agreement a study's status asks for (rods.checks), and an energy balance as tight as the contact's own
TARGETS = {
    "peak_force": 100 * checks.AGREE_FORCE,
    "duration_transits": checks.AGREE_TRANSITS,
    "energy": checks.VERIFY_ENERGY,
}  # [%], [d/c of the thinner rod], [-]
MESH_CHECK = 2.0  # the scene's element sizes / the mesh check's [-]
MODEL_FORM_RATIO = 8.0  # a gap this many times the mesh change is the reference's model form [-]
MAX_STRAIN_LAG = 10e-6  # [s] the lag search's range
NOT_ENDED = "not ended"  # a table cell: the first contact was still open at end_time (its duration null)


def gap_is_model_form(gap: float, change: float) -> bool:
    """Whether the gap [s or %] between the FE and the analytical model is the latter's model form, given the
    FE's change from the default mesh to the finer one (default minus finer): the refinement widens the gap, or
    the gap exceeds :data:`MODEL_FORM_RATIO` times the change (see the module docstring). NaN change: no."""
    if not math.isfinite(change):
        return False
    return gap * change < 0.0 or abs(gap) > MODEL_FORM_RATIO * abs(change)


def case_description(base: Scene, name: str) -> str:
    """What case ``name`` runs on ``base``: the words of :data:`CASES`, which name the paper's rods, on the paper
    scene's bodies and impact; on another scene its label and the case's overrides (the words misnamed it: a fuzz,
    2026-12-06, had "the paper scene, 2.197 m/s" over a 2.178 m/s run, "flat Rod 2" over a curved one)."""
    words, overrides = CASES[name]
    if plan.scene_difference(load_scene(PAPER_SCENE), base, cut=False) is None:
        return words
    return f"{base.label}, {base.speed:.4g} m/s" if not overrides else f"{base.label}: {', '.join(overrides)}"


def case_scene(base: Scene, name: str, extra: Sequence[str] = ()) -> Scene:
    """Case ``name`` of :data:`CASES` on ``base``, with the caller's ``extra`` overrides last. A caller's override of
    a key the case sets is refused (it would run the case as another scene under the case's name: ``--set
    impact.speed=3`` ran "speed-1.0" at 3 m/s), and a refused value names the case whose setting it meets."""
    own = dict(parse_override(o) for o in CASES[name][1])
    for key, value in (parse_override(o) for o in extra):
        if key in own:
            raise SceneError(
                key, value, f"verification case '{name}' sets this key itself (to {own[key]!r})",
                "leave it to the case, or pick the cases that do not set it with --case",
            )  # fmt: skip
    try:
        return base.with_overrides(*CASES[name][1], *extra)
    except SceneError as e:
        settings = ", ".join(CASES[name][1]) or "the scene as given"
        raise SceneError(
            e.key, e.value, f"{e.allowed}, in verification case '{name}' ({settings})",
            e.hint or "pick the cases this scene allows with --case",
        ) from None  # fmt: skip


def case_costs(
    base: Scene,
    name: str,
    extra: Sequence[str],
    ranks: int,
    force: bool = False,
    comm: Any = None,
    cases: Sequence[str] = CASES,
) -> list[Any]:
    """The estimated costs (rods.cost) of case ``name``'s runs: its analytical model, its global model and the
    finer global over the contact phase (:func:`finer`); a refused setting raises as the run would, before it,
    and so does an ``end_time`` the analytical first contact outlasts (SceneError: no duration to compare). The
    analytical model's own cost is checked first (its budgets unless ``force``): the contact phase is planned with
    it."""
    from rods import cost

    sc = case_scene(base, name, extra)
    analytical = cost.check(cost.analytical_cost(sc), force, comm=comm)  # comm: every rank refuses alike
    first = plan.first_contact_summary(sc)
    if checks.contact_warning(first, sc.end_time, sc) is not None:  # the matrix compares its duration: it must end
        raise SceneError(
            "simulation.end_time",
            sc.end_time,
            f"verification case '{name}': the first contact (analytical model) has not ended by then, so there is "
            "no duration to compare",
            f"lengthen simulation.end_time past every case's contact: at least "
            f"{matrix_end_time(base, extra, cases):.2g}",  # over the cases run: all of them named one not asked for
        )
    return [
        analytical,
        cost.fe_cost(sc, ranks, what=f"{name}: the global"),
        cost.fe_cost(finer(sc, plan.contact_phase(first, sc.end_time)), ranks, what=f"{name}: the global 2 x finer"),
    ]


def matrix_end_time(base: Scene, extra: Sequence[str] = (), cases: Sequence[str] = CASES) -> float:
    """The shortest end time [s] that every case's analytical first contact ends within, with the contact phase's
    margin (rods.plan.CONTACT_MARGIN): what a refused ``simulation.end_time`` is told to become (it named one case's
    twice before, which the next case refused again). Each case's first contact over its own window (a 1 s end time
    lets :func:`rods.plan.first_contact_summary` pick it: milliseconds of the analytical model)."""
    ends = []
    for name in cases:
        sc = case_scene(base, name, [*extra, "simulation.end_time=1.0"])
        end = plan.first_contact_end(plan.first_contact_summary(sc))
        ends.append(end if end is not None else sc.end_time)
    return plan.CONTACT_MARGIN * max(ends)


def finer(scene: Scene, end_time: float, factor: float = MESH_CHECK) -> Scene:
    """``scene`` with fe.axial_size and fe.radial_size divided by ``factor`` (a graded tip follows the radial
    size), to ``end_time`` [s]."""
    return scene.with_overrides(
        override("fe.axial_size", scene["fe.axial_size"] / factor),
        override("fe.radial_size", scene["fe.radial_size"] / factor),
        override("simulation.end_time", end_time),
    )


def case_row(
    name: str,
    analytical: Mapping[str, Any],
    fe: Mapping[str, Any],
    scene: Scene,
    refined: Mapping[str, Any] | None = None,
    paper_law: Mapping[str, Any] | None = None,
    description: str | None = None,
) -> dict[str, Any]:
    """One matrix row from the two models' summaries and histories (``{"summary", "history"}`` each), the
    mesh check's FE summary ``refined`` (:func:`finer`; None: no mesh check) and the analytical model with the
    paper's contact law ``paper_law`` (:data:`rods.analytical.PAPER_LAW`; None: not run); ``description``: what
    the case runs (:func:`case_description`; default its words in :data:`CASES`)."""
    sa, sf = analytical["summary"], fe["summary"]
    window = metrics.strain_window(scene.rod2)
    rms, lag = _strain_comparison(fe["history"], analytical["history"], window)
    # a contact still open at end_time has no duration (null): its row says so and fails the target
    d_dur = difference(sf["contact_duration"], sa["contact_duration"])
    mesh_dur = math.nan if refined is None else difference(sf["contact_duration"], refined["contact_duration"])
    row = {
        "case": name,
        "description": description or (CASES[name][0] if name in CASES else name),
        "overrides": list(CASES[name][1]) if name in CASES else [],
        "impact_speed": scene.speed,
        "contact_law": sa.get("contact_law"),
        "contact_compliance": sa.get("contact_compliance"),
        "peak_force_analytical": sa["peak_contact_force"],
        "peak_force_fe": sf["peak_contact_force"],
        "peak_force_pct": percent(sf["peak_contact_force"], sa["peak_contact_force"]),
        "duration_analytical": sa["contact_duration"],
        "duration_fe": sf["contact_duration"],
        "duration_difference": d_dur,
        "peak_speed_pct": percent(sf["midpoint_peak_speed"], sa["midpoint_peak_speed"]),
        "strain_rms": rms,
        "strain_lag": lag,
        "strain_window": list(window),
        "mesh_check": MESH_CHECK,
        "duration_mesh_change": mesh_dur,
        "peak_force_mesh_change_pct": math.nan
        if refined is None
        else percent(sf["peak_contact_force"], refined["peak_contact_force"]),
        # the duration gap is the reference's model form when the refinement widens it or moves the FE far less
        "duration_gap_is_model_form": gap_is_model_form(d_dur, mesh_dur),
        "energy_error": sf["energy_error"],
        "wall_time": sf["wall_time"] + sf.get("setup_time", 0.0),
        "dofs": sf["dofs"],
        "steps": sf["steps"],
        "contact": sf.get("contact"),
        "penalty_factor": sf.get("penalty_factor"),
        # the two runs' own checks (rods.checks): a figure a run calls unreliable is named beside the row
        "warnings": [f"{m}: {w}" for m, sm in (("analytical", sa), ("global", sf)) for w in sm.get("warnings", [])],
    }
    row["duration_target"] = checks.agree_duration(scene)  # [s]
    row["passes"] = passes(row["peak_force_pct"], d_dur, sf["energy_error"], row["duration_target"])
    if paper_law is not None:
        row["paper_law"] = _paper_law_row(fe, paper_law, window, row["duration_target"])
    return row


def _paper_law_row(
    fe: Mapping[str, Any], paper_law: Mapping[str, Any], window: Any, duration_target: float
) -> dict[str, Any]:
    """The same FE run against the analytical model with the paper's contact law (Eq. 8); ``duration_target`` [s]:
    the case's (:func:`passes`)."""
    sf, se = fe["summary"], paper_law["summary"]
    rms, lag = _strain_comparison(fe["history"], paper_law["history"], window)
    out = {
        "contact_law": se.get("contact_law"),
        "peak_force_analytical": se["peak_contact_force"],
        "peak_force_pct": percent(sf["peak_contact_force"], se["peak_contact_force"]),
        "duration_analytical": se["contact_duration"],
        "duration_difference": difference(sf["contact_duration"], se["contact_duration"]),
        "peak_speed_pct": percent(sf["midpoint_peak_speed"], se["midpoint_peak_speed"]),
        "strain_rms": rms,
        "strain_lag": lag,
    }
    out["passes"] = passes(out["peak_force_pct"], out["duration_difference"], sf["energy_error"], duration_target)
    return out


def passes(
    peak_force_pct: float, duration_difference: float, energy_error: float, duration_target: float
) -> dict[str, bool]:
    """Each targeted column against :data:`TARGETS`, the duration's against ``duration_target`` [s], the scene's
    (rods.checks.agree_duration) (NaN, a value the runs could not measure, fails)."""
    return {
        "peak_force": abs(peak_force_pct) <= TARGETS["peak_force"],
        "duration": abs(duration_difference) <= duration_target,
        "energy": energy_error <= TARGETS["energy"],
    }


def _strain_comparison(
    fe: Mapping[str, Any], analytical: Mapping[str, Any], window: tuple[float, float]
) -> tuple[float, float]:
    """Midpoint strain RMS difference [-] over ``window`` and the FE's lag that minimises it [s]; NaN where
    either history ends before the window does."""
    strains = (fe["time"], fe["rod2_mid_strain"], analytical["time"], analytical["rod2_mid_strain"], window)
    rms = metrics.window_rms_difference(*strains)
    return (rms, metrics.time_lag(*strains, MAX_STRAIN_LAG)[0]) if math.isfinite(rms) else (math.nan, math.nan)


def run_matrix(
    base: Scene,
    out: Path,
    comm: Any,
    cases: Sequence[str] = tuple(CASES),
    extra: Sequence[str] = (),
    log: Callable[[str], None] | None = None,
    progress: Any = None,
    tables: Path | None = None,
) -> dict[str, Any]:
    """Run ``cases`` (names of :data:`CASES`) on ``base`` plus ``extra`` overrides into ``out/<case>/``
    (analytical/ and global/ per case; collective on ``comm``) and return the matrix data, written as
    ``verification.json`` with its markdown rendering ``verification.md`` into ``tables`` (default ``out``)
    on rank 0."""
    from rods.study import stages

    rows, t0 = [], time.perf_counter()
    for name in cases:
        sc = case_scene(base, name, extra)
        what = case_description(base, name)
        if log is not None:
            log(f"verification case '{name}': {what}")
        a = stages.analytical(sc, out / name / "analytical", comm)
        e = stages.analytical(sc.with_overrides(PAPER_LAW), out / name / "analytical-paper-law", comm)
        g = stages.global_model(sc, out / name / "global", comm, progress=progress, log=log)
        phase = plan.contact_phase(a.summary, sc.end_time)
        c = stages.global_model(finer(sc, phase), out / name / "global-finer", comm, progress=progress, log=log)
        hist = g.history if comm.rank == 0 else {}
        if comm.rank == 0:
            fe = {"summary": g.summary, "history": hist}
            ana, paper_law = ({"summary": r.summary, "history": r.history} for r in (a, e))
            rows.append(case_row(name, ana, fe, sc, c.summary, paper_law, what))
    data = {
        "base_scene": base.name,
        "extra_overrides": list(extra),
        "targets": TARGETS,
        "ranks": comm.size,
        "wall_time": max(comm.allgather(time.perf_counter() - t0)),  # [s] the slowest rank's
        "rows": rows,
    }
    if comm.rank == 0:
        tables = out if tables is None else Path(tables)
        io.write_data(tables / "verification.json", data)
        io.atomic_write_text(tables / "verification.md", render_markdown(data))
    return data


def duration_words(data: Mapping[str, Any]) -> str:
    """The duration target of a matrix's or a probe's ``data`` in words: in diameter transits with the range in µs
    its rows had (``duration_target``), or in µs (data written before the target was in the scene's time scale)."""
    t = data["targets"]
    if "duration_transits" not in t:
        return f"{t['duration'] * 1e6:g} µs"
    band = sorted({float(f"{r['duration_target'] * 1e6:.3g}") for r in data["rows"] if "duration_target" in r})  # [µs]
    here = "" if not band else f"{band[0]:g}" if len(band) == 1 else f"{band[0]:g}-{band[-1]:g}"
    return f"{t['duration_transits']:g} d/c of the thinner rod" + (f" ({here} µs here)" if here else "")


def _mark(ok: bool) -> str:
    return "" if ok else " ✗"


def render_markdown(data: Mapping[str, Any]) -> str:
    """verification.md from the matrix data (nothing else)."""
    t = data["targets"]
    lines = [
        "# Verification matrix: global FE model at default settings against the analytical model",
        "",
        f"Base scene `{data['base_scene']}`"
        + (f" with {', '.join(data['extra_overrides'])}" if data["extra_overrides"] else "")
        + f"; {data['ranks']} rank(s). Targets (issue 13): peak force within {t['peak_force']:g}%, first contact "
        f"duration within {duration_words(data)}, energy error below {t['energy']:g}. ✗ marks a miss. "
        "Strain RMS: midpoint strain over the first five periods 2 L2/c2 (rods.metrics.strain_window); strain lag: "
        "the shift of the FE strain that minimises it (negative: the FE leads). Mesh change: default mesh minus a "
        f"mesh {MESH_CHECK:g} x finer (over the contact phase); the gap to the analytical model is the latter's "
        f"model form where it exceeds {MODEL_FORM_RATIO:g} x that change or the refinement widens it. "
        f"The analytical model's contact law: {_laws(data['rows'])} (c: its rod-end term, rods.analytical; χ of ν, "
        "the cap's depth and the patch's size from static elasticity solves, "
        "[rod-end-compliance.md](rod-end-compliance.md), nothing fitted to these runs; each rod a bar of its own "
        "mass).",
        "",
        "| case | peak force FE [N] | vs analytical | mesh change | duration FE [µs] | Δ duration [µs] "
        "| mesh change [µs] | avg. peak speed vs analytical | strain RMS [µε] | strain lag [µs] | energy error "
        "| DOFs | steps | wall [s] |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in data["rows"]:
        p = r["passes"]
        lines.append(
            f"| {r['description']} | {r['peak_force_fe']:.1f} | {r['peak_force_pct']:+.3f}%{_mark(p['peak_force'])} "
            f"| {cell(r.get('peak_force_mesh_change_pct'), '+.3f', '%')} "
            f"| {cell(r['duration_fe'], '.2f', scale=1e6, missing=NOT_ENDED)} "
            f"| {cell(r['duration_difference'], '+.2f', scale=1e6)}{_mark(p['duration'])} "
            f"| {cell(r.get('duration_mesh_change'), '+.2f', scale=1e6)} "
            f"| {cell(r['peak_speed_pct'], '+.2f', '%')} | {cell(r['strain_rms'], '.2f', scale=1e6)} "
            f"| {cell(r.get('strain_lag'), '+.2f', scale=1e6)} "
            f"| {r['energy_error']:.1e}{_mark(p['energy'])} | {r['dofs']:,} | {r['steps']:,} | {r['wall_time']:.1f} |"
        )
    n_pass = sum(all(r["passes"].values()) for r in data["rows"])
    lines += ["", f"{n_pass} of {len(data['rows'])} cases meet every target."]
    misses = [r for r in data["rows"] if not r["passes"]["duration"]]
    open_rows = [r["description"] for r in data["rows"] if not measured(r["duration_fe"])]
    if open_rows:
        lines[-1] += (
            f" {NOT_ENDED}: the FE's first contact had not ended by end_time ({'; '.join(open_rows)}), so its "
            "duration is not compared; lengthen simulation.end_time."
        )
    form = [r for r in misses if r.get("duration_gap_is_model_form")]
    if form:
        worst = max(abs(r["duration_mesh_change"]) for r in form) * 1e6
        lines[-1] += (
            f" {len(form)} of the {len(misses)} duration misses are the analytical model's form, not the FE's "
            f"discretisation: there the gap is over {MODEL_FORM_RATIO:g} x the FE's own mesh change or the "
            f"refinement widens it (changes of at most {worst:.2f} µs)."
        )
    warned = [r for r in data["rows"] if r.get("warnings")]
    if warned:  # e.g. an average peak speed over fewer plateaus than it needs, at a shortened end time
        lines += ["", "The runs' own warnings (their figures in the row above are to be read with them):"]
        lines += [f"- {r['description']}: {w}" for r in warned for w in r["warnings"]]
    lines += _paper_law_table(data["rows"])
    return "\n".join(lines) + "\n"


def _laws(rows: Sequence[Mapping[str, Any]]) -> str:
    """The reference's contact law(s), each with its distinct rod-end terms c [µm/kN]."""
    laws: dict[str, list[str]] = {}
    for r in rows:
        c = laws.setdefault(f"`{r.get('contact_law')}`", [])
        if r.get("contact_compliance") and (x := f"{r['contact_compliance'] * 1e9:+.3f}") not in c:
            c.append(x)
    return "; ".join(law + (f", c = {', '.join(c)} µm/kN" if c else "") for law, c in laws.items()) or "–"


def _paper_law_table(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """The same FE runs against the analytical model with the paper's contact law (rows that carry it)."""
    rows = [r for r in rows if r.get("paper_law")]
    if not rows:
        return []
    lines = [
        "",
        "## Against the paper's contact law",
        "",
        f"`{PAPER_LAW}` (the paper's Eq. 8): Hertz's half-space approach, whose far field the 1D bars count a "
        "second time, so the contact is too compliant and lasts longer. Same FE runs, same targets.",
        "",
        "| case | duration analytical [µs] | Δ duration [µs] | peak force vs analytical "
        "| avg. peak speed vs analytical | strain RMS [µε] | strain lag [µs] |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        e, p = r["paper_law"], r["paper_law"]["passes"]
        lines.append(
            f"| {r['description']} "
            f"| {cell(e['duration_analytical'], '.2f', scale=1e6, missing=NOT_ENDED)} "
            f"| {cell(e['duration_difference'], '+.2f', scale=1e6)}{_mark(p['duration'])} "
            f"| {e['peak_force_pct']:+.3f}%{_mark(p['peak_force'])} | {cell(e['peak_speed_pct'], '+.2f', '%')} "
            f"| {cell(e['strain_rms'], '.2f', scale=1e6)} | {cell(e['strain_lag'], '+.2f', scale=1e6)} |"
        )
    n_pass = sum(all(r["paper_law"]["passes"].values()) for r in rows)
    gaps = [abs(d) for r in rows if measured(d := r["paper_law"]["duration_difference"])]
    within = f"; durations within {max(gaps) * 1e6:.2f} µs" if gaps else ""
    lines += ["", f"{n_pass} of {len(rows)} cases meet every target{within}."]
    return lines
