"""Scenes: one impact described in TOML, validated before anything runs.

A scene file has the tables ``[rod1]``, ``[rod2]`` (each with a ``[rodN.material]`` table),
``[impact]``, ``[simulation]`` and optional ``[analytical]``, ``[fe]``, ``[[station]]`` and a
top-level ``effects`` list. Every value is in SI units. ``load_scene(path, overrides)`` applies
command-line overrides (``impact.speed=1.848``) *before* validation, so overrides pass the same
checks as the file. Any problem raises :class:`SceneError` naming the key, the value and the
allowed range; nothing is run or written on a bad scene.
"""

from __future__ import annotations

import copy
import dataclasses
import difflib
import json
import math
import numbers
import re
import tomllib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from decimal import Decimal
from functools import cached_property
from pathlib import Path
from typing import Any

from rods.preflight import short

__all__ = [
    "EFFECTS",
    "Material",
    "Rod",
    "Scene",
    "SUBMODEL_LEVELS",
    "SUBMODEL_LEVEL_SIZES",
    "SUBMODEL_PHASES",
    "submodel_phase_size",
    "SUBMODEL_EFFECTS",
    "SceneError",
    "Station",
    "auto_end_time",
    "auto_output_interval",
    "check_submodel_length",
    "cut_record_end",
    "cut_records",
    "impedance_force",
    "last_per_key",
    "values_without",
    "first_difference",
    "load_scene",
    "nearest_key",
    "override",
    "parse_override",
    "scene_from_dict",
    "scene_from_summary",
]

EFFECTS = ("wave_response", "contact_patch", "subsurface_stress", "fields", "misalignment")
FE_KINDS = ("axisymmetric", "3d")
SYMMETRIES = ("full", "half", "quarter")
# array backends of the explicit loop (rods.fe.backend): petsc = the MPI path; numpy, cupy serial; auto = cupy on a GPU
FE_BACKENDS = ("petsc", "numpy", "cupy", "auto")
# how the loop applies K (rods.fe.matrixfree): the assembled matrix, or element by element on an array backend
FE_OPERATORS = ("assembled", "matrix-free")
# the axisymmetric mesh across a rod (rods.fe.layout.radial_columns): uniform at fe.radial_size, or that size in a core
# around the patch (CORE_RADII x a_P) growing outward to the bar's size; auto grades where that halves a rod's elements
RADIAL_GRADINGS = ("auto", "uniform", "graded")
RADIAL_COARSENINGS = ("auto", "none")  # fe.radial_coarsening: rods.fe.layout.coarsening
# submodel mesh levels -> uniform element size across and along [m] (paper: coarse/mid/fine = 0.25/0.125/0.0625
# mm; each level halves the last, so any three consecutive levels have the Richardson ratio 2). The levels below
# ultra-fine serve small rods' patches ("auto" picks them where a_P < 0.0625 mm: 2 mm rods with a 5 mm tip at
# 1 m/s, a = 0.127 mm, had -2.2% peak pressure at ultra-fine, 8 elements across); those above coarse serve large
# ones (a_P > 2 mm: 100 mm rods with a 200 mm tip at 1 m/s, a_P = 5.9 mm, put 24/48/95 elements across the patch at
# coarse/mid/fine, 3.7 h for the fine level on one core). The ladder spans the element sizes the schema accepts
# (fe.radial_size 1e-8 to 0.1 m; a rod's radius / BAR_ELEMENTS is at most 62.5 mm): elastodynamics with Hertz
# contact has no length of its own, so "auto" finds three levels on every scene of the schema's range (an audit,
# 2026-12-07: ending at 1.95 µm, the paper scene x 0.01 took three levels from 7.8 µm, coarser than its global,
# and x 0.001 levels wider than its rods). The one definition: rods.fe.submodel.LEVEL_SIZES is this table (kept
# here so that scenes validate without DOLFINx).
SUBMODEL_LEVEL_SIZES = {
    **{f"ultra-coarse-x{2**k}": 2**k * 1e-3 for k in range(6, 0, -1)},  # [m] 64 mm down to 2 mm
    "ultra-coarse": 1e-3,  # [m]
    "extra-coarse": 0.5e-3,  # [m]
    "coarse": 0.25e-3,  # [m]
    "mid": 0.125e-3,  # [m]
    "fine": 0.0625e-3,  # [m]
    "extra-fine": 0.03125e-3,  # [m]
    "ultra-fine": 0.015625e-3,  # [m]
    **{f"ultra-fine-x{2**k}": 0.015625e-3 / 2**k for k in range(1, 11)},  # [m] 7.8 µm down to 15 nm
}
SUBMODEL_LEVELS = tuple(SUBMODEL_LEVEL_SIZES)
# meshes per submodel level in the phase-averaged convergence study (submodel_phase_size); the middle one is the
# level's own size [-]
SUBMODEL_PHASES = 5


def submodel_phase_size(h: float, a: float, phase: int, phases: int = SUBMODEL_PHASES) -> float:
    """Element size [m] of member ``phase`` (0 .. ``phases`` - 1) of the level of size ``h`` [m], for a contact
    radius about ``a`` [m].

    The node-based contact closes node by node, so the discrete contact radius depends on where the edge falls
    between two nodes, by about ±0.4% of a at 0.125 mm and ±0.2% at 0.0625 mm on the paper scene
    (results/edge-scatter.md), more than a halving of h changes it. That scatter is a function of the edge's
    phase a/h mod 1; the members place the edge at ``phases`` equally spaced phases around the level's own,
    a/h_k = a/h + (k - (phases - 1)/2)/phases (stratified over one period, the middle member is h itself), so the
    mean over the members cancels the scatter's harmonics below ``phases`` and leaves the trend in h.
    ``a`` need only be within some ten per cent (the analytical model's Hertz radius serves): the members then
    span 0.9 to 1.1 periods instead of one."""
    if not (h > 0 and a > 0 and 0 <= phase < phases):
        raise ValueError(f"submodel phase: need h > 0, a > 0 and 0 <= phase < {phases} (h={h}, a={a}, {phase=})")
    return a / (a / h + (phase - (phases - 1) / 2) / phases)


# contact force laws: rods.fe.contact (penalty, the paper's) and rods.fe.kinematic (Lagrange, penalty-free)
CONTACT_LAWS = ("penalty", "kinematic")
ANALYTICAL_CONTACT_LAWS = ("hertz", "hertz-rod")  # rods.analytical: the contact law of the 1D model
SUBMODEL_DRIVINGS = ("displacement", "traction", "mixed")  # rods.fe.submodel.make_driver
SUBMODEL_EFFECTS = ("contact_patch", "subsurface_stress")  # the effects that run the submodel (rods.plan)


# scene keys that save a run's state and never change it: a restart may change them (turn periodic checkpoints on),
# a study keeps its finished stages across them (rods.fe.checkpoint, rods.study.stages)
RESULT_NEUTRAL = ("fe.checkpoint_interval",)

# keys whose "auto" a Scene resolves -> the property that does ([] reads the resolved value)
_RESOLVED = {
    "simulation.end_time": "end_time",
    "simulation.output_interval": "output_interval",
    "fe.radial_size": "radial_size",
    "fe.axial_size": "axial_size",
    "submodel.levels": "submodel_levels",
    "fe.submodel_length": "submodel_length",
    "fe.penalty": "penalty",
}
# the keys whose value a record (Scene.as_dict, json_safe) holds resolved: the times and sizes the run used
_RECORDED_RESOLVED = ("simulation.end_time", "simulation.output_interval", "fe.radial_size", "fe.axial_size",
                      "fe.submodel_length")  # fmt: skip
RESOLVED_KEYS = (*_RESOLVED, "fe.tip_grading")  # the keys whose "auto" follows from others (as_dict resolves them)


class SceneError(ValueError):
    """A scene value is missing, unknown, of the wrong type or out of range."""

    def __init__(self, key: str, value: Any, allowed: str, hint: str = "", argument: bool = False):
        self.key, self.value, self.allowed, self.hint = key, value, allowed, hint
        # a command-line argument (--scene) is no scene key; a scene file's key named "--x" still is one
        what = key if argument else f"scene key '{key}'"
        msg = f"{what} = {short(value)}: {allowed}"  # a 200k-entry list stays one short line
        if hint:
            msg += f" ({hint})"
        super().__init__(msg)


# --------------------------------------------------------------------------------------------
# Schema: key -> (kind, default, check).  REQUIRED marks keys without a default.
# kind: "float", "int", "str", "list[str]", "float|auto"; check(key, value) raises SceneError.
# --------------------------------------------------------------------------------------------
REQUIRED = object()
# the paper's scene (Table 1's rods at 2.197 m/s), which the main job runs
PAPER_SCENE = Path(__file__).resolve().parents[1] / "workflows" / "scenes" / "paper.toml"


def _positive(unit: str, hi: float = math.inf, hint_hi: str = "", lo: float = 0.0, hint_lo: str = ""):
    """Check 0 < value <= hi, or lo <= value <= hi where a floor ``lo`` > 0 is given: a length, time or speed far
    below any continuum scene (:data:`TINY`), whose counts (cells, steps, samples) would overflow a float, or a
    material constant below any solid's; ``hint_hi`` and ``hint_lo`` explain a too-large or too-small value (often
    wrong units)."""
    span = f"({lo:g}, {hi:g}]" if lo == 0.0 else f"[{lo:g}, {hi:g}]"

    def check(key: str, v: float) -> None:
        if not (v > 0.0 and v >= lo):
            if lo > 0.0:
                hint = (hint_lo or "the floor: a smaller value is below any continuum scene") if v > 0.0 else ""
                raise SceneError(key, v, f"must be in {span} {unit}", hint)
            raise SceneError(key, v, f"must be > 0 {unit}" if hi == math.inf else f"must be in {span} {unit}")
        if v > hi:
            raise SceneError(key, v, f"must be in {span} {unit}", hint_hi)

    return check


def _interval(lo: float, hi: float, unit: str = "", closed_lo: bool = False, closed_hi: bool = False):
    def check(key: str, v: float) -> None:
        ok_lo = v >= lo if closed_lo else v > lo
        ok_hi = v <= hi if closed_hi else v < hi
        if not (ok_lo and ok_hi):
            br = ("[" if closed_lo else "(") + f"{lo:g}, {hi:g}" + ("]" if closed_hi else ")")
            raise SceneError(key, v, f"must be in {br} {unit}".rstrip())

    return check


def _only(value: Any, why: str):
    """A key with one supported value (kept in the schema so that scenes may state it)."""

    def check(key: str, v: Any) -> None:
        if v != value:
            raise SceneError(key, v, f"must be {value} ({why})")

    return check


def _choice(options: Iterable[str]):
    opts = tuple(options)

    def check(key: str, v: str) -> None:
        if v not in opts:
            raise SceneError(key, v, f"must be one of {', '.join(opts)}")

    return check


def _choices(options: Iterable[str], noun: str = "entry"):
    """Check a list whose entries come from ``options`` and do not repeat."""
    opts = tuple(options)

    def check(key: str, v: list[str]) -> None:
        for e in v:
            if e not in opts:
                raise SceneError(key, e, f"unknown {noun}; known: {', '.join(opts)}")
        if len(set(v)) != len(v):
            raise SceneError(key, v, "entries must not repeat")

    return check


MAX_TIP_RADIUS = 1e4  # [m] a curved tip's largest radius: the Hertz stiffness grows as sqrt(R), and at 1e300 m the
# analytical model's contact is so stiff that its integration did not end (1e3, 1e4, 1e6 m: 1.8, 2.4, 7.0 s)


# floors of the lengths, times and speeds [m, s, m/s]: far below any continuum scene (a micrometre rod crosses its
# diameter in ~1e-10 s), but above where a scene's cell, step and sample counts overflow a float (5e-324 m/s, a
# 1e-160 m element: OverflowError and ZeroDivisionError instead of a refusal naming the key)
TINY = {"diameter": 1e-6, "size": 1e-8, "time": 1e-12, "dt": 1e-15, "speed": 1e-9}
MAX_SIZE = 0.1  # largest fe.axial_size and fe.radial_size [m]
MIN_YIELD_STRAIN = 1e-5  # lowest yield_strength / youngs_modulus accepted: a tenth of the softest metals' [-]


