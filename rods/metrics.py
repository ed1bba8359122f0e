"""Scalar measures taken from histories, defined once and shared by every model.

* Contact duration: from first touch to separation, the first contact episode of the electrical-continuity trigger
  of the experiment: the force counts as contact while above ``CONTACT_THRESHOLD`` = 1e-6 of its peak, a
  round-off guard, not a physical level. Each end is placed between samples by the Hertz law: the compression
  δ ∝ F^(2/3) goes through zero linearly in time at touch and at release, so F^(2/3) is extrapolated linearly from
  the two samples inside the episode to zero, clipped to the sample interval that brackets the end (exact for a
  sampled Hertz pulse to second order; on the analytical model it lands within 0.05 µs of the solver's release
  event at 0.25 µs sampling). Gaps shorter than :func:`min_gap` (``MIN_GAP_TRANSITS`` = 0.4 of the thinner rod's
  diameter transit d/c: 0.99 µs on the paper's rods) do not end an episode: contact nodes chatter on a nanosecond
  scale, and the experiment (sampled every 2.26 µs) cannot see such gaps either. The gap is in the scene's own time
  scale, not in seconds: a scene scaled by λ in length has every time x λ (the auto sampling and mesh included), and
  a fixed 1 µs merged a real 0.72 µs separation of a half-size scene whose full-size one parted for 1.44 µs
  (contact duration +16%, a fuzz, 2026-12-07).
  A threshold at a fraction of the peak (1e-3, used here before) is ill-conditioned: a stiff or wide contact ends
  in a long low tail (Rod 1 with a 1 m tip on the paper rods, 5 mm rods: 0.05-0.3% of the peak for ~30 µs), the
  duration there was the threshold's choice (1 m tip: 154 µs at 0.2%, 196 µs at 0.05%, analytical), and the FE
  and analytical tails crossed it 4-12 µs apart while they separate within 1-3 µs (results/scene-probe.md).
* Average peak speed (Table 2): the paper averages the Rod-2 midpoint speed over the first five
  plateaus, taking samples >= 1.0 m/s (``rods.paper_data``: ``plateau_threshold``). A fixed 1.0 m/s cannot apply to
  the 1.848 m/s trial (its plateaus sit near s1/2 = 0.92 m/s), so the default threshold here is
  relative: ``0.9 x`` the largest midpoint speed, about the paper's 1.0 m/s at 2.2 m/s; an absolute
  ``threshold`` [m/s] reproduces the paper's rule. A plateau is a maximal run of samples at or above
  the threshold, where a dip below it shorter than :func:`plateau_gap` (Rod 2's diameter over its bar wave speed)
  does not end the run; the result is the mean of the samples at or above the threshold in the first five
  plateaus. The gap rule is for the FE model's lateral (Pochhammer-Chree) ringing behind a front, which the 1D
  model lacks: where the plateaus stand barely above the threshold (a titanium striker on an aluminium Rod 2, 20 mm
  rods), ringing dipped one plateau's end below it for 0.2-2 µs and left 1-sample "plateaus" (1.205 m/s) in the
  average where the analytical model had a whole plateau (1.270 m/s). On scenes whose plateaus stand clear of the
  threshold (the paper's) no dip is that short, and the value is the plain runs' mean.
* Smoothed peak force: the largest value of the force averaged over a sliding window (:func:`smoothing`:
  ``SMOOTHING_TRANSITS`` = 0.8 of the shorter diameter transit d/c, 1.99 µs on the paper's rods, below the experiment's
  2.26 µs sampling). Stiff penalties make contact nodes rattle and add nanosecond spikes to the raw force; the
  smoothed peak is what a sensor would see.
* RMS strain difference (Table 2): over the first five periods 2 L2/c2 of the midpoint strain,
  counted from impact (:func:`strain_window`); the two histories are compared on the first one's
  sample times.
* Edge-period contact radius (:func:`edge_period_radius`): a node-based contact closes node by node, so the
  contact radius at one instant depends on where the edge sits between two nodes (a sawtooth in that phase;
  ±0.4% at 0.125 mm on the paper scene, results/edge-scatter.md). The ratio a/a_H(F) to Hertz at the same force
  is averaged, uniformly in a, over the last node spacing the edge swept before the peak force (one whole
  period of the phase, over which the sawtooth averages out) and applied at the peak force. Quasi-static
  loading (a ∝ F^(1/3) over that sweep) is the assumption; at least ``EDGE_MIN_SAMPLES`` history samples must
  fall in the sweep, else NaN.
* Strain lag (:func:`time_lag`): the shift of one history against the other that minimises that RMS (negative:
  the first leads); it tells a timing offset from a difference of shape.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from rods.scene import Rod, Scene

__all__ = [
    "contact_episodes",
    "contact_duration",
    "edge_period_radius",
    "first_contact_open",
    "longer_transit",
    "midpoint_peak_speed",
    "min_gap",
    "plateau_bounds",
    "plateau_gap",
    "reaches_end",
    "plateau_level",
    "plateaus",
    "rms_difference",
    "shorter_transit",
    "smoothed_peak",
    "smoothing",
    "strain_window",
    "time_lag",
    "window_rms_difference",
]

CONTACT_THRESHOLD = 1e-6  # fraction of the peak force below which it is zero (round-off guard) [-]
# gaps shorter than this many of the thinner rod's diameter transits d/c do not separate contact episodes [-]
MIN_GAP_TRANSITS = 0.4
TAIL_FRACTION = 0.01  # the level, of the peak force, below which the end of a contact is its tail [-]
# longest tail of the first contact of an "ok" run, in the thinner rod's diameter transits d/c (paper rods: 39.7 µs;
# 2% of it, 0.32 d/c, inside rods.checks.AGREE_TRANSITS); in the scene's time scale, not in seconds: a scene scaled by
# λ in length has its tail x λ (a fixed 40 µs warned on the paper scene at 10 m/s scaled x 2, 66 µs, not at x 1,
# 33 µs) [-]. A touch whose force stays below TAIL_FRACTION of the episode's peak before it, within this of it, is that
# episode's tail, not a contact of its own (:func:`contact_episodes`)
TAIL_TRANSITS = 16.0
SMOOTHING_TRANSITS = 0.8  # sliding-average window of the smoothed peak force, in the shorter diameter transit d/c [-]
PATCH_ELEMENTS_MIN = 2.0  # fewest elements across the contact radius that resolve a patch [-]
# a picture of the contact's half-width in contact radii [-]: the patch and the stress under it (Hertz's largest
# von Mises stress lies 0.48 a deep, its field fades over a few a); the paper scene's 1.09 mm patch: 2.7 mm
PICTURE_PATCHES = 2.5
# the contact force's panel in first contacts [-]: the first contact and as long again after it (later contacts)
FORCE_PANEL_CONTACTS = 2.0
PLATEAU_FRACTION = 0.9  # fraction of the largest midpoint speed that marks a plateau [-]
PLATEAU_COUNT = 5  # plateaus averaged for the average peak speed [-]
# a probe speed below this fraction of the impact speed is no arrival of the wave: the explicit FE's dispersive
# precursor ahead of the front (3e-49 m/s at the paper's midpoint at 20 µs, a "plateau" of noise before) [-]
ARRIVAL = 1e-3
EDGE_MIN_SAMPLES = 8  # history samples the edge-period average needs in its sweep [-]
STRAIN_PERIODS = 5  # periods 2 L2/c2 of the midpoint strain compared by the RMS difference [-]


def _hertz_end(t: np.ndarray, y: np.ndarray, inside: int, step: int, outside: int, level: float) -> float:
    """Where y = F^(2/3) (∝ the Hertz compression, linear in time at touch and release) reaches zero: extrapolated
    from the sample ``inside`` the episode and its neighbour ``inside - step`` further in, clipped to the interval
    between ``inside`` and ``outside``; where the neighbour does not lie further in (a one-sample episode, or y not
    falling towards the end), the interval's linear interpolation to ``level``."""
    a, b = t[inside], t[outside]
    far = inside - step
    if 0 <= far < t.size and y[far] > y[inside]:
        tc = a + y[inside] * (a - t[far]) / (y[far] - y[inside])
    else:
        tc = a + (y[inside] - level) * (b - a) / (y[inside] - y[outside]) if y[inside] != y[outside] else a
    return float(min(max(tc, min(a, b)), max(a, b)))


