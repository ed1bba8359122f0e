"""A stand-in for CuPy on a machine without a GPU: the CuPy backend's code run with its host/device discipline.

CI has no GPU, so the CuPy path (``fe.backend = "cupy"``) would run only where one is lent. This module builds
modules named ``cupy``, ``cupyx``, ``cupyx.scipy.sparse`` and ``cupyx.cusparse`` whose arrays are NumPy arrays
behind a wrapper (:class:`ndarray`) that behaves as CuPy's do where a host/device slip matters:

* no implicit conversion: ``numpy.asarray(device)`` (and so SciPy on a device array) raises TypeError, as
  CuPy's ``__array__`` does; a host array where the device namespace needs a device array (an operand of a
  ufunc, a ``cupy.*`` function, a ``cupyx.scipy.sparse`` product, an assigned value) raises TypeError, as
  CuPy does ("Unsupported type <class 'numpy.ndarray'>"); ``.get()``, ``cupy.asnumpy`` and ``cupy.asarray``
  are the explicit copies;
* reductions return 0-d device arrays (``float()`` of one is the copy), and NumPy functions called on device
  arrays dispatch to the device namespace (NEP 18, as CuPy's ``__array_function__``);
* integer and boolean host index arrays are accepted (CuPy converts them);
* every device operation (a ufunc, a ``cupy.*`` function, a method, a fancy index, a sparse product, a kernel) and
  every copy either way is counted in :data:`LAUNCHES` (a device scalar read on the host, ``float(x)``, is a
  "copy to host": on a GPU it waits for the device), so a test can bound what a step launches and copies.

What it is not: a GPU. It does not check streams, events or pinned memory (they are host no-ops here), nor
performance; the one elementwise kernel it knows is the one the library defines (:data:`KERNELS`: a new kernel
fails here until it is added). The tests that run the CuPy path on it (``fake-gpu`` in tests/fe/test_backend.py
and tests/fe/test_matrixfree.py) check that the device code never lets a host array in or a device array out
unnoticed, and that it computes the same histories; the CuPy tests proper run where a GPU is present.
"""

from __future__ import annotations

import contextlib
import sys
import types
from collections.abc import Iterator
from typing import Any

import numpy as np
import scipy.sparse

NAME = b"fake GPU (NumPy arrays, host memory)"


LAUNCHES: dict[str, int] = {}  # device operations by name since the last reset (kernels, products, copies)


def _launch(name: str) -> None:
    LAUNCHES[name] = LAUNCHES.get(name, 0) + 1


class HostArrayError(TypeError):
    """A host array where the device namespace needs a device array (CuPy raises TypeError)."""


def _strict(x: Any, where: str) -> Any:
    """``x`` with its device arrays unwrapped, refusing host arrays (lists and tuples walked)."""
    if isinstance(x, ndarray):
        return x._a
    if isinstance(x, np.ndarray):
        raise HostArrayError(f"{where}: a host numpy array {x.shape} where CuPy takes device arrays only")
    if scipy.sparse.issparse(x):
        raise HostArrayError(f"{where}: a host SciPy matrix where CuPy takes device arrays only")
    if isinstance(x, csr_matrix):
        return x._m
    if isinstance(x, (list, tuple)):
        return type(x)(_strict(i, where) for i in x)
    if isinstance(x, dict):
        return {k: _strict(v, where) for k, v in x.items()}
    return x


def _index(k: Any) -> Any:
    """An index: device arrays unwrapped, host integer/boolean arrays accepted (CuPy converts them)."""
    if isinstance(k, ndarray):
        return k._a
    if isinstance(k, tuple):
        return tuple(_index(i) for i in k)
    return k


def _wrap(x: Any) -> Any:
    """Results back on the device: arrays and NumPy scalars (reductions give 0-d device arrays)."""
    if isinstance(x, np.ndarray):
        return ndarray(x)
    if isinstance(x, np.generic):
        return ndarray(np.asarray(x))
    if isinstance(x, tuple):
        return tuple(_wrap(i) for i in x)
    return x


