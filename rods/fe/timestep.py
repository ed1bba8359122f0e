"""The explicit model's step: its limits and the step it marches at (:mod:`rods.fe.explicit` for the theory).

:func:`time_step` computes, once per model after K, the lumped mass and the contact are set up:

* ω_max [rad/s] of M^-1 (K + K_c), K_c the contact stiffness at full engagement, by SLEPc Krylov-Schur on
  M^-½ (K + K_c) M^-½ (:func:`omega_max`; on a device backend thick-restart Lanczos there,
  :func:`largest_eigenvalue_on`), to the step's need (an upper estimate within
  :data:`rods.fe.explicit.EIGEN_TOL`: solved to round-off it was most of a 3D set-up, serial 2026-11-27:
  10.2 s of set-up at 132k DOFs and 156.9 s at 983k, now 3.8 s and 30.6 s), and without contact (one solve
  when the contact law has no springs, as the default kinematic law: the operator is the same); the linear limit
  Δt_crit = 2/ω_max (sqrt(1 + ξ²) - ξ) with the bulk-viscosity fraction ξ (:func:`rods.fe.explicit.stable_step`);
* the Gershgorin bound ω_max² <= max_i Σ_j |(K + K_c)_ij| / m_i (:func:`gershgorin`), a check, marched at only
  where the eigenvalue solve does not converge (a true upper bound: a smaller step, with a warning);
* the contact-switching limit SWITCHING/ω_c of an isolated penalty pair (:func:`rods.fe.explicit.switching_step`);
* the element estimate h_min/c_d, c_d the largest dilatational wave speed;
* the step: ``fe.dt_fraction`` x Δt_crit capped by the switching limit when ``fe.dt`` is "auto", else
  ``fe.dt`` checked against both limits (:class:`rods.scene.SceneError` above either), and the stiffness-
  proportional damping β = 2ξ/ω_max [s] and the step count to the scene's end time.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import dolfinx
import numpy as np
import scipy.sparse
from mpi4py import MPI
from petsc4py import PETSc

from rods.fe.backend import Backend
from rods.fe.explicit import EIGEN_TOL, NotConverged, largest_eigenvalue
from rods.fe.forms import assemble_csr
from rods.fe.mesh import cell_sizes
from rods.fe.mesh3d import cell_sizes_3d
from rods.scene import SceneError
from rods.stability import march_step, one_step_remedy, stable_step, switching_step

__all__ = [
    "TimeStep",
    "abs_row_sums",
    "gershgorin",
    "largest_eigenvalue_on",
    "omega_max",
    "start_vector",
    "stiffness_row_sums",
    "time_step",
]


@dataclass(frozen=True)
class TimeStep:
    """The explicit step and the limits it was chosen under (:func:`time_step`): the highest frequency with and
    without the contact, the critical step (rods.stability.stable_step of ω_max and the bulk viscosity ξ), the
    element and Gershgorin estimates, the contact-switching limit, and the step marched at with its count to the end
    time."""

    ω_max: float  # [rad/s] with the contact at full engagement
    ω_max_K: float  # [rad/s] without contact
    ξ: float  # fe.bulk_viscosity: stiffness-proportional damping, fraction of critical at ω_max [-]
    dt_critical: float  # [s] the linear limit with contact
    dt_critical_no_contact: float  # [s]
    dt_gershgorin: float  # [s] a safe lower bound of dt_critical
    ω_contact: float  # [rad/s] an isolated contact pair's frequency (0: kinematic)
    dt_switching: float  # [s] the contact-switching limit (inf: none)
    h_min: float  # [m] the smallest element
    dt_element: float  # [s] h_min / c_d
    dt: float  # [s] the step marched at
    β_visc: float  # [s] stiffness-proportional damping C = β K
    steps: int  # steps to the scene's end time


class SetUpModel(Protocol):
    """What the step is computed from: an explicit model after its set-up (:class:`rods.fe.model.ExplicitModel`
    is one; named here by what is read, so that this module does not import the model that calls it)."""

    scene: Any  # rods.scene.Scene
    kind: str  # "axisymmetric" | "3d"
    comm: MPI.Comm
    backend: Backend
    V: dolfinx.fem.FunctionSpace
    rm: Any  # the rods' mesh (rods.fe.mesh), its .mesh the DOLFINx mesh
    stiffness: dolfinx.fem.Form  # the stiffness form K
    K: Any  # K assembled: a PETSc Mat, or a SciPy CSR matrix on the array backends
    inv_mass: np.ndarray  # owned lumped inverse mass [1/kg], 0 on constrained entries
    contact: Any  # rods.fe.contact.PenaltyContact or rods.fe.kinematic.KinematicContact
    n_local: int  # owned DOFs
    n_global: int
    bs: int  # block size (the displacement's components)


def _vec(comm: MPI.Comm, a: np.ndarray, n_global: int, bs: int) -> PETSc.Vec:
    """A PETSc Vec that shares the memory of the owned numpy array ``a``."""
    return PETSc.Vec().createWithArray(a, size=(a.size, n_global), bsize=bs, comm=comm)


def omega_max(model: SetUpModel, with_contact: bool, K_device=None) -> float:
    """ω_max [rad/s] of M^-1 (K [+ K_c at full engagement]) via M^-½ (K + K_c) M^-½: SLEPc on the host
    (K a PETSc Mat or the array backends' SciPy CSR), or thick-restart Lanczos on the device when the
    backend is one (``K_device``: K there, :func:`largest_eigenvalue_on`), from :func:`start_vector`."""
    start = start_vector(model)
    if scipy.sparse.issparse(model.K):  # the array backends: the operator on their arrays (:func:`_scaled`)
        on_device = model.backend.on_device
        scaled = _scaled(model, with_contact, K_device if on_device else model.K)
        if on_device:
            return math.sqrt(largest_eigenvalue_on(model.backend, scaled, model.n_local, start=start))

        def add_scaled(x: np.ndarray, y: np.ndarray) -> None:
            y += scaled(x)

        return math.sqrt(largest_eigenvalue(add_scaled, model.n_local, model.comm, start=start))
    D = np.sqrt(model.inv_mass)
    z, Kz = np.zeros(model.n_local), np.zeros(model.n_local)
    zv, Kzv = (_vec(model.comm, a, model.n_global, model.bs) for a in (z, Kz))

    def apply(x: np.ndarray, y: np.ndarray) -> None:
        np.multiply(D, x, out=z)
        model.K.mult(zv, Kzv)
        if with_contact:
            model.contact.apply_stiffness(z, Kz)
        y += D * Kz

    return math.sqrt(largest_eigenvalue(apply, model.n_local, model.comm, start=start))


def start_vector(model: SetUpModel) -> np.ndarray:
    """The eigenvalue solves' start vector, owned entries: 1 + 0.1 sin(k·x + 7.9 c) at each DOF's node x [m]
    and component c, k = (3.1, 4.3, 5.7)/h_ref with h_ref = the thinner rod's diameter / 127 (1e-4 m on the
    paper's 12.7 mm rods; a fixed 1e-4 m was smooth across the elements of a scene 10 x smaller): a wavelength
    below the elements whatever the scene's size, so it is
    rough from node to node like the top modes and not orthogonal to them by any symmetry of the mesh, and the
    same vector on any rank count and DOF numbering (the estimate of ω_max depends on the start at the level of
    its residual, rods.fe.explicit.EIGEN_TOL)."""
    V, bs = model.V, model.bs
    x = V.tabulate_dof_coordinates()[: V.dofmap.index_map.size_local]  # [m] owned nodes
    h_ref = min(rod.diameter for rod in model.scene.rods) / 127.0  # [m]
    phase = x @ (np.array([3.1, 4.3, 5.7]) / h_ref)
    return (1.0 + 0.1 * np.sin(phase[:, None] + 7.9 * np.arange(bs)[None, :])).ravel()


def _scaled(model: SetUpModel, with_contact: bool, K: Any) -> Callable[[Any], Any]:
    """x -> M^-½ (K [+ K_c]) M^-½ x on the backend's arrays (``K`` there: a CSR matrix)."""
    D = model.backend.asarray(np.sqrt(model.inv_mass))

    def apply(x: Any) -> Any:
        z = D * x.ravel()
        y = K @ z
        if with_contact:
            model.contact.apply_stiffness(z, y)
        return D * y

    return apply


def largest_eigenvalue_on(
    backend: Backend,
    apply: Callable[[Any], Any],
    n: int,
    tol: float = EIGEN_TOL,
    ncv: int = 40,
    keep: int = 20,
    start: np.ndarray | None = None,
) -> float:
    """Upper estimate θ + ‖A y - θ y‖ of the largest eigenvalue of the symmetric operator x -> ``apply(x)``
    (arrays of ``backend``; as :func:`rods.fe.explicit.largest_eigenvalue`) by thick-restart Lanczos (Wu &
    Simon 2000; the Krylov-Schur restart of SLEPc for a symmetric operator), written once against the
    backend's array namespace: on a device every vector operation stays there.

    ``ncv`` basis vectors, fully reorthogonalised (classical Gram-Schmidt twice); the projected matrix
    T = V A Vᵀ (ncv x ncv) lives on the host. At each restart the ``keep`` largest Ritz pairs are kept and
    the residual direction is appended. Converged when the largest Ritz pair's residual
    ‖A y - θ y‖ = β |s_last| <= ``tol`` θ (SLEPc's relative criterion and the same tolerance as
    :func:`rods.fe.explicit.largest_eigenvalue`), returned as θ + β |s_last|; the same deterministic start
    vector (or ``start``). :class:`rods.fe.explicit.NotConverged` after 100 n_cv products without convergence.
    (CuPy's own ``eigsh`` tests an absolute residual, which an operator of norm ~1e14 never meets.)"""
    xp = backend.xp
    ncv = max(2, min(ncv, n))
    keep = max(1, min(keep, ncv - 2))
    V = xp.zeros((ncv, n))
    T = np.zeros((ncv, ncv))
    v0 = backend.asarray(1.0 + 0.1 * np.sin(np.arange(n, dtype=np.float64)) if start is None else start)
    V[0] = v0 / float(xp.linalg.norm(v0))
    j, products = 0, 0
    while True:
        while j < ncv:  # expand the basis: column j of T = V A V[j]
            w = apply(V[j])
            products += 1
            h = V[: j + 1] @ w
            w -= V[: j + 1].T @ h
            h2 = V[: j + 1] @ w  # second pass: orthogonal to round-off
            w -= V[: j + 1].T @ h2
            T[: j + 1, j] = T[j, : j + 1] = backend.to_host(h + h2)
            β = float(xp.linalg.norm(w))
            if j + 1 < ncv:
                if β == 0.0:  # an invariant subspace: T holds the exact eigenvalues
                    return float(np.linalg.eigvalsh(T[: j + 1, : j + 1])[-1])
                V[j + 1] = w / β
            j += 1
        θ, S = np.linalg.eigh(T)  # ascending
        residual = β * abs(S[-1, -1])  # ‖A y - θ y‖ of the largest Ritz pair
        if residual <= tol * abs(θ[-1]) or β == 0.0:
            return float(θ[-1] + residual)
        if products >= 100 * ncv:
            raise NotConverged(f"Lanczos: largest eigenvalue not converged after {products} products")
        top = S[:, -keep:]  # thick restart: the keep largest Ritz vectors, then the residual direction
        V[:keep] = backend.asarray(np.ascontiguousarray(top.T)) @ V
        V[keep] = w / β
        T[:] = 0.0
        T[:keep, :keep] = np.diag(θ[-keep:])
        j = keep


def abs_row_sums(S: scipy.sparse.spmatrix, chunk: int = 1 << 22) -> np.ndarray:
    """Σ_j |S_ij| of every row of a CSR or BSR matrix, ``chunk`` stored values at a time: ``abs(S)`` copies the
    whole matrix, values and indices (3D, 983k DOFs, serial, one run each: 1.86 s for the CSR K, 0.33 s in chunks;
    BSR 1.53 s, 0.59 s)."""
    bsr = S.format == "bsr"
    if not bsr and S.format != "csr":
        S = S.tocsr()
    bs, bc = S.blocksize if bsr else (1, 1)
    data, indptr = S.data.reshape(-1, bs, bc), S.indptr
    n_rows = indptr.size - 1  # (block) rows
    out = np.zeros((n_rows, bs))
    step = max(1, chunk * n_rows // max(int(indptr[-1]) * bs * bc, 1))  # (block) rows per chunk
    for r0 in range(0, n_rows, step):
        r1 = min(r0 + step, n_rows)
        starts = indptr[r0:r1]
        filled = np.flatnonzero(indptr[r0 + 1 : r1 + 1] > starts)  # reduceat needs every start inside
        if filled.size:
            seg = np.abs(data[indptr[r0] : indptr[r1]]).sum(axis=2)  # [stored blocks x bs]
            out[r0 + filled] = np.add.reduceat(seg, starts[filled] - indptr[r0], axis=0)
    return out.ravel()


def stiffness_row_sums(model: SetUpModel) -> np.ndarray:
    """Σ_j |K_ij| [N/m] of this rank's owned rows (collective): the array backends' K, else DOLFINx's own CSR
    matrix assembled for this (:func:`rods.fe.forms.assemble_csr`, its ghost rows' contributions summed into their
    owners' rows: without that a row on a partition boundary holds only this rank's cells' part, and the bound
    below could fall under ω_max²)."""
    K = model.K if scipy.sparse.issparse(model.K) else assemble_csr(model.stiffness)
    return abs_row_sums(K)[: model.n_local]


def gershgorin(model: SetUpModel) -> float:
    """Gershgorin bound on ω_max² [1/s²]: max_i Σ_j |(K + K_c)_ij| / m_i over unconstrained entries."""
    rows = stiffness_row_sums(model)
    model.contact.add_abs_row_sums(rows)
    return model.comm.allreduce(float(np.max(rows * model.inv_mass, initial=0.0)), op=MPI.MAX)


def _omega_or_bound(model: SetUpModel, with_contact: bool, K_device: Any, ω_bound: float) -> float:
    """:func:`omega_max`, or the Gershgorin bound ``ω_bound`` [rad/s] with a warning where the eigenvalue solve
    does not converge (a smaller, safe step: never a Ritz value that may lie below ω_max)."""
    try:
        return omega_max(model, with_contact, K_device)
    except NotConverged as e:
        warnings.warn(f"{e}; the step is set from the Gershgorin bound (smaller, safe)", RuntimeWarning, stacklevel=2)
        return ω_bound


def time_step(model: SetUpModel) -> TimeStep:
    """The limits and the step of ``model`` (collective); see the module docstring."""
    sc, be = model.scene, model.backend
    ω_bound = math.sqrt(gershgorin(model))  # [rad/s] a true upper bound, with the contact at full engagement
    K_device = be.csr(model.K) if be.on_device else None  # copied once for both eigenvalues
    ω_K, ξ = _omega_or_bound(model, False, K_device, ω_bound), sc["fe.bulk_viscosity"]
    # a law without springs adds nothing to the operator: the second solve would repeat the first exactly
    ω = _omega_or_bound(model, True, K_device, ω_bound) if model.contact.stiffens else ω_K
    del K_device
    dt_critical = stable_step(ω, ξ)
    ω_contact = model.contact.pair_frequency(model.inv_mass)
    dt_switching = switching_step(ω_contact)
    h_min = min(cell_sizes_3d(model.rm.mesh) if model.kind == "3d" else cell_sizes(model.rm.mesh))
    c_d = max(r.material.dilatational_wave_speed for r in sc.rods)  # [m/s]
    req = sc["fe.dt"]
    if req == "auto":
        dt = march_step(sc["fe.dt_fraction"], dt_critical, dt_switching)
    elif req > dt_critical:
        remedy = "fe.dt = 'auto' picks a stable step, fe.dt_fraction of it"
        raise SceneError("fe.dt", req, f"must be <= stable limit {dt_critical:g} s", remedy)
    elif req > dt_switching:
        raise SceneError(
            "fe.dt",
            req,
            f"must be <= contact-switching limit {dt_switching:g} s (stiff penalty: "
            "contact nodes would rattle and pump energy; lower fe.penalty or fe.dt)",
        )
    else:
        dt = float(req)
    if sc.end_time < dt:  # one step would march past the end: a record of t = 0 alone, its force that of Δt
        raise SceneError(
            "simulation.end_time", sc.end_time, f"must be >= one time step Δt = {dt:.4g} s of this mesh",
            one_step_remedy(req != "auto"),
        )  # fmt: skip
    return TimeStep(
        ω_max=ω,
        ω_max_K=ω_K,
        ξ=ξ,
        dt_critical=dt_critical,
        dt_critical_no_contact=stable_step(ω_K, ξ),
        dt_gershgorin=stable_step(ω_bound, ξ),
        ω_contact=ω_contact,
        dt_switching=dt_switching,
        h_min=h_min,
        dt_element=h_min / c_d,
        dt=dt,
        β_visc=2.0 * ξ / ω,
        steps=math.ceil(sc.end_time / dt * (1 - 1e-12)),
    )
