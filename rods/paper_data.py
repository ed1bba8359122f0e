"""The paper's published numbers (Tables 2 and 3), read by named keys from ``rods/paper_data.toml``.

The one place these values live: tables, figures and the report take them from :func:`load`, never
retype them. SI units throughout (radii [m], areas [m^2], speeds [m/s], strain [-]).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

__all__ = ["PaperData", "Table3Entry", "Trial", "load"]


@dataclass(frozen=True)
class Trial:
    """One Table-2 row."""

    name: str
    specimen: int
    trial: int
    impact_speed: float  # [m/s]
    circularity: float  # [m]
    experimental_radius: float  # [m]
    analytical_radius: float  # [m] the paper's analytical model
    experimental_peak_speed: float  # [m/s] NaN: not reported
    analytical_peak_speed: float  # [m/s]
    rms_strain_difference: float  # [-]


@dataclass(frozen=True)
class Table3Entry:
    force: float  # peak contact force [N]
    area: float  # contact area [m^2]


@dataclass(frozen=True)
class PaperData:
    trials: dict[str, Trial]  # Table 2, by scene name (trial-1-3, ...)
    table3: dict[str, Table3Entry]  # global, submodel_coarse/mid/fine, analytical
    experimental_area: float  # [m^2] Table 3's printed experimental area
    fe_trial: str  # the trial the FE models simulate
    plateau_threshold: float  # the paper's average-peak-speed plateau threshold [m/s]

    @property
    def fe_experiment(self) -> Trial:
        """The experiment at the FE impact speed (Table 2, Spec. 1 Trial 3)."""
        return self.trials[self.fe_trial]

    def table3_submodel(self, level: str) -> Table3Entry | None:
        """The paper's submodel row of ``level`` (coarse/mid/fine), None for levels the paper did not run."""
        return self.table3.get(f"submodel_{level}")


@cache
def load() -> PaperData:
    """Parse ``rods/paper_data.toml`` (cached)."""
    raw = tomllib.loads(Path(__file__).with_name("paper_data.toml").read_text(encoding="utf-8"))
    t3 = dict(raw["table3"])
    experimental_area = float(t3.pop("experimental_area"))
    return PaperData(
        trials={name: Trial(name=name, **row) for name, row in raw["table2"].items()},
        table3={k: Table3Entry(**v) for k, v in t3.items()},
        experimental_area=experimental_area,
        fe_trial=raw["fe_trial"],
        plateau_threshold=float(raw["plateau_threshold"]),
    )