class ndarray:  # noqa: N801 (CuPy's name)
    """A device array: a NumPy array that never meets a host array implicitly."""

    __array_priority__ = 100

    def __init__(self, a: np.ndarray):
        self._a = a

    # what CuPy refuses
    def __array__(self, dtype=None, copy=None):
        raise TypeError(
            "Implicit conversion to a NumPy array is not allowed. Please use `.get()` to construct a NumPy array "
            "explicitly."
        )

    def __array_ufunc__(self, ufunc, method, *inputs, **kw):
        where = f"numpy.{ufunc.__name__}"
        _launch(where if method == "__call__" else f"{where}.{method}")
        if "out" in kw:
            kw["out"] = tuple(_strict(o, where) for o in kw["out"])
        return _wrap(getattr(ufunc, method)(*(_strict(i, where) for i in inputs), **kw))

    def __array_function__(self, func, types_, args, kwargs):
        return getattr(_module, func.__name__)(*args, **kwargs)

    # the explicit copy
    def get(self, stream=None, order="C", out=None, blocking=True):  # noqa: ARG002
        _launch("copy to host")
        if out is None:
            return self._a.copy()
        out[...] = self._a
        return out

    # attributes and methods: NumPy's, strict on their arguments, results on the device
    shape = property(lambda self: self._a.shape)
    size = property(lambda self: self._a.size)
    ndim = property(lambda self: self._a.ndim)
    dtype = property(lambda self: self._a.dtype)
    nbytes = property(lambda self: self._a.nbytes)
    T = property(lambda self: ndarray(self._a.T))

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):  # NumPy's __array_interface__ and __array_struct__ would be implicit conversions
            raise AttributeError(name)
        attr = getattr(self._a, name)
        if not callable(attr):
            return _wrap(attr)

        def method(*args, **kw):
            _launch("copy to host" if name in ("item", "tolist") else f"ndarray.{name}")
            return _wrap(attr(*_strict(args, f"ndarray.{name}"), **_strict(kw, f"ndarray.{name}")))

        return method

    def __getitem__(self, k):
        if not isinstance(k, (int, slice)):  # a basic index is a view; anything else a gather kernel
            _launch("ndarray.__getitem__")
        return _wrap(self._a[_index(k)])

    def __setitem__(self, k, value):
        _launch("ndarray.__setitem__")
        self._a[_index(k)] = _strict(value, "ndarray.__setitem__")

    def __len__(self) -> int:
        return len(self._a)

    def __iter__(self) -> Iterator[Any]:
        return (_wrap(x) for x in self._a)

    def __float__(self) -> float:
        _launch("copy to host")  # a device scalar read on the host: a copy (and a wait)
        return float(self._a)

    def __int__(self) -> int:
        _launch("copy to host")
        return int(self._a)

    def __bool__(self) -> bool:
        _launch("copy to host")
        return bool(self._a)

    def __repr__(self) -> str:
        return f"fake_gpu.ndarray({self._a!r})"

    def __matmul__(self, other):
        if isinstance(other, csr_matrix):
            return NotImplemented
        return _wrap(self._a @ _strict(other, "ndarray @"))

    def __rmatmul__(self, other):
        return _wrap(_strict(other, "@ ndarray") @ self._a)


def _binary(ufunc, reflected=False):
    if reflected:
        return lambda self, other: ufunc(other, self)
    return lambda self, other: ufunc(self, other)


def _inplace(ufunc):
    def op(self, other):
        ufunc(self, other, out=(self,))
        return self

    return op


for _name, _uf in {
    "add": np.add, "sub": np.subtract, "mul": np.multiply, "truediv": np.true_divide, "pow": np.power,
    "floordiv": np.floor_divide, "mod": np.remainder, "and": np.bitwise_and, "or": np.bitwise_or,
    "xor": np.bitwise_xor,
}.items():  # fmt: skip
    setattr(ndarray, f"__{_name}__", _binary(_uf))
    setattr(ndarray, f"__r{_name}__", _binary(_uf, reflected=True))
    setattr(ndarray, f"__i{_name}__", _inplace(_uf))