def _tip_radius(key: str, v: float) -> None:
    """A tip radius: inf (flat) or in (0, MAX_TIP_RADIUS] m."""
    if v != math.inf:
        _positive("m (inf = flat)", hi=MAX_TIP_RADIUS, hint_hi="a flatter tip is flat for the contact: use inf")(key, v)


def _rod_schema(n: int) -> dict[str, tuple[str, Any, Callable | None]]:
    p = f"rod{n}"
    return {
        f"{p}.length": ("float", REQUIRED, _positive("m", hi=20.0, hint_hi="looks like millimetres; give metres")),
        f"{p}.diameter": (
            "float",
            REQUIRED,
            _positive("m", hi=1.0, hint_hi="looks like millimetres; give metres", lo=TINY["diameter"]),
        ),
        f"{p}.tip_radius": ("float|inf", math.inf, _tip_radius),
        f"{p}.material.density": (
            "float",
            REQUIRED,
            _positive("kg/m^3", hi=1e5, lo=100.0, hint_lo="looks like g/cm^3; give kg/m^3"),
        ),
        f"{p}.material.youngs_modulus": (
            "float",
            REQUIRED,
            _positive("Pa", hi=1e13, lo=1e6, hint_lo="looks like GPa or MPa; give Pa"),
        ),
        f"{p}.material.poisson_ratio": ("float", REQUIRED, _interval(-1.0, 0.5)),
        f"{p}.material.yield_strength": ("float|none", None, _positive("Pa", hi=1e11)),
    }


# simulation.end_time = "auto" (auto_end_time): the time the effects need, END_MARGIN x the longer of the Rod-2
# midpoint's END_PERIODS periods 2 L2/c2 (the strain window and the plateaus the wave response compares,
# rods.metrics.STRAIN_PERIODS and PLATEAU_COUNT; a test ties them) and END_CONTACT_ROUND_TRIPS round trips of the
# slower rod (a first contact ends within them: the striker's wave returns after one). The paper's rods: 1.507 ms, the
# 1.5 ms its Fig. 4 spans; it was 1.5 ms on every scene (2 m rods: 1.9 of their five periods, 3 of 5 plateaus;
# 3 cm rods ran 23 times the 64 µs they need).
END_PERIODS = 5  # [-]
END_CONTACT_ROUND_TRIPS = 2  # [-]
END_MARGIN = 1.1  # [-]
# simulation.output_interval = "auto" (auto_output_interval): this many samples a diameter's transit d/c of the thinner
# rod's (the period scale of the lateral ringing that shapes the force's rise and the midpoint's plateau fronts,
# rods.checks): the paper's rods 0.248 µs, the 0.25 µs it states; it was 0.25 µs on every scene (a 2 mm rod's d/c,
# 0.4 µs, got under two samples) ...
SAMPLES_PER_DIAMETER_TRANSIT = 10  # [-]
AUTO_SAMPLES_MAX = 2e5  # ... and at most this many over the run (a soft rod's long run: its histories) [-]
# field frames when the "fields" effect asks without fe.field_interval: this many a round trip 2 L/c of the rod whose
# round trip is the shortest (a wave crosses it in five frames: the paper's Rod 1, 97.6 µs, a frame every 9.76 µs;
# a 5 cm rod's waves, crossing it in 10 µs, were one frame a transit at the 10 µs it was on every scene) [-] ...
FIELD_FRAMES_PER_ROUND_TRIP = 10
FIELD_FRAMES_DEFAULT_MAX = 400  # ... and at most this many over the run (a short rod's long run: its files) [-]
PATCH_ELEMENTS = 4  # fe.radial_size = "auto": elements across the expected contact radius [-] (Scene.radial_size)
# ... where the first contact's peak rests on the contact stiffness (Scene.stiffness_sensitivity S at or above the
# ramp's top), and linearly in S between the ramp's ends: the patch's discretisation error in the contact's
# stiffness reaches the peak force times S, nothing where the force is impedance-bound (S -> 0)
PATCH_ELEMENTS_STIFF = 6  # [-]
SENSITIVITY_RAMP = (0.02, 0.1)  # [-]
# ... and, where S is larger, enough that S times the discretised patch's stiffness ripple stays within PEAK_SHARE of
# the peak force: the ripple, measured as the peak's error / S at PATCH_ELEMENTS_STIFF elements (0.70-1.27% on four
# scenes of S 0.23-0.68, Scene.patch_elements), falls as 1/n² (a drawn S = 0.66 scene's FE-analytical band over the
# force's rise: 2.0 / 1.06 / 0.69 points at 6 / 8 / 10 elements)
PATCH_RIPPLE = 0.013  # the patch stiffness's relative ripple at PATCH_ELEMENTS_STIFF elements [-]
# the peak force's accuracy target against the analytical model (issue 13's acceptance; the study's agreement check,
# rods.checks.AGREE_FORCE, and the patch count's share of it, PEAK_SHARE) [-]
PEAK_FORCE_TARGET = 0.005
PEAK_SHARE = PEAK_FORCE_TARGET / 2  # of it, the patch's stiffness ripple's share [-]
BAR_ELEMENTS = 8  # ... and at least this many across the thinner rod's radius [-]
# fe.penalty = "auto" (Scene.penalty): at least this factor x E*/h [-]. With the default contact damping, over x0.5
# to x4 of it the peak force moved < 0.06% and the first contact < 0.6 µs on the paper rods at 2.197 and 1.0 m/s
# (results/contact-study.md), its layer 1.6% of Hertz's approach on the 4 elements across the patch auto puts ...
PENALTY_FACTOR = 10.0
PENALTY_MAX = 1e4  # the largest fe.penalty and submodel.penalty [x E*/h], and so the most "auto" gives
# ... and stiff enough that its layer's delay of the contact, the layer's share of the approach times the time the
# impact speed takes to close it, share x t_P, stays within this many diameter transits d/c of the thinner rod [-] (the
# scale of the duration's targets, rods.checks.agree_duration; so geometrically similar scenes get the same factor):
# the layer adds share x δ to the approach. An audit (2026-12-08, eight scenes at 10 x E*/h, damped) found the
# duration's spread over x0.5 to x4 1.6 to 2.6 x share x t_P (0.15 µs on a drawn scene with t_P = 5.4 µs; 1.18 and
# 1.27 µs, over issue 13's 1 µs, on two slow contacts with t_P = 43 and 52 µs), so 0.1 d/c (0.25 µs on the paper's
# 12.7 mm rods) holds it to ~0.26 d/c (0.65 µs there). The paper scene's factor stays 10 ...
LAYER_DELAY_TRANSITS = 0.1
# ... and at most this [s]: the 1 µs is a time, and 0.1 d/c of a thicker rod let it pass (20 mm rods at
# 0.5 m/s, d/c = 3.9 µs: 1.02 µs over x0.5 to x4, 0.26 d/c; 2026-12-08), so rods thicker than the paper's (steel
# 12.7 mm) get the paper's delay, and only scenes up to that size are similar in their factor
LAYER_DELAY_MAX = 0.25e-6
# a graded mesh (fe.radial_grading) keeps fe.radial_size out to this many Hertz radii a_P from the axis [-]: the
# patch (a <= a_P) and the ring around it where Hertz's stresses still vary on the patch's scale (their gradients
# fall as (a/r)^3 outside it); the elements then grow by rods.fe.layout.GROWTH per element to the bar's size
CORE_RADII = 3.0
AXIAL_PER_DIAMETER = 12.7  # fe.axial_size = "auto": at most the thinner rod's diameter / this (the paper's 1 mm) [-]
# fe.submodel_length = "auto": the cut planes this many diameters of the thicker rod from the tips [-]: past the
# contact's Saint-Venant zone (about one diameter), where the section's stress is the bar's (the paper's 14 mm cut
# on its 12.7 mm rods, so the paper scene's auto is its 14 mm exactly); > 2 cap heights by construction (a cap is
# at most a radius high)
SUBMODEL_DIAMETERS = 14e-3 / 12.7e-3  # [-]
# the submodel's cut band (rods.fe.cut: the global's recorded nodes around each cut plane, the driver's interpolation
# and traction support) reaches this many global axial elements either side of the plane [-]
BAND_ELEMENTS = 2
# ... and at most the wavelength c t_rise of the contact force's rise / this [-] (Scene.axial_size: 50 left the
# ringing overshoot of a force rising in 3-3.5 transits to the mesh, measured there)
RISE_ELEMENTS = 75

