"""How the axisymmetric mesh of the rods is laid out (paper Sec. 2.2), counted before anything is built.

Pure geometry and counting, no gmsh or DOLFINx, so a plan (:mod:`rods.cost`) prices a run from the very rules the
mesher (:mod:`rods.fe.mesh`) builds by, cell for cell:

* along a rod, :func:`axial_spacing`: a graded block at the tip (``fe.tip_grading``), a graded submodel's core, then
  uniform elements to the far end;
* the tip: one block from the apex to the rim, or a near-hemispherical cap's butterfly of three blocks
  (:func:`butterfly`; five, graded: :func:`graded_butterfly`);
* across a rod, :func:`radial_columns`: one column at ``fe.radial_size``, or a core of that size around the patch and
  columns growing outward to the bar's size (``fe.radial_grading``);
* away from the tips, :func:`coarsening`: layers of 3:1 templates merging the columns down to the bar's size
  (``fe.radial_coarsening``);
* :func:`mesh_counts`: the cells and nodes that all of this makes;
* :func:`tip_row`: the corners of the cells on a one-block tip face, whose distorted rim cells set a curved tip's
  stable step (:func:`rods.cost._tip_step`);
* :func:`tip_faces`: each tip face's nodes and the row of cells under them, whose masses and areas set the penalty
  contact's switching limit (:func:`rods.cost._switching_step`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from rods.scene import BAND_ELEMENTS, BAR_ELEMENTS, Rod, Scene

__all__ = [
    "AxialSpacing",
    "Butterfly",
    "Coarsening",
    "Column",
    "GradedButterfly",
    "RodLayout",
    "TipFace",
    "altitudes",
    "axial_blocks",
    "axial_spacing",
    "bar_size",
    "butterfly",
    "butterfly_tip_element",
    "coarsening",
    "coarsening_start",
    "element_count",
    "element_sizes",
    "face_areas",
    "graded_butterfly",
    "mesh_counts",
    "radial_columns",
    "rod_layouts",
    "scene_columns",
    "row_volumes",
    "tip_faces",
    "tip_row",
]

GROWTH = 1.2  # target size ratio between neighbouring elements in a graded block (tip or radial) [-]
# a graded rod's elements across at most this x the axial size [-]: no wider than long. 4 (R/8 binding, 1.56 mm on
# 0.47 mm) gave a 6 mm rod striking a 25 mm one the same contact on half the DOFs (+0.140% against +0.156% uniform,
# 101k DOFs against 211k) but moved the thick rod's midpoint response (velocity history 1.3% RMS, peak speed -0.93%;
# 2026-11-29), where 1 moves a graded rod's by less than halving the uniform mesh's radial size does
RIM_ASPECT = 1.0  # [-]
GRADED_SHARE = 0.5  # [-] fe.radial_grading "auto": a rod is graded where that leaves at most this share of its elements
# across [-]: above it the uniform mesh, the one results/verification.md measured, is kept (the paper rods: 19 of 24)


@dataclass(frozen=True)
class AxialSpacing:
    """Graded block at the tip (``n_graded`` elements, ratio ``ratio``, length ``graded_length``)
    followed by ``n_uniform`` uniform elements; a graded submodel's (:func:`axial_spacing` with a core) starts with
    ``n_core`` elements of ``h_tip`` over ``core_length`` before them."""

    n_graded: int
    ratio: float
    graded_length: float  # [m]
    n_uniform: int
    h_tip: float  # [m]
    n_core: int = 0
    core_length: float = 0.0  # [m]

    @property
    def n(self) -> int:
        """Elements along the rod [-]."""
        return self.n_core + self.n_graded + self.n_uniform


# a graded submodel's core along each rod (axial_spacing) at least this many cap heights long [-]: the mesher spaces
# every column of the block alike, so the rim's cells are (L - c)/L of the axis's; 10 keeps them within 10% of the
# uniform region's
CAP_HEIGHTS = 10.0


def element_count(length: float, h: float) -> int:
    """Elements of about size ``h`` [m] over ``length`` [m]: at least one, rounded up, with 1e-9 of slack so a
    length that is a whole number of sizes up to round-off gets no extra element."""
    return max(1, math.ceil(length / h - 1e-9))


def axial_spacing(rod: Rod, h: float, grading: float, core: float = 0.0, h_far: float = 0.0) -> AxialSpacing:
    """Element counts along one rod for nominal size ``h`` [m] and tip grading ``g`` (h_tip = g h). With a ``core``
    [m] (a graded submodel, :func:`rods.fe.submodel.submodel_grading`; g = 1): elements of h over at least
    ``core`` and :data:`CAP_HEIGHTS` cap heights, then growing by at most GROWTH per element to ``h_far`` [m] (its
    global's axial size), then of h_far to the far end; uniform h where the rod is too short for that."""
    if core > 0.0 and h_far >= 2.0 * h:
        graded = _cored_spacing(rod, h, core, h_far)
        if graded is not None:
            return graded
    L = rod.length
    if grading >= 1.0:
        n = element_count(L, h)
        return AxialSpacing(0, 1.0, 0.0, n, L / n)
    n_g = max(1, math.ceil(math.log(1.0 / grading) / math.log(GROWTH)))
    q = (1.0 / grading) ** (1.0 / n_g)  # sizes g h q^k, k = 0..n_g-1; the last is h / q
    a = grading * h  # the tip element [m]
    length = a * (q**n_g - 1.0) / (q - 1.0)
    cap = rod.cap_height
    if length < 2.0 * cap:  # keep the block's flat side clear of the cap: a longer block, the same tip element
        length = 2.0 * cap + h
        n_g, q = _graded_counts(a, length, h, n_g)
    n_u = element_count(L - length, h)
    return AxialSpacing(n_g, q, length, n_u, a)


def _cored_spacing(rod: Rod, h: float, core: float, h_far: float) -> AxialSpacing | None:
    """:func:`axial_spacing` with a core: n_c elements of h, n_g growing by q <= GROWTH from h q to h_far, n_u of
    h_far; None where they do not fit the rod."""
    n_c = element_count(max(core, CAP_HEIGHTS * rod.cap_height), h)
    n_g = max(1, math.ceil(math.log(h_far / h) / math.log(GROWTH)))
    q = (h_far / h) ** (1.0 / n_g)  # sizes h q^k, k = 1..n_g: the last is h_far
    graded = _grown(h, n_g, q)
    rest = rod.length - n_c * h - graded
    if rest < h_far:
        return None
    return AxialSpacing(n_g, q, graded, element_count(rest, h_far), h, n_c, n_c * h)


def _graded_counts(a: float, length: float, h: float, n0: int) -> tuple[int, float]:
    """(n, q): the fewest n >= ``n0`` elements growing by q <= GROWTH from ``a`` [m] that fill ``length`` [m],
    a (q^n - 1)/(q - 1) = length, with none longer than ``h`` [m] (a deep cap's long graded block keeps the
    tip element; stretching the block's elements instead made it 2.2x longer on a 30 mm rod, 35 mm tip). No n below
    length/h can hold it (none longer than h), so the search starts there: a 0.1 µm axial size counted one n at a
    time to ~1e4 and overflowed q^n on the way (a fuzz, 2026-12-07, before the plan's refusal could speak)."""
    n = max(n0, math.ceil(length / h))
    while True:
        if n * a >= length:  # uniform elements of length/n <= a fill it
            return n, 1.0
        lo, hi = 1.0, GROWTH
        if _block_length(a, hi, n) >= length:
            for _ in range(200):  # bisection: the block's length grows with q
                q = 0.5 * (lo + hi)
                lo, hi = (q, hi) if _block_length(a, q, n) < length else (lo, q)
            if (n - 1) * math.log(hi) <= math.log(h / a):  # the last element a q^(n-1) <= h
                return n, hi
        n += 1


def _block_length(a: float, q: float, n: int) -> float:
    """a (q^n - 1)/(q - 1) [m]: n elements growing by q from a; inf where q^n is beyond a float."""
    if q == 1.0:
        return a * n
    grown = n * math.log(q)
    return math.inf if grown > 700.0 else a * math.expm1(grown) / (q - 1.0)


BUTTERFLY_ANGLE = math.radians(70.0)  # rim angle asin(R/r_k) above which a cap is meshed as a butterfly [rad]


@dataclass(frozen=True)
class Butterfly:
    """Layout of a near-hemispherical cap (:func:`butterfly`), in (r, depth from the apex) [m].

    The single transfinite block of a flatter cap has a corner where the arc meets the cylinder; its angle is
    90° + the rim angle asin(R/r_k), so a hemisphere's corner element degenerates (180°) and sets the stable
    step: 0.95 ns instead of 19 ns on the paper rods with a 6.35 mm tip (277 402 steps for the contact phase).
    The butterfly splits the cap into three blocks without such a corner: two bands of thickness ``t`` along
    the arc (apex A to P, P to the rim E) around a core (D, C, G, O) whose far side O-G lies in the rim plane.
    ``t`` and P make every block's edges about equally long: t = (cap + R - r_k φ)/2 (> 0 for every φ) and
    the arc A-P is R - t long, P-E cap - t."""

    t: float  # thickness of the bands along the arc [m]
    theta_p: float  # polar angle of P seen from the sphere's centre [rad]
    points: dict[str, tuple[float, float]]  # A, P, E, G, O, D, C and the centre Oc

    @property
    def arcs(self) -> tuple[float, float]:
        """Lengths of the arcs A-P and P-E [m]."""
        rt = self.points["Oc"][1]
        return rt * self.theta_p, rt * (math.asin(self.points["E"][0] / rt) - self.theta_p)


def butterfly(rod: Rod) -> Butterfly | None:
    """The butterfly layout of ``rod``'s cap, or None where one transfinite block serves (flat or flatter tips,
    rim angle up to :data:`BUTTERFLY_ANGLE`: the paper's 35 mm tip has 10.4°)."""
    rt, R = rod.tip_radius, rod.diameter / 2
    if math.isinf(rt) or R / rt <= math.sin(BUTTERFLY_ANGLE):
        return None
    phi, cap = math.asin(R / rt), rod.cap_height
    t = 0.5 * (cap + R - rt * phi)
    th = (R - t) / rt
    P = (rt * math.sin(th), rt * (1.0 - math.cos(th)))
    C = (P[0] * (1.0 - t / rt), P[1] + t * (rt - P[1]) / rt)  # P moved by t along the normal to the centre
    pts = {"A": (0.0, 0.0), "P": P, "E": (R, cap), "G": (R - t, cap), "O": (0.0, cap), "D": (0.0, t), "C": C}
    return Butterfly(t, th, {**pts, "Oc": (0.0, rt)})


@dataclass(frozen=True)
class GradedButterfly:
    """A butterfly cap (:class:`Butterfly`) graded outside a core at the apex (``fe.radial_grading``): the arc A-P
    split at K, ``n_core`` elements of hr from the apex to K, then ``n_g`` growing by ``q_g`` to P; its inner
    companions D-C (at K') and O-G (at K'', in the rim plane, ``r_core`` = n_core hr from the axis) split alike, so
    band and core are two blocks each; across the bands ``m`` elements from hr at the face growing inward by
    ``q_m``, along P-E (and C-G, D-O, K'-K'') ``n_b`` growing on by ``q_b``. Neighbours differ by at most
    :data:`GROWTH` everywhere: K-P grows to at most GROWTH x the bands' largest element, which the body's columns
    meet at G. The rod's body has three columns: the core, the graded part to G and the band's, whose elements
    shrink to hr at the rim E."""

    n_core: int
    n_g: int
    q_g: float  # [-]
    m: int
    q_m: float  # [-]
    n_b: int
    q_b: float  # [-]
    r_core: float  # [m] K'' in the rim plane
    R: float  # [m] the rod's radius
    t: float  # [m] the bands' thickness

    @property
    def columns(self) -> tuple[Column, ...]:
        """The body's columns under the cap's rim line O-K''-G-E."""
        return (
            Column(self.r_core, self.n_core),
            Column(self.R - self.t, self.n_g, self.q_g),
            Column(self.R, self.m, 1.0 / self.q_m),
        )


def graded_butterfly(rod: Rod, hr: float, h: float, core: float, grading: str) -> GradedButterfly | None:
    """The graded layout of ``rod``'s butterfly cap at radial size ``hr``, axial size ``h`` and core radius ``core``
    [m] under ``fe.radial_grading``, or None: uniform (asked, no butterfly, "auto" where grading leaves more than
    :data:`GRADED_SHARE` of the uniform elements across, or an arc or band too short to grade: none of the
    single progressions by at most :data:`GROWTH` fits, or they meet at G or P with a larger ratio)."""
    b = butterfly(rod)
    H = bar_size(rod, h)
    if grading == "uniform" or b is None or H < 2.0 * hr:
        return None
    arc_ap, arc_pe = b.arcs
    n_core = element_count(arc_to(rod, core), hr)
    across, along = _progression(hr, H, b.t), _progression(hr, H, arc_ap - n_core * hr)
    if across is None or along is None:
        return None
    # the bands' and the arc's progressions meet at G (the body's columns) and P: capped alike, at GROWTH x the
    # shorter one's largest element, so the longer one grows no further than its neighbour allows
    cap = min(H, GROWTH * hr * min(q ** (n - 1) for n, q in (across, along)))
    across, along = _progression(hr, cap, b.t), _progression(hr, cap, arc_ap - n_core * hr)
    if across is None or along is None:
        return None
    (m, q_m), (n_g, q_g) = across, along
    s_band, s_p = hr * q_m ** (m - 1), hr * q_g ** (n_g - 1)  # [m] their largest: at G, and before P
    on = _progression(s_p, max(H, s_p), arc_pe) or (element_count(arc_pe, s_p), 1.0)
    s_on = arc_pe / on[0] if on[1] == 1.0 else arc_pe * (on[1] - 1.0) / (on[1] ** on[0] - 1.0)  # [m] after P
    if max(s_band / s_p, s_p / s_band, s_p / s_on, s_on / s_p) > GROWTH * (1 + 1e-9):
        return None  # a join no single progressions make smooth (short arcs on a coarse mesh)
    gb = GradedButterfly(n_core, n_g, q_g, m, q_m, *on, n_core * hr, rod.diameter / 2, b.t)
    n_a, _, m_uniform = butterfly_counts(b, hr)
    return gb if _saves(n_core + n_g + m, n_a + m_uniform, grading) else None


def _progression(first: float, H: float, width: float) -> tuple[int, float] | None:
    """(n, q): n elements first q^k (k = 0..n-1) filling ``width`` [m], q in [1, :data:`GROWTH`], the last at most
    ``H`` [m], n the fewest; None where the width is under two first elements or no such n fits."""
    if width < 2.0 * first:
        return None
    for n in range(2, math.floor(width / first * (1 + 1e-12)) + 1):
        q_max = min(GROWTH, (H / first) ** (1.0 / (n - 1)))
        if _grown(first, n, q_max) / q_max >= width:  # sizes first q^k, k = 0..n-1: the k = 1..n sum over q
            lo, hi = 1.0, q_max
            for _ in range(100):
                q = 0.5 * (lo + hi)
                lo, hi = (q, hi) if _grown(first, n, q) / q < width else (lo, q)
            return n, hi
    return None


def arc_to(rod: Rod, r: float) -> float:
    """Length [m] of the tip face's profile from the apex out to the radius ``r`` [m]: r flat, r_t asin(r/r_t) on a
    spherical cap."""
    rt = rod.tip_radius
    return r if math.isinf(rt) else rt * math.asin(min(1.0, r / rt))


def tip_arc_length(rod: Rod) -> float:
    """Length [m] of the tip face's profile from the apex to the rim (:func:`arc_to` at the rod's radius)."""
    return arc_to(rod, rod.diameter / 2)


def cap_depth(rho: Any, r: float) -> Any:
    """Cap depth c(ρ) = r - sqrt(r² - ρ²) [m] at the radius ``rho`` [m] (array or float) of a sphere of radius r
    (0 for a flat tip)."""
    if math.isinf(r):
        return np.zeros_like(rho)
    return r - np.sqrt(np.maximum(r * r - np.asarray(rho) ** 2, 0.0))


def face_count(rod: Rod, hr: float) -> int:
    """Elements along a one-block tip face at size ``hr`` [m], counted on its arc, so that a curved face's nodes
    are as far apart as the flat face's it meets (divided by the radius, a 10 mm tip on 12.7 mm rods had them
    8% farther apart, and the one-pass node-to-surface contact lost 4.6% of the peak pressure at the axis)."""
    return element_count(tip_arc_length(rod), hr)


@dataclass(frozen=True)
class Column:
    """One column of a rod's mesh across its radius, running the rod's whole length: from the column before it (or
    the axis) to the radius ``r_end`` [m], ``n`` elements whose sizes grow outward by ``ratio`` [-] (1: uniform)."""

    r_end: float  # [m]
    n: int
    ratio: float = 1.0


def radial_columns(rod: Rod, hr: float, h: float, core: float, grading: str) -> tuple[Column, ...]:
    """The columns across ``rod`` at radial size ``hr`` and axial size ``h`` [m] under ``fe.radial_grading``.

    Uniform: one column, :func:`face_count` elements. Graded: a core out to ``core`` [m] (the scene's
    :attr:`~rods.scene.Scene.graded_core`, around the contact patch, rounded up to whole elements) at ``hr`` along
    the tip face (as :func:`face_count`: a curved face's nodes as far apart as the flat face's it meets), then
    elements growing by at most :data:`GROWTH` per element up to at most the bar's size H = min(:data:`RIM_ASPECT` h,
    R / BAR_ELEMENTS) (the axial size resolves the waves along the rod, BAR_ELEMENTS the rod's section), then a
    uniform column at the last one's size to the rim (no neighbours' ratio above GROWTH anywhere, the core's edge
    included). The core holds the patch and the smallest element, so a graded rod keeps the uniform one's contact
    and step (longer on a curved cap, whose rim cells are wider: rods.cost._tip_step) and loses the
    fine elements where nothing needs them: a structured mesh at the patch's size otherwise runs the whole radius
    (4 mm tip on a 4.2 mm rod at 0.177 m/s: 72 elements of 0.029 mm across). "auto" grades where that leaves at
    most :data:`GRADED_SHARE` of the uniform count ("graded": fewer than it); a core past the rim or leaving a band
    no such elements fill (under hr, 1.2-2 hr, 2.64-3 hr), and H < 2 hr stay uniform. A butterfly cap
    (:func:`butterfly`) is graded by :func:`graded_butterfly` (its body's three columns), else one column of its
    n_a + m elements across."""
    R = rod.diameter / 2
    if (b := butterfly(rod)) is not None:
        if (gb := graded_butterfly(rod, hr, h, core, grading)) is not None:
            return gb.columns
        n_a, _, m = butterfly_counts(b, hr)
        return (Column(R, n_a + m),)
    uniform = (Column(R, face_count(rod, hr)),)
    H = bar_size(rod, h)
    if grading == "uniform" or core >= R or H < 2.0 * hr:
        return uniform
    n_core = element_count(arc_to(rod, core), hr)
    rt = rod.tip_radius  # the core's elements hr long along the face: its edge where the face's arc is n_core hr
    core = n_core * hr if math.isinf(rt) else rt * math.sin(min(n_core * hr / rt, math.asin(R / rt)))
    if core >= R:
        return uniform
    outside = _outside_columns(hr, H, core, R)
    if outside is None:
        return uniform
    columns = (Column(core, n_core), *outside)
    if not _saves(sum(c.n for c in columns), uniform[0].n, grading):
        return uniform
    return columns


def _saves(graded: int, uniform: int, grading: str) -> bool:
    """Whether ``graded`` elements across are worth it against ``uniform`` under ``fe.radial_grading``: "auto" at
    most :data:`GRADED_SHARE` of them, "graded" any fewer (none where hr fills a band alone)."""
    return graded < uniform and (grading != "auto" or graded <= GRADED_SHARE * uniform)


def bar_size(rod: Rod, h: float) -> float:
    """The bar's element size across ``rod`` at axial size ``h`` [m]: H = min(:data:`RIM_ASPECT` h, R /
    BAR_ELEMENTS), the largest a graded mesh grows to (the axial size resolves the waves along the rod,
    BAR_ELEMENTS the rod's section)."""
    return min(RIM_ASPECT * h, rod.diameter / 2 / BAR_ELEMENTS)


def _grown(hr: float, n: int, q: float) -> float:
    """Width [m] of n elements hr q^k, k = 1..n."""
    return n * hr if q == 1.0 else hr * q * (q**n - 1.0) / (q - 1.0)


def _outward_ratio(hr: float, n: int, n_tail: int, width: float, q_max: float) -> float:
    """The ratio q in [1, ``q_max``] at which n elements hr q^k (k = 1..n) and ``n_tail`` more of hr q^n fill
    ``width`` [m] (bisection: the total grows with q; the caller puts the root in the interval)."""
    lo, hi = 1.0, q_max
    for _ in range(100):
        q = 0.5 * (lo + hi)
        lo, hi = (q, hi) if _grown(hr, n, q) + n_tail * hr * q**n < width else (lo, q)
    return hi


def _outside_columns(hr: float, H: float, core: float, R: float) -> tuple[Column, ...] | None:
    """The columns from the core's edge ``core`` to the rim ``R`` [m]: elements from hr q growing by q <= GROWTH
    to at most H, then uniform at the last one's size; None where none fill a band this narrow (under hr, 1.2 to 2 hr,
    2.64 to 3 hr: n elements of hr q^k, q <= GROWTH, span n hr to hr (q + ... + q^n))."""
    width = R - core  # [m]
    n_g = math.ceil(math.log(H / hr) / math.log(GROWTH) - 1e-9)
    q_H = (H / hr) ** (1.0 / n_g)
    if width - _grown(hr, n_g, q_H) >= H:
        # n_g growing to s = hr q^n_g, then n_u of size s; n_u >= (width - grown(q_H))/H puts q in [1, q_H] (s <= H)
        n_u = element_count(width - _grown(hr, n_g, q_H), H)
        q = _outward_ratio(hr, n_g, n_u, width, q_H)
        return Column(core + _grown(hr, n_g, q), n_g, q), Column(R, n_u)
    for n in range(1, math.floor(width / hr * (1 + 1e-12)) + 1):  # the rim before H: n hr <= width, none below hr
        q_max = min(GROWTH, (H / hr) ** (1.0 / n))
        if _grown(hr, n, q_max) >= width:
            return (Column(R, n, _outward_ratio(hr, n, 0, width, q_max)),)
    return None


# fe.radial_coarsening = "auto" (:func:`coarsening`): a rod's columns merge 3:1 from this many diameters of the thicker
# rod from the tips [-], past the contact's Saint-Venant zone (about a diameter: there the tip's columns resolve the
# patch's stresses) and, whichever is farther, a submodel's cut band (:func:`coarsening_start`)
COARSEN_DIAMETERS = 2.0
# three elements merge where their width is at most the bar's size H (:func:`bar_size`, at least BAR_ELEMENTS across
# the radius), up to this round-off [-]: the paper rods' 24 elements of R/24 merge into 8 of R/8 = H
MERGE_SLACK = 1e-6


@dataclass(frozen=True)
class Coarsening:
    """A rod's columns merged 3:1 along it (``fe.radial_coarsening``, :func:`coarsening`): after ``rows`` elements of
    the uniform block, one layer an element long per entry of ``layers``, each the groups across it, axis to rim (3:
    three elements merge into one in the 3:1 template of four quadrilaterals, :func:`_coarsening_layers`; 1: one
    passes through), then the rest of the uniform block on the last layer's elements. ``radii``: the nodes across at
    each station [m], the columns' own first; ``z``: the first layer's distance from the tip [m]; ``dz``: a layer's
    length, the uniform block's element [m]."""

    rows: int
    layers: tuple[tuple[int, ...], ...]
    radii: tuple[tuple[float, ...], ...]
    z: float
    dz: float

    @property
    def cells(self) -> int:
        """Quadrilaterals in the layers [-]."""
        return sum(4 * g.count(3) + g.count(1) for g in self.layers)

    @property
    def n_far(self) -> int:
        """Elements across past the layers [-]."""
        return len(self.radii[-1]) - 1


def _merged(sizes: np.ndarray, H: float) -> tuple[int, ...]:
    """One layer's groups over elements of ``sizes`` [m], axis to rim: each next three whose width is at most ``H``
    [m] (:data:`MERGE_SLACK`) merge, else one passes through."""
    groups, i = [], 0
    while i < len(sizes):
        g = 3 if i + 3 <= len(sizes) and sizes[i : i + 3].sum() <= H * (1.0 + MERGE_SLACK) else 1
        groups.append(g)
        i += g
    return tuple(groups)


def coarsening(
    rod: Rod, columns: tuple[Column, ...], h: float, spacing: AxialSpacing, start: float
) -> Coarsening | None:
    """The 3:1 merges (:class:`Coarsening`) of ``rod``'s ``columns`` from ``start`` [m] from its tip (inf: none) at
    bar axial size ``h`` [m] (:func:`bar_size`) along its axial ``spacing``: layers until no three elements fit the
    bar's size, starting in the uniform block at the first row boundary past ``start``. Why: the columns resolve the
    patch at the tip, and a structured mesh runs them the rod's whole length; past the contact's zone a bar wave needs
    only the bar's size across (what a graded rod's rim has, :func:`radial_columns`), so the paper rods' 24 columns
    run 8 wide there (the paper rods at 0.1 m/s: 36 graded, 14 and 13 there). The step stays the tip's (the layers'
    elements are no narrower than the columns they merge). None where nothing merges or the rod ends before the
    layers and a row past them."""
    if not math.isfinite(start):
        return None
    radii = [np.concatenate(([0.0], np.cumsum(element_sizes(columns))[:-1], [rod.diameter / 2]))]
    layers: list[tuple[int, ...]] = []
    while 3 in (groups := _merged(np.diff(radii[-1]), bar_size(rod, h))):
        layers.append(groups)
        radii.append(radii[-1][np.concatenate(([0], np.cumsum(groups)))])
    h_u = (rod.length - spacing.core_length - spacing.graded_length) / spacing.n_uniform  # [m]
    rows = max(1, math.ceil((start - spacing.core_length - spacing.graded_length) / h_u - 1e-9))
    if not layers or rows + len(layers) >= spacing.n_uniform:
        return None
    z = spacing.core_length + spacing.graded_length + rows * h_u  # [m]
    return Coarsening(rows, tuple(layers), tuple(tuple(float(x) for x in r) for r in radii), z, h_u)


def coarsening_start(scene: Scene) -> float:
    """Where ``scene``'s axisymmetric global coarsens across (``fe.radial_coarsening`` "auto", :func:`coarsening`)
    [m from each tip]: :data:`COARSEN_DIAMETERS` of the thicker rod, or past a submodel's cut band (fe.submodel_length
    and the band's BAND_ELEMENTS axial elements, one more for margin) where that is farther, so a driving global's
    cut sees the tip's columns; inf for "none" and the 3D model (an O-grid: no columns)."""
    if scene["fe.radial_coarsening"] == "none" or scene["fe.kind"] != "axisymmetric":
        return math.inf
    band = scene.submodel_length + (BAND_ELEMENTS + 1) * scene["fe.axial_size"]
    return max(COARSEN_DIAMETERS * max(r.diameter for r in scene.rods), band)


def scene_columns(scene: Scene) -> tuple[tuple[Column, ...], tuple[Column, ...]]:
    """Both rods' columns (:func:`radial_columns`) on ``scene``'s global axisymmetric mesh."""
    hr, h, core, grading = (
        scene["fe.radial_size"],
        scene.bar_axial_size,
        scene.graded_core,
        scene["fe.radial_grading"],
    )
    return tuple(radial_columns(rod, hr, h, core, grading) for rod in scene.rods)  # type: ignore[return-value]


def graded_words(graded: tuple[bool, ...]) -> str:
    """Which rods a graded mesh grades, in a plan's words ("both rods", "rod 2"); "" where none."""
    return "both rods" if all(graded) else next((f"rod {k + 1}" for k, g in enumerate(graded) if g), "")


def progression(length: float, n: int, q: float) -> np.ndarray:
    """The sizes [m] of ``n`` elements growing by ``q`` that fill ``length`` [m]: the first length (q - 1)/(q^n - 1),
    or length/n where q = 1 (a deep cap's block of equal elements, :func:`_graded_counts`)."""
    return first_size(length, n, q) * q ** np.arange(n)


def first_size(length: float, n: int, q: float) -> float:
    """The first of :func:`progression`'s sizes [m], without the other n - 1 (a block of 1.2e8 elements)."""
    return length / n if q == 1.0 else length * (q - 1.0) / (q**n - 1.0)


def element_sizes(columns: tuple[Column, ...]) -> np.ndarray:
    """Every element's size across [m] of a rod's ``columns``, axis to rim (:func:`progression` in each)."""
    sizes, r0 = [], 0.0
    for c in columns:
        sizes.append(progression(c.r_end - r0, c.n, c.ratio))
        r0 = c.r_end
    return np.concatenate(sizes)


@dataclass(frozen=True)
class RodLayout:
    """One rod of a scene's axisymmetric mesh as the mesher lays it out (:func:`rod_layouts`)."""

    rod: Rod
    columns: tuple[Column, ...]
    spacing: AxialSpacing
    coarsened: Coarsening | None
    butterfly: Butterfly | None
    graded: GradedButterfly | None = None  # the butterfly's grading (:func:`graded_butterfly`; None: uniform)


def rod_layouts(scene: Scene) -> tuple[RodLayout, RodLayout]:
    """Both rods' layouts on ``scene``'s axisymmetric mesh (a global's, or a submodel's region): the columns across
    (:func:`scene_columns`), the spacing along (:func:`axial_spacing` at fe.axial_size and the tip grading, a graded
    submodel's core), the 3:1 merges (:func:`coarsening`) and a near-hemispherical tip's butterfly, graded or not."""
    h, g, start = scene["fe.axial_size"], scene.tip_grading, coarsening_start(scene)
    hr, h_bar, core, grading = (
        scene["fe.radial_size"],
        scene.bar_axial_size,
        scene.graded_core,
        scene["fe.radial_grading"],
    )
    layouts = []
    for rod, columns in zip(scene.rods, scene_columns(scene), strict=True):
        sp = axial_spacing(rod, h, g, *scene.axial_core)
        co = coarsening(rod, columns, h_bar, sp, start)
        b = butterfly(rod)
        layouts.append(
            RodLayout(rod, columns, sp, co, b, graded_butterfly(rod, hr, h_bar, core, grading) if b else None)
        )
    return layouts[0], layouts[1]


def butterfly_tip_element(b: Butterfly, hr: float, gb: GradedButterfly | None) -> float:
    """The element normal to a butterfly cap's face at the apex [m] (the mesh's h_tip there): the band's thickness
    over its m elements across, or, graded, hr (its bands grow inward from hr at the face)."""
    return b.t / butterfly_counts(b, hr)[2] if gb is None else hr


def axial_blocks(rod: Rod, sp: AxialSpacing, co: Coarsening | None) -> list[tuple[float, int, float, Any]]:
    """A rod's axial blocks from its tip face to its far end, as the mesher draws them (rods.fe.mesh._rod_body), each
    (its end's distance from the apex [m], elements, their growth ratio away from the tip, the end station's node
    radii where a coarsening's first layer starts, else None): a graded submodel's core, the tip's graded block, the
    uniform block (in two where it coarsens, the layers between them drawn by their template)."""
    blocks: list[tuple[float, int, float, Any]] = []
    if sp.n_core:
        blocks.append((sp.core_length, sp.n_core, 1.0, None))
    if sp.n_graded:
        blocks.append((sp.core_length + sp.graded_length, sp.n_graded, sp.ratio, None))
    if co is not None:
        blocks.append((co.z, co.rows, 1.0, co.radii[0]))
    blocks.append((rod.length, sp.n_uniform - (0 if co is None else co.rows + len(co.layers)), 1.0, None))
    return blocks


def tip_row(layout: RodLayout) -> np.ndarray:
    """The corners [m] of the row of cells on a one-block tip face (a flat or curved tip below the butterfly), shape
    (cells, 4, 2) as (r, distance from the apex along the axis), each cell's face side first: the face's nodes (each
    column's elements along its arc, rods.fe.mesh._flat_block_cap) joined to the first block's end station (each
    column's across) by straight lines graded as the block, the transfinite surface between them, of which this row
    is the first (progression) share. The rim's cells are the most distorted: the face slopes there and they are
    (L - c)/L as thick as the axis's under a cap of height c over a block of length L."""
    rod, columns = layout.rod, layout.columns
    rt, R = rod.tip_radius, rod.diameter / 2
    top, r0 = [0.0], 0.0
    for c in columns:
        top.extend(r0 + np.cumsum(progression(c.r_end - r0, c.n, c.ratio)))
        r0 = c.r_end
    z_end, n, ratio, split = axial_blocks(rod, layout.spacing, layout.coarsened)[0]
    r_face = _on_profile(rod, _column_arcs(rod, columns))
    r_top = np.asarray(split if split is not None else [*top[:-1], R])
    on_face = np.stack([r_face, cap_depth(r_face, rt)], axis=1)
    first = first_size(1.0, n, ratio)  # not progression()[0]: 1.2e8 sizes along a 1 µm rod's partner, 1 GB (a fuzz)
    below = on_face + first * (np.stack([r_top, np.full_like(r_top, z_end)], axis=1) - on_face)
    return np.stack([on_face[:-1], on_face[1:], below[:-1], below[1:]], axis=1)


def _column_arcs(rod: Rod, columns: tuple[Column, ...]) -> np.ndarray:
    """The arc lengths [m] from the apex of a one-block face's nodes (each column's elements along its arc,
    rods.fe.mesh._flat_block_cap), the apex's 0 first."""
    arcs, r0 = [np.zeros(1)], 0.0
    for c in columns:
        s0, s1 = arc_to(rod, r0), arc_to(rod, c.r_end)
        arcs.append(s0 + np.cumsum(progression(s1 - s0, c.n, c.ratio)))
        r0 = c.r_end
    return np.concatenate(arcs)


def _on_profile(rod: Rod, arcs: np.ndarray) -> np.ndarray:
    """The radii [m] of the face's points ``arcs`` [m] along its profile from the apex, the last the rim exactly (as
    the mesher's last point)."""
    rt = rod.tip_radius
    r = arcs.copy() if math.isinf(rt) else rt * np.sin(arcs / rt)
    r[-1] = rod.diameter / 2
    return r


@dataclass(frozen=True)
class TipFace:
    """A rod's tip face as the mesher lays it (:func:`tip_faces`): its nodes from the apex to the rim."""

    rod: Rod
    arc: np.ndarray  # [m] each node's arc length from the apex along the face's profile
    r: np.ndarray  # [m] each node's radius
    area: np.ndarray  # [m^2] ∫ N_i r ds along the face: each node's tributary area over 2π
    volume: np.ndarray  # [m^3] ∫ N_i r dA over the row of cells under each node: its lumped mass over 2π ρ
    h_tip: float  # [m] the mesher's element normal to the face (rods.fe.mesh.RodsMesh.h_tip is the rods' smaller)


def tip_faces(scene: Scene) -> tuple[TipFace, TipFace]:
    """Both rods' tip faces on ``scene``'s axisymmetric mesh (a global's or a submodel's region): a one-block face's
    nodes along its columns over the first row of its first axial block (:func:`tip_row`'s), a butterfly's along
    its arcs A-P (graded: A-K-P) and P-E over its band's first element across (rods.fe.mesh._butterfly_cap)."""
    hr = scene["fe.radial_size"]
    faces = []
    for layout in rod_layouts(scene):
        rod, b = layout.rod, layout.butterfly
        if b is None:
            arcs = _column_arcs(rod, layout.columns)
            r = _on_profile(rod, arcs)
            faces.append(TipFace(rod, arcs, r, face_areas(arcs, r), row_volumes(tip_row(layout)), layout.spacing.h_tip))
            continue
        gb, (arc_ap, arc_pe) = layout.graded, b.arcs
        if gb is None:
            n_a, n_b, _ = butterfly_counts(b, hr)
            pieces = [progression(arc_ap, n_a, 1.0), progression(arc_pe, n_b, 1.0)]
        else:
            core = gb.n_core * hr
            pieces = [np.full(gb.n_core, hr), progression(arc_ap - core, gb.n_g, gb.q_g)]
            pieces = [*pieces, progression(arc_pe, gb.n_b, gb.q_b)]
        h_tip = butterfly_tip_element(b, hr, gb)
        arcs = np.concatenate(([0.0], np.cumsum(np.concatenate(pieces))))
        r = _on_profile(rod, arcs)
        area = face_areas(arcs, r)
        faces.append(TipFace(rod, arcs, r, area, area * h_tip / 2.0, h_tip))  # the band's first row: h_tip thick
    return faces[0], faces[1]


def face_areas(arc: np.ndarray, r: np.ndarray) -> np.ndarray:
    """∫ N_i r ds [m^2] of a face's nodes at arc lengths ``arc`` and radii ``r`` [m] (linear elements along the
    profile, r linear on each): the set-up's tributary areas (rods.fe.forms.tributary_area_form) over 2π."""
    ds, ra, rb = np.diff(arc), r[:-1], r[1:]
    a = np.zeros(r.size)
    a[:-1] += ds * (2.0 * ra + rb) / 6.0
    a[1:] += ds * (ra + 2.0 * rb) / 6.0
    return a


# 2-point Gauss rule on [0, 1]: exact for the cubic ξ-dependence of N r det J on a bilinear cell
_GAUSS = (0.5 - 0.5 / math.sqrt(3.0), 0.5 + 0.5 / math.sqrt(3.0))


def row_volumes(cells: np.ndarray) -> np.ndarray:
    """∫ N_i r dA [m^3] of a face's nodes over the row of cells ``cells`` under it (corners as :func:`tip_row`'s:
    (face node i, face node i + 1, the two below), bilinear, 2 x 2 Gauss points): the lumped (row-sum) mass of
    the face's nodes over 2π ρ (rods.fe.forms.lumped_mass_form), which only that row's cells carry."""
    P = [cells[:, k] for k in range(4)]
    volume = np.zeros(cells.shape[0] + 1)
    for ξ in _GAUSS:
        for η in _GAUSS:
            N = ((1 - ξ) * (1 - η), ξ * (1 - η), (1 - ξ) * η, ξ * η)
            dξ = (1 - η) * (P[1] - P[0]) + η * (P[3] - P[2])
            dη = (1 - ξ) * (P[2] - P[0]) + ξ * (P[3] - P[1])
            r = sum(n * p[:, 0] for n, p in zip(N, P, strict=True))
            w = 0.25 * r * np.abs(dξ[:, 0] * dη[:, 1] - dξ[:, 1] * dη[:, 0])  # the rule's weight 1/4 on [0, 1]²
            volume[:-1] += N[0] * w
            volume[1:] += N[1] * w
    return volume


def altitudes(cells: np.ndarray) -> np.ndarray:
    """Each quadrilateral's smallest distance [m] from a corner to the line of a side it is not on (corners ordered
    as :func:`tip_row`'s: sides 0-1, 2-3, 0-2, 1-3): its thickness across its thinnest direction, which sets its
    highest frequency, a rectangle's shorter side."""

    def distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        t, d = b - a, p - a
        return np.abs(t[:, 0] * d[:, 1] - t[:, 1] * d[:, 0]) / np.hypot(t[:, 0], t[:, 1])

    P = [cells[:, k] for k in range(4)]
    pairs = (((0, 1), (2, 3)), ((2, 3), (0, 1)), ((0, 2), (1, 3)), ((1, 3), (0, 2)))  # a side, the corners opposite
    return np.min([distance(P[c], P[a], P[b]) for (a, b), opposite in pairs for c in opposite], axis=0)


def butterfly_counts(b: Butterfly, hr: float) -> tuple[int, int, int]:
    """Elements (n_a, n_b, m) of a butterfly at size ``hr`` [m]: along the arcs A-P and P-E, across the bands."""
    n_a, n_b = (element_count(x, hr) for x in b.arcs)
    return n_a, n_b, element_count(b.t, hr)


def mesh_counts(
    rod: Rod,
    hr: float,
    h: float,
    grading: float,
    core: float = math.inf,
    radial: str = "uniform",
    h_bar: float | None = None,
    core_along: tuple[float, float] = (0.0, 0.0),
    coarsen_from: float = math.inf,
) -> tuple[int, int]:
    """(cells, nodes) of one rod's mesh at radial size ``hr``, axial ``h`` [m], tip grading and radial grading
    ``radial`` around a core of radius ``core`` [m] (:func:`radial_columns`, its bar's size bounded by ``h_bar``,
    default ``h``: :attr:`rods.scene.Scene.bar_axial_size`; along, a graded submodel's ``core_along``,
    :attr:`rods.scene.Scene.axial_core`), coarsened across from ``coarsen_from`` [m] (:func:`coarsening`); what the
    mesher makes. Nodes: a simply connected quadrilateral mesh has V = F + E_b/2 + 1 (Euler's V - E + F = 1 with
    4F = 2E - E_b), E_b its boundary edges: the tip, the axis, the outer surface and the far end; with a butterfly
    cap the tip's arcs A-P-E, the axis A-D-O and the shaft, the far end as wide as the body's last station."""
    sp = axial_spacing(rod, h, grading, *core_along)
    n_z, b, h_bar = sp.n, butterfly(rod), h if h_bar is None else h_bar
    columns = radial_columns(rod, hr, h_bar, core, radial)
    n = sum(c.n for c in columns)
    co = coarsening(rod, columns, h_bar, sp, coarsen_from)
    # the body: n across over n_z rows, or n over the rows to the coarsening, its layers, n_far over the rest
    body, far = n * n_z, n
    if co is not None:
        rest = sp.n_uniform - co.rows - len(co.layers)
        body, far = n * (n_z - len(co.layers) - rest) + co.cells + co.n_far * rest, co.n_far
    if b is None:
        cells, boundary = body, n + far + 2 * n_z
    else:
        gb = graded_butterfly(rod, hr, h_bar, core, radial)
        n_a, n_b, m = butterfly_counts(b, hr) if gb is None else (gb.n_core + gb.n_g, gb.n_b, gb.m)
        cells, boundary = (n_a + n_b) * m + n_a * n_b + body, 2 * (n_a + n_b + m + n_z) - n + far
    return cells, cells + boundary // 2 + 1
