"""The central-difference stepper (rods.fe.explicit.CentralDifference), mesh-free: a two-DOF spring-mass
chain against its closed form (second order), the scheme's discrete energy, the recovered K u_n."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from rods.fe.explicit import CentralDifference, stable_step

from .toy import petsc_matrix

# fixed-free chain: ground -k1- m1 -k2- m2 [N/m, kg]
K = np.array([[3.0e4 + 1.0e4, -1.0e4], [-1.0e4, 1.0e4]])
MASS = np.array([2.0, 1.0])
V0 = np.array([0.3, -0.1])  # [m/s]


def closed_form(t: float) -> np.ndarray:
    """u(t) of M u'' + K u = 0, u(0) = 0, u'(0) = V0: Σ_i φ_i (φ_i·M V0) sin(ω_i t)/ω_i (M-orthonormal modes)."""
    ω2, φ = scipy.linalg.eigh(K, np.diag(MASS))
    ω = np.sqrt(ω2)
    return φ @ ((φ.T @ (MASS * V0)) * np.sin(ω * t) / ω)


def march(dt: float, steps: int, keep: bool = False, β: float = 0.0):
    st = CentralDifference(petsc_matrix(K), MASS, 1.0 / MASS, dt, V0, β)
    for _ in range(steps + 1):
        st.step(keep)
        yield st


def u_at(T: float, n: int) -> np.ndarray:
    *_, st = march(T / n, n)
    return st.u.copy()  # u_n after step n


@pytest.mark.convergence
def test_two_dof_chain_converges_at_second_order():
    """u(T) against the closed form over ~3 periods of the slow mode, Δt halved 4 times: fitted order 2."""
    ω = np.sqrt(scipy.linalg.eigh(K, np.diag(MASS), eigvals_only=True))
    T = 3 * 2 * math.pi / ω.min()  # [s]
    ns = np.array([200, 400, 800, 1600])
    err = [np.abs(u_at(T, n) - closed_form(T)).max() for n in ns]
    order = np.polyfit(np.log(T / ns), np.log(err), 1)[0]
    assert order >= 2 - 0.1, (order, err)
    assert err[-1] < 1e-3 * np.abs(V0).max() / ω.min()


def test_discrete_energy_is_conserved_to_round_off():
    """H_n = ½ v_{n-½}·M v_{n+½} + ½ u_n·K u_n is invariant (module docstring of rods.fe.explicit), with ½ u·K u
    recovered from the stepper's increment (-½ (M/Δt) u_n·increment) and checked against K u_n."""
    dt = 0.9 * stable_step(math.sqrt(scipy.linalg.eigh(K, np.diag(MASS), eigvals_only=True).max()))
    H = []
    for st in march(dt, 2000, keep=True):
        assert np.allclose(st.increment, -dt / MASS * (K @ st.u), rtol=1e-12, atol=1e-15)
        H.append(0.5 * st.v_prev @ (MASS * st.v) - 0.5 * (st.mass_dt * st.u) @ st.increment)
    H = np.array(H)
    assert H[0] == pytest.approx(0.5 * V0 @ (MASS * V0), rel=1e-15)
    assert np.abs(H - H[0]).max() <= 1e-13 * H[0]


def test_damping_dissipates_and_the_state_is_restorable():
    """β > 0: the discrete energy decays; state()/restore() resumes the same trajectory bit for bit."""
    dt = 1e-4
    ref = [st.u.copy() for st in march(dt, 300, β=2e-3)]
    a = CentralDifference(petsc_matrix(K), MASS, 1.0 / MASS, dt, V0, 2e-3)
    for _ in range(101):
        a.step()
    saved = {k: np.copy(v) for k, v in a.state().items()}
    b = CentralDifference(petsc_matrix(K), MASS, 1.0 / MASS, dt, np.zeros(2), 2e-3)
    b.restore(saved)
    for n in range(101, 301):
        b.step()
        assert np.array_equal(b.u, ref[n]) and b.n == n
    E_end = 0.5 * b.v @ (MASS * b.v) + 0.5 * b.u @ K @ b.u
    assert E_end < 0.5 * (0.5 * V0 @ (MASS * V0))  # ξ ω_1 = β ω_1²/2 ~ 20/s over 30 ms


