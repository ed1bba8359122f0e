"""The stiffness applied element by element (scene key ``fe.operator = "matrix-free"``): K x without the
assembled matrix, for the serial array backends (:mod:`rods.fe.backend`; issue 16's element kernel).

The explicit step is one product K u_n, bound by memory traffic (results/gpu-throughput.md: cuSPARSE's CSR
product at 77-80% of the device copy rate). The assembled CSR matrix of vector Q1 hexahedra reads ~81 values
and column indices a row, 3 rows a node: ~2.9 kB a node. This kernel reads, per cell, its node indices, the
inverse Jacobian J⁻¹ and the weight w_q |det J| at each Gauss point (per-element geometry: graded and
curved-cap cells exact, no uniform-box shortcut) and the cell's Lamé parameters: 8 x (9 + 1) + 2 values, ~0.7 kB
a cell, about one cell a node. The products are the same bilinear form as :func:`rods.fe.forms.stiffness_form`
at the same quadrature rule, so K x agrees with the assembled product to round-off
(``tests/fe/test_matrixfree.py``):

    (K u)_a,i = Σ_cells Σ_q w_q |det J_q| W(x_q) [σ(ε(u))_ij ∂N_a/∂x_j + δ_i,r σ_θθ N_a / r]   (axisymmetric term
    only there; W = 2πr axisymmetric, 1 in 3D)

with ∇u = Σ_a u_a ⊗ ∇̂N_a J⁻¹ at each point, ε its symmetric part (and ε_θθ = u_r / r), σ = λ tr ε I + 2μ ε.
The cells' products are summed into the nodes by a constant 0/1 matrix (one sparse product), so the same
code runs on NumPy/SciPy and on CuPy/cuSPARSE (``xp``): the contractions with the reference gradients are
matrix products (BLAS), the pointwise physics one vector operation per tensor component.

Measured (``benchmarks/gpu_throughput.py --backend numpy``, 2026-11-28, this 2-core machine, one core): the 3D
coarse mesh's product (132k DOFs) 65.8 ms against 10.7 ms for the CSR product (6.1x); the axisymmetric paper mesh
(4 x 4 Gauss points) 25x. So on a CPU the default stays the assembled matrix. On a GPU not measured: as array
operations each pointwise step is a kernel that reads and writes (points x cells) arrays, so expect it to lose to
cuSPARSE there too unless the pointwise part is fused into one kernel; the benchmark's "element / SpMV" column
says which to keep.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import basix
import dolfinx
import numpy as np
import scipy.sparse
import ufl
from ufl.algorithms import compute_form_data

from rods.fe.backend import axpy_of
from rods.fe.forms import Materials

__all__ = ["ElementOperator", "ElementStiffness", "element_stiffness", "quadrature_degree"]


@dataclass
class ElementStiffness:
    """What the kernel reads (host arrays; :meth:`to` copies them to a backend), the cells along the last axis
    so that every pointwise operation is one vector operation over all cells and points.

    ``dofs`` (nodes, dim, cells) the cells' DOFs; ``dN`` (dim, points, nodes) the reference gradients ∂N_a/∂ξ_k
    and ``N`` (points, nodes) the values at the Gauss points; ``J_inv`` (dim, dim, points, cells) = ∂ξ/∂x;
    ``weight`` (points, cells) = w_q |det J| W(x_q) [m^3; axisymmetric: per cell of revolution, W = 2πr];
    ``inv_r`` (points, cells) 1/r [1/m] (axisymmetric, else None); ``λ``, ``μ`` (cells,) [Pa]; ``gather``: the
    (DOFs x nodes·dim·cells) 0/1 matrix that sums the cells' products into the nodes; ``K`` the assembled matrix
    (host CSR, the model's: its step limits need it), read only for the contact's rows."""

    dofs: Any
    dN: Any
    N: Any
    J_inv: Any
    weight: Any
    inv_r: Any
    λ: Any
    μ: Any
    gather: Any
    n: int
    K: scipy.sparse.csr_matrix | None = None

    def to(self, backend) -> ElementStiffness:
        """The same arrays on ``backend`` (one copy to a device)."""
        a = backend.asarray
        return ElementStiffness(
            a(self.dofs), a(self.dN), a(self.N), a(self.J_inv), a(self.weight),
            None if self.inv_r is None else a(self.inv_r), a(self.λ), a(self.μ), backend.csr(self.gather), self.n,
            self.K,
        )  # fmt: skip

    def operator(self, backend, scale: Any) -> ElementOperator:
        """A = diag(scale) K with these arrays on ``backend`` (rods.fe.backend.Backend.operator)."""
        return ElementOperator(backend, self, scale)

    def product(self, x: Any, xp: Any) -> Any:
        """K x (module docstring), arrays of namespace ``xp``: the contractions with the reference gradients as
        matrix products (points x nodes against nodes x cells, BLAS), the rest one vector operation per tensor
        component (dim <= 3: loops over components, never over cells or nodes)."""
        dim, points, nodes = self.dN.shape
        u = x[self.dofs]  # [m] (nodes, dim, cells)
        # ∇u_ij = Σ_k ∇̂u_ik (J⁻¹)_kj at every point, ∇̂u_ik = Σ_a ∂N_a/∂ξ_k u_a,i (points, cells)
        grad_ref = [[self.dN[k] @ u[:, i] for k in range(dim)] for i in range(dim)]
        grad = [[sum(grad_ref[i][k] * self.J_inv[k, j] for k in range(dim)) for j in range(dim)] for i in range(dim)]
        tr = sum(grad[i][i] for i in range(dim))
        if self.inv_r is not None:  # the hoop strain u_r / r
            ε_θθ = (self.N @ u[:, 0]) * self.inv_r
            tr = tr + ε_θθ
        λ, μ = self.λ, self.μ
        # w σ_ij = w (λ tr δ_ij + μ (∇u_ij + ∇u_ji)), then P_ik = Σ_j w σ_ij (J⁻¹)_kj
        λ_tr = λ * tr
        wσ = [[self.weight * ((λ_tr if i == j else 0.0) + μ * (grad[i][j] + grad[j][i])) for j in range(dim)]
              for i in range(dim)]  # fmt: skip
        f = xp.empty((nodes, dim, self.dofs.shape[-1]))
        for i in range(dim):  # f_a,i = Σ_q,k ∂N_a/∂ξ_k(q) P_ik(q) [N]
            f[:, i] = sum(self.dN[k].T @ sum(wσ[i][j] * self.J_inv[k, j] for j in range(dim)) for k in range(dim))
        if self.inv_r is not None:
            f[:, 0] += self.N.T @ ((λ_tr + 2.0 * μ * ε_θθ) * self.weight * self.inv_r)
        return self.gather @ f.reshape(-1)


def quadrature_degree(form: ufl.Form) -> int:
    """The quadrature degree FFCx integrates ``form``'s cell integral with: its metadata's, else UFL's
    estimate (the axisymmetric Q1 stiffness: 7, a 4 x 4 Gauss rule; 3D: :data:`rods.fe.forms.QUADRATURE_DEGREE_3D`)."""
    lowering = dict(do_apply_function_pullbacks=True, do_apply_integral_scaling=True, do_apply_geometry_lowering=True)
    data = compute_form_data(form, **lowering, do_apply_restrictions=True, complex_mode=False)
    (integral,) = (i for d in data.integral_data for i in d.integrals)
    meta = integral.metadata()
    return int(meta.get("quadrature_degree", meta["estimated_polynomial_degree"]))


def element_stiffness(
    V: dolfinx.fem.FunctionSpace, mat: Materials, kind: str, form: ufl.Form, K: scipy.sparse.csr_matrix | None = None
) -> ElementStiffness:
    """The kernel's arrays for the stiffness ``form`` (:func:`rods.fe.forms.stiffness_form` on ``V``, Q1, serial)
    at ``form``'s own Gauss rule (:func:`quadrature_degree`); ``K`` its assembled matrix, if any (the rows)."""
    msh = V.mesh
    cell, dim = msh.basix_cell(), msh.geometry.dim
    points, wq = basix.make_quadrature(cell, quadrature_degree(form))
    Q1 = basix.create_element(basix.ElementFamily.P, cell, 1, basix.LagrangeVariant.gll_warped)
    tab = Q1.tabulate(1, points)  # (1 + dim, points, nodes, 1)
    N, dN = tab[0, :, :, 0], np.moveaxis(tab[1:, :, :, 0], 0, -1)
    geo = msh.geometry
    n_cells = msh.topology.index_map(msh.topology.dim).size_local
    X = geo.x[geo.dofmaps[0][:n_cells], :dim]  # [m] (cells, nodes, dim): Q1 geometry, the same node order
    J = np.einsum("eai,qak->eqik", X, dN)  # ∂x/∂ξ
    x_q = np.einsum("qa,eai->eqi", N, X)
    weight = wq * np.abs(np.linalg.det(J))
    inv_r = None
    if kind == "axisymmetric":
        weight = weight * 2 * np.pi * x_q[..., 0]
        inv_r = 1.0 / x_q[..., 0]
    bs = V.dofmap.index_map_bs
    nodes = V.dofmap.list[:n_cells]
    dofs = nodes.T[:, None, :] * bs + np.arange(bs)[None, :, None]  # (nodes, dim, cells)
    n = (V.dofmap.index_map.size_local + V.dofmap.index_map.num_ghosts) * bs
    gather = scipy.sparse.csr_matrix(
        (np.ones(dofs.size), (dofs.reshape(-1), np.arange(dofs.size))), shape=(n, dofs.size)
    )
    J_inv = np.ascontiguousarray(np.linalg.inv(J).transpose(2, 3, 1, 0))  # (k, j, points, cells)
    cells = np.arange(n_cells)
    return ElementStiffness(
        dofs, np.ascontiguousarray(dN.transpose(2, 0, 1)), N, J_inv, np.ascontiguousarray(weight.T),
        None if inv_r is None else np.ascontiguousarray(inv_r.T), mat.λ.x.array[cells].copy(),
        mat.μ.x.array[cells].copy(), gather, n, K,
    )  # fmt: skip


class ElementOperator:
    """A = diag(scale) K applied with :class:`ElementStiffness` (the same interface as the CSR operator:
    ``mult``, ``mult_add``, ``axpy``; ``rows`` for the kinematic contact's prediction, from ``es.K``)."""

    def __init__(self, backend, es: ElementStiffness, scale: Any):
        self.backend, self.xp = backend, backend.xp
        self.es = es.to(backend)
        self.scale = backend.asarray(scale)
        self._K, self._scale_host = es.K, backend.to_host(scale)
        self.axpy = axpy_of(backend)  # y += a x

    @property
    def shape(self) -> tuple[int, int]:
        return self.es.n, self.es.n

    def mult(self, x: Any, y: Any) -> None:
        """y = A x."""
        self.xp.multiply(self.scale, self.es.product(x, self.xp), out=y)

    def mult_add(self, x: Any, y: Any) -> None:
        """y += A x."""
        y += self.scale * self.es.product(x, self.xp)

    def rows(self, R: Any) -> Any:
        """R A as a CSR matrix of the backend (R: a few rows, the contact's; formed once on the host)."""
        R_host = R if scipy.sparse.issparse(R) else R.get()
        return self.backend.csr(R_host @ scipy.sparse.diags(self._scale_host) @ self._K)

    def destroy(self) -> None:
        self.es = None
