"""The shared scalar measures on synthetic signals with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rods import metrics

GAP = 1e-6  # [s] the shortest gap between two episodes (metrics.min_gap: 0.99 µs on the paper's rods)


def test_contact_duration_of_a_sampled_hertz_pulse():
    """A Hertz pulse F = K δ^(3/2), δ a half sine over 200.37 µs, sampled every 0.5 µs (touch and release between
    samples): the Hertz-law placement of both ends (F^(2/3) linear in time) recovers the duration to 1 ns, where
    linear interpolation of F is off by up to a sample (the end then at the first zero sample)."""
    T, h = 200.37e-6, 0.5e-6  # [s]
    t = -0.2e-6 + h * np.arange(601)  # [s] touch at 0, between samples
    δ = np.where((t > 0) & (t < T), 40e-6 * np.sin(np.pi * t / T), 0.0)  # [m]
    F = 2.2e10 * δ**1.5  # [N]
    assert metrics.contact_duration(t, F, GAP) == pytest.approx(T, abs=1e-9)
    start, end = metrics.contact_episodes(t, F, GAP)[0]
    assert start == pytest.approx(0.0, abs=1e-9) and end == pytest.approx(T, abs=1e-9)
    assert metrics.contact_duration(t, np.zeros_like(t), GAP) == 0.0


def test_a_low_tail_is_contact():
    """A force tail at 0.12% of the peak for 40 µs after a half-sine pulse is contact (electrical continuity sees
    it): the duration runs to the tail's end, which a threshold at 1e-3 of the peak made its own choice."""
    t = np.arange(0.0, 300e-6, 0.25e-6)  # [s]
    pulse = 5e3 * np.clip(np.sin(np.pi * t / 200e-6), 0, None) * (t < 200e-6)  # [N]
    tail = 5e3 * 1.2e-3 * ((t >= 200e-6) & (t < 240e-6))  # [N]
    assert metrics.contact_duration(t, pulse + tail, GAP) == pytest.approx(240e-6, abs=0.25e-6)
    assert metrics.contact_duration(t, pulse + tail, GAP, threshold=2e-3) == pytest.approx(200e-6, abs=0.25e-6)


def test_two_episodes_are_found():
    t = np.linspace(0, 1, 10001)
    F = np.clip(np.sin(2 * np.pi * 2 * t), 0, None)
    ep = metrics.contact_episodes(t, F, GAP)
    assert len(ep) == 2
    assert ep[1][0] == pytest.approx(0.5, abs=1e-3)


def test_average_peak_speed_of_square_plateaus():
    t = np.linspace(0, 1, 100001)
    v = np.where((np.floor(t * 10) % 2) == 1, 1.1, 0.0)  # plateaus of 1.1 at odd tenths
    assert metrics.midpoint_peak_speed(t, v) == pytest.approx(1.1, rel=1e-12)
    assert len(metrics.plateaus(t, v)) == 5


def test_ringing_dips_shorter_than_the_gap_do_not_split_a_plateau():
    """Plateaus at 1.0 barely above the 0.9 x max threshold (max 1.05), each ending in ringing that dips below
    the threshold for 0.2-2 µs (the FE model on a titanium-on-aluminium scene, rods.metrics): without the gap rule
    those dips leave 1-sample "plateaus" in the average; with it each plateau is one, the average is the plateaus'
    level over the samples above the threshold, and the 17 µs dips between plateaus (from the last spike) still
    separate them."""
    dt = 0.25e-6  # [s] the output interval
    i = np.arange(2400)  # samples: 600 µs
    t, k = i * dt, i % 400  # [s]; the sample within its 100 µs period
    v = np.where(k < 320, 1.0, 0.5)  # [m/s] a plateau of 80 µs every 100 µs, from t = 0
    v[k == 319] = 1.05  # the largest speed: the threshold is 0.945
    v[(k >= 324) & (k <= 332) & (k % 4 == 0)] = 0.96  # 1-sample spikes 1 µs apart, 1-3 µs after the plateau
    gap = 3e-6  # [s]
    assert [s.stop - s.start for s in metrics.plateaus(t, v)][:4] == [320, 1, 1, 1]  # the defect, without the rule
    runs = metrics.plateaus(t, v, gap=gap)
    assert len(runs) == 5 and all(t[s.start] == pytest.approx(k * 100e-6) for k, s in enumerate(runs))
    samples = np.concatenate([v[s] for s in runs])
    above = samples[samples >= 0.945]
    assert metrics.midpoint_peak_speed(t, v, gap=gap) == pytest.approx(above.mean(), rel=1e-14)
    assert 0.999 < metrics.midpoint_peak_speed(t, v, gap=gap) < 1.001  # no 0.5 m/s dip sample in it (0.995 with)
    assert len(metrics.plateaus(t, v, gap=16.9e-6)) == 5 and len(metrics.plateaus(t, v, gap=17.1e-6)) == 1  # 17 µs dips