@pytest.mark.parametrize("β", [0.0, 2e-3], ids=["undamped", "damped"])
def test_one_matrix_product_per_step_with_the_damping_as_the_scheme_with_two(β):
    """A step multiplies the matrix once, damped too (A v_{n-½} = (A u_n - A u_{n-1})/Δt; the first step and a
    restore multiply once more); the trajectory is the scheme's: the damping force C v_{n-½} formed by its own
    product, as the stepper did before, agrees to round-off (measured 9e-16 of max |v|, 1e-15 of max |u| here)."""
    dt, steps = 1e-4, 300
    st = CentralDifference(petsc_matrix(K), MASS, 1.0 / MASS, dt, V0, β)
    products = [0]
    for name in ("mult", "mult_add"):
        f = getattr(st.op, name)
        setattr(st.op, name, lambda x, y, f=f: products.__setitem__(0, products[0] + 1) or f(x, y))
    u_ref, v_ref = np.zeros(2), V0.astype(float).copy()  # the scheme, with C v = β K v multiplied out
    for n in range(steps + 1):
        products[0] = 0
        st.step()
        assert products[0] == (2 if n == 0 and β else 1)
        if n:
            u_ref += dt * v_ref
        a = -(K @ u_ref + β * (K @ v_ref)) / MASS
        v_ref += (0.5 if n == 0 else 1.0) * dt * a
        np.testing.assert_allclose(st.v, v_ref, rtol=0, atol=1e-12 * np.abs(V0).max())
    np.testing.assert_allclose(st.u, u_ref, rtol=0, atol=1e-12 * np.abs(u_ref).max())
    if β:
        saved = {k: np.copy(v) for k, v in st.state().items()}
        b = CentralDifference(petsc_matrix(K), MASS, 1.0 / MASS, dt, np.zeros(2), β)
        b.restore(saved)
        b.step()
        st.step()
        assert np.array_equal(b.v, st.v)  # the restore's product stands in for the step's kept one


@pytest.mark.parametrize("route", ["slepc", "lanczos"])
def test_largest_eigenvalue_is_an_upper_estimate_within_the_tolerance(route):
    """ω_max²'s estimate (rods.fe.explicit.largest_eigenvalue, SLEPc; rods.fe.timestep.largest_eigenvalue_on,
    the device's Lanczos run with NumPy) on the hardest spectrum for a Krylov method, the 1D Dirichlet Laplacian
    (its top eigenvalues 4 sin²(kπ / 2(n+1)) crowd at 4 as k -> n): never below the closed form, so the step
    errs on the stable side, and above it by at most EIGEN_TOL."""
    import scipy.sparse
    from mpi4py import MPI

    from rods.fe import backend
    from rods.fe.explicit import EIGEN_TOL, largest_eigenvalue
    from rods.fe.timestep import largest_eigenvalue_on

    n = 20_000
    L = scipy.sparse.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr")
    exact = 4.0 * math.sin(n * math.pi / (2 * (n + 1))) ** 2
    products = []

    def apply(x, y):
        products.append(1)
        y += L @ x

    if route == "slepc":
        λ = largest_eigenvalue(apply, n, MPI.COMM_SELF)
    else:
        λ = largest_eigenvalue_on(backend.select("numpy", 1), lambda x: apply(x, y := np.zeros(n)) or y, n)
    assert exact <= λ <= exact * (1 + EIGEN_TOL)
    assert len(products) < 1000  # measured: 601 (SLEPc), 600 (Lanczos); a residual of 1e-8: not in 10,220


U0 = np.array([2e-3, -1e-3])  # [m] a displaced start


def test_a_displaced_start_converges_at_second_order_and_recovers_k_u():
    """u(0) = U0 != 0 (a prestressed or displaced state): the first half step's K u_0 term matters, so u(T) converges
    at second order to M u'' + K u = 0 from (U0, V0), and the step-0 increment is -Δt M^-1 K u_0 (both terms vanish
    from rest, where a mutation to a full first step or a doubled increment passed the suite: an audit, 2026-12-07)."""
    ω2, φ = scipy.linalg.eigh(K, np.diag(MASS))
    ω = np.sqrt(ω2)

    def exact(t: float) -> np.ndarray:
        return φ @ ((φ.T @ (MASS * U0)) * np.cos(ω * t) + (φ.T @ (MASS * V0)) * np.sin(ω * t) / ω)

    def u_end(T: float, n: int, keep: bool = False) -> tuple[np.ndarray, list]:
        st = CentralDifference(petsc_matrix(K), MASS, 1.0 / MASS, T / n, V0, 0.0)
        st.u[:] = U0
        increments = []
        for _ in range(n + 1):
            st.step(keep)
            if keep:  # the increment of the u the step ends on (as test_discrete_energy_is_conserved_to_round_off)
                increments.append((st.u.copy(), st.increment.copy()))
        return st.u.copy(), increments

    T = 3 * 2 * math.pi / ω.min()  # [s]
    ns = np.array([200, 400, 800, 1600])
    err = [np.abs(u_end(T, n)[0] - exact(T)).max() for n in ns]
    order = np.polyfit(np.log(T / ns), np.log(err), 1)[0]
    assert order >= 2 - 0.1, (order, err)
    dt = T / 200
    _, inc = u_end(T, 200, keep=True)
    for u_n, increment in inc[:3]:  # the half step's and the next two
        assert np.allclose(increment, -dt / MASS * (K @ u_n), rtol=1e-12, atol=1e-15)
