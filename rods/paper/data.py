"""Stage results as JSON: NaN/inf written as null (JSON has neither) and read back as NaN; the runs later
stages read; percentage cells."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rods import io
from rods.compare import percent

__all__ = ["Run", "dump", "load", "parse_run", "pct", "read_run", "write_json"]


def _plain(x: Any) -> Any:
    if isinstance(x, Mapping):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, list | tuple | np.ndarray):
        return [_plain(v) for v in x]
    if isinstance(x, np.generic):
        return _plain(x.item())
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def _nan(x: Any) -> Any:
    if isinstance(x, dict):
        return {k: _nan(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_nan(v) for v in x]
    return math.nan if x is None else x


def dump(data: Mapping[str, Any]) -> str:
    """JSON text of a stage result (non-finite numbers as null)."""
    return json.dumps(_plain(data), indent=2, ensure_ascii=False, allow_nan=False) + "\n"


def write_json(path: str | Path, data: Mapping[str, Any]) -> None:
    io.atomic_write_text(path, dump(data))


def load(path: str | Path) -> dict[str, Any]:
    """A stage result; every null reads back as NaN (no stage writes null for anything but a number)."""
    return _nan(json.loads(Path(path).read_text(encoding="utf-8")))


def pct(ours: float, ref: float, digits: int = 1) -> str:
    """:func:`rods.compare.percent` as a signed percentage cell, '-' where a value is missing."""
    if not (math.isfinite(ours) and math.isfinite(ref)) or ref == 0:
        return "-"
    return f"{percent(ours, ref):+.{digits}f}%"


@dataclass(frozen=True)
class Run:
    """A model run as a later stage reads it: its label, history.csv columns and summary.json."""

    label: str
    history: dict[str, np.ndarray]
    summary: dict[str, Any]


def read_run(folder: str | Path, label: str = "") -> Run:
    """The run in ``folder`` (history.csv, summary.json); the label defaults to the summary's model."""
    folder = Path(folder)
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    return Run(label or summary.get("model", folder.name), io.read_history(folder / "history.csv"), summary)


def parse_run(spec: str) -> tuple[str, Path]:
    """``LABEL=FOLDER`` (or a bare folder) from the command line; the label may itself contain '='."""
    label, _, folder = spec.rpartition("=")
    return label, Path(folder)
