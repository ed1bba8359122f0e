"""Penalty contact (rods.fe.contact.PenaltyContact) on plain arrays, one process (MPI.COMM_SELF):
momentum balance to round-off, the force law p = ε <-g>, the force as the energy's derivative."""

from __future__ import annotations

import numpy as np
import pytest
from mpi4py import MPI

from rods.fe.contact import PenaltyContact, TipNodes, bilinear_pairing, edge_radius

ε = 3.0e13  # penalty [Pa/m]
R_CAP = 35e-3  # Rod 1's tip radius [m]


def axisymmetric_pair(n_s: int = 6, n_m: int = 5) -> tuple[PenaltyContact, int]:
    """A capped slave face (z_s = -(r²/2R), in r order) over a flat master face (z = 0), interleaved in an
    owned array of axial entries: slaves at 0, 2, 4, ..., masters after them."""
    r_s, r_m = np.linspace(0.0, 1e-3, n_s), np.linspace(0.0, 1.2e-3, n_m)  # [m]
    area_s, area_m = np.full(n_s, 2e-8), np.full(n_m, 3e-8)  # tributary areas [m^2]
    loc_s, loc_m = 2 * np.arange(n_s), 2 * n_s + np.arange(n_m)
    slave = TipNodes(r_s, -(r_s**2) / (2 * R_CAP), area_s, loc_s, np.arange(n_s))
    master = TipNodes(r_m, np.zeros(n_m), area_m, loc_m, np.arange(n_m))
    return PenaltyContact(slave, master, ε, MPI.COMM_SELF), 2 * n_s + n_m


def pressed(c: PenaltyContact, n: int, δ: float = 5e-6) -> np.ndarray:
    """Displacement: Rod 1's face moved δ [m] into the master, the master face slightly tilted."""
    u = np.zeros(n)
    u[c.slave.local] = δ
    u[c.master.local] = 1e-6 * c.master.r / c.master.r.max()
    return u


def test_momentum_balance_to_round_off():
    c, n = axisymmetric_pair()
    c.evaluate(pressed(c, n))
    f = np.zeros(n)
    c.add_force(f)
    assert c.force > 0 and np.count_nonzero(c.pressure) > 1
    assert abs(f.sum()) <= 1e-15 * np.abs(f).sum()
    assert -f[c.slave.local].sum() == pytest.approx(c.force, rel=1e-14)  # slaves pushed back along -z


def test_force_law():
    """p_s = ε <-g_s>, F_s = p_s a_s, g_s = z_m(r_s) - z_s with z_m linear in r, E_c = ½ Σ ε a_s <-g_s>²."""
    c, n = axisymmetric_pair()
    u = pressed(c, n)
    c.evaluate(u)
    z_s = c.slave.z + u[c.slave.local]
    z_m = np.interp(c.slave.r, c.master.r, c.master.z + u[c.master.local])
    pen = np.maximum(z_s - z_m, 0.0)
    assert np.allclose(c.gap, z_m - z_s, rtol=0, atol=1e-18)
    assert np.allclose(c.pressure, ε * pen, rtol=1e-12, atol=0)
    assert c.force == pytest.approx(float(ε * c.slave.area @ pen), rel=1e-13)
    assert c.energy == pytest.approx(0.5 * ε * float(c.slave.area @ pen**2), rel=1e-13)
    assert c.active_area() == pytest.approx(c.slave.area[pen > 0].sum())
    c.evaluate(np.zeros(n))  # the cap touches at its apex only: no penetration, no force
    assert c.force == 0.0 and c.energy == 0.0


def test_force_is_minus_the_energy_gradient():
    """f_c = -∂E_c/∂u (a conservative force), by central differences of the energy in every entry."""
    c, n = axisymmetric_pair()
    u = pressed(c, n)
    c.evaluate(u)
    f = np.zeros(n)
    c.add_force(f)
    h = 1e-12  # [m]
    grad = np.zeros(n)
    for i in range(n):
        e = np.zeros(n)
        e[i] = h
        c.evaluate(u + e)
        Ep = c.energy
        c.evaluate(u - e)
        grad[i] = (Ep - c.energy) / (2 * h)
    assert np.allclose(f, -grad, rtol=1e-5, atol=1e-6 * np.abs(f).max())


