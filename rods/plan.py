"""What a scene asks for, and therefore what runs: effects -> models (the plan).

A scene names the effects it needs (``effects = [...]``) and the workflow simulates only that:

* ``wave_response`` — Rod-2 midpoint speed and strain over the whole ``end_time``: the analytical model
  and the global FE model; no submodel.
* ``contact_patch`` — contact area, radius and pressure: the global model only through the contact phase
  (it stops after the analytical contact end plus a margin), then the submodel levels.
* ``subsurface_stress`` — σ_r near the surface (Fig. 6): as contact_patch; the submodel also samples stresses.
* ``fields`` — displacement, velocity and stress fields for ParaView from the global model (nothing else
  writes field files).
* ``misalignment`` — offset/tilted impact: needs the 3D model (``fe.kind = "3d"``, checked by the scene).

The analytical model always runs: it costs milliseconds and is every model's reference.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

from rods.scene import Scene

__all__ = ["CONTACT_MARGIN", "Plan", "make_plan"]

CONTACT_MARGIN = 1.2  # global run length for contact-only effects: 1.2 x the analytical contact end [-]


@dataclass(frozen=True)
class Plan:
    effects: tuple[str, ...]
    analytical: bool
    global_model: bool
    global_kind: str
    global_end_time: float  # [s]
    submodel_levels: tuple[str, ...]
    fields: bool
    reasons: tuple[str, ...] = field(default=())

    def describe(self) -> str:
        lines = [f"effects: {', '.join(self.effects)}"]
        lines.append("  analytical model: yes")
        if self.global_model:
            lines.append(f"  global FE model ({self.global_kind}): until t = {self.global_end_time * 1e6:.1f} µs")
        else:
            lines.append("  global FE model: no")
        lines.append(f"  submodel levels: {', '.join(self.submodel_levels) or 'none'}")
        lines.append(f"  field files: {'yes' if self.fields else 'none'}")
        lines += [f"  - {r}" for r in self.reasons]
        return "\n".join(lines)

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def make_plan(scene: Scene, contact_end: float | None = None) -> Plan:
    """The plan for ``scene``; ``contact_end`` [s] (the analytical model's last separation) bounds
    the global run when only contact effects are asked for."""
    fx = set(scene.effects)
    reasons = []
    wave = "wave_response" in fx
    contact = bool(fx & {"contact_patch", "subsurface_stress"})
    fields = "fields" in fx or scene["fe.field_interval"] > 0
    global_model = wave or contact or fields or "misalignment" in fx
    end = scene.end_time
    if global_model and not (wave or fields) and contact_end is not None:
        end = min(scene.end_time, CONTACT_MARGIN * contact_end)
        reasons.append(f"contact effects only: the global run stops at {CONTACT_MARGIN} x the analytical contact end")
    levels = tuple(scene["submodel.levels"]) if contact else ()
    if contact:
        reasons.append("contact_patch/subsurface_stress: the submodel refines the contact region")
    if wave:
        reasons.append("wave_response: the global run covers the whole end_time; no submodel needed for it")
    return Plan(
        effects=tuple(scene.effects),
        analytical=True,
        global_model=global_model,
        global_kind=scene["fe.kind"],
        global_end_time=end,
        submodel_levels=levels,
        fields=fields,
        reasons=tuple(reasons),
    )
