"""Kinematic (forward-increment Lagrange multiplier) contact, rods.fe.kinematic: the LCP against brute force,
the closed-form perfectly plastic impact of two free masses, and no penetration with a closed energy balance
on elastic bodies."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.sparse
from hypothesis import given, settings
from hypothesis import strategies as st
from mpi4py import MPI

from rods.fe.explicit import CentralDifference
from rods.fe.kinematic import KinematicContact, solve_lcp
from rods.fe.recorder import Recorder
from tests.fe.test_contact import R_CAP
from tests.fe.toy import petsc_matrix, tip


def brute_force_lcp(D: np.ndarray, g: np.ndarray) -> np.ndarray:
    """The LCP solution by trying every active set (small n)."""
    n = g.size
    for k in range(n + 1):
        for A in itertools.combinations(range(n), k):
            x = np.zeros(n)
            if A:
                idx = list(A)
                x[idx] = np.linalg.solve(D[np.ix_(idx, idx)], -g[idx])
            y = g + D @ x
            if (x >= -1e-12).all() and (y >= -1e-10 * np.abs(g).max()).all():
                return x
    raise AssertionError("no solution")


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 6), st.integers(0, 2**31 - 1))
def test_lcp_matches_brute_force(n, seed):
    rng = np.random.default_rng(seed)
    B = rng.normal(size=(n, n + 2))
    D = B @ B.T + 0.1 * np.eye(n)  # SPD, like B M^-1 Bᵀ
    g = rng.normal(size=n)
    x = solve_lcp(scipy.sparse.csr_matrix(D), g, np.ones(n, dtype=bool), {})
    y = g + D @ x
    assert (x >= 0).all() and (y >= -1e-10 * np.abs(g).max()).all()
    assert abs(x @ y) <= 1e-9 * (np.abs(g).max() * np.abs(x).max() + 1e-300)
    np.testing.assert_allclose(x, brute_force_lcp(D, g), rtol=1e-8, atol=1e-12 * np.abs(g).max())


def _two_masses(m1: float, m2: float, v1: float, v2: float, dt: float, steps: int, gap: float = 2.5e-3):
    """Two free point masses (no springs) at entries 0, 1, ``gap`` [m] apart: the stepper and the contact."""
    from rods.fe.contact import TipNodes

    mass = np.array([m1, m2])
    pairing = (np.zeros((1, 1), dtype=np.int64), np.ones((1, 1)), np.ones(1, dtype=bool))
    master = TipNodes(np.zeros(1), np.array([gap]), np.array([1e-4]), np.array([1]), np.zeros(1, dtype=np.int64))
    c = KinematicContact(tip(0, 1e-4), master, MPI.COMM_SELF, 1.0 / mass, pairing)
    s = CentralDifference(petsc_matrix(np.zeros((2, 2))), mass, 1.0 / mass, dt, np.array([v1, v2]), contact=c)
    for _ in range(steps):
        s.step()
    return s, c


def test_free_masses_stick_with_the_plastic_impact_loss():
    """Closed form: a perfectly plastic impact ends at the common velocity (m1 v1 + m2 v2)/(m1 + m2) and
    dissipates ½ m1 m2/(m1 + m2) (v1 - v2)²; the gap closes within a step (2.5 mm at 2 m/s, Δt = 1 ms)."""
    m1, m2, v1, v2 = 2.0, 3.0, 1.5, -0.5  # [kg], [m/s]
    s, c = _two_masses(m1, m2, v1, v2, 1e-3, 20)
    v = s.backend.to_host(s.v)
    v_common = (m1 * v1 + m2 * v2) / (m1 + m2)
    np.testing.assert_allclose(v, [v_common, v_common], rtol=1e-13)
    assert c.dissipated == pytest.approx(0.5 * m1 * m2 / (m1 + m2) * (v1 - v2) ** 2, rel=1e-12)
    assert c.gap.min() >= -1e-15


def test_separating_masses_feel_no_force():
    s, c = _two_masses(1.0, 1.0, -1.0, 1.0, 1e-3, 10)
    np.testing.assert_array_equal(s.backend.to_host(s.v), [-1.0, 1.0])
    assert c.force == 0.0 and c.dissipated == 0.0


def _cap_on_flat(n_s: int = 7, n_m: int = 9):
    """Two elastic chains (one per rod: 3 axial layers of springs) whose tip faces meet: a capped slave face
    z = -r²/2R over a flat master, both sorted by r. Returns (K, mass, contact, v0)."""
    from rods.fe.contact import TipNodes

    r_s, r_m = np.linspace(0.0, 1e-3, n_s), np.linspace(0.0, 1.3e-3, n_m)  # [m]
    n = 3 * (n_s + n_m)
    loc_s, loc_m = np.arange(n_s), 3 * n_s + np.arange(n_m)  # tip layers: slave entries first, master
    slave = TipNodes(r_s, -(r_s**2) / (2 * R_CAP), np.full(n_s, 2e-8), loc_s, np.arange(n_s))
    master = TipNodes(r_m, np.zeros(n_m), np.full(n_m, 3e-8), loc_m, np.arange(n_m))
    k = 2e6  # [N/m] axial springs between layers, and between radial neighbours
    K = np.zeros((n, n))

    def spring(i, j, kk=k):
        K[i, i] += kk
        K[j, j] += kk
        K[i, j] -= kk
        K[j, i] -= kk

    for base, m in ((0, n_s), (3 * n_s, n_m)):
        for layer in range(2):
            for i in range(m):
                spring(base + layer * m + i, base + (layer + 1) * m + i)
        for layer in range(3):
            for i in range(m - 1):
                spring(base + layer * m + i, base + layer * m + i + 1, 0.5 * k)
    mass = np.full(n, 1e-3)  # [kg]
    v0 = np.zeros(n)
    v0[: 3 * n_s] = 0.5  # Rod 1 at 0.5 m/s [m/s]
    c = KinematicContact(slave, master, MPI.COMM_SELF, 1.0 / mass, None)
    return K, mass, c, v0


def test_elastic_impact_never_penetrates_and_closes_the_energy_balance():
    K, mass, c, v0 = _cap_on_flat()
    dt = 0.5 * 2.0 / float(np.sqrt(np.linalg.eigvalsh(K / mass[:, None]).max()))  # half the stable step [s]
    steps = 400
    s = CentralDifference(petsc_matrix(K), mass, 1.0 / mass, dt, v0, contact=c)
    P = scipy.sparse.csr_matrix(([1.0], ([0], [0])), shape=(2, K.shape[0]))
    rec = Recorder(c, (P, [("p_velocity", "p_strain")]), mass, np.arange(steps + 1), steps, dt, MPI.COMM_SELF)
    min_gap, active = 0.0, 0
    for n in range(steps + 1):
        s.step(keep=True)
        rec.after_step(n, n * dt, s)
        min_gap = min(min_gap, float(c.gap.min()))
        active = max(active, int(np.count_nonzero(c.pressure)))
    hist = rec.history()
    summary = rec.summary(hist, steps + 1, "p", 0.0, 0.0, 1e-6)
    assert active >= 3  # the patch grew over several pairs
    assert min_gap >= -1e-12 * 0.5 * dt * steps  # no penetration beyond round-off of the approach
    assert hist["dissipated_energy"][-1] > 0.0  # pairs closing at a relative speed lose it
    assert summary["energy_error"] < 1e-10  # ... and the balance, with it counted, is closed
    p = s.backend.to_host(mass * s.v).sum()
    assert p == pytest.approx(mass @ v0, rel=1e-12)  # the contact impulses cancel pairwise


@pytest.mark.parametrize("overlap", [False, True], ids=["after-product", "overlap"])
@pytest.mark.parametrize("speed", [0.5, -0.5], ids=["closing", "separating"])
def test_one_copy_to_the_host_per_step_and_no_force_while_open(monkeypatch, speed, overlap):
    """On an array backend a step copies the tip state to the host once (on a device: its one synchronisation),
    and reading the gaps, pressures, forces and radius after it copies nothing more; while every pair is open
    the contact adds no force (no upload, no scatter). Counted on the NumPy backend, the CuPy path's code; with
    the device's overlap (rods.fe.kinematic, "Overlap") the one copy is the one started before the product."""
    import dataclasses

    from rods.fe import backend as backends
    from rods.fe.contact import PenaltyContact

    copies, scatters = [0], [0]
    to_host, add_force = backends.Backend.to_host, PenaltyContact.add_force
    to_host_async = backends.Backend.to_host_async
    monkeypatch.setattr(
        backends.Backend, "to_host", lambda self, a: copies.__setitem__(0, copies[0] + 1) or to_host(self, a)
    )
    monkeypatch.setattr(
        backends.Backend,
        "to_host_async",
        lambda self, a, out: copies.__setitem__(0, copies[0] + 1) or to_host_async(self, a, out),
    )
    monkeypatch.setattr(
        PenaltyContact, "add_force", lambda *a: scatters.__setitem__(0, scatters[0] + 1) or add_force(*a)
    )
    K, mass, c, v0 = _cap_on_flat()
    be = dataclasses.replace(backends.select("numpy", 1), overlap=overlap)
    c.use(be)
    dt = 0.5 * 2.0 / float(np.sqrt(np.linalg.eigvalsh(K / mass[:, None]).max()))  # [s]
    s = CentralDifference(scipy.sparse.csr_matrix(K), mass, 1.0 / mass, dt, np.sign(speed) * v0, contact=c, backend=be)
    assert s.overlap == overlap
    closed_steps = 0
    for _ in range(200):
        copies[0] = scatters[0] = 0
        s.step()
        _ = c.gap, c.pressure, c.slave_forces(None), c.radius(), c.force
        assert copies[0] == 1
        closed = bool(c.pressure.any())
        assert scatters[0] == (1 if closed else 0)  # the stepper's one add_force call reaches the scatter
        closed_steps += closed
    assert (10 <= closed_steps < 200) if speed > 0 else (closed_steps == 0)  # closing: open steps too (measured 15)


def test_lcp_on_a_dense_operator_and_a_singular_block():
    """solve_lcp takes a dense D as well as a sparse one (same impulses), and an active block that is not positive
    definite (a Delassus operator of a massless pair) is refused by name, not solved into NaN."""
    D = np.array([[2.0, 0.5], [0.5, 1.0]])
    g = np.array([-1.0, 0.3])
    both = np.ones(2, dtype=bool)
    np.testing.assert_array_equal(solve_lcp(D, g, both, {}), solve_lcp(scipy.sparse.csr_matrix(D), g, both, {}))
    assert solve_lcp(D, g, both)[0] == pytest.approx(0.5)
    with pytest.raises(np.linalg.LinAlgError, match="not positive definite"):
        solve_lcp(np.array([[0.0, 0.0], [0.0, 1.0]]), np.array([-1.0, -1.0]), both, {})
