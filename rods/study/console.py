"""The pipeline's console: rank 0 prints the plans and draws a progress bar, the other ranks stay silent."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

__all__ = ["progress_bar", "rank0"]


def rank0(comm: Any) -> tuple[Callable[..., None], Callable[[int, int, float], None] | None]:
    """(log, progress) for a collective run: rank 0 prints and draws the bar, the other ranks stay silent."""
    if comm.rank != 0:
        return (lambda *a, **k: None), None
    return (lambda text, file=sys.stdout: print(text, file=file, flush=True)), progress_bar


def progress_bar(step: int, total: int, elapsed: float, start: int = 0) -> None:
    """Rank-0 progress: a redrawn bar on a terminal, a line every 10% otherwise (logs stay short). ``start``:
    the checkpoint's step a resumed run went on from (the rate counts the steps run in ``elapsed`` only)."""
    rate = (step - start) / elapsed if elapsed > 0 and step > start else 0.0
    eta = (total - step) / rate if rate > 0 else 0.0
    tty = sys.stderr.isatty()
    if not tty and step != total and (step * 10) // max(total, 1) == ((step - 500) * 10) // max(total, 1):
        return
    done = int(30 * step / max(total, 1))
    line = f"[{'#' * done}{'.' * (30 - done)}] {step}/{total} steps  {rate:,.0f} steps/s  eta {eta:5.1f} s"
    sys.stderr.write(("\r" + line + " ") if tty else (line + "\n"))
    _bar["open"] = tty and step != total
    if tty and step == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


_bar = {"open": False}  # a bar redrawn on the terminal's last line, without its newline yet


def end_bar() -> None:
    """End a bar left open on the terminal (a run stopped mid-way): the next line starts on its own."""
    if _bar["open"]:
        sys.stderr.write("\n")
        _bar["open"] = False