def test_the_plateau_gap_is_rod_2s_lateral_transit(scene_with):
    """d2/c2: 2.49 µs on the paper's 12.7 mm steel Rod 2 (c2 = 5117 m/s), 3.93 µs on a 20 mm aluminium one."""
    assert metrics.plateau_gap(scene_with().rod2) == pytest.approx(0.0127 / 5116.9, rel=1e-4)
    al = scene_with("rod2.diameter=0.02", "rod2.material.youngs_modulus=70e9", "rod2.material.density=2700.0")
    assert metrics.plateau_gap(al.rod2) == pytest.approx(0.02 / np.sqrt(70e9 / 2700.0), rel=1e-12)


def test_rms_difference():
    t = np.linspace(0, 1, 1001)
    assert metrics.rms_difference(t, np.sin(t), t, np.sin(t) + 2e-6, (0, 1)) == pytest.approx(2e-6, rel=1e-9)


def test_time_lag_finds_a_known_delay():
    """A Gaussian pulse delayed by 1.37 sample spacings: the lag is found to a few percent of a spacing
    (between samples by the parabola) and the aligned RMS is far below the unaligned one."""
    t = np.linspace(0, 1e-3, 2001)  # 0.5 µs spacing
    pulse = lambda t: np.exp(-(((t - 4e-4) / 5e-5) ** 2))  # noqa: E731
    delay = 1.37 * (t[1] - t[0])  # [s]
    lag, rms = metrics.time_lag(t, pulse(t - delay), t, pulse(t), (0, 1e-3), max_lag=1e-5)
    assert lag == pytest.approx(delay, rel=0.03)
    assert rms < 0.02 * metrics.rms_difference(t, pulse(t - delay), t, pulse(t), (0, 1e-3))
    assert metrics.time_lag(t, pulse(t + delay), t, pulse(t), (0, 1e-3), max_lag=1e-5)[0] == pytest.approx(
        -delay, rel=0.03
    )


def test_chatter_shorter_than_min_gap_is_one_episode():
    t = np.linspace(0, 200e-6, 200001)
    F = 5000 * np.sin(np.pi * t / 200e-6) * (np.sin(2 * np.pi * t / 0.2e-6) > -0.5)  # gaps of ~0.07 µs
    ep = metrics.contact_episodes(t, F, GAP)
    assert len(ep) == 1
    assert ep[0][1] - ep[0][0] == pytest.approx(200e-6, rel=1e-3)


def test_absolute_plateau_threshold():
    """The paper's rule (samples >= a fixed speed) against the relative default, on plateaus of two heights."""
    t = np.linspace(0, 1, 100001)
    v = np.where((np.floor(t * 10) % 2) == 1, np.where(t < 0.5, 1.2, 0.95), 0.0)  # 1.2 twice, then 0.95
    assert metrics.midpoint_peak_speed(t, v, threshold=1.0) == pytest.approx(1.2, rel=1e-12)  # 0.95 never counts
    assert len(metrics.plateaus(t, v, threshold=1.0)) == 2 and len(metrics.plateaus(t, v, threshold=0.9)) == 5
    assert np.isnan(metrics.midpoint_peak_speed(t, v, threshold=1.5))  # nothing reaches it