SCHEMA: dict[str, tuple[str, Any, Callable | None]] = {
    "name": ("str", "", None),
    "description": ("str", "", None),
    "effects": ("list[str]", ["wave_response"], _choices(EFFECTS, "effect")),
    **_rod_schema(1),
    **_rod_schema(2),
    "impact.speed": ("float", REQUIRED, _positive("m/s", hi=100.0, hint_hi="low-speed impact model", lo=TINY["speed"])),
    "impact.offset": ("float", 0.0, _interval(0.0, 1.0, "m", closed_lo=True)),
    "impact.tilt": ("float", 0.0, _interval(0.0, 0.1, "rad", closed_lo=True)),
    "simulation.end_time": ("float|auto", "auto", _positive("s", hi=1.0, lo=TINY["time"])),  # auto: auto_end_time
    # auto: auto_output_interval
    "simulation.output_interval": ("float|auto", "auto", _positive("s", hi=1e-3, lo=TINY["time"])),
    # below 2.2e-14 SciPy's integrator raises it itself, with a warning
    "analytical.rtol": ("float", 1e-10, _interval(1e-13, 1e-2, closed_lo=True, closed_hi=True)),
    # hertz-rod: Hertz's half-space approach less the rods' end correction, which the 1D bars already carry
    # (rods.analytical; within 0.35 µs of the default FE contact on results/verification.md's six scenes);
    # hertz: the paper's law (Eq. 8), about 1-4 µs longer contacts than the FE's
    "analytical.contact": ("str", "hertz-rod", _choice(ANALYTICAL_CONTACT_LAWS)),
    "fe.kind": ("str", "axisymmetric", _choice(FE_KINDS)),
    # auto: the paper's 1 mm on its 12.7 mm rods (diameter / AXIAL_PER_DIAMETER), finer where the contact force
    # rises so fast that the rods ring (Scene.axial_size: a stiff, wide contact)
    "fe.axial_size": ("float|auto", "auto", _positive("m", hi=MAX_SIZE, lo=TINY["size"])),
    # auto: 4-13.7 elements across the expected contact radius (Scene.radial_size, Scene.patch_elements: 6 and more
    # where the peak rests on the contact stiffness), so any scene's patch is resolved (the paper's mesh, 0.25 mm, is
    # what auto gives there, 0.27 mm; at 0.05 m/s it gives 0.043 mm)
    "fe.radial_size": ("float|auto", "auto", _positive("m", hi=MAX_SIZE, lo=TINY["size"])),
    # auto: the tip elements as long as they are wide (fe.radial_size), so the contact patch is resolved
    "fe.tip_grading": ("float|auto", "auto", _interval(0.05, 1.0, closed_lo=True, closed_hi=True)),
    # axisymmetric only (the 3D section is an O-grid at fe.radial_size): rods.fe.layout.radial_columns; the submodels'
    # too, one for all levels (rods.fe.submodel.submodel_grading)
    "fe.radial_grading": ("str", "auto", _choice(RADIAL_GRADINGS)),
    # axisymmetric global only: "auto" merges a rod's columns 3:1 along it, past its contact's zone and any submodel
    # cut, down to the bar's size across (rods.fe.layout.coarsening); "none": the columns run the rod's whole length
    "fe.radial_coarsening": ("str", "auto", _choice(RADIAL_COARSENINGS)),
    # the explicit model is Q1 only: row-sum lumped Q2 masses vanish on the axis (∫ N_0 r dr = 0 at the P2 axis
    # vertex) and the 3D contact pairs Q1 face quadrilaterals; refused here, not after the analytical stage ran
    "fe.degree": ("int", 1, _only(1, "the explicit model is Q1: row-sum lumped Q2 masses vanish on the axis")),
    "fe.dt": ("float|auto", "auto", _positive("s", hi=1e-3, lo=TINY["dt"])),
    # of the stable step; below 1e-3 a run takes 1000 x the steps it needs for nothing
    "fe.dt_fraction": ("float", 0.8, _interval(1e-3, 1.0, closed_lo=True, closed_hi=True)),
    "fe.contact": ("str", "kinematic", _choice(CONTACT_LAWS)),
    # penalty law only. auto: Scene.auto_penalty, at least PENALTY_FACTOR x E*/h, stiffer where the layer would
    # lengthen a slow contact by more than LAYER_DELAY_TRANSITS d/c; step ~ 1/sqrt(factor). Softer layers lengthen
    # the contact (paper scene: 1 x +1.8 µs, 0.1 x +13.5 µs, 0.01 x +83 µs and -6.7% force): a run whose layer
    # penetrates more than rods.checks.LAYER_SHARE_OK of Hertz's approach warns (rods.checks.contact_layer_warning)
    "fe.penalty": ("float|auto", "auto", _positive("x E*/h", hi=PENALTY_MAX)),
    # penalty law only: viscous damping of each contact pair, fraction of critical (rods.fe.contact)
    "fe.contact_damping": ("float", 0.2, _interval(0.0, 0.5, "of critical", closed_lo=True, closed_hi=True)),
    # stiffness-proportional damping C = β K, β = 2 ξ/ω_max: ξ of critical in the highest mode (rods.fe.explicit; not
    # Abaqus's volumetric bulk viscosity: it damps every strain rate), the stable step shortened by sqrt(1 + ξ²) - ξ
    "fe.bulk_viscosity": ("float", 0.0, _interval(0.0, 1.0, closed_lo=True)),
    "fe.field_interval": ("float", 0.0, _interval(0.0, 1.0, "s (0 = no fields)", closed_lo=True)),
    "fe.symmetry": ("str", "full", _choice(SYMMETRIES)),
    # auto: SUBMODEL_DIAMETERS x the thicker rod's diameter (the paper's 14 mm on its 12.7 mm rods;
    # Scene.submodel_length)
    "fe.submodel_length": ("float|auto", "auto", _positive("m", hi=20.0, lo=TINY["diameter"])),
    "fe.checkpoint_interval": ("float", 0.0, _interval(0.0, 1.0, "s (0 = no checkpoints)", closed_lo=True)),
    # the guard catches instabilities, which grow the energy by orders of magnitude; below 1e-5 the round-off of the
    # energy sums (~1e-9 of E0 on the default contact) and the penalty law's O(Δt²) energy wobble (3e-7 damped, 1.1e-6
    # undamped at 10 x E*/h, measured) stop stable runs
    "fe.energy_growth_limit": (
        "float",
        0.05,
        _interval(
            1e-5,
            10.0,
            "(relative energy growth that stops a run; below 1e-5 round-off and a contact's wobble stop stable runs)",
            closed_lo=True,
        ),
    ),
    "fe.backend": ("str", "petsc", _choice(FE_BACKENDS)),
    "fe.operator": ("str", "assembled", _choice(FE_OPERATORS)),
    # auto: three consecutive levels from the coarsest that resolves the expected patch (Scene.submodel_levels)
    "submodel.levels": ("list[str]|auto", "auto", _choices(SUBMODEL_LEVELS)),
    # the submodel's own contact layer under the penalty law (fe.penalty is the global's); auto: as fe.penalty's, on
    # each level's own size (Scene.submodel_penalty)
    "submodel.penalty": ("float|auto", "auto", _positive("x E*/h", hi=PENALTY_MAX)),
    # how the global drives the submodel's cuts: mixed (its traction plus a dashpot to its velocity, rods.fe.traction),
    # its traction alone, or its displacement (the paper's)
    "submodel.driving": ("str", "mixed", _choice(SUBMODEL_DRIVINGS)),
}


def _type_check(key: str, kind: str, v: Any) -> Any:
    """Coerce and check the TOML value's type; NaN is never allowed, inf only where stated."""
    if kind == "str":
        if not isinstance(v, str):
            raise SceneError(key, v, "must be a string")
        return v
    if kind == "list[str]|auto" and v == "auto":
        return v
    if kind in ("list[str]", "list[str]|auto"):
        if isinstance(v, str):
            v = [v]
        if not isinstance(v, list | tuple) or not all(isinstance(e, str) for e in v):  # a library caller's tuple too
            raise SceneError(key, v, "must be a list of strings")
        return list(v)
    if kind == "float|auto" and v == "auto":
        return v
    if kind == "float|none" and (v is None or v == "none"):  # TOML has no null: "none" unsets a base's value
        return None
    if kind == "int":  # numbers.Integral: a library caller's NumPy integer too (np.int64 is no int)
        if isinstance(v, bool) or not isinstance(v, numbers.Integral):
            raise SceneError(key, v, "must be an integer")
        return int(v)
    if isinstance(v, bool) or not isinstance(v, numbers.Real):  # a NumPy number too (np.float32, np.int64)
        extra = {"float|auto": " or 'auto'", "float|none": " or 'none' (not stated)"}.get(kind, "")
        raise SceneError(key, v, f"must be a number{extra}", _number_example(key))
    try:
        v = float(v)
    except OverflowError:  # an integer beyond float64
        big = f"<an integer of {v.bit_length()} bits>"
        raise SceneError(key, big, "must be a number a float64 holds (below 1.8e308)") from None
    if math.isnan(v):
        raise SceneError(key, v, "must not be NaN")
    if math.isinf(v) and kind != "float|inf":
        raise SceneError(key, v, "must be finite")
    return v


def _number_example(key: str) -> str:
    """A remedy for a value that is no number: the key with its default, or else its value in the paper scene
    (:data:`PAPER_SCENE`, read only here, on the error's path), in SI units."""
    default = SCHEMA.get(key, (None, None))[1]
    if default is REQUIRED or default is None or isinstance(default, str):
        try:
            default = _flatten(tomllib.loads(PAPER_SCENE.read_text(encoding="utf-8"))).get(key)
        except (OSError, tomllib.TOMLDecodeError):  # an install without the workflows folder: no example
            default = None
    return "" if not isinstance(default, int | float) else f"e.g. {key}={default!r} (SI units)"


