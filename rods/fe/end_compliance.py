"""The end compliance of a rod under a Hertz pressure: how much stiffer a rod's end is than a half-space.

The analytical model (paper Sec. 2.1) joins two 1D bars by Hertz's force-approach law, whose approach
is the half-space's: the displacement of the contact centre relative to points *infinitely* far away.
A bar of radius b already carries the far part of that deformation as its own uniform strain F/(EA),
so bar + half-space counts the far field twice. The correct local law is the approach of the contact
centre relative to the bar's 1D displacement field extrapolated to the end,

    u_z(0, 0) - ū_1D(0) = (1 - ν²) 3F/(4aE) + χ(ν) F/(E b),

the first term being the half-space's centre displacement under p = p0 sqrt(1 - r²/a²) (Johnson, Contact
Mechanics, Eq. 4.22), the second the rod's end correction, independent of a for a << b (the load acts as a
point load seen from the far field; checked in tests/fe/test_end_compliance.py). χ < 0: the end is
stiffer than the half-space by a linear spring. :func:`end_correction` computes χ(ν) by linear elastostatics
on a rod of radius b = 1, length 8b, E = 1 (axisymmetric, Q2, mesh graded towards the loaded centre):
Hertz pressure of radius a on z = 0, the balancing uniform traction on z = L, u_r = 0 on the axis, one
axial point constraint on the far end (the loads balance, so its reaction vanishes). ū_1D is the line
fitted to the cross-section mean of u_z over the middle of the rod (0.35 L to 0.65 L), where the end
disturbances have decayed (Saint-Venant: over about one diameter). The table :data:`rods.hertz.ROD_END_CHI`
holds its values; ``python benchmarks/rod_end_compliance.py`` recomputes them.
"""

from __future__ import annotations

import math

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import ufl
from mpi4py import MPI

from rods import hertz
from rods.fe.forms import measure_weight, strain, stress
from rods.scene import Material

__all__ = ["end_correction"]

_LENGTH = 8.0  # rod length in radii [-]: two decay lengths either side of the fitted middle
_KIND = "axisymmetric"


def _graded_rod(n: int) -> dolfinx.mesh.Mesh:
    """Quadrilaterals on r in [0, 1], z in [0, L], n x 2n, graded quadratically towards r = 0, z = 0."""
    msh = dolfinx.mesh.create_rectangle(
        MPI.COMM_SELF, [[0.0, 0.0], [1.0, 1.0]], [n, 2 * n], dolfinx.mesh.CellType.quadrilateral
    )
    x = msh.geometry.x
    x[:, 0] = x[:, 0] ** 2
    x[:, 1] = _LENGTH * x[:, 1] ** 2
    return msh


def _axial_displacement_at(uh: dolfinx.fem.Function, points: np.ndarray) -> np.ndarray:
    """u_z at ``points`` (k x 3) of a serial mesh."""
    msh = uh.function_space.mesh
    tree = dolfinx.geometry.bb_tree(msh, msh.topology.dim)
    candidates = dolfinx.geometry.compute_collisions_points(tree, points)
    hits = dolfinx.geometry.compute_colliding_cells(msh, candidates, points)
    cells = np.array([hits.links(i)[0] for i in range(points.shape[0])], dtype=np.int32)
    return uh.eval(points, cells).reshape(points.shape[0], -1)[:, 1]


def end_correction(ν: float, a: float = 0.15, n: int = 48) -> float:
    """χ(ν) [-] of the module docstring: (u_z(0,0) - ū_1D(0) - (1-ν²) 3F/(4aE)) E b / F.

    ``a``: Hertz radius in rod radii (a << 1); ``n``: radial elements (the axial count is 2n)."""
    msh = _graded_rod(n)
    E, F = 1.0, 1.0  # [Pa], [N] (linear: χ is dimensionless)
    λ, μ = Material(density=1.0, youngs_modulus=E, poisson_ratio=ν).lame  # [Pa]
    V = dolfinx.fem.functionspace(msh, ("Lagrange", 2, (2,)))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    x = ufl.SpatialCoordinate(msh)
    w = measure_weight(x, _KIND)
    stiffness = ufl.inner(stress(strain(u, x, _KIND), λ, μ), strain(v, x, _KIND)) * w * ufl.dx

    fdim = msh.topology.dim - 1
    loaded = dolfinx.mesh.locate_entities_boundary(msh, fdim, lambda p: np.isclose(p[1], 0.0))
    far = dolfinx.mesh.locate_entities_boundary(msh, fdim, lambda p: np.isclose(p[1], _LENGTH))
    facets = np.concatenate([loaded, far])
    order = np.argsort(facets)
    tags = np.concatenate([np.full(loaded.size, 1, np.int32), np.full(far.size, 2, np.int32)])[order]
    # the pressure's square-root edge needs a high quadrature degree on the few facets it covers
    ds = ufl.Measure("ds", msh, subdomain_data=dolfinx.mesh.meshtags(msh, fdim, facets[order], tags))
    p0 = float(hertz.peak_pressure(F, a))  # Hertz peak pressure for force F [Pa]
    p = p0 * ufl.sqrt(ufl.max_value(1 - x[0] ** 2 / a**2, 0.0))
    load = p * v[1] * w * ds(1, degree=24) - F / math.pi * v[1] * w * ds(2)  # compresses the rod along +z

    Vr, _ = V.sub(0).collapse()
    Vz, _ = V.sub(1).collapse()
    axis = dolfinx.fem.locate_dofs_geometrical((V.sub(0), Vr), lambda p: np.isclose(p[0], 0.0))
    pin = dolfinx.fem.locate_dofs_geometrical(
        (V.sub(1), Vz), lambda p: np.isclose(p[0], 0.0) & np.isclose(p[1], _LENGTH)
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
    u1d_end = np.polyfit(z, mean, 1)[1]
    centre = _axial_displacement_at(uh, np.array([[0.0, 0.0, 0.0]]))[0]
    half_space = (1 - ν**2) * 3 * F / (4 * a * E)
    return float((centre - u1d_end - half_space) * E / F)