def shorter_transit(scene: Scene) -> float:
    """The shorter of the two rods' diameter transits d/c [s]: the scale of a contact's chatter on an auto mesh (its
    sizes follow the diameters) and of the auto output interval (rods.scene: SAMPLES_PER_DIAMETER_TRANSIT)."""
    return min(r.diameter_transit for r in scene.rods)


def longer_transit(scene: Scene) -> float:
    """The longer of the two rods' diameter transits d/c [s]: the scale of the thicker rod's lateral ringing, which
    the 1D bars lack, against which the ringing and bar-theory checks judge a force's rise and ripple (rods.checks)."""
    return max(r.diameter_transit for r in scene.rods)


def min_gap(scene: Scene) -> float:
    """The shortest gap [s] that separates two contact episodes of ``scene`` (module docstring)."""
    return MIN_GAP_TRANSITS * shorter_transit(scene)


def smoothing(scene: Scene) -> float:
    """The sliding-average window [s] of ``scene``'s smoothed peak force (module docstring)."""
    return SMOOTHING_TRANSITS * shorter_transit(scene)


def late_impulse(t: ArrayLike, force: ArrayLike, after: float, min_gap: float) -> float:
    """The share [-] of the first contact's impulse ∫P dt (:func:`contact_episodes`) delivered later than ``after``
    [s] from its start: 0 for a contact that ends sooner (where the returning reflection meets a contact still
    pushing, rods.checks.plateau_warning); NaN without a contact."""
    episodes = contact_episodes(t, force, min_gap)
    if not episodes:
        return float("nan")
    start, end = episodes[0]
    t, f = np.asarray(t, float), np.abs(np.asarray(force, float))
    inside = (t >= start) & (t <= end)
    total = float(np.trapezoid(f[inside], t[inside]))
    late = inside & (t >= start + after)
    return float(np.trapezoid(f[late], t[late])) / total if total > 0 and late.sum() > 1 else 0.0


