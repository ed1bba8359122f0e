"""Checkpoints of an explicit run: restart a killed run from its last checkpoint, same histories.

Layout in the run's output folder:
* ``checkpoint-<step>-r<rank>.npz`` — each rank's owned state (u, v_{n+1/2}, accumulators) and the
  recorded histories so far;
* ``checkpoint.json`` — written by rank 0 after every rank has written its file (a barrier between):
  the step, the time, the rank count. Each file is written to a temporary name and renamed, and the
  previous checkpoint's files are removed only after the new ``checkpoint.json`` is in place, so a
  kill at any moment leaves one complete checkpoint.

A restart needs the same scene and the same rank count (the owned arrays follow the partition).
:class:`Checkpoints` writes them as an observer of the loop (:mod:`rods.fe.observers`) from the
``state(step)`` of its parts (the stepper, the recorder); :func:`load` returns the merged dict that
each part's ``restore`` reads back.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np
from mpi4py import MPI

from rods.io import atomic_write_text

__all__ = ["Checkpoints", "load", "save"]

MANIFEST = "checkpoint.json"


def _name(step: int, rank: int) -> str:
    return f"checkpoint-{step}-r{rank}.npz"


def save(out: Path, step: int, t: float, state: dict[str, Any], comm: MPI.Comm, scene_key: str) -> None:
    """Write this rank's ``state`` (numpy arrays and scalars) for ``step``; collective."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    tmp = out / f".{_name(step, comm.rank)}.tmp"
    with open(tmp, "wb") as f:
        np.savez(f, **{k: np.asarray(v) for k, v in state.items()})
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, out / _name(step, comm.rank))
    comm.Barrier()
    if comm.rank == 0:
        old = json.loads((out / MANIFEST).read_text()) if (out / MANIFEST).exists() else None
        atomic_write_text(out / MANIFEST, json.dumps({"step": step, "time": t, "ranks": comm.size, "scene": scene_key}))
        if old and old["step"] != step:
            for r in range(old["ranks"]):
                (out / _name(old["step"], r)).unlink(missing_ok=True)
    comm.Barrier()


def load(out: Path, comm: MPI.Comm, scene_key: str) -> dict[str, np.ndarray] | None:
    """This rank's state of the last complete checkpoint in ``out``; None if there is none."""
    m = Path(out) / MANIFEST
    if not m.exists():
        return None
    meta = json.loads(m.read_text())
    if meta["ranks"] != comm.size:
        raise ValueError(
            f"checkpoint in {out} was written by {meta['ranks']} ranks; restart with mpirun -n {meta['ranks']}"
        )
    if meta["scene"] != scene_key:
        raise ValueError(f"checkpoint in {out} belongs to another scene or settings; remove it or use another --out")
    with np.load(Path(out) / _name(meta["step"], comm.rank)) as z:
        return {k: z[k] for k in z.files}


class Checkpoints:
    """Observer: saves the parts' state every ``every`` steps after ``first`` and before ``last`` into ``out``."""

    def __init__(self, out: Path, every: int, parts, comm: MPI.Comm, key: str, first: int, last: int):
        self.out, self.every, self.parts, self.comm, self.key = Path(out), every, parts, comm, key
        self.first, self.last = first, last

    def after_step(self, step: int, t: float, state) -> None:  # noqa: ARG002
        if step % self.every == 0 and self.first < step < self.last:
            merged: dict[str, Any] = {}
            for p in self.parts:
                merged.update(p.state(step))
            save(self.out, step, t, merged, self.comm, self.key)
