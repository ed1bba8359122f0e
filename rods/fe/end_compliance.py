"""The end compliance of a rod under a Hertz pressure: how much stiffer (flat end) or softer (a deep cap) a rod's
end is than a half-space.

The analytical model (paper Sec. 2.1) joins two 1D bars by Hertz's force-approach law, whose approach
is the half-space's: the displacement of the contact centre relative to points *infinitely* far away.
A bar of radius b already carries the far part of that deformation as its own uniform strain F/(EA),
so bar + half-space counts the far field twice. The correct local law is the approach of the contact
centre (the cap's apex) relative to the bar's 1D displacement field extrapolated to the 1D bar's end,

    u_z(apex) - ū_1D(z_e) = (1 - ν²) 3F/(4aE) + χ(ν, b/R, a/b) F/(E b),

the first term being the half-space's centre displacement under p = p0 sqrt(1 - r²/a²), that is
π p0 a (1 - ν²)/(2E) with p0 = 3F/(2πa²) (Johnson, Contact Mechanics, §3.4), the second the rod's end correction.
The 1D bar's end z_e is where the bar of the rod's mass ends (:attr:`rods.scene.Rod.bar_offset`: a spherical cap of
radius R and height h holds less than the cylinder of height h, so the equal-mass bar ends V_cap/(π b²) beyond the
cap's base, ΔL = h - V_cap/(π b²) from
its apex; 0 for a flat end). For a flat end (b/R = 0) χ does not depend on a for a << b (the load acts as a point
load seen from the far field; checked in tests/fe/test_end_compliance.py) and is < 0: the end is stiffer than
the half-space. A cap is softer (χ rises to -0.42 on a hemisphere at ν = 0.3 and a = 0.05 b) and its χ grows
slowly as the patch shrinks (about 0.03 per halving of a on a hemisphere: the free curved surface beside the
patch, which a half-space does not have, adds ~ F/(E R) ln(R/a); measured, not modelled), so the table has a
third axis a/b. :func:`end_correction` computes χ by linear elastostatics on a rod of radius b = 1, body length
8b, E = 1 (axisymmetric, P2 triangles by gmsh, refined towards the apex to a/24): Hertz pressure of radius a on
the tip face (axial, per projected area), the balancing uniform traction on the far end, u_r = 0 on the axis,
one axial point constraint on the far end (the loads balance, so its reaction vanishes). ū_1D is the line fitted
to the cross-section mean of u_z over the middle of the body (0.35 L to 0.65 L), where the end disturbances have
decayed (Saint-Venant: over about one diameter). The table :data:`rods.hertz.ROD_END_CHI` holds its values;
``python benchmarks/rod_end_compliance.py`` recomputes them.
"""

from __future__ import annotations

import math

import dolfinx
import dolfinx.fem.petsc
import dolfinx.io.gmsh
import numpy as np
import ufl
from mpi4py import MPI

from rods import hertz
from rods.fe.forms import measure_weight, strain, stress
from rods.scene import Material, Rod

__all__ = ["end_correction"]

_LENGTH = 8.0  # body length in radii [-]: two decay lengths either side of the fitted middle
_KIND = "axisymmetric"
_TIP, _FAR = 1, 2  # facet tags


def _unit_rod(s: float) -> Rod:
    """The rod of radius 1 with a tip of radius 1/s (s = b/R; 0: flat), body length :data:`_LENGTH`."""
    return Rod(
        _LENGTH, 2.0, math.inf if s == 0 else 1.0 / s, Material(density=1.0, youngs_modulus=1.0, poisson_ratio=0)
    )


def _capped_rod(rod: Rod, a: float, refine: float) -> tuple[dolfinx.mesh.Mesh, dolfinx.mesh.MeshTags]:
    """P2 triangles on the meridian of ``rod`` (:func:`_unit_rod`): the cap (apex at z = -h) on the body r in
    [0, 1], z in [0, L]; the elements a/(12 refine) at the apex, growing to 0.2/refine from 1.5 away (gmsh's
    distance threshold)."""
    import gmsh

    from rods.fe.mesh import start_gmsh

    h = rod.cap_height
    if gmsh.isInitialized():  # an entry point's (workflows/_cli.py): afresh, its options and fields are this mesh's
        gmsh.finalize()
    start_gmsh()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("rod_end")
        geo, coarse = gmsh.model.geo, 0.2 / refine
        apex, rim = geo.addPoint(0.0, -h, 0.0), geo.addPoint(1.0, 0.0, 0.0)
        far_rim, far_axis = geo.addPoint(1.0, _LENGTH, 0.0), geo.addPoint(0.0, _LENGTH, 0.0)
        if h == 0.0:
            tip = geo.addLine(apex, rim)
        else:
            tip = geo.addCircleArc(apex, geo.addPoint(0.0, rod.tip_radius - h, 0.0), rim)
        far = geo.addLine(far_rim, far_axis)
        loop = geo.addCurveLoop([tip, geo.addLine(rim, far_rim), far, geo.addLine(far_axis, apex)])
        surface = geo.addPlaneSurface([loop])
        geo.synchronize()
        gmsh.model.addPhysicalGroup(2, [surface], 1)
        gmsh.model.addPhysicalGroup(1, [tip], _TIP)
        gmsh.model.addPhysicalGroup(1, [far], _FAR)
        field = gmsh.model.mesh.field
        distance = field.add("Distance")
        field.setNumbers(distance, "PointsList", [apex])
        threshold = field.add("Threshold")
        field.setNumber(threshold, "InField", distance)
        for key, value in (("SizeMin", a / 12 / refine), ("SizeMax", coarse), ("DistMin", 1.2 * a), ("DistMax", 1.5)):
            field.setNumber(threshold, key, value)
        field.setAsBackgroundMesh(threshold)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)  # the arc's geometry quadratic too
        data = dolfinx.io.gmsh.model_to_mesh(gmsh.model, MPI.COMM_SELF, 0, gdim=2)
    finally:
        gmsh.finalize()
    return data.mesh, data.facet_tags


