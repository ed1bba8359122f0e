"""rods.outlook: the checks a run will likely fail, foreseen from the scene alone (and said by every plan)."""

import pytest

from rods import checks, hertz
from rods.outlook import outlook

from .conftest import in_process


def _keys(lines: list[str]) -> list[str]:
    return [line.split(":")[0] for line in lines]


@pytest.mark.parametrize(
    ("case", "foreseen"),
    [("paper", []), ("speed-1.0", []), ("speed-4.0", ["yield"]), ("titanium-rod2", []), ("tip-20mm", ["yield"]),
     ("equal-0.35m", [])],
)  # fmt: skip
def test_the_verification_matrix_foresees_what_its_runs_warned(scene_with, case, foreseen):
    """The six scenes of results/verification.md: their runs (2026-11-29) warned only of yield, at 4.0 m/s (p0 =
    2720.5 MPa at the analytical peak) and with a 20 mm tip (3235.3 MPa), against 1.1 S_y = 2420 MPa."""
    from rods.study.verification import CASES

    assert _keys(outlook(scene_with(*CASES[case][1]))) == foreseen


def test_a_near_flat_tip_foresees_the_rim_and_a_fast_rise(scene_with):
    """A 10 m tip on the paper rods: Hertz's radius at P = 5556 N is 7.19 mm, past the 6.35 mm rod (the run's rim
    warning: the FE's patch 6.35 mm, 1.00 of the radius, its force +11% from the analytical model, measured
    2026-11-29), and the approach closes in 2.35 µs, under one diameter transit."""
    sc = scene_with("rod1.tip_radius=10.0")
    lines = outlook(sc)
    assert _keys(lines) == ["contact_radius", "peak_contact_force"]
    a = hertz.at_force(sc.impedance_force, *hertz.contact_constants(sc.rod1, sc.rod2))["contact_radius"]
    assert a == pytest.approx(7.19e-3, rel=1e-3) and f"{a / 6.35e-3:.2f} of the thinner rod's radius" in lines[0]
    assert sc.estimated_rise < checks.RISE_TRANSITS * sc.rod1.diameter_transit
    assert "0.95 diameter transits" in lines[1]


def test_a_run_too_short_for_the_wave_response_is_foreseen(scene_with):
    """2 m rods at the paper's 1.5 ms: 1.9 of Rod 2's five periods, and the run warns of 3 of 5 plateaus; the line
    names the auto end time (4.3 ms), which holds them (no line; tests/test_scene.py runs it); a contact-only scene
    is not told (its global stops at the contact phase)."""
    from rods.analytical import simulate

    short = scene_with("rod1.length=2.0", "rod2.length=2.0")
    (line,) = outlook(short)
    assert line.startswith("midpoint_peak_speed: end_time = 0.0015 s holds 1.9 of the 5 periods") and "'auto'" in line
    run = simulate(short)
    s = dict(run.summary)
    checks.apply(s, run.history, short, short.end_time)
    assert any("of 5 plateaus within end_time" in w for w in s["warnings"])
    auto = short.with_overrides("simulation.end_time='auto'")
    assert outlook(auto) == [] and f"runs {auto.end_time:.3g} s" in line
    assert outlook(short.with_overrides("effects=['contact_patch']")) == []
    assert outlook(short, wave=False) == []  # a driving global's or a submodel's plan: the contact phase only


def test_a_driver_and_a_submodel_plan_no_wave_outlook(tmp_path):
    """global.py --driver and submodel.py run the contact phase only: their plans foresee no midpoint plateaus (a
    fuzz, 2026-12-06: every submodel.py plan said its end time held 0.89 of the 5 periods); global.py alone does."""
    short = ["--set", "rod1.length=2.0", "--set", "rod2.length=2.0", "--dry-run"]
    alone = in_process("global.py", *short, "--out", str(tmp_path / "g"), cwd=tmp_path)
    driver = in_process("global.py", *short, "--driver", "--out", str(tmp_path / "d"), cwd=tmp_path)
    assert alone.returncode == driver.returncode == 0, alone.stderr + driver.stderr
    assert "outlook: midpoint_peak_speed" in alone.stdout and "midpoint_peak_speed" not in driver.stdout


