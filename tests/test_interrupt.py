"""rods.interrupt: a signal during the time loop is a request the ranks honour together; a repeat within the grace
is the same request, a later one stops at once; a rank that stops alone skips the collective finishes."""

from __future__ import annotations

import signal

import numpy as np
import pytest

from rods import interrupt


@pytest.fixture
def armed(monkeypatch):
    """The handler's state inside a time loop, restored after the test."""
    monkeypatch.setattr(
        interrupt, "_state", {"armed": 1, "signal": 0, "installed": 0, "since": 0.0, "raised": 0.0, "stopping": 0}
    )
    return interrupt._state


def test_a_repeated_signal_within_the_grace_is_the_same_request(armed, monkeypatch):
    """SLURM's SIGTERM reaches each rank directly and again through mpirun, milliseconds apart: the repeat raised
    KeyboardInterrupt on that rank alone (no checkpoint; a hang where the others waited in a collective)."""
    clock = iter([100.0, 100.002, 100.0 + interrupt.REPEAT_GRACE + 0.1])
    monkeypatch.setattr(interrupt.time, "monotonic", lambda: next(clock))
    interrupt._handler(signal.SIGTERM, None)
    assert interrupt.requested() == signal.SIGTERM
    interrupt._handler(signal.SIGTERM, None)  # 2 ms later: the same request
    assert interrupt.requested() == signal.SIGTERM
    with pytest.raises(KeyboardInterrupt):  # a Ctrl-C pressed again later: at once
        interrupt._handler(signal.SIGINT, None)


def test_outside_a_loop_a_signal_stops_at_once(armed):
    armed["armed"] = 0
    with pytest.raises(KeyboardInterrupt):
        interrupt._handler(signal.SIGINT, None)


class _Stepper:
    dt = 1.0

    def step(self, keep):  # noqa: ARG002
        pass


class _Observer:
    def __init__(self, collective: bool, stop_at: int | None = None):
        self.collective, self.stop_at, self.finished = collective, stop_at, False

    def after_step(self, step, t, state):  # noqa: ARG002
        if step == self.stop_at:
            raise KeyboardInterrupt

    def finish(self):
        self.finished = True

    def finish_alone(self):  # its own part of a collective finish (the field series' XML on rank 0)
        self.finished_alone = True


def test_a_rank_stopping_alone_skips_the_collective_finishes():
    """A KeyboardInterrupt (or any error) on one rank: its collective finishes (the ADIOS2 writer's close) would wait
    for ranks that are mid-step; its own finishes (disarming the signals) still run. A run to its end finishes all."""
    from rods.fe.observers import march

    shared, own = _Observer(collective=True), _Observer(collective=False, stop_at=3)
    with pytest.raises(KeyboardInterrupt):
        march(_Stepper(), range(10), [shared, own], np.zeros(10, bool))
    assert own.finished and not shared.finished and shared.finished_alone  # the XML of the frames written, still
    shared, own = _Observer(collective=True), _Observer(collective=False)
    assert march(_Stepper(), range(10), [shared, own], np.zeros(10, bool)) is None
    assert own.finished and shared.finished


def test_a_repeat_after_the_loop_acted_on_the_request_is_still_the_same(armed, monkeypatch):
    """The ranks agree to stop (reset) and the loop disarms before it writes the histories: mpirun's forwarded copy of
    the SIGTERM arriving then raised on that rank and aborted every rank before the histories were written."""
    clock = iter([100.0, 100.005, 100.01, 100.0 + interrupt.REPEAT_GRACE + 0.1])
    monkeypatch.setattr(interrupt.time, "monotonic", lambda: next(clock))
    interrupt._handler(signal.SIGTERM, None)
    interrupt.reset()  # the collective check honoured it
    armed["armed"] = 0  # the loop's finish disarmed
    interrupt._handler(signal.SIGTERM, None)  # 10 ms later: ignored, the stop goes on
    with pytest.raises(KeyboardInterrupt):  # a signal later than the grace, outside a loop: at once
        interrupt._handler(signal.SIGINT, None)


def test_outside_a_loop_a_repeat_within_the_grace_raises_no_second_time(armed, monkeypatch):
    """A SLURM SIGTERM in the set-up: the rank's own copy raises (the entry point stops, exit 130); mpirun's
    forwarded copy milliseconds later raised again on its way to the stop or inside it (a traceback, exit 2, a rank
    gone before its line: a review, 2026-12-07). It is the same request; once the stop has begun any signal is."""
    armed["armed"] = 0
    monkeypatch.setattr(
        interrupt.time, "monotonic", iter([100.0, 100.003, 100.0 + interrupt.REPEAT_GRACE + 1]).__next__
    )
    with pytest.raises(KeyboardInterrupt):
        interrupt._handler(signal.SIGTERM, None)
    interrupt._handler(signal.SIGTERM, None)  # the forwarded copy: no second raise
    interrupt.stopping()  # the entry point's stop (_cli._abort) has begun
    interrupt._handler(signal.SIGINT, None)  # later than the grace: still the stop's, no raise inside it
    assert interrupt.requested() == signal.SIGTERM


