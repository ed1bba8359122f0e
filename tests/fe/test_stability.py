"""Stability matrix: hard cases stay stable and keep their physics (issue: hard cases stay stable).

Fast cases run on a coarse axisymmetric mesh (2 mm x 0.5 mm, 0.4 ms); each asserts energy balance,
momentum, and the wave response (Rod-2 midpoint plateau speed) and peak force against the analytical
model. The slow cases (`make test-slow`) refine the tip mesh and run 200,000 steps.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rods.fe  # noqa: F401
from rods import checks, metrics
from rods.analytical import simulate
from rods.fe.model import ExplicitModel
from rods.hertz import YieldWarning
from rods.metrics import smoothed_peak
from rods.scene import SceneError

COARSE = ("fe.axial_size=2e-3", "fe.radial_size=0.5e-3", "simulation.end_time=4e-4")
ALU = ("youngs_modulus=70e9", "density=2700.0", "poisson_ratio=0.33")

# The penalty cases were measured at 2 x E*/h without contact damping (the defaults until issue 13's damping):
# they show the undamped layer's rattle and the switching limit, so they pin that law. The damped default
# ("auto": 18 x E*/h on this mesh, 2.2 elements across the patch; ζ = 0.2) is the "penalty-default" case, raw peak
# against the analytical model.
P0 = 2.0  # [-] the penalty factor of the measurements below
PENALTY = ("fe.contact='penalty'", "fe.tip_grading=1.0", "fe.contact_damping=0.0")  # the paper's law, uniform mesh

# name -> (overrides, peak-force tolerance, midpoint plateau-speed tolerance, relative to the analytical model;
# largest energy-balance error).
# Stiff penalties (10x, 100x the default) make the contact nodes rattle: the step adapts (contact-switching
# limit, rods.fe.explicit) and the energy stays balanced, but the raw force carries spikes (+35% at 100x on
# this mesh), so those cases compare the 2 µs-smoothed peak. At 0.01 m/s the Hertz patch (0.37 mm) is smaller
# than one element, the force is 29% low and the contact softer (see the slow refined case: -5%), and the
# midpoint plateau speed is within 5% (measured +4.2% with the kinematic contact, ringing); on 0.25 m
# rods the midpoint is only 10 diameters from the tip, where the 1D model's plateau differs from the
# 3D-elastic one by ~1.3%.
# energy tolerance: about 10x each case's energy-balance error measured on 2026-11-29 (this mesh, 0.4 ms): the
# kinematic law's cases 1.6e-11 to 4.7e-11 (round-off), the damped default penalty 2.1e-6, 10x 1.5e-6, the undamped
# 100x 6.7e-4 (rattling at its switching-limited step)
KINEMATIC_ENERGY = 1e-9
CASES = {
    "penalty-10x": ((*PENALTY, f"fe.penalty={10 * P0}"), 0.02, 0.01, 2e-5),
    "penalty-100x": ((*PENALTY, f"fe.penalty={100 * P0}"), 0.05, 0.01, 5e-3),
    "penalty-default": (("fe.contact='penalty'", "fe.tip_grading=1.0"), 0.005, 0.01, 2e-5),
    "speed-0.01": (("impact.speed=0.01",), None, 0.05, KINEMATIC_ENERGY),
    "speed-20": (("impact.speed=20",), 0.01, 0.01, KINEMATIC_ENERGY),
    "steel-on-aluminium": (tuple(f"rod2.material.{a}" for a in ALU), 0.01, 0.01, KINEMATIC_ENERGY),
    "aluminium-on-steel": (tuple(f"rod1.material.{a}" for a in ALU), 0.01, 0.01, KINEMATIC_ENERGY),
    "striker-longer": (("rod1.length=0.7", "rod2.length=0.25"), 0.01, 0.02, KINEMATIC_ENERGY),
    "equal-lengths": (("rod2.length=0.25009",), 0.01, 0.02, KINEMATIC_ENERGY),
}


def run_case(scene):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", YieldWarning)
        fe = ExplicitModel(scene)
        return fe, fe.run(), simulate(scene)


def check_physics(scene, fe, r, a, force_tol, speed_tol=0.01, energy_tol=KINEMATIC_ENERGY):
    s, h = r.summary, r.history
    assert np.all(np.isfinite(h["contact_force"])) and s["energy_error"] < energy_tol
    p = h["momentum"]
    assert np.max(np.abs(p - p[0])) < 1e-13 * max(fe.steps, 10_000) * abs(p[0])  # round-off, grows with steps
    assert p[0] == pytest.approx(scene.rod1.mass * scene.speed, rel=2e-3)  # the cap's missing volume
    assert s["midpoint_peak_speed"] == pytest.approx(a.summary["midpoint_peak_speed"], rel=speed_tol)
    if force_tol is not None:
        window = metrics.smoothing(scene)  # [s]
        peak = smoothed_peak(h["time"], h["contact_force"], window)
        assert peak == pytest.approx(
            smoothed_peak(a.history["time"], a.history["contact_force"], window), rel=force_tol
        )
    if scene["fe.contact"] == "penalty" and scene["fe.contact_damping"] > 0:  # damped: no rattle spike either
        assert s["peak_contact_force"] == pytest.approx(a.summary["peak_contact_force"], rel=force_tol)


# the default suite keeps one case per kind of hardness (the damped penalty, speed extremes, an impedance mismatch; the
# 100x penalty's run at its switching-limited step is test_penalty_beyond_switching_limit_pumps_energy's reference);
# the variants of a kind run in make test-slow
VARIANTS = {"penalty-10x", "penalty-100x", "aluminium-on-steel", "striker-longer", "equal-lengths"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in VARIANTS else n for n in CASES])
def test_stability_matrix(scene_with, name):
    overrides, force_tol, speed_tol, energy_tol = CASES[name]
    scene = scene_with(*COARSE, *overrides)
    fe, r, a = run_case(scene)
    check_physics(scene, fe, r, a, force_tol, speed_tol, energy_tol)
    assert fe.dt_gershgorin <= fe.dt_critical  # Gershgorin is a lower bound of the Krylov-Schur limit
    assert fe.dt <= min(fe.dt_critical, fe.dt_switching)


def test_stiffer_penalty_shrinks_the_step(scene_with):
    """The linear limit falls once the penalty controls the spectrum; the switching limit as 1/sqrt(penalty)."""
    models = [ExplicitModel(scene_with(*COARSE, *PENALTY, f"fe.penalty={p * P0}")) for p in (1, 100)]
    assert models[1].dt_critical < 0.8 * models[0].dt_critical
    assert models[1].dt_switching == pytest.approx(models[0].dt_switching / 10, rel=1e-9)
    assert models[1].dt == pytest.approx(models[1].dt_switching)  # the switching limit controls at 100x
    assert models[0].dt == pytest.approx(0.8 * models[0].dt_critical)  # and not at the default


def test_the_step_limit_is_solved_once_without_contact_springs(scene_with, monkeypatch):
    """Kinematic contact adds no stiffness: ω_max is the rods' own, found by one eigenvalue solve (the
    penalty law: two, with its springs at full engagement raising ω_max)."""
    from rods.fe import timestep

    calls = []
    solve = timestep.omega_max
    monkeypatch.setattr(timestep, "omega_max", lambda m, c, K=None: calls.append(c) or solve(m, c, K))
    kin = ExplicitModel(scene_with(*COARSE, "fe.contact='kinematic'"))
    assert calls == [False] and kin.ω_max == kin.ω_max_K and kin.dt_switching == float("inf")
    calls.clear()
    pen = ExplicitModel(scene_with(*COARSE, *PENALTY, f"fe.penalty={100 * P0}"))
    assert calls == [False, True] and pen.ω_max > pen.ω_max_K


def test_an_unconverged_eigenvalue_solve_marches_at_the_gershgorin_bound(scene_with, monkeypatch):
    """Where Krylov-Schur does not converge (a Ritz value may then lie below ω_max), the step comes from the
    Gershgorin bound, a true upper bound of ω_max, with a warning: a smaller step, never an unstable one."""
    from rods.fe import timestep
    from rods.fe.explicit import NotConverged

    def fail(*_args, **_kw):
        raise NotConverged("Krylov-Schur: largest eigenvalue not converged")

    ref = ExplicitModel(scene_with(*COARSE))
    monkeypatch.setattr(timestep, "largest_eigenvalue", fail)
    with pytest.warns(RuntimeWarning, match="Gershgorin"):
        fe = ExplicitModel(scene_with(*COARSE))
    assert fe.dt_critical == pytest.approx(fe.dt_gershgorin, rel=1e-14) and fe.dt_gershgorin < ref.dt_critical
    assert fe.dt == pytest.approx(0.8 * fe.dt_gershgorin)


def test_another_error_in_the_eigenvalue_solve_is_no_fallback(scene_with, monkeypatch):
    """A PETSc error (a RuntimeError, raised on one rank only where its cause is local) is not a solve that did not
    converge: it propagates (the entry point aborts every rank); taken as one, that rank marched on at the
    Gershgorin step while the others waited in SLEPc (an audit, 2026-12-07)."""
    from petsc4py import PETSc

    from rods.fe import timestep

    def fail(*_args, **_kw):
        raise PETSc.Error(55)  # out of memory

    monkeypatch.setattr(timestep, "largest_eigenvalue", fail)
    with pytest.raises(PETSc.Error):
        ExplicitModel(scene_with(*COARSE))


@pytest.mark.slow  # 11-14 s: why the limit exists; the limit's refusal is in the default suite
def test_penalty_beyond_switching_limit_pumps_energy(scene_with):
    """Why the switching limit exists: 100x the default penalty marched at 0.9 x the linear limit (1.77 x the
    switching limit) rattles and pumps energy: the guard stops it (measured: energy grown by 0.076 and 0.11 x E0
    with two round-off-level variants of the gap evaluation), or its energy error is many times that of the same
    contact at the switching-limited step, and above checks.ENERGY_OK the run's status is not "ok". Closer to
    the limit the rattle is chaotic: at 0.8 x (1.58 x the switching limit) the same two variants measured
    9.3e-3 and 1.6e-3, against 3.5e-4 and 1.1e-3 at the switching-limited step."""
    from rods.fe.guards import SimulationError

    scene = scene_with(*COARSE, *PENALTY, f"fe.penalty={100 * P0}")
    safe = ExplicitModel(scene).run().summary["energy_error"]
    fe = ExplicitModel(scene)
    dt = 0.9 * fe.dt_critical
    assert dt > 1.5 * fe.dt_switching
    with pytest.raises(SceneError, match="switching"):
        ExplicitModel(scene_with(*COARSE, *PENALTY, f"fe.penalty={100 * P0}", f"fe.dt={dt}"))
    fe.dt, fe.steps = dt, int(scene.end_time / dt)  # bypass the refusal to show the instability
    try:
        r = fe.run()
    except SimulationError as e:  # pumped past the guard's growth limit: stopped
        assert "energy grew" in str(e)
        return
    assert r.summary["energy_error"] > 10 * safe
    summary = checks.apply(dict(r.summary), r.history, scene, scene.end_time)
    if r.summary["energy_error"] > checks.ENERGY_OK:
        assert summary["status"] != "ok" and any(w.startswith("energy_error") for w in summary["warnings"])


def test_yield_warning_at_high_speed(scene_with):
    with pytest.warns(YieldWarning, match="1.1 S_y"):
        simulate(scene_with("impact.speed=20", "simulation.end_time=3e-4"))


@pytest.mark.slow
def test_low_speed_needs_a_refined_tip(scene_with):
    """At 0.01 m/s the Hertz patch is ~0.37 mm: refined to 0.0625 mm the force comes within 6% (coarse: -29%).
    The midpoint's peak speed is a peak of the ringing plateau (CASES' speed-0.01): +1.1% here (measured with the
    kinematic contact), so 2%."""
    scene = scene_with(
        *COARSE, "simulation.end_time=6e-4", "impact.speed=0.01", "fe.radial_size=0.0625e-3", "fe.tip_grading=0.1"
    )
    fe, r, a = run_case(scene)
    check_physics(scene, fe, r, a, 0.06, speed_tol=0.02)


@pytest.mark.slow
def test_a_fast_rising_force_gets_an_axial_mesh_that_resolves_its_ringing(scene_with):
    """A 1 m tip on the paper rods: the force rises in ~4 µs and the rods ring (lateral inertia), so the peak
    force needs the axial mesh. The auto size (0.35 mm since 2026-11-29, c t_rise/75; 0.52 mm before) is within
    0.2% of a mesh 2x finer along and across (measured at 0.52 mm: -0.02% against 0.2 x 0.25 mm); the paper's 1 mm
    was +0.7% off (measured +0.69%)."""
    base = ("rod1.tip_radius=1.0", "simulation.end_time=1.2e-4")
    auto = scene_with(*base)
    fine = scene_with(
        *base, f"fe.axial_size={auto['fe.axial_size'] / 2!r}", f"fe.radial_size={auto['fe.radial_size'] / 2!r}"
    )
    coarse = scene_with(*base, "fe.axial_size=1e-3")
    F = {
        k: ExplicitModel(s).run().summary["peak_contact_force"]
        for k, s in (("auto", auto), ("fine", fine), ("1mm", coarse))
    }
    assert F["auto"] == pytest.approx(F["fine"], rel=2e-3)
    assert abs(F["1mm"] / F["fine"] - 1) > 4e-3


@pytest.mark.slow
def test_200k_steps_bounded_energy_drift(scene_with):
    """200,000 central-difference steps (13 ms, many wave round trips and the whole contact): drift < 1e-4."""
    scene = scene_with(*COARSE, "simulation.end_time=1.32e-2", "simulation.output_interval=1e-6")
    fe = ExplicitModel(scene)
    assert fe.steps >= 200_000
    r = fe.run()
    assert r.summary["energy_error"] < 1e-4
    E = r.history["kinetic_energy"] + r.history["strain_energy"] + r.history["contact_energy"]
    late = E[E.size // 2 :]
    assert np.ptp(late) / E[0] < 1e-4  # no secular growth in the second half


@given(
    n=st.integers(1, 40),
    density=st.floats(0.0, 0.5),
    bs=st.sampled_from([1, 2, 3]),
    chunk=st.integers(1, 64),
    seed=st.integers(0, 2**16),
)
@settings(max_examples=60, deadline=None)
def test_abs_row_sums_equal_scipys(n, density, bs, chunk, seed):
    """rods.fe.timestep.abs_row_sums (the Gershgorin bound's row sums, chunked, no copy of the matrix) equals
    SciPy's abs(S).sum(axis=1) on CSR and BSR matrices with empty rows, for any chunk size."""
    import scipy.sparse

    from rods.fe.timestep import abs_row_sums

    S = scipy.sparse.random(n * bs, n * bs, density=density, format="csr", random_state=seed) - 0.5 * (
        scipy.sparse.random(n * bs, n * bs, density=density, format="csr", random_state=seed + 1)
    )
    expected = np.asarray(abs(S).sum(axis=1)).ravel()
    for M in (S, S.tobsr(blocksize=(bs, bs))):
        np.testing.assert_allclose(abs_row_sums(M, chunk), expected, rtol=1e-14, atol=0.0)
