"""Run guards: stop an explicit run that has gone wrong, with a diagnosis, instead of writing garbage.

Checked at every recorded output step (cheap: the energies and the contact state are computed there
anyway) and, for non-finite values, on the velocity every ``FINITE_EVERY`` steps:

* a NaN/Inf in the state or the energies;
* energy growth: (E_kin + E_strain + E_contact + E_dissipated - E_0) / E_0 above ``growth_limit``
  (central differences conserve a modified energy exactly below the stable step, so growth means
  instability, not accumulated round-off);

The likely cause is named from the state: a step near or above the stable limit ("step too large"),
or a contact energy that dominates ("penalty too stiff"). Every ``INVERSION_EVERY`` steps the corner
Jacobians of the deformed cells are checked too ("mesh inverted"): displacements themselves are not
bounded, since they include the rods' rigid-body motion, which the small-strain model carries exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

__all__ = ["FINITE_EVERY", "INVERSION_EVERY", "Guard", "SimulationError"]

FINITE_EVERY = 100  # steps between non-finite checks of the velocity [-]
INVERSION_EVERY = 2000  # steps between inverted-cell checks (a few ms each at 50k DOFs: < 1% of the loop) [-]


class SimulationError(RuntimeError):
    """The run was stopped by a guard; ``partial`` holds the histories recorded so far (an FEResult)."""

    def __init__(self, message: str, step: int, time: float, cause: str, partial: Any = None):
        super().__init__(message)
        self.step, self.time, self.cause, self.partial = step, time, cause, partial


@dataclass
class Guard:
    dt: float  # [s]
    dt_critical: float  # [s]
    growth_limit: float = 0.05  # relative energy growth that stops the run [-]

    def _cause(self, contact_share: float) -> str:
        if self.dt > 0.99 * self.dt_critical:
            return f"step too large: dt = {self.dt:.4g} s is at the stable limit {self.dt_critical:.4g} s"
        if contact_share > 0.5:
            return "penalty too stiff: the contact energy dominates; lower fe.penalty or fe.dt_fraction"
        return "step too large for the current state (lower fe.dt_fraction)"

    def check(self, step: int, t: float, energies: tuple[float, ...], E0: float) -> None:
        """Raise SimulationError if the recorded state at ``step`` is not physical.

        ``energies`` = (kinetic, strain, contact, dissipated) [J]."""
        Ek, Es, Ec, W = energies
        total = Ek + Es + Ec + W
        share = abs(Ec) / max(abs(total), 1e-300)
        if not all(math.isfinite(x) for x in energies):
            cause = self._cause(share)
            raise SimulationError(
                f"non-finite state at step {step} (t = {t:.6g} s); likely cause: {cause}", step, t, cause
            )
        growth = (total - E0) / E0 if E0 > 0 else 0.0
        if growth > self.growth_limit:
            cause = self._cause(share)
            raise SimulationError(
                f"energy grew by {growth:.3g} x E0 (limit {self.growth_limit:g}) at step {step} "
                f"(t = {t:.6g} s); likely cause: {cause}",
                step,
                t,
                cause,
            )

    def check_inverted(self, step: int, t: float, n_cells: int) -> None:
        """Raise if ``n_cells`` elements are inverted in the deformed configuration."""
        if n_cells > 0:
            cause = "mesh inverted: the deformation is too large for small-strain elements (impact too violent)"
            raise SimulationError(
                f"{n_cells} inverted cell(s) at step {step} (t = {t:.6g} s); likely cause: {cause}", step, t, cause
            )

    def check_finite(self, step: int, t: float, finite: bool) -> None:
        if not finite:
            cause = self._cause(0.0)
            raise SimulationError(
                f"non-finite velocity at step {step} (t = {t:.6g} s); likely cause: {cause}", step, t, cause
            )
