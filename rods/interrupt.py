"""Ctrl-C and SIGTERM during a run: a request to stop, honoured by every rank at the same step.

A signal that arrives while a time loop is running (:func:`armed`) only records the request; the loop's
:class:`rods.fe.guards.InterruptCheck` observer reduces it over the ranks every few steps and stops all
of them together (the partial histories are written, status "interrupted", exit code 130). Outside a
loop, or at a second signal :data:`REPEAT_GRACE` or more after the first, the signal raises KeyboardInterrupt
at once (the entry point exits 130, under MPI after aborting every rank). :func:`install` is called by the
entry points only: a library user keeps Python's default handling.
"""

from __future__ import annotations

import signal
import time
from contextlib import contextmanager
from typing import Any

__all__ = ["armed", "install", "requested", "reset", "uninstall"]

_state = {"armed": 0, "signal": 0, "installed": 0, "since": 0.0}
# a signal repeated within this time of the first is the same stop request [s]: a SLURM time limit's SIGTERM reaches
# each rank directly and again through mpirun, milliseconds apart, and the second raised KeyboardInterrupt on that
# rank alone (no checkpoint; a hang where the others waited in a collective: a fuzz, 2026-12-07). A Ctrl-C pressed
# again later still stops at once.
REPEAT_GRACE = 5.0


def _handler(signum: int, frame: Any) -> None:  # noqa: ARG001
    now = time.monotonic()  # [s]
    if _state["since"] and now - _state["since"] < REPEAT_GRACE:
        return  # a repeat of a request taken within the grace: the same stop, also once the loop has acted on it
    if _state["armed"] and not _state["signal"]:  # the loop stops at its next check, on every rank together
        _state["signal"], _state["since"] = signum, now
        return
    _state["signal"] = signum  # raised inside a C extension, the interrupt may surface as another error
    raise KeyboardInterrupt


def install() -> dict[int, Any]:
    """Route SIGINT and SIGTERM through the request flag (main thread only); the previous handlers."""
    _state["installed"] = 1
    return {s: signal.signal(s, _handler) for s in (signal.SIGINT, signal.SIGTERM)}


def uninstall(previous: dict[int, Any]) -> None:
    """Back to the ``previous`` handlers (an entry point called in-process, e.g. by a test)."""
    _state["installed"] = 0
    for s, h in previous.items():
        signal.signal(s, h)


def requested() -> int:
    """The signal number asked for a stop on this rank, 0 for none."""
    return _state["signal"]


def reset() -> None:
    """The request honoured (the loop stops): a new signal is a new request, but for a repeat of this one within
    :data:`REPEAT_GRACE` (the loop's stop writes the histories after the check: mpirun's forwarded copy arriving then
    aborted every rank before they were written, a review, 2026-12-07)."""
    _state["signal"] = 0


@contextmanager
def armed():
    """While a time loop runs: signals are requests, checked collectively by the loop. Where the entry point
    installed the handler, it is installed again here: the mesher (gmsh) resets the C-level SIGTERM handler
    to the default during the set-up while Python's record of it stays unchanged."""
    if _state["installed"]:
        install()
    _state["armed"] += 1
    try:
        yield
    finally:
        _state["armed"] -= 1