def _flatten(d: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Dotted keys of a parsed scene's tables. A table given where a value belongs (``impact.speed = {}``) stays a
    value, refused by its type (an empty one vanished before: the key took its default, silently); a key set twice
    through a quoted dotted key and its table (``"rod1.length" = 0.3`` beside ``[rod1] length = 0.2``) is refused
    (one of the two was dropped, silently). An empty table that is no scene table (``[simulaton]`` with no keys) stays
    a key, refused as unknown (it vanished before: a fuzz, 2026-12-07)."""
    out: dict[str, Any] = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        # an empty table is a table only where the scene has one of that name (else a key, refused as unknown)
        table = (
            isinstance(v, Mapping) and key not in SCHEMA and (bool(v) or any(s.startswith(key + ".") for s in SCHEMA))
        )
        items = _flatten(v, key + ".") if table else {key: v}
        for name, value in items.items():
            if name in out:
                raise SceneError(name, value, "is given twice (a quoted dotted key and its table)", "remedy: keep one")
            out[name] = value
    return out


def values_without(values: Mapping[str, Any], keys: Iterable[str], default: bool = False) -> dict[str, Any]:
    """Nested scene values (Scene.as_dict) as summary.json and a checkpoint's manifest hold them (a JSON round trip),
    ``keys``' dotted keys dropped: what a kept stage or a checkpoint is compared by, less what it does not read
    (rods.study.stages, rods.fe.checkpoint); with ``default``, set to their schema defaults instead (a digest that
    stays the one of a scene that never set them: rods.preflight.scene_folder)."""
    out = json.loads(json.dumps(values))
    for key in keys:
        *parents, leaf = key.split(".")
        node = out
        for k in parents:
            node = node.get(k, {}) if isinstance(node, dict) else {}
        if isinstance(node, dict) and leaf in node:
            if default:
                node[leaf] = SCHEMA[key][1]
            else:
                del node[leaf]
    return out


def value_differences(ours: Any, theirs: Any, key: str = "") -> list[tuple[str, Any, Any]]:
    """(dotted key, our value, their value) of every difference of two nested scene values (Scene.as_dict, as
    summary.json and the run records hold them), in key order; a whole mismatch at the top is named "scene"."""
    if isinstance(ours, Mapping) and isinstance(theirs, Mapping):
        found: list[tuple[str, Any, Any]] = []
        for k in sorted(set(ours) | set(theirs), key=str):
            found += value_differences(ours.get(k), theirs.get(k), f"{key}.{k}" if key else str(k))
        return found
    return [] if ours == theirs else [(key or "scene", ours, theirs)]


def first_difference(ours: Any, theirs: Any, ignore: Iterable[str] = ()) -> tuple[str, Any, Any] | None:
    """The difference a refusal names between two nested scene values (Scene.as_dict, as a summary or a checkpoint's
    manifest holds them), ``ignore``'s keys left out: a key given before one an "auto" derives from it
    (:data:`RESOLVED_KEYS`), else the first in key order; None where they agree (a restart's refusals,
    rods.fe.checkpoint and rods.study.pipeline)."""
    diffs = value_differences(values_without(ours, ignore), values_without(theirs, ignore))
    given = [d for d in diffs if d[0] not in RESOLVED_KEYS]
    return (given or diffs)[0] if diffs else None


MAX_NESTING = 32  # [-] deepest list/table nesting a scene holds (its deepest is 3: [[station]] in a file); deeper
# input overflowed Python's recursion in tomllib, copy.deepcopy or _flatten (a fuzz: exit 1, "RecursionError")


def _nesting(value: Any) -> int:
    """How deep ``value``'s lists and tables nest (iterative: it must not recurse on what it guards against)."""
    deepest, todo = 0, [(value, 0)]
    while todo:
        v, depth = todo.pop()
        deepest = max(deepest, depth)
        if depth <= MAX_NESTING and isinstance(v, Mapping | list | tuple):
            todo.extend((e, depth + 1) for e in (v.values() if isinstance(v, Mapping) else v))
    return deepest


def _too_deep(key: str, raw: Any, argument: bool = False) -> SceneError:
    return SceneError(
        key,
        raw,
        f"nests lists or tables deeper than {MAX_NESTING} levels",
        "give numbers, strings and flat lists (README 'Scenes')",
        argument=argument,
    )


def _check_nesting(key: str, value: Any, raw: Any, argument: bool = False) -> None:
    if _nesting(value) > MAX_NESTING:
        raise _too_deep(key, raw, argument)


def parse_override(text: str) -> tuple[str, Any]:
    """Parse ``KEY=VALUE``; VALUE is read as a TOML value, else kept as a bare string."""
    if "=" not in text:
        raise SceneError(text, None, "an override must look like KEY=VALUE, e.g. impact.speed=1.848")
    key, raw = (s.strip() for s in text.split("=", 1))
    if not key:
        raise SceneError(text, None, "an override needs a key before '='")
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
        if isinstance(value, float) and math.isinf(value) and "inf" not in raw.lower():  # 1e400 reads as inf
            raise SceneError(key, raw, "must be a number a float64 holds (below 1.8e308)")
        _check_nesting(key, value, raw)
    except RecursionError:  # tomllib's parser recurses once per '[' or '{'
        raise _too_deep(key, raw) from None
    except tomllib.TOMLDecodeError as e:
        if raw[:1] and raw[:1] in "[{\"'":  # meant as a TOML list, table or string: a bare string would hide the slip
            kind = SCHEMA.get(key, ("",))[0]
            example = f'{key}="text"' if kind == "str" else 'effects=["contact_patch"]'  # ("" was in every string)
            remedy = f"e.g. --set '{example}' (quote the whole --set for the shell)"
            raise SceneError(key, raw, f"malformed TOML value ({str(e).splitlines()[0]})", remedy) from None
        value = raw
    return key, value


def _apply_override(data: dict[str, Any], key: str, value: Any) -> None:
    # stations are a list of tables: an override gives the whole list (TOML inline tables), never one field of one
    if key == "station":
        data["station"] = value  # checked with the scene (rods.scene._stations)
        return
    if key.split(".")[0].split("[")[0] == "station":
        why = "stations are a list of tables and are given whole, not one field"
        raise SceneError(key, value, why, "--set 'station=[{rod = 1, position = 0.1, name = \"gauge\"}]'")
    if key not in SCHEMA:
        raise SceneError(key, value, _unknown_msg(key))
    *parents, leaf = key.split(".")
    node = data
    for p in parents:
        node = node.setdefault(p, {})
        if not isinstance(node, dict):
            raise SceneError(p, node, "must be a table")
    node[leaf] = value


def _unknown_msg(key: str) -> str:
    """'unknown key', the nearest known key when one is close (a typo, a missing table: 'end_time' ->
    'simulation.end_time'), then the keys of its table, else of the nearest key's table (all ~60 keys, a 900-character
    line, only where neither is known)."""
    hint = nearest_key(key)
    head = key.split(".")[0]
    if not any(k.split(".")[0] == head for k in SCHEMA) and hint is not None:
        head = hint.split(".")[0]
    if key == "base":  # a scene file's own key, not a value to set
        return (
            "unknown as an override: base names a scene file's base (remedy: --scene FILE, whose base = ... it reads)"
        )
    near = sorted(k for k in SCHEMA if k.split(".")[0] == head)
    tables = sorted({k.split(".")[0] for k in SCHEMA if "." in k}) + ["station"]
    top = [k for k in SCHEMA if "." not in k]
    listing = (
        f"; keys in [{head}]: {', '.join(near)}"
        if near
        else f"; the scene's tables: {', '.join(tables)}; its other keys: {', '.join(top)} (remedy: README 'Scenes')"
    )
    return "unknown key" + (f"; did you mean '{hint}'?" if hint else "") + listing


def nearest_key(key: str, known: Iterable[str] = SCHEMA) -> str | None:
    """The ``known`` key (default the scene schema's) closest to ``key`` by its whole spelling or, failing that, by
    its last dotted part alone; None when none is close (the "did you mean" of every unknown-key error)."""
    known = list(known)
    if (same := {k.lower(): k for k in known}.get(key.lower())) is not None:  # IMPACT.SPEED: the case alone
        return same
    whole = difflib.get_close_matches(key, known, n=1, cutoff=0.8)
    if whole:
        return whole[0]
    by_leaf: dict[str, list[str]] = {}
    for k in known:
        by_leaf.setdefault(k.rsplit(".", 1)[-1], []).append(k)
    leaf = difflib.get_close_matches(key.rsplit(".", 1)[-1], list(by_leaf), n=1, cutoff=0.8)
    return by_leaf[leaf[0]][0] if leaf and len(by_leaf[leaf[0]]) == 1 else None


# --------------------------------------------------------------------------------------------
# Typed scene objects
# --------------------------------------------------------------------------------------------
def impedance_force(speed: float, rod1: Rod, rod2: Rod) -> float:
    """The impedance-bound force P = s1 Z1 Z2/(Z1 + Z2) [N] of Rod 1 at ``speed`` s1 [m/s] onto Rod 2 at rest
    (Z = ρ c A, :attr:`Rod.impedance`): the bars' stiff-contact limit (both ends move at once, each rod loaded
    behind a front of strain P/(Z_i c_i)); a Hertz contact only lowers it."""
    return speed / (1.0 / rod1.impedance + 1.0 / rod2.impedance)


@dataclass(frozen=True)
class Material:
    """A rod's isotropic, linear-elastic material (paper, Table 1): density, Young's modulus, Poisson's ratio and,
    where the scene gives one, the yield strength that the yield warnings judge the Hertz pressure against."""

    density: float  # ρ [kg/m^3]
    youngs_modulus: float  # E [Pa]
    poisson_ratio: float  # ν [-]
    yield_strength: float | None = None  # S_y [Pa]

    @property
    def wave_speed(self) -> float:
        """Bar wave speed c = sqrt(E/ρ) [m/s] (paper, after Eq. 1)."""
        return math.sqrt(self.youngs_modulus / self.density)

    @property
    def lame(self) -> tuple[float, float]:
        """Lamé parameters (λ, μ) [Pa]."""
        E, ν = self.youngs_modulus, self.poisson_ratio
        return E * ν / ((1 + ν) * (1 - 2 * ν)), E / (2 * (1 + ν))

    @property
    def dilatational_wave_speed(self) -> float:
        """P-wave speed c_d = sqrt((λ + 2μ)/ρ) [m/s]: bounds the explicit step (h / c_d)."""
        λ, μ = self.lame
        return math.sqrt((λ + 2 * μ) / self.density)


@dataclass(frozen=True)
class Rod:
    """One rod: a cylinder of ``length`` and ``diameter`` [m] whose impact end is a spherical cap of ``tip_radius`` [m]
    (``inf``: flat), of one :class:`Material` (paper, Fig. 1)."""

    length: float  # L [m]
    diameter: float  # d [m]
    tip_radius: float  # r [m]; inf = flat
    material: Material

    @property
    def area(self) -> float:
        """Cross-section A = π d²/4 [m^2]."""
        return math.pi * self.diameter**2 / 4

    @property
    def mass(self) -> float:
        """m = ρ A L_bar [kg]: the rod's, cap included (:attr:`bar_length`)."""
        return self.material.density * self.area * self.bar_length

    @property
    def impedance(self) -> float:
        """Mechanical impedance Z = ρ c A = E A / c [N s/m]."""
        return self.material.density * self.material.wave_speed * self.area

    @property
    def round_trip_time(self) -> float:
        """Round-trip time of a bar wave, 2 L_bar/c [s] (:attr:`bar_length`): the delay of Eqs. 2 and 4 under the
        default rod-end law; the paper's own law (analytical.contact = "hertz") delays by 2 L/c of the whole rod
        (rods.analytical.WaveModel.T)."""
        return 2 * self.bar_length / self.material.wave_speed

    @property
    def transit_time(self) -> float:
        """:attr:`round_trip_time`'s former name (a round trip, where every other "transit" here is one way)."""
        return self.round_trip_time

    @property
    def diameter_transit(self) -> float:
        """Time a bar wave takes to cross one diameter, d/c [s]: the period scale of the rod's lateral ringing
        (Pochhammer-Chree), against which the checks judge a force's rise and its ripple (rods.checks)."""
        return self.diameter / self.material.wave_speed

    @property
    def cap_height(self) -> float:
        """Height of the spherical cap r - sqrt(r² - (d/2)²) [m]; 0 for a flat tip."""
        r, ρ = self.tip_radius, self.diameter / 2
        return 0.0 if math.isinf(r) else r - math.sqrt(r * r - ρ * ρ)

    @property
    def cap_volume(self) -> float:
        """Volume of the spherical cap π h² (3r - h)/3 [m^3] (h: :attr:`cap_height`); 0 for a flat tip."""
        h = self.cap_height
        return 0.0 if h == 0.0 else math.pi * h * h * (3 * self.tip_radius - h) / 3

    @property
    def bar_offset(self) -> float:
        """ΔL = h - V_cap/A [m]: how far from the apex the end of the 1D bar of the rod's mass lies (a cap holds less
        than the cylinder of its height: 1/2 of it on a shallow cap, 2/3 on a hemisphere, ΔL = b/3). The 1D model's
        bar is :attr:`bar_length` long and its displacement is extrapolated to there (rods.fe.end_compliance)."""
        return self.cap_height - self.cap_volume / self.area

    @property
    def bar_length(self) -> float:
        """L_bar = L - ΔL [m]: the uniform bar of the rod's mass and section (:attr:`bar_offset`), the analytical
        model's rod at its default law (rods.analytical.WaveModel.caps; the paper's takes L itself: 0.29 mm longer
        on the paper's 35 mm tip, 2.1 mm on a hemisphere of the paper's rods, 0.85% of Rod 1's mass there)."""
        return self.length - self.bar_offset


@dataclass(frozen=True)
class Station:
    """A probe: distance ``position`` [m] from the impacted tip of rod ``rod`` (1 or 2)."""

    rod: int
    position: float
    name: str


# the auto tip grading's floor [-], far below the schema's 0.05 for a set fe.tip_grading. At 0.05 a small patch got
# tip elements deeper than they are wide: 2 mm rods at 1 mm/s (a = 8.6 µm, 0.97 µm across, 7.9 µm deep) read a peak
# force +0.86% and a contact -1.16 µs from the analytical model with status "ok" (+0.43% at half the depth, +0.16%
# square). The schema's smallest fe.radial_size over its largest fe.axial_size (1e-8 / 0.1 m = 1e-7): square tip
# elements on every scene; the graded block costs log(1/g)/log(GROWTH) elements (at most 89)
AUTO_TIP_GRADING_MIN = TINY["size"] / MAX_SIZE


def square_tip_grading(radial: float, axial: float) -> float:
    """``fe.tip_grading`` "auto": the first tip element ``radial`` long on an axial size ``axial`` [m] (square
    elements at the contact, so the patch is resolved as finely across as along), within
    [:data:`AUTO_TIP_GRADING_MIN`, 1]."""
    return min(1.0, max(AUTO_TIP_GRADING_MIN, radial / axial))


class FrozenValues(dict):
    """A scene's resolved keys, read-only: a change is a new scene (:meth:`Scene.with_overrides`), never an edit that
    leaves the fields resolved from the old value behind (``speed``, the rods, the end time). Pickles and copies as a
    dict would."""

    def _refuse(self, *args: Any, **kwargs: Any) -> None:
        raise TypeError("a scene's values are read-only: make a new scene with scene.with_overrides('KEY=VALUE')")

    __setitem__ = __delitem__ = __ior__ = clear = pop = popitem = setdefault = update = _refuse  # type: ignore[assignment]

    def __reduce__(self) -> tuple[type, tuple[dict[str, Any]]]:
        return type(self), (dict(self),)


@dataclass(frozen=True)
class Scene:
    """A validated scene (:func:`load_scene`, :func:`scene_from_dict`): the two rods, Rod 1's impact speed, the end
    time and output interval, the effects asked for, the stations, and every resolved key flat in :attr:`values`
    (read ``scene["fe.axial_size"]``: an "auto" resolves there). Immutable: a change is a new scene
    (:meth:`with_overrides`), which records what it changed."""

    name: str
    rod1: Rod
    rod2: Rod
    speed: float  # s1, Rod-1 impact speed [m/s]
    end_time: float  # [s]
    output_interval: float  # [s]
    effects: tuple[str, ...]
    stations: tuple[Station, ...]
    values: Mapping[str, Any] = field(repr=False)  # every validated key, flat (fe.*, impact.* ...)
    source: str = ""
    # the KEY=VALUE overrides given with the scene (--set, a sweep's point), last one per key; a library's own
    # with_overrides (a stage's end time, the driver's settings) keeps them and adds none
    overrides: tuple[str, ...] = ()
    # the library's own overrides on top (with_overrides: a stage's end time, a driver's or a finer mesh's sizes, the
    # paper's contact law), last one per key: summaries record them beside ``overrides`` ("stage_settings"), so that
    # the two together replay the run (the label names the user's scene only)
    settings: tuple[str, ...] = ()
    # a submodel's driving global's resolved fe.axial_size [m], which bounds the elements a radially graded submodel
    # grows to across (rods.fe.layout.bar_size: nowhere coarser than its global); 0: this scene's own fe.axial_size
    global_axial_size: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.values, FrozenValues):
            object.__setattr__(self, "values", FrozenValues(self.values))

    @property
    def identity(self) -> dict[str, Any]:
        """How summaries name and replay this scene: ``scene`` (:attr:`label`), ``scene_overrides`` (what the label
        lists), ``stage_settings`` (the library's own overrides after them, :attr:`settings`) and ``scene_file``
        (:attr:`scene_file`)."""
        return {
            "scene": self.label,
            "scene_overrides": list(self.overrides),
            "stage_settings": list(self.settings),
            "scene_file": self.scene_file,
        }

    @property
    def scene_file(self) -> str | None:
        """The absolute path of the scene file the scene was read from, None for one built otherwise (from a dict, a
        run's summary): the owner of the scene's default output folder (rods.study.runs.check_owner)."""
        p = Path(self.source) if self.source else None
        return str(p.resolve()) if p is not None and p.suffix == ".toml" and p.is_file() else None

    @property
    def label(self) -> str:
        """The scene as summaries and tables name it: its name, and the overrides it was given, so a run under
        ``--set`` is not reported as the file's scene (e.g. ``paper with impact.speed=1.0``)."""
        return f"{self.name} with {', '.join(self.overrides)}" if self.overrides else self.name

    def __getitem__(self, key: str) -> Any:
        v = self.values[key]
        return getattr(self, _RESOLVED[key]) if v == "auto" and key in _RESOLVED else v

    @property
    def field_interval(self) -> float:
        """Interval of the field frames [s]: ``fe.field_interval``; where the "fields" effect asks without one,
        :data:`FIELD_FRAMES_PER_ROUND_TRIP` frames a round trip of the rod with the shortest (the waves, whatever the
        rods' size), at most :data:`FIELD_FRAMES_DEFAULT_MAX` over the end time; 0 where no fields are written."""
        if self.values["fe.field_interval"] > 0:
            return float(self.values["fe.field_interval"])
        if "fields" not in self.effects:
            return 0.0
        round_trip = min(rod.round_trip_time for rod in self.rods)  # [s]
        return max(round_trip / FIELD_FRAMES_PER_ROUND_TRIP, self.end_time / FIELD_FRAMES_DEFAULT_MAX)

    @property
    def misaligned(self) -> bool:
        """An eccentric or tilted impact (``impact.offset`` or ``impact.tilt`` non-zero: the 3D model's alone)."""
        return bool(self["impact.offset"] or self["impact.tilt"])

    @property
    def impedance_force(self) -> float:
        """The impedance-bound force P = s1 Z1 Z2/(Z1 + Z2) [N] (Z = ρ c A): the rods' stiff-contact (bar) limit,
        rod i moving at P/Z_i behind a front of strain P/(Z_i c_i); a Hertz contact only lowers it."""
        return self._impedance_patch[0]

    @cached_property
    def _impedance_patch(self) -> tuple[float, float, float]:
        """(P [N], a_P [m], δ_P [m]): the impedance-bound force P = s1 Z1 Z2/(Z1 + Z2) (Z = ρ c A), Hertz's
        contact radius and approach there (Scene.radial_size, Scene.estimated_rise)."""
        from rods import hertz  # lazy: the scene validates without scipy's optimisers loaded

        P = impedance_force(self.speed, self.rod1, self.rod2)  # [N]
        E_star, R_star = hertz.contact_constants(self.rod1, self.rod2)
        return P, float(hertz.contact_radius(P, E_star, R_star)), float(hertz.approach(P, E_star, R_star))

    @cached_property
    def submodel_levels(self) -> list[str]:
        """``submodel.levels`` resolved. "auto": three consecutive levels (:data:`SUBMODEL_LEVEL_SIZES`; where fewer
        remain, those of the last three finer than the global, perhaps none) from the coarsest with
        :data:`PATCH_ELEMENTS` elements across the Hertz radius a_P at the impedance-bound force and
        :data:`BAR_ELEMENTS` across the thinner rod's radius (the global's auto mesh where its peak is
        impedance-bound, :attr:`auto_radial_size`; a study's levels start there whatever the peak rests on, each a
        halving: a global's 6 would double the submodel's costs for a level the study refines past anyway), or later,
        so that the finest is finer than the global across the contact where ``fe.radial_size`` is set finer than
        all three (they would add cost, not resolution: the paper scene at 0.05 mm runs mid, fine, extra-fine; the
        auto global is never that fine). The paper scene (a_P = 1.09 mm): coarse, mid, fine, the paper's; 1 m/s
        (0.84 mm): mid, fine, extra-fine; 1 mm rods with a 5 mm tip (0.105 mm): ultra-fine and the two below it, 6.7,
        13 and 27 elements across the patch, where the paper's three put 0.4, 0.8 and 1.7."""
        v = self.values["submodel.levels"]
        if v != "auto":
            return list(v)
        n, h_auto = len(SUBMODEL_LEVELS), self.submodel_start_size  # [m]
        sizes = list(SUBMODEL_LEVEL_SIZES.values())  # [m] coarse to fine
        first = next((i for i, h in enumerate(sizes) if h <= h_auto), n)
        # a global set finer than all three (paper scene, fe.radial_size = 0.05 mm): the three whose finest is finer
        first = max(first, next((i for i, h in enumerate(sizes) if h < self.radial_size), n) - 2)
        if first <= n - 3:
            return list(SUBMODEL_LEVELS[first : first + 3])
        # past the ladder's fine end (a patch under ~0.1 µm): its finest levels that are finer than the global
        # across the contact; none, and the global's contact values are the finest there are (the plan says so)
        return [lv for lv in SUBMODEL_LEVELS[n - 3 :] if SUBMODEL_LEVEL_SIZES[lv] < self.radial_size]

    @property
    def submodel_start_size(self) -> float:
        """The auto submodel levels' start [m] (:attr:`submodel_levels`): :data:`PATCH_ELEMENTS` elements across a_P,
        at most the thinner rod's radius / :data:`BAR_ELEMENTS`."""
        return self._patch_size(PATCH_ELEMENTS)

    @cached_property
    def radial_size(self) -> float:
        """``fe.radial_size`` resolved [m]. "auto": :attr:`patch_elements` (4 to 13.7) elements across the Hertz radius
        a_P at the impedance-bound force P = s1 Z1 Z2/(Z1 + Z2) (Z = ρ c A), at most the thinner rod's radius /
        :data:`BAR_ELEMENTS`. P bounds the first contact's force: the compression rate δ' = s1 - P (1/Z1 + 1/Z2)
        until the first reflection returns, so the force stops rising at P or before (paper scene: P = 5556 N, the
        analytical peak 5556 N), and a_P bounds the patch (a ∝ P^(1/3)). Measured on the paper rods' default
        kinematic contact, peak force against the analytical model: 4.4 elements across the patch +0.05%, 2.2
        elements -0.40%, 1 element (0.05 m/s at 0.25 mm) +2.3%; 4 elements at 0.05 m/s (0.077 mm) +0.11%, at 0.1 m/s
        +0.38% (:attr:`patch_elements`: these peaks rest on the contact stiffness; auto puts 6 and 7.1 there)."""
        v = self.values["fe.radial_size"]
        return self.auto_radial_size if v == "auto" else float(v)

    @cached_property
    def auto_radial_size(self) -> float:
        """What "auto" gives ``fe.radial_size`` on this scene [m], whatever the key holds (:attr:`radial_size`)."""
        return self._patch_size(self.patch_elements)

    def _patch_size(self, elements: float) -> float:
        """``elements`` across the Hertz radius a_P, at most the thinner rod's radius / :data:`BAR_ELEMENTS` [m]."""
        return min(min(r.diameter for r in self.rods) / 2 / BAR_ELEMENTS, self.impedance_patch_radius / elements)

    @property
    def patch_elements(self) -> float:
        """Elements across the Hertz radius a_P that "auto" puts (:attr:`auto_radial_size`) [-]:
        :data:`PATCH_ELEMENTS` where the first contact's peak is impedance-bound, :data:`PATCH_ELEMENTS_STIFF` where
        it rests on the contact stiffness (:attr:`stiffness_sensitivity` S >= SENSITIVITY_RAMP[1]), linear in S
        between; where S is larger still, n = PATCH_ELEMENTS_STIFF sqrt(S PATCH_RIPPLE / PEAK_SHARE), which keeps
        S x the patch's stiffness ripple (PATCH_RIPPLE (6/n)²) within :data:`PEAK_SHARE` of the peak (from S = 0.19:
        S = 0.33 8 elements, 0.68 11.3, at most 13.7).
        The discretised patch's force-approach law ripples about Hertz's as node rings enter contact (the FE-analytical
        force gap swings over the rise with the ring spacing), and the peak force carries that ripple times S, at the
        ripple's phase where the peak falls: so at high S the peak's error is not monotone in the mesh.
        Measured (2026-11-30, peak force against the analytical model, each scene's default axial size): 30 mm rods at
        2 m/s (S = 0.23) at 4 / 5 / 6 / 8 / 10 / 12 elements +0.515 / +0.309 / +0.162 / +0.064 / -0.029 / -0.031%;
        the paper rods at 0.1 m/s (S = 0.17) at 4 / 5 / 6 +0.376 / +0.242 / +0.157%; 25 mm rods with a 50 mm tip
        (0.16) +0.252 / +0.156 / +0.084%; the paper scene (S = 0.001) +0.052 / +0.077 / +0.037%: the 21 named and
        drawn probes of S < 0.02 without a peak or patch warning read +0.01 to +0.16% at 4 (results/scene-probe*.md),
        those of S 0.14-0.36 +0.25 to +0.52%. At high S, where 6 was the worst count measured: a hemispherical tip on
        the paper rods at 0.2 m/s (S = 0.33) at 4 / 5 / 6 / 7 / 8 / 12 -0.17 / -0.49 / -0.42 / -0.21 / -0.07 / +0.13%;
        two drawn scenes (results/scene-probe-random.md), S = 0.68 at 4 / 5 / 6 / 8 / 10 / 12 +0.24 / +0.40 / +0.52 /
        +0.18 / -0.17 / +0.11%, S = 0.66 at 4 / 6 / 8 / 10 +0.12 / +0.51 / +0.13 / -0.13%."""
        S, (lo, hi) = self.stiffness_sensitivity, SENSITIVITY_RAMP
        ramp = min(1.0, max(0.0, (S - lo) / (hi - lo)))
        ripple = PATCH_ELEMENTS_STIFF * math.sqrt(S * PATCH_RIPPLE / PEAK_SHARE)  # peak_ripple(ripple) = PEAK_SHARE
        return max(PATCH_ELEMENTS + (PATCH_ELEMENTS_STIFF - PATCH_ELEMENTS) * ramp, ripple)

    def peak_ripple(self, elements: float) -> float:
        """The share of the first contact's peak force that the discretised patch's stiffness ripple carries at
        ``elements`` across the Hertz radius a_P [-]: S x PATCH_RIPPLE (PATCH_ELEMENTS_STIFF / elements)², the model
        :attr:`patch_elements` inverts at PEAK_SHARE and rods.checks.stiffness_warning holds a set mesh to."""
        return self.stiffness_sensitivity * PATCH_RIPPLE * (PATCH_ELEMENTS_STIFF / elements) ** 2

    @property
    def stiffness_sensitivity(self) -> float:
        """S = ∂ln F/∂ln K [-]: how much the first contact's force when the first reflection returns rests on the
        contact stiffness K (:attr:`bar_rise`). An index of the peak's own: the peak comes at that return or after
        it, once the returning tension (the force history, delayed) has grown to stop the approach; a force still
        far from the impedance bound at that return peaks where K set it. 0 where the force reaches the bound first
        (the paper scene: τ = 6.3, S = 0.001); the paper rods at 0.1 m/s: τ = 2.25, S = 0.17."""
        return self.bar_rise[1]

    @cached_property
    def bar_rise(self) -> tuple[float, float]:
        """(F/P, S) [-, -] of the bars' rise (rods.hertz.bar_rise) at τ = t_r/t_P, t_r the shorter rod's round trip
        2 L_bar/c and t_P = δ_P/s1 (:attr:`estimated_rise`): the first contact's force over the impedance bound when
        the first reflection returns, and its sensitivity to the contact stiffness there."""
        from rods import hertz  # lazy: the scene validates without scipy's optimisers loaded

        # t_P > 0 on every valid scene: the schema refuses two flat tips and a speed of 0
        return hertz.bar_rise(min(r.round_trip_time for r in self.rods) / self.estimated_rise)

    @property
    def bar_axial_size(self) -> float:
        """The axial size [m] that bounds a radially graded mesh's largest element across (rods.fe.layout.bar_size):
        the scene's own :attr:`axial_size`, a submodel's its driving global's (:attr:`global_axial_size`)."""
        return self.global_axial_size or self.axial_size

    @property
    def axial_core(self) -> tuple[float, float]:
        """(core [m], far size [m]) along a graded submodel's rods (rods.fe.layout.axial_spacing): its size over
        :attr:`graded_core` from each tip, growing to its global's axial size (:attr:`global_axial_size`); (0, 0) on
        a global or a uniform submodel (no core: a global's tip grading grows from the tip)."""
        v = self.values
        if self.global_axial_size and v["fe.radial_grading"] == "graded" and v["fe.kind"] == "axisymmetric":
            return self.graded_core, self.global_axial_size
        return 0.0, 0.0

    @property
    def impedance_patch_radius(self) -> float:
        """Hertz's contact radius a_P [m] at the impedance-bound force (:attr:`impedance_force`): it bounds the first
        contact's patch (the auto meshes' scale, the analytical model's rod-end term's patch)."""
        return self._impedance_patch[1]

    @property
    def graded_core(self) -> float:
        """Radius [m] of the uniform core of a graded axisymmetric mesh (``fe.radial_grading``): :data:`CORE_RADII`
        Hertz radii a_P at the impedance-bound force, which bounds the first contact's patch."""
        return CORE_RADII * self.impedance_patch_radius

    @cached_property
    def axial_size(self) -> float:
        """``fe.axial_size`` resolved [m]. "auto": the thinner rod's diameter / :data:`AXIAL_PER_DIAMETER` (the
        paper's 1 mm), at most c t_rise / :data:`RISE_ELEMENTS`, c the slower bar wave speed and t_rise the
        force's :attr:`estimated_rise`. A force that rises within a few diameter transits d/c rings the rods (lateral
        inertia); its peak then needs the ringing resolved along the rod: a 1 m tip on the paper rods, peak
        force against the finest mesh (0.2 mm x 0.25 mm, +0.67% from the 1D analytical model, which has no
        ringing): 1 mm +0.69%, 0.52 mm (auto at c t_rise/50) -0.02%; drawn scenes rising in 3.0-3.5 transits (the
        analytical model warns below 2): +0.47 to +0.50% at c t_rise/50, +0.08 to +0.19% at c t_rise/75, one of them
        +0.16% on a mesh 4x finer along and 2x across (2026-11-29, :data:`RISE_ELEMENTS`). The diameter rule binds
        where the estimated rise takes more than 75/12.7 = 5.9 transits of the thinner rod (the paper scene: 6.2)."""
        v = self.values["fe.axial_size"]
        return self.auto_axial_size if v == "auto" else float(v)

    @cached_property
    def auto_axial_size(self) -> float:
        """What "auto" gives ``fe.axial_size`` on this scene [m], whatever the key holds (:attr:`axial_size`)."""
        diameter = min(r.diameter for r in self.rods) / AXIAL_PER_DIAMETER
        c = min(r.material.wave_speed for r in self.rods)  # [m/s]
        return min(diameter, c * self.estimated_rise / RISE_ELEMENTS)

    @property
    def estimated_rise(self) -> float:
        """The contact force's rise time estimated from the scene alone [s]: δ_P/s1, the time to close Hertz's
        approach δ_P at the impedance-bound force P (:attr:`impedance_force`) at the impact speed (against the
        analytical model's 10-90% rise: paper scene 15.5 / 22.5 µs, 10 m/s 9.3 / 11.5 µs, a 1 m tip 5.1 / 4.0 µs)."""
        return self._impedance_patch[2] / self.speed

    @property
    def penalty(self) -> float:
        """``fe.penalty`` resolved [x E*/h]. "auto": :attr:`auto_penalty`."""
        v = self.values["fe.penalty"]
        return self.auto_penalty if v == "auto" else float(v)

    @property
    def auto_penalty(self) -> float:
        """What "auto" gives ``fe.penalty`` on this scene [x E*/h]: the stiffer of :data:`PENALTY_FACTOR` and the
        factor whose layer delays the contact by :data:`LAYER_DELAY_TRANSITS` x d/c (the thinner rod's diameter
        transit; at most :data:`LAYER_DELAY_MAX`), share x t_P = that delay with share = 2/(π n f) the layer's
        penetration over Hertz's approach at the patch (p_0/ε over a²/R*, rods.checks.layer_share; n = a_P/h elements
        across the Hertz radius at the impedance-bound force on the scene's ``fe.radial_size``) and t_P the
        :attr:`estimated_rise`: f = 2 t_P/(π n delay), at most :data:`PENALTY_MAX`. The paper scene: t_P = 15.5 µs,
        n = 4.0, 9.9 (so 10); the paper rods at 0.1 m/s 18.5, at 1.0 m/s 12.9; a coarser mesh (smaller n) a stiffer
        layer."""
        return self.auto_penalty_at(self.radial_size)

    def auto_penalty_at(self, h: float) -> float:
        """:attr:`auto_penalty` on a mesh of ``h`` [m] across the patch (a submodel level's, :meth:`submodel_penalty`)
        [x E*/h]."""
        from rods.metrics import shorter_transit  # lazy: rods.metrics reads scenes

        n = self.impedance_patch_radius / h  # [-]
        delay = min(LAYER_DELAY_TRANSITS * shorter_transit(self), LAYER_DELAY_MAX)  # [s]
        return min(PENALTY_MAX, max(PENALTY_FACTOR, 2.0 * self.estimated_rise / (math.pi * n * delay)))

    def submodel_penalty(self, h: float) -> float:
        """``submodel.penalty`` resolved for a submodel of ``h`` [m] across [x E*/h]: "auto" is
        :meth:`auto_penalty_at` its own size, as the global's on its own mesh (the levels' patches have 4 and more
        elements across, so 10 on most scenes)."""
        v = self.values["submodel.penalty"]
        return self.auto_penalty_at(h) if v == "auto" else float(v)

    @property
    def submodel_length(self) -> float:
        """``fe.submodel_length`` resolved [m] (:func:`resolve_submodel_length`)."""
        return resolve_submodel_length(self.values["fe.submodel_length"], self.rods)

    @property
    def tip_grading(self) -> float:
        """``fe.tip_grading`` resolved [-]: "auto" is :func:`square_tip_grading` of the resolved sizes."""
        g = self.values["fe.tip_grading"]
        return square_tip_grading(self["fe.radial_size"], self["fe.axial_size"]) if g == "auto" else float(g)

    @property
    def auto_tip_grading(self) -> float:
        """What "auto" gives ``fe.tip_grading`` on the auto mesh (:attr:`auto_radial_size`, :attr:`auto_axial_size`)."""
        return square_tip_grading(self.auto_radial_size, self.auto_axial_size)

    @property
    def rods(self) -> tuple[Rod, Rod]:
        return self.rod1, self.rod2

    def result_values(self, default: bool = False) -> dict[str, Any]:
        """:meth:`as_dict` less :data:`RESULT_NEUTRAL`, the keys that change no result: what a checkpoint, a rerun
        and a run's folder are told apart by (``default``: set to their schema defaults instead of dropped, the
        digest of rods.preflight.scene_folder, which stays that of a scene that never set them)."""
        return values_without(self.as_dict(), RESULT_NEUTRAL, default)

    def as_dict(self, json_safe: bool = True) -> dict[str, Any]:
        """Nested plain dict of the validated scene (``json_safe``: inf as "inf", for summary.json)."""
        out: dict[str, Any] = {}
        for k, v in self.values.items():
            if v is None:
                continue  # optional key left unset
            node = out
            *parents, leaf = k.split(".")
            for p in parents:
                node = node.setdefault(p, {})
            if json_safe and k in _RECORDED_RESOLVED:
                v = self[k]  # a record holds the time or size the run used ("auto" resolved)
            node[leaf] = "inf" if json_safe and isinstance(v, float) and math.isinf(v) else v
        out["station"] = [{"rod": s.rod, "position": s.position, "name": s.name} for s in self.stations[1:]]
        return out

    def with_overrides(self, *overrides: str) -> Scene:
        """A new, validated scene: this one with ``KEY=VALUE`` overrides applied (its :attr:`label` kept: the
        library's own overrides are a stage's settings, not another scene)."""
        new = scene_from_dict(self.as_dict(json_safe=False), overrides, source=self.source)
        # an override that changes nothing is no setting (a study's global recorded its scene's own end time)
        changed = [o for o in overrides if new.values.get(k := parse_override(o)[0]) != self.values.get(k)]
        settings = last_per_key((*self.settings, *changed))
        return dataclasses.replace(
            new, overrides=self.overrides, settings=settings, global_axial_size=self.global_axial_size
        )