def test_stiffness_is_the_full_engagement_linearisation():
    """apply_stiffness gives K_c = Σ k_s b_s b_sᵀ: symmetric, K_c δu = -(f(u + δu) - f(u)), every pair active."""
    c, n = axisymmetric_pair()
    u = pressed(c, n, δ=5e-5)  # every slave in contact
    c.evaluate(u)
    assert np.all(c.pressure > 0)
    f0 = np.zeros(n)
    c.add_force(f0)
    du = 1e-9 * np.sin(np.arange(n))
    c.evaluate(u + du)
    f1 = np.zeros(n)
    c.add_force(f1)
    Kdu = np.zeros(n)
    c.apply_stiffness(du, Kdu)
    assert np.allclose(Kdu, -(f1 - f0), rtol=1e-9, atol=1e-9 * np.abs(Kdu).max())
    Kc = np.zeros((n, n))
    for j in range(n):
        c.apply_stiffness(np.eye(n)[j], Kc[:, j])
    assert np.allclose(Kc, Kc.T)


def test_bilinear_pairing_reproduces_linear_fields():
    """3D pairing: weights sum to 1 and interpolate linear fields exactly; slaves off the face are not paired."""
    g = np.linspace(0.0, 1.0, 4)
    X, Y = np.meshgrid(g, g, indexing="ij")
    xy_m = np.column_stack([X.ravel(), Y.ravel()])
    idx = np.arange(16).reshape(4, 4)
    quads = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1).reshape(-1, 4)
    xy_s = np.random.default_rng(1).random((20, 2))
    xy_s[0] = (1.5, 0.5)  # outside the face
    J, W, inside = bilinear_pairing(xy_s, xy_m, quads)
    assert not inside[0] and inside[1:].all()
    assert np.allclose(W[1:].sum(axis=1), 1.0)
    lin = 0.3 + 2.0 * xy_m[:, 0] - 0.7 * xy_m[:, 1]
    assert np.allclose((W * lin[J]).sum(axis=1)[1:], (0.3 + 2.0 * xy_s[:, 0] - 0.7 * xy_s[:, 1])[1:], atol=1e-12)


def _two_masses(ζ: float, dt: float):
    """Two free 1 kg masses (entries 0: slave, 1: master), the slave at 1 m/s, one penalty pair of stiffness
    k = 2e6 N/m and contact damping ζ; stepped to separation. Returns (stepper, contact, k, reduced mass)."""
    from petsc4py import PETSc

    from rods.fe.explicit import CentralDifference

    k, mass = 2.0e6, np.ones(2)  # [N/m], [kg]
    one = lambda i: TipNodes(np.zeros(1), np.zeros(1), np.array([1e-4]), np.array([i]), np.zeros(1, int))  # noqa: E731
    pairing = (np.zeros((1, 1), dtype=np.int64), np.ones((1, 1)), np.ones(1, dtype=bool))
    c = PenaltyContact(one(0), one(1), k / 1e-4, MPI.COMM_SELF, pairing)
    c.set_damping(ζ, 1.0 / mass, dt)
    K = PETSc.Mat().createAIJ((2, 2), nnz=1, comm=PETSc.COMM_SELF)
    K.setUp()
    K.assemble()
    st = CentralDifference(K, mass, 1.0 / mass, dt, np.array([1.0, 0.0]), 0.0, c)
    return st, c, k, 0.5


