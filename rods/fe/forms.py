"""UFL forms of small-strain linear elastodynamics, axisymmetric or 3D (a parameter, not a copy).

Axisymmetric (torsion-free) kinematics in cylindrical coordinates (r, θ, z) with x = r, y = z:
u = (u_r, u_z)(r, z), and the strain (ordered r, θ, z)

    ε = [[∂u_r/∂r, 0, ½(∂u_r/∂z + ∂u_z/∂r)], [0, u_r/r, 0], [·, 0, ∂u_z/∂z]],

the hoop strain u_r/r being the only term beyond the planar gradient. Volume integrals over the
solid of revolution are ∫ f 2πr dr dz, so every form carries the weight w = 2πr. In 3D the strain
is sym(∇u) and w = 1. Hooke's law σ = λ tr(ε) I + 2μ ε (isotropic, linear elastic, small strain).
Lamé parameters and density are cellwise constant (DG0) so each rod may have its own material.
"""

from __future__ import annotations

from dataclasses import dataclass

import dolfinx
import numpy as np
import scipy.sparse
import ufl

from rods.scene import Scene

__all__ = [
    "Materials",
    "assemble_csr",
    "assemble_owned",
    "lumped_mass_form",
    "materials",
    "measure_weight",
    "stiffness_form",
    "strain",
    "stress",
]

KINDS = ("axisymmetric", "3d")


def measure_weight(x: ufl.SpatialCoordinate, kind: str):
    """Volume weight w: 2πr for axisymmetric (r = x[0]), 1 in 3D."""
    if kind == "axisymmetric":
        return 2 * ufl.pi * x[0]
    if kind == "3d":
        return 1.0
    raise ValueError(f"kind must be one of {KINDS}")


def strain(u, x: ufl.SpatialCoordinate, kind: str):
    """Small strain ε(u) as a 3x3 tensor. Axisymmetric: ordered (r, θ, z) with hoop strain u_r/r."""
    if kind == "axisymmetric":
        r = x[0]
        g = ufl.grad(u)  # [[∂u_r/∂r, ∂u_r/∂z], [∂u_z/∂r, ∂u_z/∂z]]
        shear = 0.5 * (g[0, 1] + g[1, 0])
        return ufl.as_tensor([[g[0, 0], 0, shear], [0, u[0] / r, 0], [shear, 0, g[1, 1]]])
    if kind == "3d":
        return ufl.sym(ufl.grad(u))
    raise ValueError(f"kind must be one of {KINDS}")


def stress(ε, λ, μ):
    """Hooke's law σ = λ tr(ε) I + 2μ ε [Pa] (isotropic, linear elastic)."""
    return λ * ufl.tr(ε) * ufl.Identity(3) + 2 * μ * ε


@dataclass
class Materials:
    """The Lamé parameters and density as cellwise-constant fields (:func:`materials`): each rod's own."""

    λ: dolfinx.fem.Function  # [Pa], DG0
    μ: dolfinx.fem.Function  # [Pa], DG0
    ρ: dolfinx.fem.Function  # [kg/m^3], DG0


def materials(
    msh: dolfinx.mesh.Mesh, cell_tags: dolfinx.mesh.MeshTags, scene: Scene, tags: dict[str, int]
) -> Materials:
    """Cellwise (DG0) λ, μ, ρ from each rod's :class:`rods.scene.Material`, set by the cell tags."""
    Q = dolfinx.fem.functionspace(msh, ("DG", 0))
    fields = Materials(*(dolfinx.fem.Function(Q, name=n) for n in ("lambda", "mu", "rho")))
    for k, rod in enumerate(scene.rods, start=1):
        cells = cell_tags.find(tags[f"rod{k}"])
        λ, μ = rod.material.lame
        fields.λ.x.array[cells] = λ
        fields.μ.x.array[cells] = μ
        fields.ρ.x.array[cells] = rod.material.density
    for f in (fields.λ, fields.μ, fields.ρ):
        f.x.scatter_forward()
    return fields


# 3D: 2x2x2 Gauss points for the trilinear hexahedra (the usual full integration, exact for
# parallelepipeds); UFL's estimate (degree 5: 3x3x3 points) triples the assembly time for nothing. The paper's
# Abaqus model used C3D8R (one point, hourglass control): full integration has no hourglass modes and is stiffer in
# shear and bending on coarse elements, a difference in the rods' lateral ringing more than in their axial waves.
QUADRATURE_DEGREE_3D = 2


def stiffness_form(V: dolfinx.fem.FunctionSpace, mat: Materials, kind: str) -> ufl.Form:
    """a(u, v) = ∫ σ(ε(u)) : ε(v) w dx — the stiffness K (paper's linear elastic rods)."""
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    x = ufl.SpatialCoordinate(V.mesh)
    w = measure_weight(x, kind)
    dx = ufl.dx(metadata={"quadrature_degree": QUADRATURE_DEGREE_3D}) if kind == "3d" else ufl.dx
    return ufl.inner(stress(strain(u, x, kind), mat.λ, mat.μ), strain(v, x, kind)) * w * dx


def lumped_mass_form(V: dolfinx.fem.FunctionSpace, mat: Materials, kind: str) -> ufl.Form:
    """Row-sum lumped mass: m_i = Σ_j ∫ ρ N_i N_j w dx = ∫ ρ 1·v w dx (a vector form).

    Assembling the consistent mass against the constant unit field gives its row sums directly.
    Unlike vertex (nodal-quadrature) lumping, nodes on the axis keep a positive mass although the
    weight 2πr vanishes there (their basis functions do not).
    """
    v = ufl.TestFunction(V)
    x = ufl.SpatialCoordinate(V.mesh)
    one = ufl.as_vector([1.0] * V.mesh.geometry.dim)
    return mat.ρ * ufl.inner(one, v) * measure_weight(x, kind) * ufl.dx


def tributary_area_form(V: dolfinx.fem.FunctionSpace, ds: ufl.Measure, kind: str) -> ufl.Form:
    """a_i = ∫ N_i w ds on a face (axial component): the row-sum tributary area of node i [m^2]."""
    v = ufl.TestFunction(V)
    x = ufl.SpatialCoordinate(V.mesh)
    e_axis = np.zeros(V.mesh.geometry.dim)
    e_axis[1 if kind == "axisymmetric" else 2] = 1.0
    return ufl.inner(ufl.as_vector(e_axis.tolist()), v) * measure_weight(x, kind) * ds


def assemble_owned(form: dolfinx.fem.Form, n: int) -> np.ndarray:
    """The assembled vector of a compiled linear ``form``, ghost contributions summed in, its first ``n``
    (owned) entries as a numpy array (collective)."""
    import dolfinx.fem.petsc
    from petsc4py import PETSc

    b = dolfinx.fem.petsc.assemble_vector(form)
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    out = b.array_r[:n].copy()
    b.destroy()
    return out


def assemble_csr(form: dolfinx.fem.Form) -> scipy.sparse.csr_matrix:
    """The assembled matrix of a compiled bilinear ``form`` as a SciPy CSR matrix (collective: this rank's owned
    rows, ghost contributions summed in; serial: every row and column), from DOLFINx's own CSR assembly with the
    node blocks expanded: no PETSc matrix, no copy."""
    A = dolfinx.fem.assemble_matrix(form, block_mode=dolfinx.la.BlockMode.expanded)
    A.scatter_reverse()
    S = A.to_scipy()
    S._rods_owner = A  # the SciPy arrays share the DOLFINx matrix's memory: keep it alive with them
    return S
