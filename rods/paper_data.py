"""The paper's published numbers (Tables 1 to 3), read by named keys from ``rods/paper_data.toml``.

The one place these values live: tables, figures and the report take them from :func:`load`, never
retype them. SI units throughout (radii [m], areas [m^2], speeds [m/s], strain [-]).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

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


ROD_KEYS = ("length", "diameter", "tip_radius", "density", "youngs_modulus", "poisson_ratio")  # Table 1's, SI


def _rod_values(rod: Any) -> tuple[float, ...]:
    """A rods.scene.Rod's Table-1 values in :data:`ROD_KEYS` order."""
    m = rod.material
    return (rod.length, rod.diameter, rod.tip_radius, m.density, m.youngs_modulus, m.poisson_ratio)


@dataclass(frozen=True)
class PaperData:
    table1: dict[str, dict[str, float]]  # Table 1: rod1, rod2 -> ROD_KEYS
    trials: dict[str, Trial]  # Table 2, by scene name (trial-1-3, ...)
    table3: dict[str, Table3Entry]  # global, submodel_coarse/mid/fine, analytical
    experimental_area: float  # [m^2] Table 3's printed experimental area
    fe_trial: str  # the trial the FE models simulate
    plateau_threshold: float  # the paper's average-peak-speed plateau threshold [m/s]

    @property
    def fe_experiment(self) -> Trial:
        """The experiment at the FE impact speed (Table 2, Spec. 1 Trial 3)."""
        return self.trials[self.fe_trial]

    def same_rods(self, scene: Any) -> bool:
        """The scene's rods are Table 1's (every value to 1e-9 relative): the paper's setup."""
        rods = {"rod1": scene.rod1, "rod2": scene.rod2}
        return all(
            math.isclose(v, self.table1[n][k], rel_tol=1e-9)
            for n, rod in rods.items()
            for k, v in zip(ROD_KEYS, _rod_values(rod), strict=True)
        )

    def is_fe_scene(self, scene: Any) -> bool:
        """The scene of the paper's FE models (Table 3): Table 1's rods at the FE trial's impact speed; only its
        results may be set beside Table 3's numbers and that trial's experiment."""
        return self.same_rods(scene) and math.isclose(scene.speed, self.fe_experiment.impact_speed, rel_tol=1e-9)

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
        table1={n: {k: float(v[k]) for k in ROD_KEYS} for n, v in raw["table1"].items()},
        trials={name: Trial(name=name, **row) for name, row in raw["table2"].items()},
        table3={k: Table3Entry(**v) for k, v in t3.items()},
        experimental_area=experimental_area,
        fe_trial=raw["fe_trial"],
        plateau_threshold=float(raw["plateau_threshold"]),
    )