def _dashpot_restitution(ζ: float, k: float, μ: float) -> float:
    """Coefficient of restitution of a linear spring-dashpot pair whose force k x + c x' is kept >= 0 (the
    pair separates where it would pull), from an accurate ODE solve (independent of the FE stepper)."""
    from scipy.integrate import solve_ivp

    c = 2 * ζ * np.sqrt(k * μ)
    pull = lambda t, y: k * y[0] + c * y[1]  # noqa: E731
    pull.terminal, pull.direction = True, -1
    sol = solve_ivp(lambda t, y: [y[1], -(k * y[0] + c * y[1]) / μ], (0, 1.0), [0.0, 1.0], events=pull,
                    rtol=1e-12, atol=1e-15)  # fmt: skip
    return -float(sol.y_events[0][0][1])


def _rebound(ζ: float, ω_dt: float) -> tuple[float, float, float]:
    """(restitution, kinetic + dissipated energy, dissipated) [-, J, J] of the two masses at ω Δt."""
    dt = ω_dt / np.sqrt(2.0e6 / 0.5)
    st, c, _, _ = _two_masses(ζ, dt)
    for _ in range(int(6 / ω_dt)):  # about two contact durations
        st.step()
    v = st.v.getArray() if hasattr(st.v, "getArray") else np.asarray(st.v)
    assert c.force == 0.0 and v[1] > v[0]  # apart again
    return float(v[1] - v[0]), 0.5 * float((v**2).sum()) + c.dissipated, c.dissipated


def test_undamped_pair_is_elastic():
    e, energy, dissipated = _rebound(0.0, 0.05)
    assert e == pytest.approx(1.0, abs=1e-3) and energy == pytest.approx(0.5, rel=1e-3) and dissipated == 0.0


@pytest.mark.convergence
@pytest.mark.parametrize("ζ", [0.2, 0.5])
def test_contact_damping_converges_to_the_dashpot_pair(ζ):
    """Two masses through one damped penalty pair: the rebound velocity ratio converges to the spring-dashpot
    pair's (ODE, force kept compressive; ζ = 0.2: e = 0.572, 0.5: 0.298) at order >= 1 - 0.1 in Δt (the rate
    is the half step's, first order), within 1% at ω Δt = 0.025; kinetic energy plus the counted dissipation
    stays the initial 0.5 J to 1%."""
    ref = _dashpot_restitution(ζ, 2.0e6, 0.5)
    ω_dt = np.array([0.1, 0.05, 0.025])
    runs = [_rebound(ζ, x) for x in ω_dt]
    err = np.array([abs(e / ref - 1) for e, _, _ in runs])
    order = np.polyfit(np.log(ω_dt), np.log(err), 1)[0]
    assert order >= 1 - 0.1 and err[-1] < 1e-2
    for _, energy, dissipated in runs:
        assert energy == pytest.approx(0.5, rel=1e-2) and dissipated > 0.1


def test_damped_pair_restarts_bit_for_bit():
    """A damped pair stopped mid-contact and resumed from the stepper's and the contact's states (a checkpoint)
    ends exactly where the uninterrupted run ends: the law's memory (last gaps, damping forces, dissipation)."""
    dt = 0.05 / np.sqrt(2.0e6 / 0.5)
    ref, c_ref, _, _ = _two_masses(0.2, dt)
    for _ in range(120):
        ref.step()
    st, c, _, _ = _two_masses(0.2, dt)
    for _ in range(40):  # in contact from the first step on: the damping force is already at work
        st.step()
    assert c.force > 0
    saved, contact_state = st.state(), c.state()
    st2, c2, _, _ = _two_masses(0.2, dt)
    st2.restore(saved)
    c2.restore(contact_state)
    for _ in range(80):
        st2.step()
    v, v_ref = (np.asarray(s.v.getArray() if hasattr(s.v, "getArray") else s.v) for s in (st2, ref))
    assert np.array_equal(v, v_ref) and c2.dissipated == c_ref.dissipated