def _axial_displacement_at(uh: dolfinx.fem.Function, points: np.ndarray) -> np.ndarray:
    """u_z at ``points`` (k x 3) of a serial mesh."""
    msh = uh.function_space.mesh
    tree = dolfinx.geometry.bb_tree(msh, msh.topology.dim)
    candidates = dolfinx.geometry.compute_collisions_points(tree, points)
    hits = dolfinx.geometry.compute_colliding_cells(msh, candidates, points)
    cells = np.array([hits.links(i)[0] for i in range(points.shape[0])], dtype=np.int32)
    return uh.eval(points, cells).reshape(points.shape[0], -1)[:, 1]


def end_correction(ν: float, s: float = 0.0, a: float = 0.05, refine: float = 2.0) -> float:
    """χ(ν, s, a) [-] of the module docstring: (u_z(apex) - ū_1D(z_e) - (1-ν²) 3F/(4aE)) E b / F.

    ``s``: b/R, the rod's radius over its tip's (0: flat, 1: a hemisphere); ``a``: Hertz radius in rod radii
    (a << 1); ``refine``: the mesh's refinement (the elements scale as 1/refine)."""
    rod = _unit_rod(s)
    msh, facets = _capped_rod(rod, a, refine)
    E, F = 1.0, 1.0  # [Pa], [N] (linear: χ is dimensionless)
    λ, μ = Material(density=1.0, youngs_modulus=E, poisson_ratio=ν).lame  # [Pa]
    V = dolfinx.fem.functionspace(msh, ("Lagrange", 2, (2,)))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    x = ufl.SpatialCoordinate(msh)
    w = measure_weight(x, _KIND)
    stiffness = ufl.inner(stress(strain(u, x, _KIND), λ, μ), strain(v, x, _KIND)) * w * ufl.dx

    ds = ufl.Measure("ds", msh, subdomain_data=facets)
    p0 = float(hertz.peak_pressure(F, a))  # Hertz peak pressure for force F [Pa]
    p = p0 * ufl.sqrt(ufl.max_value(1 - x[0] ** 2 / a**2, 0.0))
    axial = -ufl.FacetNormal(msh)[1]  # per projected area on the cap: ∫ p 2πr dr = F exactly
    # the pressure's square-root edge needs a high quadrature degree on the few facets it covers
    load = p * axial * v[1] * w * ds(_TIP, degree=24) - F / math.pi * v[1] * w * ds(_FAR)  # compresses along +z

    Vr, _ = V.sub(0).collapse()
    Vz, _ = V.sub(1).collapse()
    axis = dolfinx.fem.locate_dofs_geometrical((V.sub(0), Vr), lambda q: np.isclose(q[0], 0.0))
    pin = dolfinx.fem.locate_dofs_geometrical(
        (V.sub(1), Vz), lambda q: np.isclose(q[0], 0.0) & np.isclose(q[1], _LENGTH)
    )
    bcs = [
        dolfinx.fem.dirichletbc(dolfinx.fem.Function(Vr), axis, V.sub(0)),
        dolfinx.fem.dirichletbc(dolfinx.fem.Function(Vz), pin, V.sub(1)),
    ]
    problem = dolfinx.fem.petsc.LinearProblem(
        stiffness,
        load,
        bcs=bcs,
        petsc_options_prefix="rods_end_compliance_",
        petsc_options={"ksp_type": "preonly", "pc_type": "lu"},
    )
    uh = problem.solve()

    # the 1D field: cross-section means (trapezoid in r, weight 2πr) at stations in the middle, a line in z
    r = np.linspace(0.0, 1.0 - 1e-12, 401)
    z = np.linspace(0.35, 0.65, 5) * _LENGTH
    pts = np.array([[ri, zi, 0.0] for zi in z for ri in r])
    uz = _axial_displacement_at(uh, pts).reshape(z.size, r.size)
    mean = np.trapezoid(uz * 2 * r, r, axis=1)  # ∫ u_z 2πr dr / π
    slope, at_base = np.polyfit(z, mean, 1)
    z_e = rod.bar_offset - rod.cap_height  # the equal-mass bar's end (z = 0: the cap's base)
    apex = _axial_displacement_at(uh, np.array([[0.0, -rod.cap_height, 0.0]]))[0]
    half_space = (1 - ν**2) * 3 * F / (4 * a * E)
    return float((apex - (at_base + slope * z_e) - half_space) * E / F)
