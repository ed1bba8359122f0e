"""Tests of the explicit FE models (rods.fe); importing rods.fe first loads the PyPI wheel's dolfinx_solver shim
where installed, before any test module imports dolfinx or petsc4py."""

import rods.fe  # noqa: F401
