"""The elastodynamic forms (rods.fe.forms) against closed forms: the uniaxial-stress patch test (energy, reaction,
equilibrium), rigid motion, lumped mass and tributary area, on distorted Q1 meshes, axisymmetric and 3D."""

from __future__ import annotations

import dolfinx
import numpy as np
import pytest
import ufl
from mpi4py import MPI

from rods.fe import forms

E, ν, ρ = 200e9, 0.29, 7850.0  # [Pa], [-], [kg/m^3]
R, L = 0.01, 0.05  # axisymmetric: rod radius and length [m]
A_X, A_Y = 0.012, 0.008  # 3D: the box's cross-section [m]
ε0 = 1e-3  # axial strain of the patch test [-]


def _distorted_mesh(kind: str):
    """A Q1 mesh of the rod (axisymmetric: [0, R] x [0, L]; 3D: a box A_X x A_Y x L) whose interior nodes are
    moved at random by up to 30% of a cell: cells are general (non-affine) quadrilaterals/hexahedra."""
    if kind == "axisymmetric":
        n = (4, 10)
        msh = dolfinx.mesh.create_rectangle(MPI.COMM_SELF, [[0, 0], [R, L]], n, dolfinx.mesh.CellType.quadrilateral)
        size = np.array([R, L])
    else:
        n = (3, 3, 8)
        pts = [[0, 0, 0], [A_X, A_Y, L]]
        msh = dolfinx.mesh.create_box(MPI.COMM_SELF, pts, n, dolfinx.mesh.CellType.hexahedron)
        size = np.array([A_X, A_Y, L])
    gdim = len(size)
    x = msh.geometry.x[:, :gdim]
    inside = np.all((x > 1e-12 * size) & (x < (1 - 1e-12) * size), axis=1)
    h = size / np.array(n)
    x[inside] += np.random.default_rng(5).uniform(-0.3, 0.3, size=(inside.sum(), gdim)) * h
    return msh, size


def _constant_materials(msh) -> forms.Materials:
    Q = dolfinx.fem.functionspace(msh, ("DG", 0))
    λ, μ = E * ν / ((1 + ν) * (1 - 2 * ν)), E / (2 * (1 + ν))  # [Pa]
    mat = forms.Materials(*(dolfinx.fem.Function(Q) for _ in range(3)))
    for f, value in zip((mat.λ, mat.μ, mat.ρ), (λ, μ, ρ), strict=True):
        f.x.array[:] = value
    return mat


def _setup(kind: str):
    msh, size = _distorted_mesh(kind)
    V = dolfinx.fem.functionspace(msh, ("Lagrange", 1, (msh.geometry.dim,)))
    mat = _constant_materials(msh)
    K = forms.assemble_csr(dolfinx.fem.form(forms.stiffness_form(V, mat, kind)))
    section = np.pi * R**2 if kind == "axisymmetric" else A_X * A_Y  # [m^2]
    return msh, size, V, mat, K, section


@pytest.mark.parametrize("kind", forms.KINDS)
def test_uniaxial_stress_patch(kind):
    """u = (-ν ε0 x_⊥, ε0 z): uniaxial stress σ_zz = E ε0, held exactly by Q1 on distorted cells. Then
    ½ uᵀ K u = ½ E ε0² A L; K u vanishes at every node off the end faces (equilibrium, traction-free lateral
    surface); the axial reactions on z = L sum to E ε0 A and those on z = 0 to -E ε0 A."""
    msh, size, V, _, K, section = _setup(kind)
    gdim = msh.geometry.dim
    u = dolfinx.fem.Function(V)
    u.interpolate(lambda x: np.vstack([-ν * ε0 * x[i] for i in range(gdim - 1)] + [ε0 * x[gdim - 1]]))
    U = u.x.array
    energy = 0.5 * U @ (K @ U)  # [J]
    assert energy == pytest.approx(0.5 * E * ε0**2 * section * L, rel=1e-12)
    f = (K @ U).reshape(-1, gdim)  # [N] nodal forces
    z = V.tabulate_dof_coordinates()[:, gdim - 1]
    top, bottom = np.isclose(z, L), np.isclose(z, 0.0)
    scale = E * ε0 * section  # [N]
    assert np.abs(f[~(top | bottom)]).max() <= 1e-10 * scale
    assert f[top, -1].sum() == pytest.approx(scale, rel=1e-12)
    assert f[bottom, -1].sum() == pytest.approx(-scale, rel=1e-12)


@pytest.mark.parametrize("kind", forms.KINDS)
def test_rigid_axial_translation_costs_no_energy(kind):
    """K (0, ..., 1) = 0: an axial translation strains nothing (in axisymmetry a radial one would: hoop strain)."""
    msh, _, V, _, K, _ = _setup(kind)
    U = np.zeros(K.shape[0])
    U[msh.geometry.dim - 1 :: msh.geometry.dim] = 1e-3  # [m]
    assert np.abs(K @ U).max() <= 1e-12 * abs(K).max() * 1e-3
    if kind == "axisymmetric":
        U_r = np.zeros(K.shape[0])
        U_r[0::2] = 1e-3  # [m] a radial "translation" stretches every hoop
        assert U_r @ (K @ U_r) > 0


@pytest.mark.parametrize("kind", forms.KINDS)
def test_lumped_mass_and_tributary_area(kind):
    """Row-sum lumped mass: every entry positive (axis nodes too), each component sums to ρ A L; the tributary
    areas of the face z = L sum to its area A."""
    msh, _, V, mat, _, section = _setup(kind)
    gdim = msh.geometry.dim
    n = V.dofmap.index_map.size_local * gdim
    m = forms.assemble_owned(dolfinx.fem.form(forms.lumped_mass_form(V, mat, kind)), n).reshape(-1, gdim)
    assert m.min() > 0
    assert np.allclose(m.sum(axis=0), ρ * section * L, rtol=1e-12)
    fdim = msh.topology.dim - 1
    facets = dolfinx.mesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[gdim - 1], L))
    tags = dolfinx.mesh.meshtags(msh, fdim, facets, np.full(len(facets), 7, dtype=np.int32))
    ds = ufl.Measure("ds", domain=msh, subdomain_data=tags)
    a = forms.assemble_owned(dolfinx.fem.form(forms.tributary_area_form(V, ds(7), kind)), n).reshape(-1, gdim)
    assert a[:, -1].sum() == pytest.approx(section, rel=1e-12) and np.all(a[:, :-1] == 0)


def test_an_unknown_kind_is_refused():
    msh, _ = _distorted_mesh("axisymmetric")
    x = ufl.SpatialCoordinate(msh)
    with pytest.raises(ValueError, match="kind must be one of"):
        forms.measure_weight(x, "plane-strain")
    with pytest.raises(ValueError, match="kind must be one of"):
        forms.strain(ufl.as_vector([x[0], x[1]]), x, "plane-strain")