def test_the_rim_line_is_the_rim_check_at_the_bound_force(scene_with):
    """The line appears exactly where checks.rim_edge of Hertz's radius at P passes checks.RIM_FRACTION: the tip
    radius that puts a_P at the threshold, 2% either side."""
    sc = scene_with()
    E_star, _ = hertz.contact_constants(sc.rod1, sc.rod2)
    a = checks.RIM_FRACTION * sc.rod1.diameter / 2  # [m]
    # a^3 = 3 P R* / (4 E*), R* = R1 for a flat Rod 2 (Eq. 5)
    R = 4 * E_star * a**3 / (3 * sc.impedance_force)  # [m]
    below, above = scene_with(f"rod1.tip_radius={0.98 * R!r}"), scene_with(f"rod1.tip_radius={1.02 * R!r}")
    assert "contact_radius" not in _keys(outlook(below))
    assert "contact_radius" in _keys(outlook(above))


def test_yield_is_foreseen_per_strength_and_never_without_one(scene_with):
    """15 m/s on the paper rods: p0 at P = 4227 MPa, 1.75 x 1.1 S_y of both steel rods (one line; the run's
    submodel says 4229 MPa at its own peak force); a Rod 2 without a yield strength drops it from the line; rods of
    two strengths get a line each; none with no strength set."""
    lines = outlook(scene_with("impact.speed=15"))
    assert _keys(lines) == ["yield"] and "1.75 x 1.1 S_y of rods 1 and 2" in lines[0] and "4227 MPa" in lines[0]
    assert "of rod 1:" in outlook(scene_with("impact.speed=15", "rod2.material.yield_strength='none'"))[0]
    two = outlook(scene_with("impact.speed=15", "rod2.material.yield_strength=3e9"))
    assert _keys(two) == ["yield", "yield"] and "of rod 1:" in two[0] and "of rod 2:" in two[1]
    none = ("rod1.material.yield_strength='none'", "rod2.material.yield_strength='none'")
    assert outlook(scene_with("impact.speed=15", *none)) == []


def test_the_bound_force_is_above_the_analytical_models_peak(scene_with):
    """Why a rim or yield line may foresee more than the run gives, never less: P bounds the peak force from above,
    and the force reaches it where it rises before a reflection returns (the paper scene's analytical peak 1.3e-5
    below P, a 10 m tip's and 15 m/s's at P to 1e-9), not where it rises longer (a 6.5 mm tip at 0.5 m/s: -5.3%)."""
    from rods import plan

    for overrides in [
        (),
        ("rod1.tip_radius=10.0",),
        ("impact.speed=15",),
        ("rod1.tip_radius=0.0065", "impact.speed=0.5"),
    ]:
        sc = scene_with(*overrides)
        assert plan.first_contact_summary(sc)["peak_contact_force"] <= sc.impedance_force * (1 + 1e-6)


def test_every_plan_says_the_outlook_before_the_cost(tmp_path):
    """global.py, analytical.py and run.py --dry-run print the outlook's lines after the plan, before the cost
    estimate; the paper scene prints none."""
    for script in ("global.py", "analytical.py", "run.py"):
        p = in_process(script, "--set", "rod1.tip_radius=10.0", "--dry-run", "--out", str(tmp_path / "o"), cwd=tmp_path)
        assert p.returncode == 0, p.stderr
        said = [line.split(":")[0] for line in p.stdout.splitlines()]
        assert said.count("outlook") == 2, p.stdout
        assert said.index("outlook") < next(i for i, w in enumerate(said) if w.startswith("cost of")), p.stdout
    paper = in_process("global.py", "--dry-run", "--out", str(tmp_path / "p"), cwd=tmp_path)
    assert paper.returncode == 0 and "outlook" not in paper.stdout


def test_an_impact_strain_beyond_small_strains_is_foreseen(scene_with):
    """A soft, dense Rod 1 (E = 1 MPa, ρ = 1e5 kg/m³) struck at the paper's speed strains 0.69 in bar theory: the
    analytical run warned of it after the run, the plan did not (a fuzz, 2026-12-06). The paper scene strains 2e-4:
    no line."""
    soft = scene_with("rod1.material.youngs_modulus=1e6", "rod1.material.density=1e5",
                      "rod1.material.yield_strength=none")  # fmt: skip
    lines = [w for w in outlook(soft) if w.startswith("impact strain:")]
    assert len(lines) == 1 and "in rod 1" in lines[0] and "above 0.01" in lines[0]
    assert lines[0] == checks.strain_warning(soft)  # the run's own line, foreseen
    assert not any(w.startswith("impact strain:") for w in outlook(scene_with()))