def test_a_probe_the_wave_has_not_reached_has_no_plateau():
    """A still midpoint (a slow rod or a short end time): no plateau and a NaN speed, not a "plateau" of zeros
    at a relative threshold of 0 (before: 0.0 m/s, reported as a number)."""
    t = np.linspace(0, 1, 1001)
    assert metrics.plateaus(t, np.zeros_like(t)) == []
    assert np.isnan(metrics.midpoint_peak_speed(t, np.zeros_like(t)))


def test_strain_window_is_five_round_trips_of_rod2(scene_with):
    rod2 = scene_with("rod2.length=0.5", "rod2.material.youngs_modulus=100e9").rod2
    c2 = np.sqrt(100e9 / rod2.material.density)
    assert metrics.strain_window(rod2) == pytest.approx((0.0, 5 * 2 * 0.5 / c2), rel=1e-12)
    assert metrics.strain_window(rod2, periods=1)[1] == pytest.approx(2 * 0.5 / c2, rel=1e-12)
    paper = scene_with().rod2
    assert metrics.strain_window(paper)[1] == pytest.approx(1370e-6, abs=0.5e-6)  # fig4.md's "1370 µs"


# ---- the edge-period contact radius (rods.metrics.edge_period_radius) ----
E_EDGE, R_EDGE = 1.1e11, 0.035  # E* [Pa], R* [m]


def _sawtooth_loading(e0: float, amplitude: float, spacing: float, shift: float, n: int = 4000):
    """A half-sine force pulse and a node-based radius a = a_H(F) (1 + e0 + A saw(a_H/spacing + shift)), the
    sawtooth rising over each spacing and dropping where the edge reaches a node (zero mean over a period)."""
    from rods.hertz import contact_radius

    t = np.linspace(0.0, 1.0, n)
    F = 5500.0 * np.sin(np.pi * t)  # [N]
    aH = contact_radius(F, E_EDGE, R_EDGE)
    phase = (aH / spacing + shift) % 1.0
    return F, aH * (1.0 + e0 + amplitude * (phase - 0.5))


@pytest.mark.parametrize("spacing", [0.25e-3, 0.125e-3, 0.0625e-3])
def test_edge_period_radius_removes_a_sawtooth_scatter_whatever_its_phase(spacing):
    """The snapshot at the peak moves by ± A/2 with the nodes' phase; the edge-period mean returns the trend e0
    to a small fraction of A (the sawtooth's slow change of a_H/a over the sweep), at every phase."""
    from rods.hertz import contact_radius

    e0, A = -0.001, 0.008
    snap, swept = [], []
    for shift in np.linspace(0.0, 1.0, 7, endpoint=False):
        F, a = _sawtooth_loading(e0, A, spacing, shift)
        a_edge, ratio, n = metrics.edge_period_radius(F, a, spacing, E_EDGE, R_EDGE)
        assert n >= metrics.EDGE_MIN_SAMPLES
        assert a_edge == pytest.approx(contact_radius(F.max(), E_EDGE, R_EDGE) * (1 + ratio), rel=1e-12)
        snap.append(a[np.argmax(F)] / contact_radius(F.max(), E_EDGE, R_EDGE) - 1)
        swept.append(ratio)
    assert np.ptp(snap) > 0.5 * A
    assert np.max(np.abs(np.array(swept) - e0)) < 0.05 * A


def test_edge_period_radius_is_nan_without_a_full_sweep():
    """No contact, under two spacings across the patch radius, or too few samples in the sweep: NaN."""
    F, a = _sawtooth_loading(0.0, 0.0, 0.1e-3, 0.0)
    assert math.isnan(metrics.edge_period_radius(np.zeros(10), np.zeros(10), 1e-4, E_EDGE, R_EDGE)[0])
    assert math.isnan(metrics.edge_period_radius(F, a, 0.6e-3, E_EDGE, R_EDGE)[0])  # a_peak ~1.1 mm < 2 x 0.6
    coarse = slice(None, None, 400)  # 10 samples over the pulse: 1-2 in the sweep
    assert math.isnan(metrics.edge_period_radius(F[coarse], a[coarse], 0.1e-3, E_EDGE, R_EDGE)[0])
    assert not math.isnan(metrics.edge_period_radius(F, a, 0.1e-3, E_EDGE, R_EDGE)[0])