@pytest.mark.parametrize("ζ", [0.0, 0.2], ids=["undamped", "damped"])
def test_one_copy_to_the_host_per_evaluation(monkeypatch, ζ):
    """On an array backend an evaluation copies its scalars (force, energy and, damped, the damping's work) to
    the host in one copy (on a device: the step's one synchronisation); the values are those of the host path."""
    from rods.fe import backend as backends

    copies = [0]
    to_host = backends.Backend.to_host
    monkeypatch.setattr(backends.Backend, "to_host", lambda s, a: copies.__setitem__(0, copies[0] + 1) or to_host(s, a))
    ref, n = axisymmetric_pair()
    c, _ = axisymmetric_pair()
    c.use(backends.select("numpy", 1))
    for law in (ref, c) if ζ else ():
        law.set_damping(ζ, np.full(n, 1e3), 1e-8)  # masses [kg], step [s]
    for δ in (1e-6, 3e-6, 5e-6):
        copies[0] = 0
        for law in (ref, c):
            law.evaluate(pressed(law, n, δ))
        assert copies[0] == 2  # one each: the PETSc path's state is numpy too, but its sums come the same way
        assert (c.force, c.energy, c.dissipated) == (ref.force, ref.energy, ref.dissipated)
    assert c.force > 0 and (c.dissipated != 0.0) == (ζ > 0)


def test_serial_gap_operator_is_the_gather_and_interpolation():
    """Serial, g = g0 + B u is one sparse product (rods.fe.contact.PenaltyContact.gap_matrix); it equals the
    MPI path's gather and interpolation to round-off, axisymmetric (linear in r) and 3D (bilinear, slaves
    off the face included), with the owned entries in any order."""
    rng = np.random.default_rng(7)
    g = np.linspace(0.0, 1e-3, 4)
    X, Y = np.meshgrid(g, g, indexing="ij")
    xy_m = np.column_stack([X.ravel(), Y.ravel()])
    idx = np.arange(16).reshape(4, 4)
    quads = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], axis=-1).reshape(-1, 4)
    xy_s = 1.2e-3 * rng.random((9, 2))  # some beyond the face
    n = 3 * (9 + 16)
    perm = rng.permutation(9 + 16)  # owned axial entries, shuffled
    slave = TipNodes(np.hypot(*xy_s.T), np.zeros(9), np.full(9, 1e-8), 3 * perm[:9] + 2, np.arange(9), xy_s)
    master = TipNodes(np.hypot(*xy_m.T), np.zeros(16), np.full(16, 1e-8), 3 * perm[9:] + 2, np.arange(16), xy_m)
    three_d = PenaltyContact(slave, master, ε, MPI.COMM_SELF, bilinear_pairing(xy_s, xy_m, quads))
    assert not three_d.inside.all()
    for c, size in ((axisymmetric_pair()[0], axisymmetric_pair()[1]), (three_d, n)):
        u = rng.normal(size=size) * 1e-6
        serial = c.normal_rates(u)
        c.serial = False  # the MPI path's gather (an Allreduce over one rank) and interpolation
        gathered = c.normal_rates(u)
        c.serial = True
        assert np.abs(serial - gathered).max() <= 1e-15 * np.abs(u).max() and np.abs(gathered).max() > 0


