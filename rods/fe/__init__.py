"""Explicit finite-element models of the rod impact (paper Sec. 2.2): the global axisymmetric model.

Importing this package loads the PyPI wheel's ``dolfinx_solver`` shim first when it is installed
(it must precede dolfinx/petsc4py there); any other DOLFINx 0.11 install works without it.
"""

try:  # wheel-specific, optional
    import dolfinx_solver  # noqa: F401
except ImportError:  # pragma: no cover
    pass