def _station_name(rod: int, pos: float) -> str:
    """A station's default name, an identifier: ``rod1_x100mm``, ``rod2_x700p99mm`` (the decimal point as p, the
    position to 0.1 µm), so a position that is not a whole number of millimetres needs no name of its own."""
    text = f"{pos * 1e3:.4f}".rstrip("0").rstrip(".")
    return f"rod{rod}_x{text.replace('.', 'p')}mm"


def _stations(raw: Any, rods: tuple[Rod, Rod]) -> tuple[Station, ...]:
    if raw is None:
        raw = []
    if not isinstance(raw, list) or not all(isinstance(s, Mapping) for s in raw):
        why = "must be an array of tables with rod, position and an optional name"
        hint = "[[station]] tables in a scene file, or --set 'station=[{rod = 1, position = 0.1}]'"
        raise SceneError("station", raw, why, hint)
    out = [Station(2, rods[1].length / 2, "rod2_mid")]
    for i, s in enumerate(raw):
        key = f"station[{i}]"
        unknown = set(s) - {"rod", "position", "name"}
        if unknown:
            raise SceneError(
                f"{key}.{sorted(unknown)[0]}", s[sorted(unknown)[0]], "unknown key; allowed: rod, position, name"
            )
        for k in ("rod", "position"):
            if k not in s:
                raise SceneError(f"{key}.{k}", None, "missing required key", "each [[station]] needs rod and position")
        rod = s["rod"]
        if isinstance(rod, bool) or not isinstance(rod, int) or rod not in (1, 2):  # 1.0 is no rod index
            raise SceneError(f"{key}.rod", rod, "must be 1 or 2")
        pos = _type_check(f"{key}.position", "float", s["position"])
        L, cap = rods[rod - 1].length, rods[rod - 1].cap_height
        if not cap <= pos <= L:
            # a station sits on the surface r = d/2 (gauge, vibrometer): on the cylinder, not inside a curved cap
            where = f"; the tip's spherical cap ends at {cap:g} m" if cap > 0 else ""
            raise SceneError(
                f"{key}.position", pos, f"must be in [{cap:g}, {L:g}] m (distance from the tip of rod {rod}{where})"
            )
        name = s.get("name", _station_name(rod, pos))
        if not isinstance(name, str) or not name.isidentifier():
            raise SceneError(f"{key}.name", name, "must be an identifier (letters, digits, _)")
        out.append(Station(rod, pos, name))
    names = [s.name for s in out]
    if len(set(names)) != len(names):
        twice = next(n for n in names if names.count(n) > 1)
        built_in = " (rod2_mid is the built-in Rod-2 midpoint station's)" if twice == "rod2_mid" else ""
        raise SceneError("station", names, f"station names must be unique: {twice!r} twice{built_in}", "rename it")
    return tuple(out)


