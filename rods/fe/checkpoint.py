"""Checkpoints of an explicit run: restart a killed run from its last checkpoint, same histories.

Layout in the run's output folder:
* ``checkpoint-<step>-r<rank>.npz`` — each rank's owned state (u, v_{n+1/2}, accumulators), and the name, bytes
  and CRC-32 of its log;
* ``checkpoint-log-<first>-r<rank>.bin`` — the state arrays that only grow (:class:`Appended`: the recorded
  histories, the per-step force), each checkpoint appending their new entries (``.npy`` records, one fsync): a
  checkpoint writes what is new since the last (each rewrote the whole before: an audit's 5917 checkpoints wrote
  8.55 GB for a 5 MB run, 23.9 s against a 2.2 s loop); a restart reads the bytes its ``.npz`` counts, checks their
  CRC, and starts a log of its own (named by its first checkpoint's step), the old one removed with its checkpoint;
* ``checkpoint.json`` — written by rank 0 after every rank has written its file (a barrier between):
  the step, the time, the rank count. Each file is written to a temporary name and renamed, and the
  previous checkpoint's files are removed only after the new ``checkpoint.json`` is in place, so a
  kill at any moment leaves one complete checkpoint.

A restart needs the same scene and the same rank count (the owned arrays follow the partition; the
state is stored in each rank's own numbering, not a global one). :func:`precheck` tells both from
``checkpoint.json`` before the model is set up (the manifest carries the rank count and
:func:`scene_hash`); :func:`load` names a damaged file and the remedy (:class:`CheckpointError`, exit 2).
:class:`Checkpoints` writes them as an observer of the loop (:mod:`rods.fe.observers`) from the
``state(step)`` of its parts (the stepper, the recorder); :func:`load` returns the merged dict that
each part's ``restore`` reads back.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import zipfile
import zlib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from mpi4py import MPI

from rods.io import atomic_write_text
from rods.preflight import InputError, one_line, short
from rods.scene import RESULT_NEUTRAL, first_difference

__all__ = ["Appended", "CheckpointError", "Checkpoints", "load", "precheck", "save", "scene_hash", "stride"]

MANIFEST = "checkpoint.json"


def stride(interval: float, dt: float) -> int:
    """Steps between checkpoints at ``fe.checkpoint_interval`` = ``interval`` [s] and step ``dt`` [s]: the nearest
    whole number, every step for an interval below Δt."""
    return max(1, int(round(interval / dt)))


def _name(step: int, rank: int) -> str:
    return f"checkpoint-{step}-r{rank}.npz"


def _log_name(first: int, rank: int) -> str:
    return f"checkpoint-log-{first}-r{rank}.bin"


LOG_GLOB = "checkpoint-log-*.bin"
# a checkpoint's files by pattern, what :func:`discard` removes besides the manifest's own: the logs, an older step's
# states (a kill after the manifest's rewrite, before their removal), the temporary names of a save cut short (a
# fuzz, 2026-12-07: 21 of 55 killed-and-resumed runs kept such files after they finished)
ORPHANS = (LOG_GLOB, "checkpoint-*-r*.npz", ".checkpoint-*-r*.npz.tmp", f".{MANIFEST}.*.tmp")


class Appended:
    """A 1D float64 state array whose entries, once there, never change between checkpoints and whose length only
    grows (a history's column, the per-step force): :func:`save` appends its new entries to the rank's log."""

    def __init__(self, values: np.ndarray):
        self.values = np.ascontiguousarray(values, dtype=np.float64)
        if self.values.ndim != 1:
            raise ValueError(f"an Appended array is 1D, not of shape {self.values.shape}")


@dataclass(frozen=True)
class Tail:
    """A rank's log after a checkpoint: its file, its bytes [B] and their CRC-32, each Appended array's length."""

    log: str
    size: int
    crc: int
    lengths: dict[str, int]


def _log_lost(out: Path, tail: Tail | None) -> bool:
    """Whether this rank's log is gone or cut under the run (another run's discard): its next save starts anew."""
    return tail is not None and (not (out / tail.log).is_file() or (out / tail.log).stat().st_size < tail.size)


def _append(out: Path, step: int, rank: int, arrays: dict[str, np.ndarray], tail: Tail | None) -> Tail:
    """Append to the rank's log, after ``tail`` (the previous checkpoint's; None: a new log, named by ``step``), one
    record of each array's entries past its length there: two .npy arrays, the counts per key (in ``arrays``' order)
    and the entries one after another as float64 (a record per key cost ~256 B of headers a checkpoint); one fsync,
    none where nothing is new."""
    tail = tail or Tail(_log_name(step, rank), 0, 0, {})
    new = [a[tail.lengths.get(k, 0) :] for k, a in arrays.items()]  # Appended: 1D float64
    lengths = {k: len(a) for k, a in arrays.items()}
    if tail.size and not any(len(a) for a in new):
        return Tail(tail.log, tail.size, tail.crc, lengths)
    buf = io.BytesIO()
    np.lib.format.write_array(buf, np.array([len(a) for a in new], dtype=np.int64))
    np.lib.format.write_array(buf, np.concatenate(new))
    data = buf.getvalue()
    path = out / tail.log
    with open(path, "r+b" if path.exists() and tail.size else "w+b") as f:
        f.seek(tail.size)  # past the entries the previous checkpoint counts: a kill's partial records are cut
        f.write(data)
        f.truncate()
        f.flush()
        os.fsync(f.fileno())
    return Tail(tail.log, tail.size + len(data), zlib.crc32(data, tail.crc), lengths)


def _read_log(out: Path, state: dict[str, np.ndarray]) -> None:
    """Replace a loaded ``state``'s log entries (``@log``, ``@log_bytes``, ``@log_crc``, ``@log_keys``) by its
    Appended arrays, read from the first ``@log_bytes`` of the log (a ValueError names a log that is short or whose
    CRC differs)."""
    if "@log" not in state:
        return
    path, size, crc = Path(out) / str(state.pop("@log")), int(state.pop("@log_bytes")), int(state.pop("@log_crc"))
    keys = [str(k) for k in state.pop("@log_keys")]
    with open(path, "rb") as f:
        data = f.read(size)
    if len(data) != size:
        raise ValueError(f"{path}: {len(data)} bytes read where the checkpoint wrote {size}")
    if zlib.crc32(data) != crc:
        raise ValueError(f"{path}: its bytes' CRC-32 differs from the checkpoint's")
    blocks: dict[str, list[np.ndarray]] = {k: [] for k in keys}
    buf = io.BytesIO(data)
    while buf.tell() < size:
        counts = np.lib.format.read_array(buf, allow_pickle=False)
        values = np.lib.format.read_array(buf, allow_pickle=False)
        for k, part in zip(keys, np.split(values, np.cumsum(counts)[:-1]), strict=True):
            blocks[k].append(part)
    state.update({k: np.concatenate(b) if b else np.zeros(0) for k, b in blocks.items()})


class CheckpointError(InputError):
    """A checkpoint that cannot be resumed: damaged, from another rank count or another scene, or absent."""


def _remedy(out: Path) -> str:
    return f"remove {Path(out) / 'checkpoint*'} to start afresh, or give another --out"


def state_values(scene: Any) -> dict[str, Any]:
    """The scene's validated values (Scene.as_dict, JSON's types) less rods.scene.RESULT_NEUTRAL: what a
    checkpoint's state depends on (a restart that turned periodic checkpoints on, as the README offers, was refused
    as "another scene": a fuzz, 2026-12-07)."""
    return scene.result_values()


def scene_hash(scene: Any) -> str:
    """The scene's :func:`state_values`, hashed: tells a checkpoint's scene before any set-up."""
    return hashlib.sha256(json.dumps(state_values(scene), sort_keys=True).encode()).hexdigest()[:16]


def run_key(scene: Any, dt: float, ranks: int, dofs: int, fmt: int, inputs: list[Any]) -> str:
    """Identifies scene + step ``dt`` [s] + partition (``ranks``, ``dofs``) + state format ``fmt`` (+ the observers'
    ``inputs``, a submodel's cut record): a checkpoint is only resumed by the same run."""
    text = json.dumps([state_values(scene), dt, ranks, dofs, fmt, *inputs], sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _manifest(out: Path) -> dict[str, Any] | None:
    """``checkpoint.json`` of ``out`` (None: there is none); a damaged one raises CheckpointError."""
    m = Path(out) / MANIFEST
    if not m.exists():
        return None
    try:
        meta = json.loads(m.read_text())
        step, ranks, _ = int(meta["step"]), int(meta["ranks"]), str(meta["scene"])
        if step < 0 or ranks < 1:
            raise ValueError(f"step {step}, ranks {ranks}: a step >= 0 by ranks >= 1")
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise CheckpointError("checkpoint file", str(m), f"damaged ({one_line(str(e))})", _remedy(out)) from None
    return meta


def precheck(out: Path, ranks: int, scene: Any | None) -> dict[str, Any]:
    """Before the set-up: ``out`` holds a checkpoint written by ``ranks`` ranks for ``scene`` (by
    :func:`scene_hash`; None: not checked here, :func:`load` checks the run's key) whose every rank's file is there
    and a readable archive (:func:`load` reads the arrays and checks their checksums); its manifest, else
    CheckpointError naming the remedy. Every rank checks the same files, so all refuse together."""
    meta = _manifest(out)
    if meta is None:
        raise CheckpointError(
            "--restart",
            str(out),
            f"no {MANIFEST} in this folder",
            "run without --restart (a Ctrl-C/SIGTERM stop leaves a checkpoint; fe.checkpoint_interval > 0 for a kill)",
        )
    if int(meta["ranks"]) != ranks:
        raise CheckpointError(
            "--restart", str(out), f"the checkpoint was written by {_ranks(meta['ranks'])}, this run has {ranks}",
            f"restart with mpirun -n {meta['ranks']}, or remove {Path(out) / 'checkpoint*'} to run it afresh on "
            f"{_ranks(ranks)}",
        )  # fmt: skip
    if scene is not None and not meta.get("scene_hash"):
        why = "the checkpoint does not name its scene (written by an older rods), so it cannot be matched to this one"
        raise CheckpointError("--restart", str(out), why, _remedy(out))
    if scene is not None and meta["scene_hash"] != scene_hash(scene):
        why = "the checkpoint belongs to another scene or settings"
        # none named where the manifest has no values (a checkpoint written before they were kept)
        values = meta.get("scene_values")
        found = first_difference(scene.as_dict(), values, RESULT_NEUTRAL) if values else None
        remedy = _remedy(out)
        if found:
            key, here, there = found
            why += f" ({key} = {short(there)} there, {short(here)} in this run)"
            remedy = f"give the stopped run's settings ({key} = {short(there)}), or {remedy}"  # the likelier slip
        raise CheckpointError("--restart", str(out), why, remedy)
    for r in range(int(meta["ranks"])):
        f = Path(out) / _name(int(meta["step"]), r)
        if not zipfile.is_zipfile(f):  # absent, a folder, truncated or not an archive
            raise CheckpointError("checkpoint file", str(f), "missing or damaged (not a readable .npz)", _remedy(out))
    return meta


def _ranks(n: Any) -> str:
    return "1 rank" if int(n) == 1 else f"{n} ranks"


def discard(out: Path, comm: MPI.Comm) -> None:
    """Remove an earlier run's checkpoint from ``out`` (collective): a run that starts afresh there would leave
    it behind, and a later --restart of this run (a study's, whose cut record the fresh run rewrote) would stop
    on it as "another scene or settings". The manifest goes first: a kill in between leaves no checkpoint."""
    if comm.rank == 0:
        try:
            old = _manifest(out)
        except CheckpointError:
            old = None
        (Path(out) / MANIFEST).unlink(missing_ok=True)
        if old:
            for r in range(int(old["ranks"])):
                (Path(out) / _name(old["step"], r)).unlink(missing_ok=True)
        for pattern in ORPHANS:  # what a kill between two of a save's steps leaves (each kill left its own)
            for f in Path(out).glob(pattern):
                f.unlink(missing_ok=True)
    comm.Barrier()


def save(
    out: Path,
    step: int,
    t: float,
    state: dict[str, Any],
    comm: MPI.Comm,
    scene_key: str,
    scene_hash: str = "",
    scene_values: Mapping[str, Any] | None = None,
    tail: Tail | None = None,
) -> Tail | None:
    """Write this rank's ``state`` (numpy arrays and scalars, :class:`Appended` arrays) for ``step``; collective. The
    manifest keeps the scene's values (``scene_values``, Scene.as_dict) so a restart of another scene names the key
    that differs. ``tail``: the rank's log after the previous checkpoint of this run (its Appended arrays up to there
    are in it; None: a new log); returns the log after this one, for the next."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    plain = {k: np.asarray(v) for k, v in state.items() if not isinstance(v, Appended)}
    arrays = {k: v.values for k, v in state.items() if isinstance(v, Appended)}
    if comm.allreduce(_log_lost(out, tail), op=MPI.LOR):  # every rank anew, named alike (rank 0 keeps that name's)
        tail = None
    if arrays:
        tail = _append(out, step, comm.rank, arrays, tail)
        plain.update({"@log": tail.log, "@log_bytes": tail.size, "@log_crc": tail.crc, "@log_keys": list(arrays)})
    tmp = out / f".{_name(step, comm.rank)}.tmp"
    with open(tmp, "wb") as f:
        np.savez(f, **plain)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, out / _name(step, comm.rank))
    comm.Barrier()
    if comm.rank == 0:
        try:
            old = _manifest(out)
        except CheckpointError:
            old = None  # a damaged manifest is replaced by this complete checkpoint
        meta = {"step": step, "time": t, "ranks": comm.size, "scene": scene_key, "scene_hash": scene_hash}
        if scene_values is not None:
            meta["scene_values"] = scene_values
        atomic_write_text(out / MANIFEST, json.dumps(meta))
        if old and old["step"] != step:
            for r in range(old["ranks"]):
                (out / _name(old["step"], r)).unlink(missing_ok=True)
        if tail is not None:  # an earlier run's logs (a restart's first checkpoint starts its own)
            mine = tail.log.rsplit("-r", 1)[0]
            for f in out.glob(LOG_GLOB):
                if f.name.rsplit("-r", 1)[0] != mine:
                    f.unlink(missing_ok=True)
    comm.Barrier()
    return tail


def load(out: Path, comm: MPI.Comm, scene_key: str) -> dict[str, np.ndarray] | None:
    """This rank's state of the last complete checkpoint in ``out``; None if there is none. A checkpoint of
    another rank count or scene, or a damaged file, raises :class:`CheckpointError` naming it."""
    meta = _manifest(out)
    if meta is None:
        return None
    if int(meta["ranks"]) != comm.size:
        why = f"written by {_ranks(meta['ranks'])}, this run has {comm.size}"
        remedy = f"restart with mpirun -n {meta['ranks']}"
        raise CheckpointError("checkpoint file", str(Path(out) / MANIFEST), why, remedy)
    if meta["scene"] != scene_key:  # the scene's values passed precheck: the run key's other parts differ
        why = (
            "written by another run (its scene, step, partition or state format differ from this run's: another "
            "fe.dt, rods or DOLFINx version)"
        )
        raise CheckpointError("checkpoint file", str(Path(out) / MANIFEST), why, _remedy(out))
    f = Path(out) / _name(meta["step"], comm.rank)
    state, problem = None, ""
    try:
        with np.load(f, allow_pickle=False) as z:
            state = {k: np.array(z[k]) for k in z.files}  # read every array now: a bad CRC shows here
        _read_log(Path(out), state)
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, zlib.error) as e:
        problem = f"{f}\0damaged ({one_line(str(e))})"
    problems = [p for p in comm.allgather(problem) if p]  # every rank refuses together: none waits alone
    if problems:
        name, why = problems[0].split("\0")
        raise CheckpointError("checkpoint file", name, why, _remedy(out))
    return state


class Checkpoints:
    """Observer: saves the parts' state every ``every`` steps after ``first`` and before ``last`` into ``out``."""

    def __init__(
        self,
        out: Path,
        every: int,
        parts,
        comm: MPI.Comm,
        key: str,
        first: int,
        last: int,
        scene_hash: str = "",
        scene_values: Mapping[str, Any] | None = None,
    ):
        self.out, self.every, self.parts, self.comm, self.key = Path(out), every, parts, comm, key
        self.first, self.last, self.scene_hash, self.scene_values = first, last, scene_hash, scene_values
        self.tail: Tail | None = None  # this rank's log after the last save (a restart starts a new log)

    def after_step(self, step: int, t: float, state) -> None:  # noqa: ARG002
        if step % self.every == 0 and self.first < step < self.last:
            self.save_now(step, t)

    def save_now(self, step: int, t: float) -> None:
        """Save the parts' state at ``step`` (collective): every ``every`` steps, and when a run is interrupted."""
        merged: dict[str, Any] = {}
        for p in self.parts:
            merged.update(p.state(step))
        self.tail = save(self.out, step, t, merged, self.comm, self.key, self.scene_hash, self.scene_values, self.tail)
