"""Explicit finite-element models of the rod impact (paper Sec. 2.2), axisymmetric or 3D, global or submodel.

Rooms: :mod:`~rods.fe.model` (ExplicitModel: mesh, spaces, K, lumped mass, constraints, contact, probes,
stable step, plan; its ``run`` is the loop), :mod:`~rods.fe.explicit` (the central-difference scheme and
its stable step), :mod:`~rods.fe.observers` (the loop's observer protocol), :mod:`~rods.fe.recorder`
(named histories, energy balance, peak), :mod:`~rods.fe.guards`, :mod:`~rods.fe.checkpoint`,
:mod:`~rods.fe.fields` (observers), :mod:`~rods.fe.contact` (penalty contact), :mod:`~rods.fe.probes`,
:mod:`~rods.fe.forms`, :mod:`~rods.fe.mesh` / :mod:`~rods.fe.mesh3d`, :mod:`~rods.fe.submodel` (cut
recording and driving, σ_r at the Gauss points, levels), :mod:`~rods.fe.backend` (the array backends of the
stepper: PETSc Mat/Vec, NumPy/SciPy, CuPy), :mod:`~rods.fe.matrixfree` (K applied element by element on the array
backends, ``fe.operator = "matrix-free"``).

Importing this package loads the PyPI wheel's ``dolfinx_solver`` shim first when it is installed
(it must precede dolfinx/petsc4py there); any other DOLFINx 0.11 install works without it.
"""

try:  # wheel-specific, optional
    import dolfinx_solver  # noqa: F401
except ImportError:  # pragma: no cover
    pass