def scene_from_dict(data: Mapping[str, Any], overrides: Iterable[str] | None = (), source: str = "") -> Scene:
    """Validate a parsed scene (plus ``KEY=VALUE`` overrides) and build a :class:`Scene`."""
    data, overrides = copy.deepcopy(dict(data)), _override_list(overrides)
    given = copy.deepcopy(data)  # the values before the overrides: the label lists those that change one
    for text in overrides:
        _apply_override(data, *parse_override(text))
    stations_raw = data.pop("station", None)
    flat = _flatten(data)
    for key, v in flat.items():
        if key not in SCHEMA:
            raise SceneError(key, v, _unknown_msg(key))
    values: dict[str, Any] = {}
    for key, (kind, default, check) in SCHEMA.items():
        if key not in flat:
            if default is REQUIRED:
                raise SceneError(key, None, "missing required key", "state it in the scene file or its base")
            values[key] = copy.copy(default)
            continue
        v = _type_check(key, kind, flat[key])
        if check is not None and v is not None and not (v == "auto" and kind.endswith("|auto")):
            check(key, v)  # a choice's "auto" only where its choices hold it (fe.kind = 'auto' ran as no kind at all)
        values[key] = v
    _cross_checks(values)

    def rod(n: int) -> Rod:
        p = f"rod{n}"
        mat = Material(
            values[f"{p}.material.density"],
            values[f"{p}.material.youngs_modulus"],
            values[f"{p}.material.poisson_ratio"],
            values[f"{p}.material.yield_strength"],
        )
        return Rod(values[f"{p}.length"], values[f"{p}.diameter"], values[f"{p}.tip_radius"], mat)

    rods = (rod(1), rod(2))
    end = values["simulation.end_time"]
    end = auto_end_time(rods, values["impact.speed"]) if end == "auto" else end  # [s]
    dt_out = values["simulation.output_interval"]
    dt_out = auto_output_interval(rods, end) if dt_out == "auto" else dt_out  # [s]
    if dt_out > end:
        given = "" if values["simulation.end_time"] != "auto" else " (simulation.end_time 'auto': these rods' waves)"
        hint = "set simulation.output_interval='auto' or at most the end time, or a longer simulation.end_time"
        raise SceneError("simulation.output_interval", dt_out, f"must be <= end_time = {end:g} s{given}", hint)
    L_s = resolve_submodel_length(values["fe.submodel_length"], rods)
    check_submodel_length(L_s, rods, caps=bool(set(values["effects"]) & set(SUBMODEL_EFFECTS)))
    return Scene(
        name=values["name"] or (Path(source).stem if source else "scene"),
        rod1=rods[0],
        rod2=rods[1],
        speed=values["impact.speed"],
        end_time=end,
        output_interval=dt_out,
        effects=tuple(values["effects"]),
        stations=_stations(stations_raw, rods),
        values=values,
        source=source,
        overrides=_told(given, overrides, values),
    )


