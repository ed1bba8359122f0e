"""Result files: ``summary.json``, ``history.csv`` and the stages' data files (JSON), written atomically on rank 0;
a run as a later stage reads it (:class:`Run`).

Atomic means write to a temporary file in the same folder, then ``os.replace``: a killed run leaves
either the old file or the new one, never half of one. The file gets the mode an ``open()`` would give
(0666 less the process umask: 0644 under the usual 022), not ``mkstemp``'s private 0600, so that a group or a
ParaView server under another account can read the results.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "CONTACT_KEYS",
    "SUMMARY_KEYS",
    "WAVE_KEYS",
    "Run",
    "atomic_write_text",
    "cut_identity",
    "dumps",
    "file_mode",
    "offscreen_pyvista",
    "provenance",
    "read_data",
    "read_history",
    "write_data",
    "write_history",
    "write_summary",
]

# The summary.json contract (foundation issue): every model writes these keys, SI units; the contact's and the
# wave response's are the keys a study takes from its most refined stage (rods.plan.most_refined)
CONTACT_KEYS = ("peak_contact_force", "contact_radius", "contact_area", "peak_contact_pressure", "contact_duration")
WAVE_KEYS = ("midpoint_peak_speed", "midpoint_peak_strain")
SUMMARY_KEYS = ("model", "scene", "impact_speed", *CONTACT_KEYS, *WAVE_KEYS, "wall_time")


def file_mode() -> int:
    """The mode ``open()`` gives a new file: 0o666 less the process umask (read without changing it where
    /proc tells it; else set and restored at once)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return 0o666 & ~int(line.split()[1], 8)
    except OSError:
        pass
    umask = os.umask(0o022)
    os.umask(umask)
    return 0o666 & ~umask