def contact_episodes(
    t: ArrayLike, force: ArrayLike, min_gap: float, threshold: float = CONTACT_THRESHOLD
) -> list[tuple[float, float]]:
    """Intervals [start, end] in which ``force`` (compressive magnitude, >= 0) exceeds ``threshold x peak``, their
    ends placed between samples by the Hertz law (module docstring); episodes separated by less than ``min_gap`` [s]
    (:func:`min_gap` of the scene) are one, and so is a touch whose force stays below :data:`TAIL_FRACTION` of the
    episode's peak before it, within the tail's :data:`TAIL_TRANSITS` d/c of it (its low tail: an audit's first
    contact read 367.5 µs where a touch at 0.7% of its peak 3.6 µs later ran its tail to 394 µs, FE 324-394 µs by the
    mesh; a short striker's rebounds at 1.4%, 0.66% and 0.32% of the first's peak are each half the one before: four
    impacts)."""
    t, f = np.asarray(t, float), np.abs(np.asarray(force, float))
    if f.size == 0 or f.max() <= 0:
        return []
    cut = threshold * f.max()  # [N]
    y, level, on = f ** (2.0 / 3.0), cut ** (2.0 / 3.0), f > cut
    edges = np.flatnonzero(np.diff(on.astype(np.int8)))
    out, start, first = [], (t[0] if on[0] else None), 0
    for i in edges:
        if on[i + 1]:
            start, first = _hertz_end(t, y, i + 1, -1, i, level), i + 1
        elif start is not None:
            out.append((start, _hertz_end(t, y, i, 1, i + 1, level), float(f[first : i + 1].max())))
            start = None
    if start is not None:
        out.append((start, t[-1], float(f[first:].max())))
    tail = TAIL_TRANSITS / MIN_GAP_TRANSITS * min_gap  # [s] the tail's window (min_gap is MIN_GAP_TRANSITS d/c)
    merged: list[tuple[float, float]] = []
    before = 0.0  # [N] the peak of the episode so far
    for a, b, peak in out:
        gap = a - merged[-1][1] if merged else math.inf
        if gap < min_gap or (peak < TAIL_FRACTION * before and gap < tail):
            merged[-1], before = (merged[-1][0], b), max(before, peak)
        else:
            merged.append((a, b))
            before = peak
    return merged