def _spell(value: Any) -> str:
    """An override's value as the label spells it, one spelling per value (``4e-4`` and ``0.0004`` name one run):
    a float's shortest spelling (:func:`_spell_float`), a bare word as it is, a list or any other string as TOML, None
    as the schema's ``none``; it reads back as the same value."""
    if value is None:  # a yield strength of "none"
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):  # a NumPy integer as its Python int
        return str(int(value))
    if isinstance(value, numbers.Real):  # a NumPy float as its Python float (NumPy 2's repr reads np.float64(...))
        return _spell_float(float(value))
    if isinstance(value, str) and re.fullmatch(r"[A-Za-z0-9_.+-]+", value):
        return value
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_spell(v) if not isinstance(v, str) else json.dumps(v) for v in value) + "]"
    return json.dumps(value) if isinstance(value, str) else str(value)


def override(key: str, value: Any) -> str:
    """The ``KEY=VALUE`` override that sets ``key`` to ``value``, spelled as a label spells it (:func:`_spell`): a
    NumPy number as its Python value (``f"{key}={value!r}"`` wrote ``np.float64(7e-05)`` under NumPy 2, which the
    scene refused as no number: a library audit, 2026-12-07)."""
    return f"{key}={_spell(value)}"


def _spell_float(x: float) -> str:
    """The shorter of a float's positional and scientific spellings with its shortest round-trip digits
    (``0.0004`` -> ``4e-4``, ``2.1e11`` stays, ``2.197`` and ``4.0`` positional)."""
    text = repr(x)
    if not math.isfinite(x):
        return text
    positional = text  # 4.0, not 4: a float reads as one
    sign, digits, exponent = Decimal(text).normalize().as_tuple()
    mantissa = str(digits[0]) + ("." + "".join(map(str, digits[1:])) if len(digits) > 1 else "")
    scientific = f"{'-' if sign else ''}{mantissa}e{int(exponent) + len(digits) - 1}"
    if "e" in positional:  # repr's own exponent form (1e-08): the scientific spelling is shorter or as short
        return scientific
    return scientific if len(scientific) < len(positional) else positional


def _told(before: Mapping[str, Any], overrides: Sequence[str], values: Mapping[str, Any]) -> tuple[str, ...]:
    """The overrides a scene's label lists (:attr:`Scene.overrides`), in key order (:func:`by_key`): the last of each
    key, only where it changes the value ``before`` them (the scene file's, or the schema default where the file
    sets none: a run given the file's own value is the file's scene, as its folder is), each spelled from its
    validated value in ``values`` (:func:`_spell`); ``name`` is left out (it heads the label) and stations are kept
    as given."""
    flat = _flatten({k: v for k, v in before.items() if k != "station"})
    told = []
    for text in last_per_key(overrides):
        key, value = parse_override(text)
        if key == "name":
            continue
        if key == "station":
            if value != before.get("station"):
                told.append(text)
            continue
        kind, default, _ = SCHEMA[key]
        try:
            old = _type_check(key, kind, flat[key]) if key in flat else default
        except SceneError:  # the file's own value was invalid: the override made it valid
            old = REQUIRED
        if old != values[key]:
            told.append(f"{key}={_spell(values[key])}")
    return by_key(told)


def by_key(overrides: Iterable[str]) -> tuple[str, ...]:
    """``KEY=VALUE`` overrides in the order of their keys: one label whatever order they were given in (a fuzz:
    `--set impact.speed=4.0 --set fe.dt_fraction=0.7` and the reverse named one run two ways)."""
    return tuple(sorted(overrides, key=lambda text: text.split("=", 1)[0].strip()))


def reduced_mass(rods: tuple[Rod, Rod]) -> float:
    """m1 m2/(m1 + m2) [kg] of the rods (:attr:`Rod.mass`, caps counted): their impact as rigid bodies."""
    return rods[0].mass * rods[1].mass / (rods[0].mass + rods[1].mass)


def auto_end_time(rods: tuple[Rod, Rod], speed: float) -> float:
    """``simulation.end_time = "auto"`` [s] at the impact ``speed`` [m/s]: END_MARGIN x max(END_PERIODS x Rod 2's
    round trip 2 L2/c2, the first contact's bound), within the schema's 1 s (module constants' comment). The
    contact's bound: END_CONTACT_ROUND_TRIPS x the slower rod's round trip (a contact the waves end: the striker's
    returns after one), or Hertz's impact of the rods as rigid masses (rods.hertz.rigid_impact_duration: a contact
    slow against the transits, stubby rods, lasts it; 2 of 60 drawn scenes outlasted the round trips alone)."""
    from rods import hertz  # lazy: the scene validates without scipy's optimisers loaded

    periods = END_PERIODS * rods[1].round_trip_time
    quasi_static = hertz.rigid_impact_duration(reduced_mass(rods), speed, *hertz.contact_constants(*rods))
    contact = max(END_CONTACT_ROUND_TRIPS * max(r.round_trip_time for r in rods), quasi_static)
    return min(END_MARGIN * max(periods, contact), 1.0)


def auto_output_interval(rods: tuple[Rod, Rod], end_time: float) -> float:
    """``simulation.output_interval = "auto"`` [s]: the thinner rod's diameter transit d/c over
    SAMPLES_PER_DIAMETER_TRANSIT, at least ``end_time`` [s] / AUTO_SAMPLES_MAX and at most the end time itself (a
    run shorter than one sample: its start and end) (module constants' comment)."""
    dt = max(min(r.diameter_transit for r in rods) / SAMPLES_PER_DIAMETER_TRANSIT, end_time / AUTO_SAMPLES_MAX)
    return min(dt, end_time)


def last_per_key(overrides: Iterable[str]) -> tuple[str, ...]:
    """The overrides as given (``KEY=VALUE``, stripped), the last one of each key, keys in their first order."""
    last = {parse_override(t)[0]: "=".join(p.strip() for p in t.split("=", 1)) for t in overrides}
    return tuple(last.values())


def _mesh_fits_rods(v: dict[str, Any]) -> None:
    """Element sizes no larger than each rod: axial within its length, radial within its radius."""
    for n in (1, 2):
        for k, lim, what in (
            ("fe.axial_size", v[f"rod{n}.length"], "length"),
            ("fe.radial_size", v[f"rod{n}.diameter"] / 2, "radius"),
        ):
            if v[k] != "auto" and v[k] > lim:  # auto: within the thinner rod's radius by construction
                raise SceneError(k, v[k], f"must be <= {lim:g} m (rod {n} {what})")
    radius = min(v["rod1.diameter"], v["rod2.diameter"]) / 2  # [m]
    levels = v["submodel.levels"]
    if set(v["effects"]) & set(SUBMODEL_EFFECTS) and levels != "auto":  # auto: <= submodel_start_size <= radius
        for lv in levels:
            if SUBMODEL_LEVEL_SIZES[lv] > radius:  # the submodel mesh's limit, as fe.radial_size's: before any run
                fit = [k for k, h in SUBMODEL_LEVEL_SIZES.items() if h <= radius]
                raise SceneError(
                    "submodel.levels",
                    lv,
                    f"its {SUBMODEL_LEVEL_SIZES[lv]:g} m elements are wider than the thinner rod's radius {radius:g} m",
                    f"use {fit[0]} or finer" if fit else "no level fits: use workflows/submodel.py --size",
                )


def resolve_submodel_length(value: float | str, rods: Iterable[Rod]) -> float:
    """``fe.submodel_length`` [m] for ``value``: a length as given; "auto" :data:`SUBMODEL_DIAMETERS` x the thicker
    rod's diameter (the paper's 14 mm on 12.7 mm rods; 2.2 mm on 2 mm rods, where 14 mm made the submodel most of a
    20 mm striker and its finest level six times dearer), at most half the shorter rod (a short thin rod struck by
    a thick one)."""
    if value != "auto":
        return float(value)
    rods = tuple(rods)
    return min(SUBMODEL_DIAMETERS * max(rod.diameter for rod in rods), 0.5 * min(rod.length for rod in rods))


def cut_record_end(scene: Scene, record_until: float | None = None) -> float:
    """The last time [s] a global of ``scene`` records the submodels' cut band: ``record_until`` (a global with
    --record-cut), never past the run's end, default the end time (a driver records its whole run, the contact
    phase). The recorder (rods.fe.cut.CutRecorder), the plan's cost and a restart's check of a kept record read it."""
    return scene.end_time if record_until is None else min(record_until, scene.end_time)


