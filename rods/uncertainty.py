"""Uncertainty bands on model predictions from uncertain inputs (first-order, one at a time).

Each uncertain input is moved by ± its standard uncertainty with everything else fixed; the half-spread
of each output is combined in quadrature (root-sum-square: independent inputs, locally linear response,
GUM/JCGM 100 §5.1.2). The band is nominal ± that combined uncertainty.

Default inputs for the paper's rods (stated assumptions, not from the paper except the speed):
* impact speed ± 0.02 m/s — the paper's drop-to-drop scatter (Sec. 2.3);
* Young's modulus ± 1% — typical of the impulse-excitation method (ASTM E1876);
* density ± 0.3% — mass and volume of one specimen by balance and micrometer;
* Poisson ratio ± 0.01;
* tip radius ± 1% — the lapped 35 mm cap.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from rods.scene import Scene, override

__all__ = ["PAPER_UNCERTAINTY", "Band", "propagate"]

# key -> (kind, amount): "abs" adds ± amount, "rel" scales by (1 ± amount); applied to both rods where named rodN
PAPER_UNCERTAINTY: dict[str, tuple[str, float]] = {
    "impact.speed": ("abs", 0.02),  # [m/s]
    "rod*.material.youngs_modulus": ("rel", 0.01),  # [-]
    "rod*.material.density": ("rel", 0.003),  # [-]
    "rod*.material.poisson_ratio": ("abs", 0.01),  # [-]
    "rod1.tip_radius": ("rel", 0.01),  # [-]
}


@dataclass(frozen=True)
class Band:
    nominal: float
    uncertainty: float  # combined standard uncertainty (same unit as nominal)
    contributions: Mapping[str, float]

    @property
    def low(self) -> float:
        return self.nominal - self.uncertainty

    @property
    def high(self) -> float:
        return self.nominal + self.uncertainty


def _moved(scene: Scene, key: str, kind: str, amount: float, sign: int) -> Scene:
    keys = [key.replace("*", "1"), key.replace("*", "2")] if "*" in key else [key]
    over = []
    for k in keys:
        v = scene[k]
        new = v + sign * amount if kind == "abs" else v * (1 + sign * amount)
        over.append(override(k, new))
    return scene.with_overrides(*over)


def propagate(
    scene: Scene,
    quantities: Callable[[Scene], Mapping[str, float]],
    inputs: Mapping[str, tuple[str, float]] = PAPER_UNCERTAINTY,
) -> dict[str, Band]:
    """Bands on every quantity ``quantities(scene)`` returns, from the uncertain ``inputs``."""
    nominal = quantities(scene)
    spread: dict[str, dict[str, float]] = {q: {} for q in nominal}
    for key, (kind, amount) in inputs.items():
        if "*" not in key and math.isinf(scene[key]):
            continue  # a flat tip has no radius to be uncertain about
        hi, lo = quantities(_moved(scene, key, kind, amount, +1)), quantities(_moved(scene, key, kind, amount, -1))
        for q in nominal:
            spread[q][key] = 0.5 * abs(hi[q] - lo[q])
    return {q: Band(nominal[q], math.sqrt(sum(d * d for d in spread[q].values())), spread[q]) for q in nominal}
