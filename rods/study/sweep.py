"""Parameter sweeps: one CSV row per run, read from each run's summary.json by named keys."""

from __future__ import annotations

import csv
import io as _io
import json
from collections.abc import Sequence
from pathlib import Path

from rods import io

__all__ = ["FIELDS", "write_sweep_table"]

# the columns of results/sweep-*.csv (after "path"): summary keys, SI units
FIELDS = (
    "model",
    "impact_speed",
    "peak_contact_force",
    "contact_radius",
    "contact_duration",
    "midpoint_peak_speed",
    "midpoint_peak_strain",
    "wall_time",
    "dofs",
    "dt",
    "energy_error",
)


def write_sweep_table(path: str | Path, summaries: Sequence[str | Path], fields: Sequence[str] = FIELDS) -> None:
    """Write ``path``: a ``path`` column (the summary file) and ``fields`` from each summary (empty if absent)."""
    buf = _io.StringIO()
    w = csv.DictWriter(buf, fieldnames=["path", *fields], lineterminator="\r\n")
    w.writeheader()
    for p in summaries:
        s = json.loads(Path(p).read_text())
        w.writerow({"path": str(p), **{k: s.get(k) for k in fields}})
    io.atomic_write_text(path, buf.getvalue())
