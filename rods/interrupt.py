"""Ctrl-C and SIGTERM during a run: a request to stop, honoured by every rank at the same step.

A signal that arrives while a time loop is running (:func:`armed`) only records the request; the loop's
:class:`rods.fe.guards.InterruptCheck` observer reduces it over the ranks every few steps and stops all
of them together (the partial histories are written, status "interrupted", exit code 130). Outside a
loop, or at a second signal :data:`REPEAT_GRACE` or more after the first, the signal raises KeyboardInterrupt
at once (the entry point exits 130, under MPI after aborting every rank). :func:`install` is called by the
entry points only: a library user keeps Python's default handling.

Python runs a handler only when the main thread is back in the interpreter: a rank waiting in a collective that
another rank has left (a hang) never ran it, and SIGTERM and Ctrl-C did nothing; only SIGKILL ended it (an audit,
2026-12-07). So :func:`install` also starts a watcher thread woken through :func:`signal.set_wakeup_fd`, which
Python's C-level handler writes at once: where the handler has not run :data:`STUCK_GRACE` after a signal, the
watcher stops the process itself (one line, exit 130; under MPI every rank aborted), through the entry point's own
stop where it gave one (:func:`install`). It needs the main thread to have released the GIL, as MPI's blocking
calls through mpi4py do: a call that holds it (SLEPc's solve) is not covered.
"""

from __future__ import annotations

import os
import signal
import socket
import sys
import threading
import time
from collections.abc import Callable
from contextlib import contextmanager
from typing import Any

__all__ = ["armed", "install", "requested", "reset", "stopping", "uninstall"]

_state = {"armed": 0, "signal": 0, "installed": 0, "since": 0.0, "handled": 0.0, "raised": 0.0, "stopping": 0}
# a signal repeated within this time of the first is the same stop request [s]: a SLURM time limit's SIGTERM reaches
# each rank directly and again through mpirun, milliseconds apart, and the second raised KeyboardInterrupt on that
# rank alone (no checkpoint; a hang where the others waited in a collective: a fuzz, 2026-12-07). A Ctrl-C pressed
# again later still stops at once.
REPEAT_GRACE = 5.0  # [s]
# a signal whose Python handler has not run this long after it arrived finds the main thread stuck in a call (a
# collective another rank left) or in a long one (a 3D mesh's generation): the watcher stops the process [s]. Longer
# than a rank may wait in a collective for another's file (a 3D field frame of 7.6M DOFs is ~0.7 GB, a cut record
# several GB): a loop's stop at its next check, checkpointed, is worth the wait. Below SLURM's default KillWait (30 s),
# whose SIGKILL would otherwise come first, without the line or the folder's release
STUCK_GRACE = 20.0  # [s]
# [s] how long before the watcher woke the handler may have run for this signal: the watcher takes the GIL after the
# main thread's next switch (milliseconds), so a handler that ran just before it woke counts as this signal's
HANDLER_LAG = 0.5
# [s] how long after a signal's raise the entry point's stop must have begun (:func:`stopping`): Python drops a
# KeyboardInterrupt that lands in a weakref callback or a __del__ ("Exception ignored in", about one SIGTERM in 30 at
# the set-up's start: that rank went on while the others aborted it, a review, 2026-12-07); on its way a raise takes
# microseconds to the stop, through the finishes it passes
LOST_GRACE = 2.0  # [s]
EXIT_INTERRUPTED = 130  # the exit code of an interrupted command (128 + SIGINT)
_STOP = threading.Lock()  # the stop's flag, set by the main thread (an entry point's abort) or the watcher
_watch: dict[str, Any] = {}  # the watcher: its socket pair, thread and the wakeup fd it replaced


def _handler(signum: int, frame: Any) -> None:  # noqa: ARG001
    now = time.monotonic()  # [s]
    _state["handled"] = now  # the main thread is in the interpreter: the watcher stands down
    if _state["stopping"]:
        return  # the entry point's stop is under way: the same stop, never a raise inside its prints and waits
    if _state["since"] and now - _state["since"] < REPEAT_GRACE:
        return  # a repeat within the grace: the same stop, also once the loop has acted on it or the stop has raised
    if _state["armed"] and not _state["signal"]:  # the loop stops at its next check, on every rank together
        _state["signal"], _state["since"] = signum, now
        return
    # a stop at once. A repeat within the grace (mpirun's forwarded copy of a SLURM SIGTERM) is the same, not a second
    # raise on its way to the stop (a traceback, a rank gone before its line: a review, 2026-12-07); a raise Python
    # drops (one landing in a weakref callback) is the watcher's (:data:`LOST_GRACE`). Raised inside a C extension,
    # the interrupt may surface as another error
    _state["signal"], _state["since"], _state["raised"] = signum, now, now
    raise KeyboardInterrupt


def stopping() -> bool:
    """The entry point's stop (its line, its folder's release, the ranks' abort) begins: a signal from here on is
    the same stop, not raised inside it, and the watcher knows the raise arrived (a review, 2026-12-07). Whether this
    call began it (the main thread's and the watcher's, one of the two first: :data:`_STOP`)."""
    with _STOP:
        first, _state["stopping"] = not _state["stopping"], 1
    return first


