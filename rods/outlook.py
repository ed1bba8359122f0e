"""What a run of a scene will likely warn about, said in its plan, before anything runs.

The run's own checks (rods.checks) judge its results after hours of stepping; a scene outside the models' range
is known from closed forms at once. Each line here foresees one of those checks from the scene alone, at the
bound force P: the impedance bound s1 Z1 Z2/(Z1 + Z2) (rods.scene.Scene.impedance_force: the stiff-contact bar limit),
or Hertz's impact of the rods as rigid masses where that is lower (rods.hertz.rigid_impact_force: stubby rods, a slow
contact), and the rise time δ_P/s1 the impedance bound implies (rods.scene.Scene.estimated_rise):

* **rim**: Hertz's contact radius at P against :data:`rods.checks.RIM_FRACTION` of the rod's radius
  (:func:`rods.checks.rim_edge`, offset and tilt counted);
* **yield**: Hertz's peak pressure at P against the paper's 1.1 S_y (rods.hertz.yield_check), per yield strength;
* **bar theory**: the estimated rise against :data:`rods.checks.RISE_TRANSITS` diameter transits d/c of the
  longer-transit rod;
* **impact strain**: rod i's bar front strain P/(Z_i c_i) against :data:`rods.checks.SMALL_STRAIN`
  (:func:`rods.checks.strain_warning` on the scene alone: the run's check at its own midpoint follows);
* **end time**: a wave response whose end time holds fewer than :data:`rods.scene.END_PERIODS` periods 2 L2/c2
  (the plateaus and the strain window: fewer plateaus than averaged, the run's warning);
* **the global's mesh** (FE runs): sizes above :data:`rods.checks.COARSE_OK` x auto (rods.checks.coarse_warning, the
  run's own line), and the patch at Hertz's radius at P (rods.checks.patch_resolution: too few elements across it,
  or in 3D a node ring above :data:`rods.checks.RING_STEP_OK` of its area, as every 3D run this machine can afford
  has: resolving it takes elements of ~27 µm on the paper scene), and a Poisson ratio above
  :data:`rods.checks.NU_LOCKING` (rods.checks.locking_warning: the Q1 elements lock; the run's own line).

P bounds the analytical force from above and that force reaches it where it rises before a reflection returns
(the paper scene's peak 1.3e-5 below it; a 6.5 mm tip at 0.5 m/s, rising longer, 5.3% below), so a rim or yield
line may foresee a warning the run does not give; it misses one only where the FE's ringing lifts its peak above P
(on the 57 rows of results/*probe*.json of 2026-11-29 neither happened). The rise is an estimate (against the
analytical model's 10-90% rise: 15.5 / 22.5 µs on the paper scene, 5.1 / 4.0 µs with a 1 m tip), so a scene near
the threshold may warn without a line here (there, 2 of 57 rows: a 1 m tip, 2.1 transits estimated, 1.6-1.7
measured) or get a line without the warning (3 of 57). The paper scene gets none.
"""

from __future__ import annotations

from typing import Any

from rods import checks, hertz, metrics
from rods.scene import END_PERIODS, auto_end_time, reduced_mass

__all__ = ["outlook"]

# the rigid masses' Hertz force, raised by this for the bound [-]: the FE's peak on the audit's stubby rods was 0.35%
# above it (60.7 N against 60.5 N with the caps' mass), the rods' end term stiffening its contact a little
RIGID_MARGIN = 1.02


