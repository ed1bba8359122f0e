"""Array backends of the explicit time loop (scene key ``fe.backend``): where the state lives and how
the scaled stiffness A = -Δt M^-1 K is applied.

* ``petsc`` (default, any rank count): the state is numpy, A is the assembled PETSc block matrix and
  acts through Vecs sharing the state's memory (MatMultAdd, VecAXPY): the MPI path.
* ``numpy`` (serial): A as a SciPy CSR matrix (the model's K, assembled once as DOLFINx's own CSR,
  :func:`rods.fe.forms.assemble_csr`, copied and scaled); every step is numpy/SciPy. It runs the same
  scheme as ``petsc`` (histories equal to round-off, ``tests/fe/test_backend.py``) and is the CPU twin
  of ``cupy``.
* ``cupy`` (serial, NVIDIA GPU, ``pip install rods[gpu]``): the same code with CuPy arrays and a
  cuSPARSE CSR matrix. DOLFINx assembles K, the lumped mass and the contact data on the host once;
  they are copied to the device once. What is read on the host is copied back: the contact's one
  copy per step (the kinematic law's tip gaps and rates, the penalty law's force, energy and damping
  work), the recorder's scalars and probe values at the output steps, field frames, checkpoints and
  the submodel's cut band (:class:`HostView`).
* ``auto``: ``cupy`` when CuPy imports and sees a device, else ``petsc``.

The stepper (:class:`rods.fe.explicit.CentralDifference`), the contact, the recorder and the cut
driver are written once against :class:`Backend` (``xp``: the array namespace) and an operator
(:class:`PetscOperator` or :class:`CSROperator`: ``mult``, ``mult_add``, ``axpy``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numpy as np
import scipy.sparse

from rods.scene import FE_BACKENDS, SceneError

__all__ = [
    "FE_BACKENDS",
    "PETSC",
    "Backend",
    "CSROperator",
    "HostView",
    "PetscOperator",
    "csr_of",
    "product",
    "resolve",
    "select",
]

GPU_REMEDY = "install the GPU extra: pip install rods[gpu] (CuPy for CUDA 13)"


def _host_dot(a: np.ndarray, b: np.ndarray) -> float:
    """a·b without BLAS (a threaded BLAS dot stalls the time loop when the cores are shared)."""
    return float(np.einsum("i,i->", a, b))


@dataclass(frozen=True)
class Backend:
    """An array namespace (``xp``: numpy or cupy) and its sparse module; ``name`` is the scene value."""

    name: str
    xp: ModuleType
    sparse: ModuleType
    # the kinematic contact's predicted rates formed before the step's matrix product, their copy to the host
    # started then and waited for after it is queued, so the host's LCP runs while the device multiplies
    # (rods.fe.kinematic, "Overlap"); on by default where there is a device to overlap with
    overlap: bool = False

    @property
    def on_device(self) -> bool:
        """True when the arrays live off the host (copies are needed to write them)."""
        return self.xp is not np

    @property
    def device(self) -> str:
        """Where the time loop runs, for the run's summary: "CPU", or the GPU's name (CuPy's device 0)."""
        if not self.on_device:
            return "CPU"
        name = self.xp.cuda.runtime.getDeviceProperties(self.xp.cuda.Device().id)["name"]
        return name.decode() if isinstance(name, bytes) else str(name)

    def asarray(self, a: Any) -> Any:
        """``a`` in this namespace (no copy when it is there already)."""
        return self.xp.asarray(a)

    def to_host(self, a: Any) -> np.ndarray:
        """``a`` as a numpy array (the array itself on the host, a device-to-host copy otherwise)."""
        return a if isinstance(a, np.ndarray) else a.get()

    def host_buffer(self, n: int) -> np.ndarray:
        """A float64 host array of ``n`` entries that a device copies into without a wait (page-locked on a
        device: :meth:`to_host_async`; a plain numpy array on the host)."""
        if not self.on_device:
            return np.empty(n)
        import cupyx

        return cupyx.empty_pinned((n,), dtype=np.float64)

    def to_host_async(self, a: Any, out: np.ndarray) -> Callable[[], None]:
        """Start copying ``a`` into the host array ``out`` (a :meth:`host_buffer`) and return the wait: call it
        before reading ``out``. On a device the copy is queued on the current stream behind the work that
        forms ``a`` and the call returns at once (cupy.asnumpy(blocking=False) and an event); on the host the
        copy is made now and the wait does nothing."""
        if not self.on_device:
            out[...] = a
            return _done
        self.xp.asnumpy(a, out=out, blocking=False)
        event = self.xp.cuda.Event(disable_timing=True)
        event.record()
        return event.synchronize

    def synchronize(self) -> None:
        """Wait for the work queued on the device (timings); nothing to wait for on the host."""
        if self.on_device:
            self.xp.cuda.get_current_stream().synchronize()

    def dot(self, a: Any, b: Any) -> float:
        """a·b as a Python float (host: without BLAS, see :func:`_host_dot`)."""
        return _host_dot(a, b) if self.xp is np else float(self.xp.dot(a, b))

    def sum_product(self, a: Any, b: Any) -> Any:
        """a·b as a scalar of this namespace, left where it is (on a device: no wait for it); the value of
        :meth:`dot`."""
        return np.einsum("i,i->", a, b) if self.xp is np else self.xp.dot(a, b)

    def csr(self, S: scipy.sparse.spmatrix) -> Any:
        """A host SciPy sparse matrix as this namespace's CSR matrix (probe maps, cut weights)."""
        return S if self.xp is np else self.sparse.csr_matrix(scipy.sparse.csr_matrix(S))

    def operator(self, A: Any, scale: Any, arrays: tuple[Any, ...]) -> PetscOperator | CSROperator:
        """The operator A_scaled = diag(scale) A (a PETSc Mat, a SciPy matrix or a callable returning one, or the
        element kernel's arrays, :class:`rods.fe.matrixfree.ElementStiffness`) acting on the state ``arrays``
        (allocated by the caller before A is assembled)."""
        if hasattr(A, "operator"):  # the element kernel (rods.fe.matrixfree; select refuses it where it cannot run)
            return A.operator(self, scale)
        A = A() if callable(A) and not hasattr(A, "getSize") else A
        if self.name == "petsc":
            return PetscOperator(A, scale, arrays)
        return CSROperator(self, csr_of(A), scale)


def _done() -> None:
    """The wait of a copy that is made already."""


def _numpy() -> Backend:
    return Backend("numpy", np, scipy.sparse)


def _cupy() -> Backend:
    import cupy
    import cupyx.scipy.sparse

    return Backend("cupy", cupy, cupyx.scipy.sparse, overlap=True)


PETSC = Backend("petsc", np, scipy.sparse)  # the state in numpy, the operator a PETSc Mat


def gpu_available() -> bool:
    """CuPy imports and sees at least one CUDA device."""
    try:
        import cupy

        return cupy.cuda.runtime.getDeviceCount() > 0
    except Exception:  # not installed, no driver, no device: the CPU paths remain
        return False


def resolve(name: str, ranks: int) -> str:
    """The backend ``fe.backend`` = ``name`` runs on ``ranks`` MPI ranks: "auto" is "cupy" serial where CuPy
    sees a device, else "petsc"; any other name is itself."""
    if name == "auto":
        return "cupy" if ranks == 1 and gpu_available() else "petsc"
    return name


def select(name: str, ranks: int, operator: str = "assembled") -> Backend:
    """The backend a scene's ``fe.backend`` names, on ``ranks`` MPI ranks, for its ``fe.operator`` (SceneError if
    it cannot run; "auto" with the element kernel is "cupy" on a GPU, else "numpy"). First the DOLFINx install
    itself (:func:`rods.fe.check_stack`: InputError)."""
    from rods.fe import check_stack

    check_stack()
    if name not in FE_BACKENDS:
        raise SceneError("fe.backend", name, f"must be one of {FE_BACKENDS}")
    asked, name = name, resolve(name, ranks)
    if name == "petsc" and operator == "matrix-free":
        if asked != "auto" or ranks > 1:
            why = f"runs on the serial array backends, not with fe.backend = '{asked}' on {ranks} MPI rank(s)"
            raise SceneError("fe.operator", operator, why, "set fe.backend = 'numpy' or 'cupy' and run serial")
        name = "numpy"
    if name == "petsc":
        return PETSC
    if ranks > 1:
        raise SceneError("fe.backend", name, f"runs serial only ({ranks} MPI ranks); use 'petsc' under MPI")
    if name == "numpy":
        return _numpy()
    try:
        return _cupy()
    except ImportError as e:
        raise SceneError("fe.backend", name, f"CuPy is not importable ({e}); {GPU_REMEDY}") from e


def csr_of(A: Any) -> scipy.sparse.csr_matrix:
    """A host CSR form of ``A``: a PETSc Mat (serial; AIJ or BAIJ, through MatGetRow; destroyed, it was
    assembled for this copy) or a SciPy matrix (as it is: the operator copies before it scales)."""
    if scipy.sparse.issparse(A):
        return A.tocsr()
    indptr, indices, data = A.getValuesCSR()
    n_rows, n_cols = A.getSize()
    A.destroy()
    return scipy.sparse.csr_matrix((data, indices, indptr), shape=(n_rows, n_cols))


def plain_aij(A: Any) -> Any:
    """``A`` (an assembled PETSc Mat, owned) as AIJ without PETSc's inode routines (a BAIJ one converted).

    Why: DOLFINx assembles the serial axisymmetric K as SeqBAIJ with 2 x 2 blocks, and with this PETSc (3.25, the
    wheel's -O2 build) both that block product and SeqAIJ's inode product (the structure's row pairs) ran at about a
    third of the plain AIJ loop on the same values: y += A x at 52k DOFs 1.50 ms (BAIJ) and y = A x 2.2 ms (AIJ,
    inodes) against 0.47 ms (AIJ, no inodes; SciPy's CSR loop 0.49 ms), 2026-11-27 on the 2-core machine. Under MPI
    the matrix is MPIAIJ and the variants tied (0.26 ms a rank), as did the 3D SeqAIJ (bs 3: 13 ms at 132k DOFs);
    those keep their values and lose only the inode flag. The plain loop sums each row in column order: a serial
    axisymmetric run's histories move by round-off against the BAIJ product."""
    from petsc4py import PETSc

    if "baij" in A.getType():
        # the BAIJ Mat is dropped with its last reference, not destroyed here: an explicit MatDestroy of the
        # DOLFINx-assembled BAIJ left its AIJ conversion crashing in the next product (segfault, 2026-11-27)
        A = A.convert("aij")
    A.setOption(PETSc.Mat.Option.USE_INODES, False)
    A.assemble()  # the inode structure is found at assembly: again, now without it
    return A


class PetscOperator:
    """A = diag(scale) K as the PETSc Mat (scaled in place; plain AIJ, :func:`plain_aij`), applied to the numpy
    state arrays through Vecs sharing their memory (one per array, found by identity)."""

    def __init__(self, A: Any, scale: np.ndarray, arrays: tuple[np.ndarray, ...]):
        from petsc4py import PETSc

        A = plain_aij(A)
        comm = A.getComm().tompi4py()
        n_global, bs = A.getSize()[0], A.getBlockSize()

        def vec(a: np.ndarray) -> Any:  # a Vec that shares the owned numpy array's memory
            return PETSc.Vec().createWithArray(a, size=(a.size, n_global), bsize=bs, comm=comm)

        self._vecs = {id(a): vec(a) for a in arrays}
        A.diagonalScale(L=vec(scale))
        self.A = A

    def mult(self, x: np.ndarray, y: np.ndarray) -> None:
        """y = A x."""
        self.A.mult(self._vecs[id(x)], self._vecs[id(y)])

    def mult_add(self, x: np.ndarray, y: np.ndarray) -> None:
        """y += A x."""
        vy = self._vecs[id(y)]
        self.A.multAdd(self._vecs[id(x)], vy, vy)

    def axpy(self, y: np.ndarray, a: float, x: np.ndarray) -> None:
        """y += a x."""
        self._vecs[id(y)].axpy(a, self._vecs[id(x)])

    def destroy(self) -> None:
        self.A.destroy()


try:  # SciPy's CSR kernel (private): what A @ x calls after its checks of shape, type and format
    from scipy.sparse._sparsetools import csr_matvec as _csr_matvec
except ImportError:  # a SciPy without it: A @ x
    _csr_matvec = None


def product(A: Any, x: Any) -> Any:
    """A @ x. For a host SciPy CSR matrix and a float64 numpy vector: SciPy's own kernel into zeros, the sums of
    ``A @ x`` to the bit without its per-call checks (~20 µs of Python, the whole cost of the small products of the
    contact and the recorder on every step: the gap operator's tens of rows, the probe map); else ``A @ x``."""
    if (
        _csr_matvec is None
        or not isinstance(x, np.ndarray)
        or x.dtype != np.float64
        or x.ndim != 1
        or not (scipy.sparse.issparse(A) and A.format == "csr" and A.dtype == np.float64)
    ):
        return A @ x
    y = np.zeros(A.shape[0])
    _csr_matvec(A.shape[0], A.shape[1], A.indptr, A.indices, A.data, x, y)
    return y


def _spmv_numpy(A: scipy.sparse.csr_matrix) -> Callable[[np.ndarray, np.ndarray], None]:
    """y += A x in place (SciPy's CSR kernel; without it, A @ x into a temporary)."""
    if _csr_matvec is None:

        def spmv(x: np.ndarray, y: np.ndarray) -> None:
            y += A @ x

        return spmv
    n_rows, n_cols = A.shape

    def spmv(x: np.ndarray, y: np.ndarray) -> None:
        _csr_matvec(n_rows, n_cols, A.indptr, A.indices, A.data, x, y)

    return spmv


def _spmv_cupy(A: Any) -> Callable[[Any, Any], None]:
    """y += A x in place (cuSPARSE SpMV with β = 1; without the generic API, A @ x into a temporary)."""
    import cupyx.cusparse

    if cupyx.cusparse.check_availability("spmv"):

        def spmv(x: Any, y: Any) -> None:
            cupyx.cusparse.spmv(A, x, y=y, alpha=1.0, beta=1.0)

        return spmv

    def spmv_fallback(x: Any, y: Any) -> None:
        y += A @ x

    return spmv_fallback


def axpy_of(backend: Backend) -> Callable[[Any, float, Any], None]:
    """y += a x in place on ``backend``'s arrays: on a device one fused kernel (no temporary a x each step)."""
    if not backend.on_device:

        def axpy(y: Any, a: float, x: Any) -> None:
            y += a * x

        return axpy
    kernel = backend.xp.ElementwiseKernel("float64 a, float64 x", "float64 y", "y += a * x", "rods_axpy")
    return lambda y, a, x: kernel(a, x, y)


class CSROperator:
    """A = diag(scale) K as a CSR matrix of ``backend`` (``K``: a host CSR matrix, scaled in place, then
    copied to the device once), applied in place."""

    def __init__(self, backend: Backend, K: scipy.sparse.csr_matrix, scale: Any):
        self.xp = xp = backend.xp
        row_scale = np.repeat(backend.to_host(scale), np.diff(K.indptr))  # row i scaled by scale_i
        if backend.on_device:  # scaled values, column indices and row pointers copied to the device once
            parts = (K.data * row_scale, K.indices.astype(np.int32), K.indptr.astype(np.int32))
            self.A = backend.sparse.csr_matrix(tuple(xp.asarray(a) for a in parts), shape=K.shape)
            self._spmv = _spmv_cupy(self.A)
        else:  # a copy: K may be the model's, kept for later steppers
            self.A = K = scipy.sparse.csr_matrix(K, copy=True)
            K.data *= row_scale
            self._spmv = _spmv_numpy(K)
        self.axpy = axpy_of(backend)

    @property
    def shape(self) -> tuple[int, int]:
        return self.A.shape

    def rows(self, R: Any) -> Any:
        """R A as a CSR matrix of the backend (R: a few rows of the backend, the contact's)."""
        return R @ self.A

    def mult(self, x: Any, y: Any) -> None:
        """y = A x."""
        y.fill(0.0)
        self._spmv(x, y)

    def mult_add(self, x: Any, y: Any) -> None:
        """y += A x."""
        self._spmv(x, y)

    def destroy(self) -> None:
        self.A = None


class HostView:
    """The stepper's state as host arrays, copied on access: what an observer that writes or checks
    on the host (field frames, guards, checkpoints) reads from a device stepper."""

    def __init__(self, stepper: Any, backend: Backend):
        self._stepper, self._backend = stepper, backend

    def __getattr__(self, name: str) -> Any:
        value = getattr(self._stepper, name)
        return self._backend.to_host(value) if isinstance(value, self._backend.xp.ndarray) else value


class OnHost:
    """Observer wrapper: hands ``observer`` a :class:`HostView` of the state (device backends only)."""

    def __init__(self, observer: Any, backend: Backend):
        self.observer, self.backend = observer, backend

    def after_step(self, step: int, t: float, state: Any) -> None:
        self.observer.after_step(step, t, HostView(state, self.backend))

    @property
    def collective(self) -> bool:
        return getattr(self.observer, "collective", False)

    def finish(self) -> None:
        if hasattr(self.observer, "finish"):
            self.observer.finish()
