"""Observers of the explicit loop on the mesh-free toy impact: checkpoint round trip, guards firing with
the right likely cause, finish() after a stop, progress."""

from __future__ import annotations

import math

import numpy as np
import pytest
from mpi4py import MPI

from rods.fe import checkpoint
from rods.fe.explicit import stable_step
from rods.fe.guards import FINITE_EVERY, Guard, RunGuard, SimulationError
from rods.fe.observers import Progress, march

from .toy import K_CONTACT, bodies, impact, omega_max

COMM = MPI.COMM_SELF


def critical_step() -> float:
    K, mass, _ = bodies()
    Kc = K.copy()
    Kc[1:3, 1:3] += K_CONTACT * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return stable_step(omega_max(Kc, mass))


def test_checkpoint_round_trip(tmp_path):
    """A run resumed from its checkpoint records the same histories, bit for bit, as one that was not stopped."""
    dt = 0.3 * critical_step()
    N = 120
    st, rec, _ = impact(dt, N)
    ck = checkpoint.Checkpoints(tmp_path, 25, (st, rec), COMM, "toy", 0, N)
    march(st, range(N + 1), [rec, ck], rec.is_out)
    saved = checkpoint.load(tmp_path, COMM, "toy")
    assert int(saved["step"]) == 100 and not list(tmp_path.glob("checkpoint-75-*"))  # the last one only
    st2, rec2, _ = impact(dt, N)
    st2.restore(saved)
    rec2.restore(saved)
    march(st2, range(st2.n + 1, N + 1), [rec2], rec2.is_out)
    for name, col in rec.history().items():
        assert np.array_equal(rec2.history()[name], col), name
    assert np.array_equal(rec2.force, rec.force) and rec2.peak["F"] == rec.peak["F"]
    with pytest.raises(ValueError, match="another run"):
        checkpoint.load(tmp_path, COMM, "other")


def guarded(dt: float, steps: int):
    st, rec, _ = impact(dt, steps)
    guard = RunGuard(Guard(dt, critical_step()), rec, lambda u: 0, COMM)
    return st, rec, guard


def test_guard_stops_energy_growth_above_the_stable_step():
    """Δt = 1.2 Δt_crit: the energy grows, the guard stops the run at a recorded step: 'step too large'."""
    st, rec, guard = guarded(1.2 * critical_step(), 400)

    class Closed:
        done = False

        def after_step(self, step, t, state):
            pass

        def finish(self):
            self.done = True

    closed = Closed()
    err = march(st, range(401), [rec, guard, closed], rec.is_out)
    assert isinstance(err, SimulationError) and closed.done  # finish() runs after a stop too
    assert "energy grew" in str(err) and err.cause.startswith("step too large")
    assert 0 < err.step < 400 and err.time == pytest.approx(err.step * st.dt)
    h = rec.history()
    E = h["kinetic_energy"] + h["strain_energy"] + h["contact_energy"]
    assert E[-1] > 1.05 * E[0] and np.all(E[:-1] <= 1.05 * E[0])  # stopped at the first record past the limit


def test_guard_stable_run_passes():
    st, rec, guard = guarded(0.5 * critical_step(), 300)
    assert march(st, range(301), [rec, guard], rec.is_out) is None


def test_guard_likely_causes():
    """Below the stable step, growth with the contact energy dominating names the penalty; a NaN velocity
    is caught at the next finite check."""
    g = Guard(dt=1e-8, dt_critical=2e-8)
    with pytest.raises(SimulationError, match="penalty too stiff") as e:
        g.check(7, 7e-8, (0.1, 0.1, 5.0, 0.0), 1.0)
    assert e.value.step == 7
    with pytest.raises(SimulationError, match="lower fe.dt_fraction"):
        g.check(7, 7e-8, (2.0, 0.1, 0.1, 0.0), 1.0)
    st, rec, guard = guarded(0.5 * critical_step(), 300)
    march(st, range(FINITE_EVERY), [rec, guard], rec.is_out)
    st.v[2] = math.nan
    with pytest.raises(SimulationError, match="non-finite velocity"):
        guard.after_step(FINITE_EVERY, FINITE_EVERY * st.dt, st)


def test_the_guard_weighs_growth_against_the_work_put_in_as_the_summary_does():
    """A driven submodel's cut brings work in: the balance's excess over E0 is relative to the larger of E0 and that
    work (rods.fe.recorder.balance_scale), in the guard's growth as in the summary's energy error. A 0.1 J excess
    with 10 J put in onto 1 J is 1% (passes a 5% limit), not 10% of E0 (stopped before)."""
    from rods.fe.recorder import balance_scale

    assert balance_scale(1.0, np.array([0.0, -10.0, 4.0])) == 10.0 and balance_scale(2.0, 0.5) == 2.0
    g = Guard(dt=1e-8, dt_critical=2e-8, growth_limit=0.05)
    state = (6.0, 5.0, 0.0, 0.1 - 10.0)  # E_k, E_s, E_c, dissipated less the 10 J of work: 1.1 J in all
    g.check(7, 7e-8, state, 1.0, balance_scale(1.0, 10.0))
    with pytest.raises(SimulationError, match="energy grew by 0.1 x E0"):
        g.check(7, 7e-8, state, 1.0)


def test_progress_every_and_last():
    calls = []
    p = Progress(lambda step, total, elapsed: calls.append((step, total)), total=1001, every=500)
    for step in range(1002):
        p.after_step(step, 0.0, None)
    assert calls == [(0, 1001), (500, 1001), (1000, 1001), (1001, 1001)]


def test_progress_of_a_resumed_run_counts_only_its_own_steps(capsys):
    """A run resumed from the checkpoint of step 17864 of 31177: the bar's rate is over the steps run since,
    not over all 17865+ (the resumed fine submodel printed 8,922 steps/s and eta 1.4 s at 19000 on a ~600/s run)."""
    from rods.study.console import progress_bar

    calls = []
    p = Progress(lambda *a: calls.append(a), total=31177, every=500, start=17864)
    p.after_step(18000, 0.0, None)
    assert calls[0][0] == 18000 and calls[0][3] == 17864
    progress_bar(18000, 18000, 1.0, 17864)  # 136 steps in 1 s (the last step: a log prints it)
    assert "136 steps/s" in capsys.readouterr().err
    progress_bar(1000, 1000, 1.0)  # a fresh run: unchanged
    assert "1,000 steps/s" in capsys.readouterr().err
    # a library caller's callable of three, as documented (stages.Progress), is called with three on a resume too
    three = []
    Progress(lambda step, total, elapsed: three.append(step), total=31177, every=500, start=17864).after_step(
        18000, 0.0, None
    )
    assert three == [18000]


def test_discard_removes_an_earlier_runs_checkpoint(tmp_path):
    """A run that starts afresh in a folder removes the checkpoint an earlier run left there: else a later
    --restart (a study's, whose global rewrote the cut record) stops on it as "another scene or settings"."""
    checkpoint.save(tmp_path, 40, 1e-6, {"x": np.arange(3.0)}, COMM, "old")
    assert checkpoint.load(tmp_path, COMM, "old") is not None
    checkpoint.discard(tmp_path, COMM)
    assert checkpoint.load(tmp_path, COMM, "new") is None and not list(tmp_path.glob("checkpoint*"))
    checkpoint.discard(tmp_path, COMM)  # nothing there: nothing to do
