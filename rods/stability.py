"""The central-difference scheme's step limits as closed forms, without PETSc (rods.fe.explicit's scheme, whose
module docstring derives them; rods.fe.timestep solves the eigenvalues they take; rods.cost estimates them before a
mesh is built), so the run and its plan march by one rule:

* Δt_crit = 2/ω_max (sqrt(1 + ξ²) - ξ): central differences with a damping ratio ξ at the highest mode ω_max
  (bulk viscosity, fe.bulk_viscosity; ξ = 0 undamped);
* Δt_switch = :data:`SWITCHING` / ω_c: an isolated penalty pair of frequency ω_c switching on and off (inf without
  a spring: the kinematic contact);
* the step a run marches at with fe.dt = "auto": fe.dt_fraction of Δt_crit, at most Δt_switch.
"""

from __future__ import annotations

import math

__all__ = ["SWITCHING", "damping_factor", "march_step", "one_step_remedy", "stable_step", "switching_step"]

SWITCHING = 1.0  # largest ω_c Δt of an isolated contact pair [-] (rods.fe.explicit's module docstring)


def damping_factor(ξ: float) -> float:
    """sqrt(1 + ξ²) - ξ [-]: the stable step with a damping ratio ξ at ω_max over the undamped one."""
    return math.sqrt(1.0 + ξ * ξ) - ξ


def stable_step(ω_max: float, ξ: float = 0.0) -> float:
    """Δt_crit = 2/ω_max (sqrt(1 + ξ²) - ξ) [s] for central differences with damping ratio ξ at ω_max [rad/s]."""
    return 2.0 / ω_max * damping_factor(ξ)


def switching_step(ω_contact: float) -> float:
    """Δt_switch = SWITCHING / ω_c [s]: the contact-switching limit; inf without contact stiffness (ω_c = 0)."""
    return SWITCHING / ω_contact if ω_contact > 0 else math.inf


def march_step(fraction: float, stable: float, switching: float) -> float:
    """The step [s] of fe.dt = "auto": ``fraction`` (fe.dt_fraction) of the stable step, at most the switching
    limit."""
    return min(fraction * stable, switching)


def one_step_remedy(given: bool | str) -> str:
    """The remedy of an end time below one time step; ``given``: the step was set (finer sizes would not change it),
    by fe.dt, or by the key named (a submodel's --dt)."""
    if not given:
        return "a longer end time, or finer sizes for a smaller step"
    return f"a longer end time, or a smaller {given if isinstance(given, str) else 'fe.dt'}"