def install(stop: Callable[[str, int], Any] | None = None) -> dict[int, Any]:
    """Route SIGINT and SIGTERM through the request flag (main thread only), with the watcher (module docstring),
    which stops a stuck process by ``stop(message, 130)`` (an entry point's abort: its line, its folder released,
    every rank aborted; default: the line and exit); the previous handlers."""
    _state["installed"] = 1
    if stop is not None:
        _watch["stop"] = stop
    previous = {s: signal.signal(s, _handler) for s in (signal.SIGINT, signal.SIGTERM)}
    if "thread" not in _watch:
        reader, writer = socket.socketpair()
        writer.setblocking(False)  # the C-level handler must never block on it
        _watch["old_fd"] = signal.set_wakeup_fd(writer.fileno(), warn_on_full_buffer=False)
        _watch["sockets"] = (reader, writer)
        _watch["thread"] = threading.Thread(target=_watcher, args=(reader,), name="rods-interrupt", daemon=True)
        _watch["thread"].start()
    return previous


def uninstall(previous: dict[int, Any]) -> None:
    """Back to the ``previous`` handlers (an entry point called in-process, e.g. by a test); the watcher stopped, the
    command's requests and stop forgotten (a next command in the process starts afresh)."""
    _state.update(installed=0, signal=0, since=0.0, raised=0.0, stopping=0)
    for s, h in previous.items():
        signal.signal(s, h)
    if "thread" in _watch:
        signal.set_wakeup_fd(_watch["old_fd"])
        reader, writer = _watch["sockets"]
        writer.close()  # the watcher's read returns empty: it ends
        _watch["thread"].join(timeout=1.0)
        reader.close()
        _watch.clear()


def _watcher(reader: socket.socket) -> None:
    """Wait for SIGINT/SIGTERM's wakeup bytes; where the handler has not run within :data:`STUCK_GRACE`, stop."""
    while True:
        # [s] the signal came after this: a handler run since then was for it, however late the watcher wakes (the
        # main thread may hold the GIL in a long C call right after the handler: a 3D step; a review, 2026-12-07)
        started = time.monotonic()
        try:
            data = reader.recv(64)
        except OSError:
            return
        if not data:
            return
        if not {signal.SIGINT, signal.SIGTERM} & set(data):
            continue
        woke = time.monotonic()  # [s]
        earliest = min(started, woke - HANDLER_LAG)  # [s] the signal arrived after this
        while _waiting(earliest) and time.monotonic() - woke < STUCK_GRACE:
            time.sleep(0.1)
        if _waiting(earliest):  # checked once more after the last sleep: a handler that ran in it stands it down
            _stuck()
        # from the raise, not the wake: a handler held back by a long call raises seconds after the watcher woke
        while _lost(earliest) and time.monotonic() - _state["raised"] < LOST_GRACE:
            time.sleep(0.05)
        if _lost(earliest) and stopping():  # the stop is the watcher's only where the main thread's has not begun
            _stuck(lost=True)


def _lost(earliest: float) -> bool:
    """Whether the handler raised for a signal since ``earliest`` [s] and the entry point's stop has not begun
    (:func:`stopping`), the watcher still wanted: the raise may have been dropped."""
    return _state["raised"] >= earliest and not _state["stopping"] and "thread" in _watch


def _waiting(earliest: float) -> bool:
    """Whether the handler has not run since ``earliest`` [s] and the watcher is still wanted (installed)."""
    return _state["handled"] < earliest and "thread" in _watch


def _stuck(lost: bool = False) -> None:
    """The signal's handler never ran: the main thread does not return from a call; or (``lost``) its raise never
    reached the entry point's stop. Stop: the entry point's ``stop`` (:func:`install`), else one line and exit 130
    (under MPI every rank aborted: the others may wait for this one)."""
    message = (
        f"interrupted, but the stop did not begin within {LOST_GRACE:g} s of the signal (its KeyboardInterrupt lost "
        "in a callback): stopped without writing"
        if lost
        else f"interrupted, but this process did not return from a call within {STUCK_GRACE:g} s (another rank "
        "waiting in a collective this one left, or a long set-up step): stopped without writing"
    )
    if (stop := _watch.get("stop")) is not None:
        try:
            stop(message, EXIT_INTERRUPTED)
        except BaseException:  # noqa: BLE001, S110  (the stop below must happen whatever this one met)
            pass
    print(f"error: {message}", file=sys.stderr, flush=True)
    mpi = sys.modules.get("mpi4py.MPI")
    if mpi is not None and mpi.Is_initialized() and not mpi.Is_finalized() and mpi.COMM_WORLD.size > 1:
        mpi.COMM_WORLD.Abort(EXIT_INTERRUPTED)
    os._exit(EXIT_INTERRUPTED)


def requested() -> int:
    """The signal number asked for a stop on this rank, 0 for none."""
    return _state["signal"]


def reset() -> None:
    """The request honoured (the loop stops): a new signal is a new request, but for a repeat of this one within
    :data:`REPEAT_GRACE` (the loop's stop writes the histories after the check: mpirun's forwarded copy arriving then
    aborted every rank before they were written, a review, 2026-12-07)."""
    _state["signal"] = 0
    # the grace runs on every rank, also on one stopped by another's request whose own copy comes later: from this
    # rank's request where it made one just now, else from the stop (a review, 2026-12-07)
    now = time.monotonic()  # [s]
    if now - _state["since"] >= REPEAT_GRACE:
        _state["since"] = now


@contextmanager
def armed():
    """While a time loop runs: signals are requests, checked collectively by the loop. Where the entry point
    installed the handler, it is installed again here, a fallback: a C library that resets the C-level handler
    while Python's record of it stays (gmsh does, rods.fe.mesh.start_gmsh puts it back) leaves it in place again."""
    if _state["installed"]:
        install()
    _state["armed"] += 1
    try:
        yield
    finally:
        _state["armed"] -= 1