def first_contact_open(episodes: Sequence[Sequence[float]], last: float) -> bool:
    """Whether the first of ``episodes`` (:func:`contact_episodes`) is still open at ``last`` [s], the record's last
    sample: it ends there (to 1e-9 of it), so its duration is unknown."""
    return bool(episodes) and episodes[0][1] >= last * (1 - 1e-9)


def contact_duration(t: ArrayLike, force: ArrayLike, min_gap: float, threshold: float = CONTACT_THRESHOLD) -> float:
    """Duration of the first contact episode [s] (see module docstring; ``min_gap`` [s]: :func:`min_gap`); 0 if
    there is none."""
    ep = contact_episodes(t, force, min_gap, threshold=threshold)
    return ep[0][1] - ep[0][0] if ep else 0.0


def edge_period_radius(
    force: ArrayLike,
    radius: ArrayLike,
    spacing: float,
    E_star: float,
    R_star: float,
    peak_force: float | None = None,
) -> tuple[float, float, int]:
    """(a_edge [m], mean ratio a/a_H(F) - 1 [-], samples used) from the force [N] and contact radius [m]
    histories and the node ``spacing`` [m] at the edge (module docstring); a_edge is the ratio applied at
    ``peak_force`` [N] (the run's every-step peak, which the radius is compared at), else at the histories' largest
    sample (up to 8e-4 below it at the output interval: the radius 3e-4 short). The sweep: the samples from the
    last one with a < a_peak - spacing (exclusive) up to the peak force; the ratio is integrated over a
    (trapezoid, samples ordered by a) and divided by the a-range covered. NaN where the sweep holds fewer
    than EDGE_MIN_SAMPLES samples, where the edge starts inside one spacing of the axis (a_peak < 2 spacing:
    under two elements across the patch radius), or there is no contact."""
    from rods.hertz import contact_radius

    F, a = np.asarray(force, float), np.asarray(radius, float)
    nan = (float("nan"), float("nan"), 0)
    if F.size == 0 or not (F.max() > 0) or not (spacing > 0) or not np.isfinite(R_star):
        return nan
    ip = int(np.argmax(F))
    a_pk = a[ip]
    if not a_pk >= PATCH_ELEMENTS_MIN * spacing:
        return nan
    below = np.flatnonzero(a[: ip + 1] < a_pk - spacing)
    if below.size == 0:
        return nan
    sweep = slice(int(below[-1]) + 1, ip + 1)
    aa, FF = a[sweep], F[sweep]
    if aa.size < EDGE_MIN_SAMPLES or not (FF > 0).all():
        return nan
    ratio = aa / contact_radius(FF, E_star, R_star) - 1.0
    order = np.argsort(aa, kind="stable")
    aa, ratio = aa[order], ratio[order]
    if not aa[-1] > aa[0]:
        return nan
    e = float(np.trapezoid(ratio, aa) / (aa[-1] - aa[0]))
    F_peak = F[ip] if peak_force is None else peak_force  # [N]
    return float(contact_radius(F_peak, E_star, R_star)) * (1.0 + e), e, int(aa.size)


