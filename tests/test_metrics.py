"""The shared scalar measures on synthetic signals with known answers."""

from __future__ import annotations

import numpy as np
import pytest

from rods import metrics


def test_contact_duration_of_a_half_sine():
    t = np.linspace(0, 300e-6, 30001)
    F = np.where(t < 200e-6, 5000 * np.sin(np.pi * t / 200e-6), 0.0)
    # threshold 1e-3 of the peak cuts (2/π)·asin(1e-3)·100 µs ≈ 0.064 µs off each end
    expected = 200e-6 * (1 - 2 * np.arcsin(1e-3) / np.pi)
    assert metrics.contact_duration(t, F) == pytest.approx(expected, rel=1e-6)
    assert metrics.contact_duration(t, np.zeros_like(t)) == 0.0


def test_two_episodes_are_found():
    t = np.linspace(0, 1, 10001)
    F = np.clip(np.sin(2 * np.pi * 2 * t), 0, None)
    ep = metrics.contact_episodes(t, F)
    assert len(ep) == 2
    assert ep[1][0] == pytest.approx(0.5, abs=1e-3)


def test_average_peak_speed_of_square_plateaus():
    t = np.linspace(0, 1, 100001)
    v = np.where((np.floor(t * 10) % 2) == 1, 1.1, 0.0)  # plateaus of 1.1 at odd tenths
    assert metrics.midpoint_peak_speed(t, v) == pytest.approx(1.1, rel=1e-12)
    assert len(metrics.plateaus(t, v)) == 5


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
    ep = metrics.contact_episodes(t, F)
    assert len(ep) == 1
    assert ep[0][1] - ep[0][0] == pytest.approx(200e-6, rel=1e-3)


def test_absolute_plateau_threshold():
    """The paper's rule (samples >= a fixed speed) against the relative default, on plateaus of two heights."""
    t = np.linspace(0, 1, 100001)
    v = np.where((np.floor(t * 10) % 2) == 1, np.where(t < 0.5, 1.2, 0.95), 0.0)  # 1.2 twice, then 0.95
    assert metrics.midpoint_peak_speed(t, v, threshold=1.0) == pytest.approx(1.2, rel=1e-12)  # 0.95 never counts
    assert len(metrics.plateaus(t, v, threshold=1.0)) == 2 and len(metrics.plateaus(t, v, threshold=0.9)) == 5
    assert np.isnan(metrics.midpoint_peak_speed(t, v, threshold=1.5))  # nothing reaches it


def test_strain_window_is_five_round_trips_of_rod2(scene_with):
    rod2 = scene_with("rod2.length=0.5", "rod2.material.youngs_modulus=100e9").rod2
    c2 = np.sqrt(100e9 / rod2.material.density)
    assert metrics.strain_window(rod2) == pytest.approx((0.0, 5 * 2 * 0.5 / c2), rel=1e-12)
    assert metrics.strain_window(rod2, periods=1)[1] == pytest.approx(2 * 0.5 / c2, rel=1e-12)
    paper = scene_with().rod2
    assert metrics.strain_window(paper)[1] == pytest.approx(1370e-6, abs=0.5e-6)  # fig4.md's "1370 µs"
