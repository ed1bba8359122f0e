"""The stand-in device (tests/fake_gpu.py) refuses what CuPy refuses, so that a pass on it means something: implicit
conversions either way, host operands of device operations, host matrices against device vectors; and it allows
what CuPy allows (explicit copies, scalars, host index arrays, NumPy functions dispatched to the device)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse

from . import fake_gpu


@pytest.fixture
def cp():
    with fake_gpu.installed() as module:
        yield module


def test_implicit_conversions_are_refused(cp):
    import cupyx.scipy.sparse

    d, h = cp.arange(4.0), np.arange(4.0)
    with pytest.raises(TypeError, match="Implicit conversion"):
        np.asarray(d)
    for slip in (lambda: d + h, lambda: h * d, lambda: cp.concatenate((d, h)), lambda: cp.dot(d, h)):
        with pytest.raises(TypeError, match="host numpy array"):
            slip()
    with pytest.raises(TypeError):
        scipy.sparse.identity(4, format="csr") @ d  # a host matrix against a device vector
    with pytest.raises(TypeError, match="host numpy array"):
        cupyx.scipy.sparse.csr_matrix(
            scipy.sparse.identity(4, format="csr")
        ) @ h  # a device matrix against a host vector
    with pytest.raises(TypeError, match="host numpy array"):
        d[:2] = h[:2]  # an assigned host value
    with pytest.raises(TypeError, match="host numpy array"):
        d += h


def test_what_cupy_allows(cp):
    import cupyx.scipy.sparse

    d = cp.asarray(np.arange(4.0))  # the explicit copy to the device
    assert isinstance(d, cp.ndarray) and not isinstance(d, np.ndarray)
    s = cp.sum(d)
    assert isinstance(s, cp.ndarray) and s.ndim == 0 and float(s) == 6.0  # a reduction stays on the device
    assert isinstance(np.sum(d), cp.ndarray)  # a NumPy function dispatched to the device (NEP 18)
    assert np.array_equal(d[np.array([3, 0])].get(), [3.0, 0.0])  # a host index array
    d *= 2.0
    d[1:3] = cp.zeros(2)
    assert np.array_equal(cp.asnumpy(d), [0.0, 0.0, 0.0, 6.0]) and isinstance(d.get(), np.ndarray)
    A = cupyx.scipy.sparse.csr_matrix(scipy.sparse.identity(4, format="csr") * 3.0)
    y = cp.ones(4)
    import cupyx.cusparse

    cupyx.cusparse.spmv(A, d, y=y, alpha=1.0, beta=1.0)
    assert np.array_equal(y.get(), [1.0, 1.0, 1.0, 19.0]) and isinstance(A @ d, cp.ndarray)
    with pytest.raises(NotImplementedError, match="KERNELS"):
        cp.ElementwiseKernel("float64 x", "float64 y", "y = x * x", "square")


def test_only_inside_the_block(monkeypatch):
    """The fake modules leave with the block; a module first imported inside it stays (h5py cannot be imported
    twice in one process: a block that dropped it broke the next block's field writer)."""
    import sys

    monkeypatch.delitem(sys.modules, "colorsys", raising=False)
    with fake_gpu.installed():
        import colorsys

        import cupy

        assert cupy.cuda.runtime.getDeviceCount() == 1
    assert sys.modules.get("cupy") is not cupy and sys.modules["colorsys"] is colorsys