for _name, _uf in {"lt": np.less, "le": np.less_equal, "gt": np.greater, "ge": np.greater_equal,
                   "eq": np.equal, "ne": np.not_equal}.items():  # fmt: skip
    setattr(ndarray, f"__{_name}__", _binary(_uf))
ndarray.__neg__ = lambda self: np.negative(self)
ndarray.__abs__ = lambda self: np.absolute(self)
ndarray.__invert__ = lambda self: np.invert(self)
ndarray.__hash__ = None


# ------------------------------------------------------------------------------------------------
# the namespaces
# ------------------------------------------------------------------------------------------------
def _device_function(func: Any, where: str) -> Any:
    def call(*args, **kw):
        _launch(where)
        return _wrap(func(*_strict(args, where), **_strict(kw, where)))

    call.__name__ = where
    return call


def asarray(a: Any, dtype=None, order=None, copy=None, blocking=False) -> ndarray:  # noqa: ARG001
    """A host array copied to the device (a device array as it is)."""
    if isinstance(a, ndarray):
        return a if dtype is None or a.dtype == dtype else ndarray(a._a.astype(dtype))
    _launch("copy to device")
    return ndarray(np.array(a, dtype=dtype, copy=True))


def asnumpy(a: Any, stream=None, order="C", out=None, blocking=True) -> np.ndarray:  # noqa: ARG001
    """A device array copied to the host (into ``out`` if given)."""
    _launch("copy to host")
    host = a._a if isinstance(a, ndarray) else np.asarray(a)
    if out is None:
        return host.copy()
    out[...] = host
    return out


# elementwise kernels the library defines, by their operation (rods.fe.backend.axpy_of)
KERNELS = {"y += a * x": lambda a, x, y: np.add(y, np.multiply(a, x), out=y)}


class ElementwiseKernel:
    def __init__(self, in_params: str, out_params: str, operation: str, name: str = "kernel"):  # noqa: ARG002
        if operation not in KERNELS:
            raise NotImplementedError(f"fake GPU: kernel {name!r} ({operation!r}) is not emulated: add it to KERNELS")
        self._op = KERNELS[operation]

    def __call__(self, *args):
        _launch("ElementwiseKernel")
        return self._op(*(_strict(a, "ElementwiseKernel") for a in args))


class _Event:
    def __init__(self, **_):
        pass

    def record(self, stream=None):
        pass

    def synchronize(self):
        pass


def _module_getattr(namespace: Any, prefix: str):
    def __getattr__(name: str) -> Any:  # noqa: N807
        func = getattr(namespace, name)
        return _device_function(func, f"{prefix}.{name}") if callable(func) else func

    return __getattr__


_module = types.ModuleType("cupy")
_module.__version__ = "0+fake-gpu"
_module.ndarray = ndarray
_module.asarray = asarray
_module.array = asarray
_module.asnumpy = asnumpy
_module.ElementwiseKernel = ElementwiseKernel
_module.float64, _module.float32, _module.int32, _module.int64 = np.float64, np.float32, np.int32, np.int64
_module.newaxis = None
_module.get_array_module = lambda *args: _module
_module.__getattr__ = _module_getattr(np, "cupy")
_module.linalg = types.ModuleType("cupy.linalg")
_module.linalg.__getattr__ = _module_getattr(np.linalg, "cupy.linalg")
_runtime = types.SimpleNamespace(getDeviceCount=lambda: 1, getDeviceProperties=lambda i: {"name": NAME})
_stream = types.SimpleNamespace(synchronize=lambda: None)
_module.cuda = types.SimpleNamespace(
    runtime=_runtime,
    Device=lambda i=0: types.SimpleNamespace(id=i, synchronize=lambda: None),
    Event=_Event,
    get_current_stream=lambda: _stream,
)