def test_smoothed_peak_is_the_largest_window_average():
    """rods.metrics.smoothed_peak from running sums equals the sliding-window convolution it replaced (to
    round-off), on a noisy pulse and on a record shorter than the window (zero beyond its ends); the running sums
    keep it linear in the samples (a 0.1 ns output interval took 17 s as a convolution)."""
    from rods.metrics import smoothed_peak

    rng = np.random.default_rng(1)
    t = np.arange(0.0, 3e-4, 2.5e-8)  # [s]
    f = 5e3 * np.clip(np.sin(np.pi * t / 2.5e-4), 0.0, None) + rng.normal(0.0, 50.0, t.size)  # [N]
    n = 80  # the 2 µs window in samples
    assert smoothed_peak(t, f, 2e-6) == pytest.approx(np.convolve(f, np.ones(n) / n, mode="valid").max(), rel=1e-12)
    short = f[:30]
    assert smoothed_peak(t[:30], short, 2e-6) == pytest.approx(short.sum() / n, rel=1e-12)
    assert smoothed_peak(t, f, window=2.5e-8) == pytest.approx(f.max(), rel=1e-12)


def test_a_precursor_ahead_of_the_wave_is_no_plateau():
    """Before the wave arrives an explicit FE probe reads its dispersive precursor (3e-49 m/s at the paper's
    midpoint at 20 µs): below ARRIVAL x the impact speed it is no plateau (NaN, the analytical model's null),
    where a relative threshold of its own maximum made a plateau of the noise; the arrived wave still is one."""
    t = np.arange(0.0, 2e-5, 1e-8)  # [s]
    speed = 2.197  # [m/s]
    noise = 3e-49 * np.exp(-((t - 2e-5) ** 2) / 1e-12)  # [m/s]
    floor = metrics.ARRIVAL * speed
    assert metrics.plateaus(t, noise) and not metrics.plateaus(t, noise, floor=floor)  # the defect, and the fix
    assert np.isnan(metrics.midpoint_peak_speed(t, noise, floor=floor))
    arrived = np.where(t > 1e-5, 0.5 * speed, noise)
    assert metrics.midpoint_peak_speed(t, arrived, floor=floor) == pytest.approx(0.5 * speed)


def test_a_strain_rms_over_a_window_needs_both_histories_through_it():
    """window_rms_difference: the RMS of the difference over the whole window (a sine against its shift: the closed
    form sqrt(2) sin(φ/2) / sqrt(2) over whole periods), NaN where either history ends before the window does, not
    a value over the part they share."""
    t = np.linspace(0.0, 1.0, 20001)
    a, b = np.sin(2 * np.pi * 4 * t), np.sin(2 * np.pi * 4 * t - 0.3)
    rms = metrics.window_rms_difference(t, a, t, b, (0.0, 1.0))
    assert rms == pytest.approx(2 * np.sin(0.15) / np.sqrt(2), rel=1e-3)
    short = t <= 0.9
    assert np.isnan(metrics.window_rms_difference(t[short], a[short], t, b, (0.0, 1.0)))
    assert np.isnan(metrics.window_rms_difference(t, a, t[short], b[short], (0.0, 1.0)))
    assert metrics.window_rms_difference(t[short], a[short], t, b, (0.0, 0.9)) == pytest.approx(rms, rel=2e-2)


def test_edge_period_radius_applies_its_ratio_at_the_runs_peak_force():
    """The ratio is a property of the sweep; the radius is it applied at the run's every-step peak force, which a
    history sampled at the output interval can miss (the radius is compared with Hertz at that force)."""
    from rods.hertz import contact_radius

    F, a = _sawtooth_loading(-0.001, 0.008, 0.125e-3, 0.3)
    sampled, ratio, _ = metrics.edge_period_radius(F, a, 0.125e-3, E_EDGE, R_EDGE)
    peak = 1.001 * F.max()  # [N] between two samples
    a_edge, same, _ = metrics.edge_period_radius(F, a, 0.125e-3, E_EDGE, R_EDGE, peak)
    assert same == ratio and a_edge == pytest.approx(contact_radius(peak, E_EDGE, R_EDGE) * (1 + ratio), rel=1e-12)
    assert a_edge / sampled - 1 == pytest.approx(1.001 ** (1 / 3) - 1, rel=1e-9)