def cut_records(scene: Scene, dt: float, steps: int, record_until: float | None = None, every: int = 1) -> int:
    """How many records of the cut band a global of ``scene`` marching ``steps`` steps of ``dt`` [s] keeps, one every
    ``every`` steps from step 0: they cover [0, :func:`cut_record_end`], one past it, capped at the run's last step.
    The recorder allocates this many (rods.fe.cut.CutRecorder) and the plan counts them (rods.cost): beside the
    scene, which both read, so that the FE recorder imports no planner."""
    until = cut_record_end(scene, record_until)
    return min(int(math.ceil(until / (dt * every) - 1e-9)), steps // every) + 1


def check_submodel_length(L_s: float, rods: Iterable[Rod], caps: bool = True) -> None:
    """``fe.submodel_length`` L_s [m]: the submodel cuts both rods at L_s from their tips, so L_s lies within
    each rod (a cut beyond a far end has no band to record: the fuzz test's 1 m) and, where a submodel runs
    (``caps``), beyond twice each cap height (checked with the scene, not after the global and driver ran)."""
    for k, rod in enumerate(rods, start=1):
        if L_s >= rod.length:
            raise SceneError(
                "fe.submodel_length", L_s, f"must be < rod{k}.length = {rod.length:g} m (the submodel cuts both rods)"
            )
        if caps and L_s <= 2 * rod.cap_height:
            need = 2 * rod.cap_height
            raise SceneError(
                "fe.submodel_length",
                L_s,
                f"must be > 2 x the cap height of rod {k} = {need:g} m (the submodel's rods keep a cylinder)",
                f"e.g. --set fe.submodel_length={1.1 * need:.3g}",
            )


def _rod_checks(v: dict[str, Any], n: int) -> None:
    """One rod's checks that involve several of its keys (cap, slenderness, units of E, ρ and S_y)."""
    r, d = v[f"rod{n}.tip_radius"], v[f"rod{n}.diameter"]
    if r < d / 2:
        raise SceneError(
            f"rod{n}.tip_radius", r, f"must be >= diameter/2 = {d / 2:g} m (a cap wider than a hemisphere)"
        )
    if v[f"rod{n}.length"] < 2 * d:
        raise SceneError(
            f"rod{n}.length", v[f"rod{n}.length"], f"must be >= 2 x diameter = {2 * d:g} m (a slender rod)"
        )
    E, S = v[f"rod{n}.material.youngs_modulus"], v[f"rod{n}.material.yield_strength"]
    if S is not None and S >= E:
        raise SceneError(
            f"rod{n}.material.yield_strength",
            S,
            f"must be < youngs_modulus = {E:g} Pa",
            f"looks like wrong units; 'none' drops a base scene's value: --set rod{n}.material.yield_strength=none",
        )
    if S is not None and S < MIN_YIELD_STRAIN * E * (1 - 1e-12):  # the bound as printed passes (2043000.0 < 2.043e6+)
        raise SceneError(
            f"rod{n}.material.yield_strength",
            S,
            f"must be >= {MIN_YIELD_STRAIN:g} x youngs_modulus = {MIN_YIELD_STRAIN * E:g} Pa (a yield strain below "
            "any solid's: annealed lead, copper and aluminium 1.4e-4 to 3e-4)",
            "looks like MPa or GPa; give Pa (250 MPa: 250e6)",
        )


def _cross_checks(v: dict[str, Any]) -> None:
    """Checks that involve several keys (contradictions, geometry)."""
    for n in (1, 2):
        _rod_checks(v, n)
    if math.isinf(v["rod1.tip_radius"]) and math.isinf(v["rod2.tip_radius"]):
        raise SceneError(
            "rod1.tip_radius",
            math.inf,
            "at least one tip must be curved (Hertz contact of two flats is undefined)",
            "give rod1.tip_radius or rod2.tip_radius a radius [m], e.g. rod1.tip_radius=0.035 (the paper's)",
        )
    _mesh_fits_rods(v)
    if "misalignment" in v["effects"] and v["fe.kind"] != "3d":
        raise SceneError(
            "effects",
            v["effects"],
            "'misalignment' needs fe.kind = '3d'",
            "--set fe.kind='3d' (with an offset or tilt)",
        )
    if v["submodel.levels"] == [] and set(v["effects"]) & set(SUBMODEL_EFFECTS):
        why = f"must name a level where effects ask for the contact region ({', '.join(SUBMODEL_EFFECTS)})"
        raise SceneError("submodel.levels", [], why, "'auto', or e.g. ['fine']")
    if (v["impact.offset"] > 0 or v["impact.tilt"] > 0) and v["fe.kind"] != "3d":
        key = "impact.offset" if v["impact.offset"] > 0 else "impact.tilt"
        raise SceneError(
            key,
            v[key],
            "an offset or tilt needs fe.kind = '3d' (axisymmetric is centric)",
            f"set fe.kind = '3d', or {key} = 0",
        )
    _misaligned_contact_on_the_tips(v)
    if v["fe.operator"] == "matrix-free" and v["fe.backend"] == "petsc":
        raise SceneError(
            "fe.operator", "matrix-free", "runs on the serial array backends", "set fe.backend = 'numpy' or 'cupy'"
        )
    if v["fe.symmetry"] != "full" and v["fe.kind"] != "3d":
        raise SceneError(
            "fe.symmetry", v["fe.symmetry"], "half/quarter symmetry applies to fe.kind = '3d' only",
            "set fe.symmetry = 'full' (an axisymmetric model is one already), or fe.kind = '3d'",
        )  # fmt: skip
    if v["fe.radial_grading"] == "graded" and v["fe.kind"] == "3d":
        raise SceneError(
            "fe.radial_grading",
            "graded",
            "applies to fe.kind = 'axisymmetric' only (the 3D section is an O-grid)",
            "set fe.radial_grading = 'auto' or 'uniform', or fe.kind = 'axisymmetric'",
        )
    # the 3D model's mirrors: half (y -> -y) holds for an offset along x and a tilt about y; quarter (x and y)
    # needs a centric, aligned impact
    if v["fe.symmetry"] == "quarter" and (v["impact.offset"] > 0 or v["impact.tilt"] > 0):
        need = "quarter symmetry needs impact.offset = 0 and impact.tilt = 0 (use 'half' or 'full')"
        raise SceneError("fe.symmetry", "quarter", need)


def first_contact_offsets(R1: float, R2: float, e: float, θ: float) -> tuple[float, float]:
    """Distances [m] of the first contact point from Rod 1's and Rod 2's axes for tip radii R1, R2 [m] (inf:
    flat; not both), Rod 1 offset by e [m] and tilted by θ [rad] about its apex (rods.fe.mesh3d.Placement: the
    touching point of Rod 1's cap moves to x = e - R1 sin θ). The common normal n of the two spheres (centres
    (e - R1 sin θ, -R1 cos θ) and (0, R2) in the x-z plane, touching) has n_x = (R1 sin θ - e)/(R1 + R2); the
    contact lies R2 |n_x| off Rod 2's axis and R1 |sin(asin n_x - θ)| off Rod 1's; the flat limits are
    (R1 sin θ, |R1 sin θ - e|) for a flat Rod 2 and ((e + R2 sin θ)/cos θ, R2 sin θ) for a flat Rod 1."""
    if math.isinf(R2):
        return R1 * math.sin(θ), abs(R1 * math.sin(θ) - e)
    if math.isinf(R1):
        return (e + R2 * math.sin(θ)) / math.cos(θ), R2 * math.sin(θ)
    n_x = (R1 * math.sin(θ) - e) / (R1 + R2)
    if abs(n_x) >= 1.0:  # the spheres' common normal lies across the rods: far beyond either face
        return math.inf, math.inf
    return R1 * abs(math.sin(math.asin(n_x) - θ)), R2 * abs(n_x)


def _misaligned_contact_on_the_tips(v: dict[str, Any]) -> None:
    """An offset or tilt must leave the first contact point on both tips (inside each face or cap rim): beyond a
    rim the rods meet edge first, which neither the tip model nor Hertz describes (the 3D mesh would find out
    only after its set-up)."""
    e, θ = v["impact.offset"], v["impact.tilt"]
    if e == 0.0 and θ == 0.0:
        return
    dists = first_contact_offsets(v["rod1.tip_radius"], v["rod2.tip_radius"], e, θ)
    for k, dist in enumerate(dists, start=1):
        R = v[f"rod{k}.diameter"] / 2
        if not dist < R:
            key = "impact.offset" if e > 0 else "impact.tilt"
            raise SceneError(
                key,
                v[key],
                f"puts the first contact {dist:.3g} m off Rod {k}'s axis, beyond its tip face (radius {R:g} m): an "
                "edge impact, which the tip model does not describe",
                "a smaller impact.offset or impact.tilt",
            )


def scene_from_summary(
    values: Mapping[str, Any],
    overrides: Iterable[str] | None = (),
    source: str = "",
    given: Iterable[str] | None = (),
) -> Scene:
    """Rebuild a scene from a summary.json's ``scene_values`` (where inf was written as "inf"), ``overrides``
    applied; ``given``: the overrides that run was given (its summary's ``scene_overrides``), already in
    ``values`` and kept for the :attr:`Scene.label` only."""

    def restore(d: Any) -> Any:
        if isinstance(d, Mapping):
            return {k: restore(v) for k, v in d.items()}
        if isinstance(d, list):
            return [restore(v) for v in d]
        return math.inf if d == "inf" else d

    scene = scene_from_dict(restore(values), overrides, source=source)
    return dataclasses.replace(scene, overrides=by_key(last_per_key((*_override_list(given), *scene.overrides))))


def _override_list(overrides: Iterable[str] | str | None) -> tuple[str, ...]:
    """``overrides`` as KEY=VALUE strings: one string is one override (it was read letter by letter: "scene key 'i'
    = None" for "impact.speed=1.0"), None none (a TypeError of tuple(None) before); anything else but strings is
    refused naming the argument."""
    given = (overrides,) if isinstance(overrides, str) else () if overrides is None else tuple(overrides)
    if odd := [o for o in given if not isinstance(o, str)]:
        raise TypeError(f"overrides: KEY=VALUE strings, e.g. ['impact.speed=1.0'], not {odd[0]!r}")
    return given


def load_scene(path: str | Path, overrides: Iterable[str] | None = ()) -> Scene:
    """Read, override and validate a scene file; raises SceneError on any problem."""
    p = Path(path)
    if not p.is_file():
        raise SceneError(
            "--scene",
            str(path),
            _not_a_file(path),
            "give a .toml scene, e.g. workflows/scenes/paper.toml",
            argument=True,
        )
    return scene_from_dict(_read_with_base(p, ()), overrides, source=str(p))


def _not_a_file(path: str | Path) -> str:
    """Why ``path`` is no scene file (an empty path is Path('.'), a folder)."""
    p = Path(path)
    if not str(path).strip():
        return "an empty path"
    if p.is_dir():
        return "is a folder, not a scene file"
    return "not a regular file (a device or pipe)" if p.exists() else "no such scene file"


def _read_with_base(p: Path, seen: tuple[Path, ...]) -> dict[str, Any]:
    """Parse TOML; a top-level ``base = "other.toml"`` (relative to this file) is read first and
    this file's tables are merged over it, so a trial scene states only what differs; its name is its own (the
    file's stem where it sets none), never its base's."""
    if p.resolve() in seen:
        chain = " -> ".join(q.name for q in (*seen, p.resolve()))
        raise SceneError("base", str(p), f"scene files include each other in a cycle, {chain}",
                         "remove the base line of one of them")  # fmt: skip
    # the file given, or a base it names (a damaged base was reported as the --scene option: a fuzz, 2026-12-07)
    what, flag = ("--scene", True) if not seen else ("base", False)
    try:
        # UTF-8 whatever the locale; a byte-order mark some editors write is dropped
        data = tomllib.loads(p.read_text(encoding="utf-8-sig"))
        _check_nesting(what, data, str(p), argument=flag)  # before copy.deepcopy and _flatten recurse on it
    except RecursionError:  # tomllib's parser recurses once per '[' or '{'
        raise _too_deep(what, str(p), argument=flag) from None
    except tomllib.TOMLDecodeError as e:
        fix = "fix the TOML syntax there (strings quoted, tables as [rod1], one key = value a line)"
        raise SceneError(what, str(p), f"malformed TOML: {e}", fix, argument=flag) from None
    except UnicodeDecodeError:
        fix = "save it as UTF-8 text (a TOML file)"
        raise SceneError(what, str(p), "not a text (UTF-8) TOML file", fix, argument=flag) from None
    except OSError as e:  # unreadable: permissions, a device, an I/O error
        why = f"cannot be read ({e.strerror or e})"
        raise SceneError(what, str(p), why, "give a readable TOML file", argument=flag) from None
    base = data.pop("base", None)
    if base is None:
        return data
    if not isinstance(base, str):
        raise SceneError("base", base, "must be a path string to another scene file")
    bp = p.parent / base
    if not base.strip() or not bp.is_file():
        why = "an empty path" if not base.strip() else f"{_not_a_file(bp)} ({bp})"
        raise SceneError("base", base, why, f'a scene file relative to {p.name}\'s folder, e.g. base = "paper.toml"')
    merged = _read_with_base(bp, (*seen, p.resolve()))
    _merge(merged, data)
    if "name" not in data:  # its own name, not its base's: a derived scene named "paper" ran into the paper's
        merged["name"] = p.stem  # folders and labels (a fuzz, 2026-12-06)
    if "description" not in data and merged.get("description"):  # the base's words may not be this scene's (a 4 m/s
        merged["description"] = f"derived from {bp.name}: {merged['description']}"  # copy kept "at 2.197 m/s")
    return merged


def _merge(into: dict[str, Any], new: Mapping[str, Any]) -> None:
    for k, v in new.items():
        if isinstance(v, Mapping) and isinstance(into.get(k), dict):
            _merge(into[k], v)
        else:
            into[k] = copy.deepcopy(v)