class csr_matrix:  # noqa: N801 (cupyx.scipy.sparse's name)
    """A device CSR matrix: built from a host SciPy matrix (the copy) or from device (data, indices, indptr)."""

    format = "csr"

    def __init__(self, arg: Any, shape=None, dtype=None):
        if isinstance(arg, csr_matrix):
            m = arg._m.copy()
        elif scipy.sparse.issparse(arg):
            m = scipy.sparse.csr_matrix(arg, copy=True)
        elif isinstance(arg, tuple):
            m = scipy.sparse.csr_matrix(tuple(_strict(a, "csr_matrix") for a in arg), shape=shape)
        else:
            raise HostArrayError(f"cupyx.scipy.sparse.csr_matrix: cannot build from {type(arg).__name__}")
        self._m = m if dtype is None else m.astype(dtype)

    shape = property(lambda self: self._m.shape)
    nnz = property(lambda self: self._m.nnz)
    dtype = property(lambda self: self._m.dtype)
    data = property(lambda self: ndarray(self._m.data))
    indices = property(lambda self: ndarray(self._m.indices))
    indptr = property(lambda self: ndarray(self._m.indptr))
    T = property(lambda self: csr_matrix(self._m.T.tocsr()))

    def get(self) -> scipy.sparse.csr_matrix:
        return self._m.copy()

    def tocsr(self) -> csr_matrix:
        return self

    def __matmul__(self, other):
        _launch("csr_matrix @")
        if isinstance(other, csr_matrix):
            return csr_matrix(self._m @ other._m)
        return _wrap(self._m @ _strict(other, "csr_matrix @"))

    def __rmatmul__(self, other):
        return csr_matrix(_strict(other, "@ csr_matrix") @ self._m)

    dot = __matmul__

    def __mul__(self, scalar):
        if not np.isscalar(scalar):
            return NotImplemented
        return csr_matrix(self._m * scalar)

    __rmul__ = __mul__


def _spmv(A: csr_matrix, x: ndarray, y: ndarray | None = None, alpha: float = 1.0, beta: float = 0.0):
    """y = α A x + β y in place (cuSPARSE's SpMV)."""
    _launch("cusparse.spmv")
    Ax = A._m @ _strict(x, "cusparse.spmv")
    if y is None:
        return ndarray(alpha * Ax)
    ya = _strict(y, "cusparse.spmv")
    ya *= beta
    ya += alpha * Ax
    return y


def modules() -> dict[str, types.ModuleType]:
    """The fake ``cupy``, ``cupyx``, ``cupyx.scipy``, ``cupyx.scipy.sparse`` and ``cupyx.cusparse``."""
    cupyx = types.ModuleType("cupyx")
    cupyx.empty_pinned = lambda shape, dtype=np.float64: np.empty(shape, dtype=dtype)
    cupyx.zeros_pinned = lambda shape, dtype=np.float64: np.zeros(shape, dtype=dtype)
    cupyx.scipy = types.ModuleType("cupyx.scipy")
    sparse = types.ModuleType("cupyx.scipy.sparse")
    sparse.csr_matrix = csr_matrix
    sparse.issparse = lambda x: isinstance(x, csr_matrix)
    sparse.isspmatrix_csr = sparse.issparse
    cupyx.scipy.sparse = sparse
    cusparse = types.ModuleType("cupyx.cusparse")
    cusparse.check_availability = lambda name: name == "spmv"
    cusparse.spmv = _spmv
    cupyx.cusparse = cusparse
    return {
        "cupy": _module,
        "cupy.linalg": _module.linalg,
        "cupyx": cupyx,
        "cupyx.scipy": cupyx.scipy,
        "cupyx.scipy.sparse": sparse,
        "cupyx.cusparse": cusparse,
    }


@contextlib.contextmanager
def installed() -> Iterator[types.ModuleType]:
    """The fake modules importable as CuPy inside the block (whatever was there before, after it). Only their own
    names are restored: a module first imported inside the block stays imported (unittest.mock.patch.dict would
    drop it, and h5py, for one, cannot be imported twice in a process)."""
    fakes = modules()
    before = {name: sys.modules.get(name) for name in fakes}
    sys.modules.update(fakes)
    try:
        yield _module
    finally:
        for name, module in before.items():
            if module is None:
                sys.modules.pop(name, None)
            else:
                sys.modules[name] = module
