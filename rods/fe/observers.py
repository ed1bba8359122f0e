"""The explicit loop and its observers: the caller owns the loop (cf. dolfiny's ``odeint.ODEInt2``).

:func:`march` advances a :class:`rods.fe.explicit.CentralDifference` step by step and hands the state
(u_n, v_{n+½}) to each :class:`Observer` in turn. An observer may read the state, prescribe entries of
v_{n+½} (a driven cut: it then runs before the recorder), record, check or write. Its protocol:

* ``after_step(step, t, state)`` — every step, t = step Δt [s];
* ``external_work()`` (optional) — this rank's accumulated work on the model [J] (energy balance);
* ``finish()`` (optional) — once after the loop, also when a guard stopped it (close files).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Protocol

import numpy as np

from rods.fe.explicit import CentralDifference
from rods.fe.guards import SimulationError

__all__ = ["Observer", "Progress", "march"]


class Observer(Protocol):
    """What the time loop calls after every step (:func:`march`): the recorder, the guards, checkpoints, field
    frames, the cut recorder and driver. ``state`` is the stepper itself: its arrays are updated in place."""

    def after_step(self, step: int, t: float, state: CentralDifference) -> None: ...


def march(
    stepper: CentralDifference, steps: range, observers: Sequence[Observer], keep: np.ndarray
) -> SimulationError | None:
    """Run ``steps`` (keeping the energy increments where ``keep[step]``); the guard's error, if one stopped it.

    A guard's or the interrupt check's stop comes on every rank at the same step, so the observers finish together
    (collective closes: the ADIOS2 writer's). Anything else (a second Ctrl-C, an error) stops this rank alone while
    the others are mid-step: there an observer's collective finish waited forever (a double SIGTERM hung a 2-rank run
    in VTXWriter.close, a fuzz, 2026-12-07), so only the rank's own finishes run and the entry point aborts all. A
    library caller under MPI whose loop raises so is left with the ADIOS2 copy unclosed (the XDMF series' XML is
    written whole by its rank-0 part, ``finish_alone``)."""
    try:
        for step in steps:
            stepper.step(keep[step])
            t = step * stepper.dt
            for o in observers:
                o.after_step(step, t, stepper)
    except SimulationError as e:
        _finish(observers)
        return e
    except BaseException:
        _finish(observers, alone=True)
        raise
    _finish(observers)
    return None


def _finish(observers: Sequence[Observer], alone: bool = False) -> None:
    """Each observer's ``finish``; ``alone`` (this rank stops without the others): not the collective ones
    (an observer's ``collective`` true), whose ``finish_alone`` runs instead where they have one (this rank's own
    part: the field series' XML)."""
    for o in observers:
        if alone and getattr(o, "collective", False):
            if hasattr(o, "finish_alone"):
                o.finish_alone()
        elif hasattr(o, "finish"):
            o.finish()


class Progress:
    """Observer: ``progress(step, total, elapsed)`` every ``every`` steps and at the last one; a run resumed
    from the checkpoint of step ``start`` (> 0) calls ``progress(step, total, elapsed, start)`` where ``progress``
    takes a fourth argument: the steps before ``start`` were not run in ``elapsed`` (a rate over all of them
    overstated it ~10x). A callable of three, as documented for the library's callers, is called with three (a
    resumed run had raised a TypeError in it right after the restore: a library audit, 2026-12-07)."""

    def __init__(self, progress: Callable[..., None], total: int, every: int = 500, start: int = 0):
        self.progress, self.total, self.every, self.start = progress, total, every, start
        self.resumed = (start,) if start > 0 and _takes_four(progress) else ()
        self.t_start = time.perf_counter()

    def after_step(self, step: int, t: float, state: CentralDifference) -> None:  # noqa: ARG002
        if step % self.every == 0 or step == self.total:
            self.progress(step, self.total, time.perf_counter() - self.t_start, *self.resumed)


def _takes_four(f: Callable[..., None]) -> bool:
    """Whether ``f`` accepts four positional arguments (one without a readable signature is taken as not)."""
    import inspect

    try:
        inspect.signature(f).bind(0, 0, 0.0, 0)
    except (TypeError, ValueError):
        return False
    return True