def _watch_one_signal(monkeypatch, act, after=None) -> list[bool]:
    """The watcher on a socket pair with short graces; ``act(state)`` plays the handler's part before the signal's
    wakeup byte is sent, ``after(state)`` after it (a handler held back by a long call); returns the ``lost`` flag of
    each stop the watcher made."""
    import socket
    import threading
    import time

    stops = []
    state = {"armed": 0, "signal": 0, "installed": 1, "since": 0.0, "handled": 0.0, "raised": 0.0, "stopping": 0}
    monkeypatch.setattr(interrupt, "_state", state)
    monkeypatch.setattr(interrupt, "_watch", {"thread": object()})
    monkeypatch.setattr(interrupt, "STUCK_GRACE", 1.0)
    monkeypatch.setattr(interrupt, "LOST_GRACE", 0.3)
    monkeypatch.setattr(interrupt, "_stuck", lambda lost=False: stops.append(lost))
    reader, writer = socket.socketpair()
    watcher = threading.Thread(target=interrupt._watcher, args=(reader,), daemon=True)
    watcher.start()
    time.sleep(0.05)
    act(state)
    writer.send(bytes([signal.SIGTERM]))
    if after is not None:
        after(state)
    time.sleep(0.6)
    writer.close()
    watcher.join(timeout=3.0)
    reader.close()
    return stops


def test_the_watcher_stops_a_process_whose_raise_was_lost(monkeypatch):
    """The handler raised, but Python dropped the KeyboardInterrupt (it landed in a weakref callback: "Exception
    ignored in", about one SIGTERM in 30 at the set-up's start): the entry point's stop never began and the rank went
    on. The watcher stops it after LOST_GRACE; where the stop began (interrupt.stopping), it stands down."""
    import time

    def lost(state):
        state["handled"] = state["raised"] = state["since"] = time.monotonic()

    def delivered(state):
        lost(state)
        interrupt.stopping()

    assert _watch_one_signal(monkeypatch, lost) == [True]
    assert _watch_one_signal(monkeypatch, delivered) == []


def test_the_lost_grace_runs_from_the_raise_not_from_the_watchers_wake(monkeypatch):
    """The signal came while the main thread was in a long call (an MPI wait, a 3D mesh's generation): the handler
    ran and raised when it returned, later than LOST_GRACE after the watcher woke, and its stop began 0.1 s after the
    raise. The watcher measured the grace from its wake and stopped that healthy stop at once, racing it (two lines,
    two releases of the folder: a review, 2026-12-07)."""
    import time

    def late(state):
        time.sleep(0.5)  # the long call: past LOST_GRACE (0.3 s) after the wake, within STUCK_GRACE (1 s)
        state["handled"] = state["raised"] = state["since"] = time.monotonic()
        time.sleep(0.1)
        interrupt.stopping()  # the main thread's stop

    assert _watch_one_signal(monkeypatch, lambda state: None, late) == []


def test_the_stop_is_begun_once(monkeypatch):
    """The main thread's stop and the watcher's: whichever comes first begins it, the other learns it came second."""
    monkeypatch.setattr(interrupt, "_state", {"stopping": 0})
    assert interrupt.stopping() is True
    assert interrupt.stopping() is False


def test_a_rank_stopped_by_another_takes_its_own_late_copy_as_the_same_request(armed, monkeypatch):
    """Rank 0 got the signal, the ranks agreed to stop (reset on every rank): rank 1's own copy arriving after that
    raised (it had no request of its own, so no grace) and aborted every rank before the histories were written."""
    armed["since"] = 40.0  # an earlier stop's, long ago: no grace of its own now
    clock = iter([100.0, 100.02])
    monkeypatch.setattr(interrupt.time, "monotonic", lambda: next(clock))
    interrupt.reset()  # rank 1: the loop's collective check found rank 0's request
    armed["armed"] = 0  # the loop disarmed, the histories being written
    interrupt._handler(signal.SIGTERM, None)  # its own copy, 20 ms later: no raise
    assert interrupt.requested() == 0


def test_the_watcher_stands_down_for_a_handler_that_ran_long_before_it_woke(monkeypatch):
    """The handler ran at once, then the main thread held the GIL in a long C call (a large 3D step) before the
    watcher could wake: the watcher took the handler for an earlier signal's and stopped a healthy run after
    STUCK_GRACE (a review, 2026-12-07). A handler run since the watcher began waiting counts."""
    import socket
    import threading
    import time

    stuck = []
    monkeypatch.setattr(
        interrupt,
        "_state",
        {"armed": 1, "signal": 0, "installed": 1, "since": 0.0, "handled": 0.0, "raised": 0.0, "stopping": 0},
    )
    monkeypatch.setattr(interrupt, "_watch", {"thread": object()})
    monkeypatch.setattr(interrupt, "HANDLER_LAG", 0.05)
    monkeypatch.setattr(interrupt, "STUCK_GRACE", 0.3)
    monkeypatch.setattr(interrupt, "_stuck", lambda: stuck.append(1))
    reader, writer = socket.socketpair()
    watcher = threading.Thread(target=interrupt._watcher, args=(reader,), daemon=True)
    watcher.start()
    time.sleep(0.1)  # the watcher waits
    interrupt._state["handled"] = time.monotonic()  # the handler ran ...
    time.sleep(0.3)  # ... and the watcher woke only after a long hold
    writer.send(bytes([signal.SIGTERM]))
    time.sleep(0.6)  # past STUCK_GRACE after the wake
    writer.close()
    watcher.join(timeout=2.0)
    reader.close()
    assert not stuck