def test_stubby_rods_are_judged_at_the_rigid_masses_hertz_force(scene_with):
    """A hemisphere on the paper's rods cut to 30 mm, at 0.1 m/s, peaks at ~61 N (FE 60.7 N, an audit), where the
    impedance bound is 253 N: the plan said "may yield, 2482 MPa" there; the bound is now the rigid masses' Hertz
    force where lower (x 1.02), still above the analytical peak, and the plan says nothing the run will not."""
    from rods import hertz, outlook, plan

    sc = scene_with("rod1.length=0.03", "rod2.length=0.03", "rod1.tip_radius=0.00635", "impact.speed=0.1")
    from rods.scene import reduced_mass

    rigid = hertz.rigid_impact_force(reduced_mass(sc.rods), sc.speed, *hertz.contact_constants(sc.rod1, sc.rod2))
    peak = plan.first_contact_summary(sc)["peak_contact_force"]
    assert rigid < sc.impedance_force / 4 and peak <= outlook.RIGID_MARGIN * rigid and peak > 0.97 * rigid
    assert not [line for line in outlook.outlook(sc) if line.startswith("yield")]
    assert [line for line in outlook.outlook(scene_with("impact.speed=4"))][0].startswith("yield")


@pytest.mark.parametrize("case", ["paper", "speed-4.0", "titanium-rod2", "tip-20mm", "equal-0.35m"])
def test_the_global_at_auto_sizes_foresees_no_mesh_warning(scene_with, case):
    """The verification matrix's globals (axisymmetric, auto sizes) gave no patch or resolution warning: a global's
    plan foresees none either."""
    from rods.study.verification import CASES

    sc = scene_with(*CASES[case][1])
    assert outlook(sc, fe=True) == outlook(sc)


def test_a_3d_global_foresees_its_node_ring_warning(scene_with):
    """A 3D global at auto sizes on the paper scene (6.6M DOFs, hours): one node ring is 2h/a = 50% of the patch at
    Hertz's radius at P (1.09 mm, h = 0.273 mm); every 3D run this machine affords warns of it (a helper's runs of
    five scenes at coarse to 2 x auto sizes, 2026-12-07), and its plan said nothing. Only for an FE global."""
    sc = scene_with("fe.kind=3d")
    lines = outlook(sc, fe=True)
    assert _keys(lines) == ["contact_area"] and "one ring 2h/a = 50% of its area" in lines[0]
    assert "which bounds the run's but for its ringing" in lines[0] and "from the axisymmetric model" in lines[0]
    assert outlook(sc) == []  # the analytical model's plan
    a_P = hertz.at_force(sc.impedance_force, *hertz.contact_constants(sc.rod1, sc.rod2))["contact_radius"]
    for a in (a_P, 0.8 * a_P):  # the run's radius is at most a_P: its own check warns too
        assert checks.patch_resolution(a, sc.radial_size, sc).startswith("contact_area")


def test_a_coarse_global_foresees_its_resolution_and_patch_warnings(scene_with):
    """The coarse 3D scene's sizes (1 mm across, 4 mm along: 3.67 and 4 x auto) give the run's resolution warning,
    the scene's alone, and 1.09 elements across Hertz's radius at P (its run: 1.09 across the radius, 2026-12-06)."""
    sc = scene_with("fe.kind=3d", "fe.radial_size=1e-3", "fe.axial_size=4e-3")
    lines = outlook(sc, fe=True)
    assert _keys(lines) == ["fe.radial_size", "contact_radius"]
    assert lines[0] == checks.coarse_warning(sc)
    assert "1.09 elements across the 1.09 mm contact radius" in lines[1]


@pytest.mark.parametrize("ν", [0.49, 0.4999])
def test_a_near_incompressible_global_foresees_its_locking_warning(scene_with, ν):
    """ν above rods.checks.NU_LOCKING: the global's run warns that its Q1 elements lock (an audit's ν = 0.4999 run:
    +16.9%, locking named), and its plan said nothing. The FE plan's line is the run's, word for word; the analytical
    model's plan has none (no elements)."""
    sc = scene_with(*(f"rod{i}.material.poisson_ratio={ν}" for i in (1, 2)))
    lines = outlook(sc, fe=True)
    assert checks.locking_warning(None, sc) in lines
    assert checks.locking_warning({"model": "fe-global"}, sc) == checks.locking_warning(None, sc)
    assert not any(line.startswith("poisson_ratio") for line in outlook(sc))
    assert checks.locking_warning(None, scene_with()) is None