def plateau_gap(rod2: Rod) -> float:
    """The shortest dip [s] below the threshold that separates two plateaus of the Rod-2 midpoint speed: the rod's
    diameter over its bar wave speed, the period scale of its lateral ringing behind a front (2.5 µs on the paper's
    rods; module docstring). The dips between real plateaus last a large part of Rod 1's round trip."""
    return rod2.diameter_transit


def reaches_end(t: ArrayLike, scene: Scene) -> bool:
    """Whether a history's times ``t`` [s] reach ``scene``'s end: its last sample within one output interval (1%
    slack) of the end time. A run writes its history whole (atomically); one cut short was damaged from outside, and
    read as a finished run's it gave fewer plateaus ("over the first 74 µs only": a fuzz, 2026-12-07)."""
    t = np.asarray(t, float)
    return t.size > 0 and bool(t[-1] >= scene.end_time - 1.01 * scene.output_interval)


def plateau_bounds(scene: Scene) -> tuple[float, float]:
    """(floor [m/s], gap [s]) of a scene's Rod-2 midpoint plateaus (:func:`plateaus`): :data:`ARRIVAL` x the impact
    speed, below which the wave has not arrived, and :func:`plateau_gap`. Every model's average peak speed and the
    plateau checks take both from here (the analytical model took no floor before: one definition)."""
    return ARRIVAL * scene.speed, plateau_gap(scene.rod2)


def plateau_level(v: np.ndarray, fraction: float = PLATEAU_FRACTION, threshold: float | None = None) -> float:
    """The plateau threshold [m/s]: ``threshold`` when given, else ``fraction`` of the largest speed."""
    return fraction * float(v.max()) if threshold is None else threshold


def plateaus(
    t: ArrayLike,
    v: ArrayLike,
    count: int = PLATEAU_COUNT,
    fraction: float = PLATEAU_FRACTION,
    threshold: float | None = None,
    floor: float = 0.0,
    gap: float = 0.0,
) -> list[slice]:
    """Index ranges of the first ``count`` runs of ``v >= fraction x max(v)``, or of ``v >= threshold``
    [m/s] when an absolute threshold is given; runs apart by less than ``gap`` [s] (from the last sample of one to
    the first of the next: :func:`plateau_gap`) are one. None when ``v`` never exceeds ``floor`` [m/s] (the wave
    has not reached the probe by the end time: :data:`ARRIVAL` x the impact speed): a relative threshold of a
    precursor's or of 0 would call noise or the whole rest a plateau."""
    t, v = np.asarray(t, float), np.asarray(v, float)
    if threshold is None and not v.max() > floor:
        return []
    on = v >= plateau_level(v, fraction, threshold)
    edges = np.flatnonzero(np.diff(np.concatenate(([0], on.astype(np.int8), [0]))))
    starts, stops = edges[::2], edges[1::2]
    apart = t[starts[1:]] - t[stops[:-1] - 1] >= gap  # a shorter dip is ringing inside one plateau
    starts, stops = np.concatenate((starts[:1], starts[1:][apart])), np.concatenate((stops[:-1][apart], stops[-1:]))
    return [slice(a, b) for a, b in zip(starts[:count], stops[:count], strict=True)]


def midpoint_peak_speed(
    t: ArrayLike,
    v: ArrayLike,
    count: int = PLATEAU_COUNT,
    threshold: float | None = None,
    floor: float = 0.0,
    gap: float = 0.0,
) -> float:
    """Average peak speed: mean of the samples at or above the threshold in the first ``count`` plateaus [m/s]
    (relative threshold by default, ``threshold`` [m/s] if given; ``gap`` [s]: :func:`plateaus`); NaN when no
    sample reaches the threshold or exceeds ``floor`` [m/s]."""
    v = np.asarray(v, float)
    runs = plateaus(t, v, count, threshold=threshold, floor=floor, gap=gap)
    if not runs:
        return float("nan")
    samples = np.concatenate([v[s] for s in runs])
    return float(samples[samples >= plateau_level(v, PLATEAU_FRACTION, threshold)].mean())