@pytest.mark.parametrize("θ", [0.05, 0.3, 0.6, 0.95])
def test_the_penalty_contact_radius_wherever_the_edge_falls_between_nodes(θ):
    """PenaltyContact.radius (axisymmetric) on a Hertz contact (a = 1.09 mm, 0.0625 mm nodes) whose closed nodes
    penetrate by the penalty's 0.65 µm x sqrt(1 - r²/a²) and whose open gaps are Hertz's separation: within 0.1% of
    a wherever the edge falls, a fraction θ of an element inside the next node. The linear zero crossing between the
    outermost closed node and the next (the penalty law's radius until 2026-12-08) read -0.32% to +0.21% here and
    -3.1% to +1.7% over the phase members of a submodel level, whose first open gap is under-resolved; the outermost
    node or the next would be up to h/a = 5.7% off. No active node: zero."""
    from types import SimpleNamespace

    a, R, h = 1.091e-3, 35e-3, 0.0625e-3  # [m]
    r = a - θ * h + h * np.arange(-17, 30)  # [m] node 17 a fraction θ of an element inside the edge
    gap = hertz_separation(r, a, R)
    closed = r < a
    gap[closed] = -0.65e-6 * np.sqrt(1.0 - (r[closed] / a) ** 2)  # [m] penalty penetration, p/ε_pen
    fake = SimpleNamespace(three_d=False, pressure=np.where(closed, 1.0, 0.0), slave=SimpleNamespace(r=r), gap=gap)
    assert PenaltyContact.radius(fake) == pytest.approx(a, rel=1e-3)
    fake.pressure = np.zeros_like(r)
    assert PenaltyContact.radius(fake) == 0.0


@pytest.mark.parametrize("a", [0.31e-3, 0.5e-3, 0.549e-3])  # [m]
def test_edge_radius_recovers_a_three_halves_gap(a):
    """Exact for the (r - a)^{3/2} separation outside a smooth contact, wherever the edge falls between nodes."""
    r = np.linspace(0.0, 1e-3, 21)  # [m]
    gap = 3e-2 * np.clip(r - a, 0.0, None) ** 1.5  # [m]
    assert edge_radius(r, gap, gap == 0.0) == pytest.approx(a, rel=1e-12)
    assert edge_radius(r, gap, np.zeros(r.size, dtype=bool)) == 0.0


def hertz_separation(r: np.ndarray, a: float, R: float) -> np.ndarray:
    """Separation [m] of a Hertz contact of radius a [m] and relative radius R [m] (Johnson, Sec. 4.2):
    r²/2R - δ + ū_z(r), ū_z the summed surface displacement of the elliptical pressure, zero for r <= a."""
    ro = np.maximum(r, a)
    uz = ((2 * a * a - ro**2) * np.arcsin(a / ro) + a * np.sqrt(ro**2 - a * a)) / (np.pi * R)
    return np.where(r > a, ro**2 / (2 * R) - a * a / R + uz, 0.0)


@pytest.mark.parametrize("θ", [0.05, 0.2, 0.35])
def test_edge_radius_when_a_node_closes_just_beyond_the_edge(θ):
    """A node a fraction θ of an element beyond the Hertz edge closed with a vanishing force (as the discrete
    contact does: measured 0.2 h at the 0.058 mm submodel): the open nodes' gaps still place the edge within
    0.1% of a, not at that node (which would read up to θ h / a = 1.2% too wide here)."""
    a, R, h = 1.091e-3, 35e-3, 0.0625e-3  # [m]
    r = a + θ * h + h * np.arange(-18, 30)  # [m] node k = 18 at a + θ h
    g = hertz_separation(r, a, R)
    closed = r <= r[18]
    g[closed] = 0.0
    assert edge_radius(r, g, closed) == pytest.approx(a, rel=1e-3)


@pytest.mark.parametrize("h", [0.25e-3, 0.125e-3, 0.0625e-3])
def test_edge_radius_on_the_hertz_profile_wherever_the_edge_falls(h):
    """The paper scene's contact at peak (a = 1.09 mm, R = 35 mm) on nodes spaced h, the edge at 40 positions
    between two nodes: within 0.6% of a at h = 0.25 mm (the pure 3/2 law is exact only as r -> a), the error
    falling at least as h^1.5."""
    a, R = 1.091e-3, 35e-3  # [m]
    errors = []
    for θ in np.linspace(0.0, 1.0, 40, endpoint=False):
        r = np.arange(0.0, 3e-3, h) + θ * h  # [m]
        g = hertz_separation(r, a, R)
        errors.append(edge_radius(r, g, g == 0.0) / a - 1.0)
    assert np.abs(errors).max() < 0.006 * (h / 0.25e-3) ** 1.5 + 1e-4