def atomic_write_text(path: str | Path, text: str | Iterable[str]) -> None:
    """Write ``text`` (a string, or its pieces in turn: only one in memory at a time) to ``path`` through a temporary
    file and an atomic rename (mode: :func:`file_mode`)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, file_mode())  # mkstemp creates 0600
        with os.fdopen(fd, "w", encoding="utf-8") as f:  # µ, σ, ✗: not the locale's encoding
            for piece in [text] if isinstance(text, str) else text:
                f.write(piece)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _jsonable(x: Any) -> Any:
    """Plain JSON types; a non-finite float becomes null (JSON has no inf or nan)."""
    if isinstance(x, Mapping):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, np.generic):
        return _jsonable(x.item())
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def write_summary(path: str | Path, summary: Mapping[str, Any]) -> None:
    """Write ``summary.json``, strict JSON: a non-finite number is null (the kinematic contact's switching limit
    ``dt_contact_switching``, inf, was the string "inf" where readers expect a number; the scene's own inf, a flat
    tip, stays "inf" in ``scene_values``, as a scene file writes it); refuses a summary that misses a contract key."""
    missing = [k for k in SUMMARY_KEYS if k not in summary]
    if missing:
        raise KeyError(f"summary lacks contract keys {missing}")
    summary = {**summary, "provenance": summary.get("provenance") or provenance()}
    atomic_write_text(path, json.dumps(_jsonable(summary), indent=2, allow_nan=False) + "\n")


def provenance() -> dict[str, Any]:
    """What produced a result, for its summary.json: the rods version and, in a git checkout, the commit it was at;
    Python's and the numerical libraries' versions (DOLFINx and PETSc where the run loaded them). The commit is read
    from the repository's files, not by running git: a fork under MPI upsets some interconnects (and a work tree's
    uncommitted changes are not seen)."""
    import importlib.metadata
    import platform
    import sys

    out: dict[str, Any] = {"python": platform.python_version()}
    for dist in ("rods", "numpy", "scipy"):
        try:
            out[dist] = importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            out[dist] = None
    for module in ("dolfinx", "petsc4py"):
        if module in sys.modules:
            out[module] = getattr(sys.modules[module], "__version__", None)
    if (commit := _git_commit(Path(__file__).resolve().parents[1] / ".git")) is not None:
        out["git_commit"] = commit
    return out


def _git_commit(git: Path) -> str | None:
    """The commit a checkout's HEAD names (a detached hash, a branch's loose ref or its packed-refs line); None where
    it cannot be read (no checkout, a worktree's .git file)."""
    try:
        head = (git / "HEAD").read_text().strip()
        if not head.startswith("ref: "):
            return head or None
        ref = head[5:]
        if (git / ref).is_file():
            return (git / ref).read_text().strip() or None
        for line in (git / "packed-refs").read_text().splitlines():
            if line.endswith(" " + ref):
                return line.split()[0]
    except OSError:
        return None
    return None


def dumps(data: Mapping[str, Any]) -> str:
    """A stage's data as strict JSON text: NaN and inf written as null (readers see "no value", never a string where
    a number belongs), numpy scalars and arrays as numbers and lists."""
    return json.dumps(_jsonable(data), indent=1, ensure_ascii=False, allow_nan=False) + "\n"


def write_data(path: str | Path, data: Mapping[str, Any]) -> None:
    """Write a stage's data file (e.g. ``table3.json``, ``fig4.json``) atomically (:func:`dumps`)."""
    atomic_write_text(path, dumps(data))


def _nan(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: _nan(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_nan(v) for v in x]
    return math.nan if x is None else x


def read_data(path: str | Path) -> dict[str, Any]:
    """A stage's data file; every null reads back as NaN (no stage writes null for anything but a number)."""
    return _nan(json.loads(Path(path).read_text(encoding="utf-8")))


@dataclass(frozen=True)
class Run:
    """A model run as a later stage reads it: its label, history.csv columns and summary.json."""

    label: str
    history: dict[str, np.ndarray]
    summary: dict[str, Any]


HISTORY_CHUNK_ROWS = 20_000  # rows of a history CSV formatted at a time [-]


def write_history(
    path: str | Path, columns: Mapping[str, Sequence[float] | np.ndarray], units: Mapping[str, str]
) -> None:
    """Write a CSV of equally long columns; the header carries the units, ``name [unit]``."""
    names = list(columns)
    data = np.column_stack([np.asarray(columns[n], dtype=float) for n in names])
    header = ",".join(f"{n} [{units.get(n, '-')}]" for n in names)
    row = ",".join(["%.10e"] * len(names))  # one format per row: half the time of one f-string per value

    def pieces() -> Iterable[str]:  # a chunk's text at a time (the whole file's, as one string, took ~4x its size)
        yield header + "\n"
        for i in range(0, len(data), HISTORY_CHUNK_ROWS):
            yield "".join(map(f"{row}\n".__mod__, map(tuple, data[i : i + HISTORY_CHUNK_ROWS].tolist())))

    atomic_write_text(path, pieces())


def read_history(path: str | Path) -> dict[str, np.ndarray]:
    """Read a history CSV back into ``{name: array}`` (units stripped from the header)."""
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {h.split(" [")[0]: data[:, i] for i, h in enumerate(header)}


def bar_format(largest: float) -> str:
    """A colour bar's label format for values up to ``largest``: three significant digits at the top (MPa of a
    steel patch, fractions of one of a soft scene's), no more decimals than that."""
    digits = 0 if largest <= 0 else max(0, 2 - math.floor(math.log10(largest)))
    return f"%.{digits}f"


def offscreen_pyvista() -> Any:
    """pyvista for off-screen pictures (each Plotter is made with ``off_screen=True``): the one place that says so.
    On a headless Linux machine (no X or Wayland display) VTK's render window defaults to EGL: else VTK probes X first
    and prints "bad X server connection" on every picture. Where a display is (a notebook on a desktop) and off
    Linux (macOS has no EGL) nothing global is set, so the caller's own pyvista windows stay on screen (pyvista's
    OFF_SCREEN had been set for good: a library audit, 2026-12-07)."""
    import os
    import sys

    if sys.platform.startswith("linux") and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    return pv


def cut_identity(path: str | Path) -> str:
    """The identity of the cut record at ``path``: the random id its recording wrote (``record_id``), so the
    same record wherever its study folder is copied or however it is spelled, and another for each recording
    (a global rerun into the same folder). A checkpoint of the submodel it drove
    (rods.fe.cut.CutDriver.checkpoint_identity), a study's restart and compare.py (a submodel summary's
    ``cut_record``) tell them apart. A record written before the id existed: its resolved path, size and
    modification time. Here, not in rods.fe.cut, so that a stage reading it loads no DOLFINx/MPI."""
    import h5py

    with h5py.File(path, "r") as f:
        record = f.attrs.get("record_id")
    if record is not None:
        return f"record:{record}"
    stat = Path(path).stat()
    return f"{Path(path).resolve()}:{stat.st_size}:{stat.st_mtime_ns}"