def outlook(scene: Any, wave: bool = True, fe: bool = False) -> list[str]:
    """The checks a run of ``scene`` will likely fail (module docstring), one line each; empty where none. ``wave``:
    the run compares the wave response over the scene's end time (not a driving global's or a submodel's contact
    phase, whose plans said it would fall short of plateaus they do not measure: a fuzz, 2026-12-06). ``fe``: the
    run holds a global FE model (its mesh checks, below)."""
    E_star, R_star = hertz.contact_constants(scene.rod1, scene.rod2)
    m = reduced_mass(scene.rods)  # [kg]
    # [N] the lower bound of the two: the bars' (slender rods) or the rigid masses' Hertz (stubby rods, a slow contact:
    # P = 253 N said "may yield, 2482 MPa" on an audit's hemisphere on 30 mm rods whose force peaks at 61 N)
    P = min(scene.impedance_force, RIGID_MARGIN * hertz.rigid_impact_force(m, scene.speed, E_star, R_star))
    at_P = hertz.at_force(P, E_star, R_star)
    lines = []
    if (edge := checks.rim_edge(at_P["contact_radius"], scene)) > checks.RIM_FRACTION:
        lines.append(
            f"contact_radius: Hertz's radius at the bound force P = {P:.4g} N is "
            f"{at_P['contact_radius'] * 1e3:.3g} mm, {edge:.2f} of {checks.rim_where(scene)} (the rim check: "
            f"{checks.RIM_FRACTION:g}): the patch may reach the rim, where Hertz's half-space and the analytical "
            f"rod-end term no longer hold ({checks.rim_remedy(scene)} keeps it inside)"
        )
    p0, what = hertz.bearing_pressure(P, at_P["contact_radius"], at_P["peak_pressure"], scene.rods)  # [Pa]
    lower = hertz.pressure_lowered_by(what, "speed")
    for S_y, which in hertz.rods_by_strength(scene.rods).items():
        if hertz.yield_check(p0, S_y):
            continue
        lines.append(
            f"yield: the {what} at P = {P:.4g} N is {p0 / 1e6:.4g} MPa, "
            f"{p0 / (hertz.YIELD_FACTOR * S_y):.2f} x 1.1 S_y of {which}: the contact may yield, where the elastic "
            f"models no longer hold ({lower} lowers it)"
        )
    rise, transit = scene.estimated_rise, metrics.longer_transit(scene)  # [s]
    if rise < checks.RISE_TRANSITS * transit:
        lines.append(
            f"peak_contact_force: the force should rise in about {rise * 1e6:.3g} µs, {rise / transit:.2g} diameter "
            f"transits d/c (the bar-theory check: {checks.RISE_TRANSITS:g}): the 1D bars will miss the rods' ringing; "
            "expect the FE's peak above the analytical one by ~0.5% or more (the auto fe.axial_size is refined to "
            "follow the rise)"
        )
    if (strain := checks.strain_warning(scene)) is not None:  # closed form already: the run's own line
        lines.append(strain)
    if fe:  # the global's mesh: its sizes against auto (the scene alone), its patch at Hertz's radius at P, which
        # bounds the run's (a default 3D plan of 5-9 h said nothing of the node-ring warning every such run gives)
        checked = (checks.coarse_warning(scene), _patch_line(at_P["contact_radius"], P, scene))
        lines += [w for w in (*checked, checks.locking_warning(None, scene)) if w]
    periods = scene.end_time / scene.rod2.round_trip_time  # Rod 2's round trips 2 L2/c2 the run holds [-]
    if wave and "wave_response" in scene.effects and periods < END_PERIODS:
        lines.append(
            f"midpoint_peak_speed: end_time = {scene.end_time:g} s holds {periods:.2g} of the {END_PERIODS} periods "
            "2 L2/c2 the wave response compares (the midpoint's plateaus, the strain window): simulation.end_time = "
            f"'auto' runs {auto_end_time(scene.rods, scene.speed):.3g} s"
        )
    return lines


def _patch_line(a_P: float, P: float, scene: Any) -> str | None:
    """The global's patch check (rods.checks.patch_resolution) at Hertz's radius ``a_P`` [m] at the bound force ``P``
    [N]: the run's radius is at most that (but for ringing that lifts its peak above P, a fraction of a percent: the
    module docstring), so where this warns the run does, unless near the threshold."""
    if (w := checks.patch_resolution(a_P, scene.radial_size, scene)) is None:
        return None
    return f"{w} (at Hertz's radius at the bound force P = {P:.4g} N, which bounds the run's but for its ringing)"