def strain_window(rod2: Rod, periods: int = STRAIN_PERIODS) -> tuple[float, float]:
    """Time window [s] of the strain RMS difference: the first ``periods`` periods 2 L2/c2 of the Rod-2
    midpoint strain, counted from impact (a wave needs 2 L2/c2 to cross Rod 2 and come back)."""
    return (0.0, periods * rod2.round_trip_time)


def rms_difference(t: ArrayLike, a: ArrayLike, t_b: ArrayLike, b: ArrayLike, window: tuple[float, float]) -> float:
    """RMS of a(t) - b(t) over ``window``, with b interpolated linearly onto a's samples."""
    t, a = np.asarray(t, float), np.asarray(a, float)
    m = (t >= window[0]) & (t <= window[1])
    bi = np.interp(t[m], np.asarray(t_b, float), np.asarray(b, float))
    return float(np.sqrt(np.mean((a[m] - bi) ** 2)))


def window_rms_difference(
    t: ArrayLike, a: ArrayLike, t_b: ArrayLike, b: ArrayLike, window: tuple[float, float]
) -> float:
    """:func:`rms_difference` over the whole ``window``, NaN where either history ends before it does (to 1e-3 of
    it): a history cut short would be compared over less than the window, or against its last value held."""
    if min(float(np.asarray(t)[-1]), float(np.asarray(t_b)[-1])) < 0.999 * window[1]:
        return float("nan")
    return rms_difference(t, a, t_b, b, window)


def time_lag(
    t: ArrayLike, a: ArrayLike, t_b: ArrayLike, b: ArrayLike, window: tuple[float, float], max_lag: float
) -> tuple[float, float]:
    """The lag τ [s], |τ| <= ``max_lag``, that minimises the RMS of a(t) - b(t - τ) over ``window``, and that
    RMS: τ > 0 when a trails b. Searched on a's sample spacing, then refined by the vertex of the parabola
    through the three mean squares around the best sample (the mean square, not the RMS, is quadratic in a
    small lag error). The RMS at τ = 0 is :func:`rms_difference`."""
    t, t_b = np.asarray(t, float), np.asarray(t_b, float)
    step = float(t[1] - t[0])
    lags = step * np.arange(-int(max_lag / step), int(max_lag / step) + 1)
    r = np.array([rms_difference(t, a, t_b + lag, b, window) for lag in lags])
    i = int(np.argmin(r))
    if 0 < i < r.size - 1:  # vertex of the parabola through (i-1, i, i+1)
        q = r[i - 1 : i + 2] ** 2
        d = q[0] - 2 * q[1] + q[2]
        lag = lags[i] + (0.5 * step * (q[0] - q[2]) / d if d > 0 else 0.0)
        return float(lag), rms_difference(t, a, t_b + lag, b, window)
    return float(lags[i]), float(r[i])


def smoothed_peak(t: ArrayLike, force: ArrayLike, window: float) -> float:
    """Largest sliding average of ``force`` over ``window`` [s] (:func:`smoothing` of the scene; equally spaced
    samples ``t``), from running sums:
    O(samples) whatever the window holds (a convolution was O(samples x window): 17 s at a 0.1 ns output
    interval); a record shorter than the window counts as zero beyond its ends (its sum over the window)."""
    t, f = np.asarray(t, float), np.asarray(force, float)
    n = max(1, int(round(window / (t[1] - t[0])))) if t.size > 1 else 1
    if n >= f.size:
        return float(f.sum() / n)
    sums = np.concatenate(([0.0], np.cumsum(f)))
    return float(((sums[n:] - sums[:-n]) / n).max())