def test_a_history_reaches_its_end_within_one_output_interval(scene_with):
    """rods.metrics.reaches_end, what a kept stage and Fig. 4 read a history's completeness by: its last sample
    within one output interval of the end time; one cut short, or empty, does not."""
    sc = scene_with("simulation.end_time=3e-4")
    dt = sc.output_interval  # [s]
    assert metrics.reaches_end(np.arange(0.0, sc.end_time + dt / 2, dt), sc)
    assert metrics.reaches_end([0.0, sc.end_time - dt], sc)
    assert not metrics.reaches_end([0.0, 7.4e-5], sc) and not metrics.reaches_end([], sc)


def test_late_impulse_is_the_share_of_the_first_contact_after_a_time():
    """A half-sine pulse of 100 µs: half its impulse after 50 µs from its start, none after 100 µs; a second
    contact later does not count; no contact: NaN."""
    t = np.linspace(0.0, 400e-6, 40001)  # [s]
    pulse = np.where((t > 10e-6) & (t < 110e-6), np.sin(np.pi * (t - 10e-6) / 100e-6), 0.0)  # [N]
    second = np.where((t > 200e-6) & (t < 300e-6), 1.0, 0.0)
    assert metrics.late_impulse(t, pulse + second, 50e-6, 1e-6) == pytest.approx(0.5, abs=2e-3)
    assert metrics.late_impulse(t, pulse, 100e-6, 1e-6) == pytest.approx(0.0, abs=1e-3)
    assert np.isnan(metrics.late_impulse(t, 0 * t, 50e-6, 1e-6))


def test_a_low_touch_soon_after_a_contact_is_its_tail_not_a_contact():
    """An audit's first contact read 367.5 µs where a touch at 0.7% of the peak 3.6 µs later ran its low tail to
    394 µs (FE 324-394 µs by the mesh, tip radii 35-45 mm flipping it): such a touch within the tail's window is the
    episode's tail; a second impact of its own (30% of the peak), or a low touch past the window, is an episode."""
    t = np.linspace(0.0, 1e-3, 100001)  # [s]
    d = 12.7e-3 / 5100.0  # [s] a diameter transit
    gap = metrics.MIN_GAP_TRANSITS * d  # [s] min_gap
    main = np.where(t < 367.5e-6, np.sin(np.pi * t / 367.5e-6), 0.0)  # [N/N_peak]

    def touch(start: float, height: float) -> np.ndarray:
        return np.where((t > start) & (t < start + 20e-6), height * np.sin(np.pi * (t - start) / 20e-6), 0.0)

    assert metrics.contact_episodes(t, main + touch(371.1e-6, 0.007), gap)[0][1] == pytest.approx(391.1e-6, abs=2e-7)
    assert len(metrics.contact_episodes(t, main + touch(371.1e-6, 0.3), gap)) == 2
    late = 367.5e-6 + 1.1 * metrics.TAIL_TRANSITS * d  # past the tail's window
    assert len(metrics.contact_episodes(t, main + touch(late, 0.007), gap)) == 2


def test_the_contact_duration_is_the_first_episodes_alone():
    """Two contact episodes 50 µs apart (a rebound): the duration is the first's, 20 µs, not the span from the first
    start to the last end (a mutation to that passed this file; only an FE recorder test caught it: an audit)."""
    from rods.metrics import contact_duration

    t = np.linspace(0.0, 100e-6, 10001)  # [s]
    F = np.where(t < 20e-6, np.sin(np.pi * t / 20e-6), 0.0) + np.where(
        (t > 70e-6) & (t < 80e-6), np.sin(np.pi * (t - 70e-6) / 10e-6), 0.0
    )  # [N]
    assert contact_duration(t, 1e3 * F, min_gap=1e-6) == pytest.approx(20e-6, abs=2e-8)
