"""Explicit finite-element models of the rod impact (paper Sec. 2.2), axisymmetric or 3D, global or submodel.

Rooms: :mod:`~rods.fe.model` (ExplicitModel: mesh, spaces, K, lumped mass, constraints, contact, probes,
stable step, plan; its ``run`` is the loop), :mod:`~rods.fe.explicit` (the central-difference scheme and
its stable step), :mod:`~rods.fe.observers` (the loop's observer protocol), :mod:`~rods.fe.recorder`
(named histories, energy balance, peak), :mod:`~rods.fe.guards`, :mod:`~rods.fe.checkpoint`,
:mod:`~rods.fe.fields` (observers), :mod:`~rods.fe.contact` (penalty contact), :mod:`~rods.fe.probes`,
:mod:`~rods.fe.forms`, :mod:`~rods.fe.layout` (the axisymmetric mesh laid out and counted), :mod:`~rods.fe.mesh`
(built) / :mod:`~rods.fe.mesh3d`, :mod:`~rods.fe.kinematic` (penalty-free kinematic contact), :mod:`~rods.fe.timestep`
(the step's limits and the step), :mod:`~rods.fe.end_compliance` (the rod-end correction of the Hertz approach),
:mod:`~rods.fe.submodel` (the submodel scene and run, σ_r at the Gauss points, levels), :mod:`~rods.fe.cut` (the
band the global records, the displacement driver), :mod:`~rods.fe.traction` (traction and mixed driving at the
cuts), :mod:`~rods.fe.backend` (the array backends of the
stepper: PETSc Mat/Vec, NumPy/SciPy, CuPy), :mod:`~rods.fe.matrixfree` (K applied element by element on the array
backends, ``fe.operator = "matrix-free"``).

Importing this package loads the PyPI wheel's ``dolfinx_solver`` shim first when it is installed
(it must precede dolfinx/petsc4py there); any other DOLFINx 0.11 install works without it.
"""

import sys as _sys

try:  # wheel-specific, optional
    import dolfinx_solver  # noqa: F401
except ImportError:  # pragma: no cover
    pass


def _utf8(text: str) -> bool:
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:  # a byte Python kept as a surrogate
        return False
    return True


if not all(map(_utf8, _sys.argv)):
    # DOLFINx hands sys.argv to C++ as it loads (init_logging), which takes valid UTF-8 only: an argument that is not
    # (a Latin-1 folder name) failed every FE entry point with a TypeError. Loaded here with such arguments made
    # printable, PETSc too; the command line itself stays as given (it names the folder).
    _argv = _sys.argv
    _sys.argv = [a.encode("utf-8", "surrogateescape").decode("utf-8", "replace") for a in _argv]
    try:
        import dolfinx  # noqa: F401
        from petsc4py import PETSc  # noqa: F401
    finally:
        _sys.argv = _argv


DOLFINX_SERIES = (0, 11)  # the DOLFINx release series this package is written against (its API: forms, CSR, io)
STACK_REMEDY = (
    "install the pinned stack (./.ci/ensure-venv, requirements.txt), or a DOLFINx 0.11 built on real, double-precision "
    "PETSc (DOLFINx containers: source /usr/local/bin/dolfinx-real-mode)"
)


def check_stack() -> None:
    """Refuse a DOLFINx install the models cannot run on, before any set-up: another release series than
    :data:`DOLFINX_SERIES` (the API differs), or PETSc built with complex or single-precision scalars (K, the lumped
    mass and the contact's arrays are real float64; a complex build would make every form complex), or no slepc4py
    (the stable step's eigenvalue solve, rods.fe.explicit.largest_eigenvalue). :class:`rods.preflight.InputError`
    naming what was found (an entry point: one line, exit 2)."""
    import importlib.util

    import dolfinx
    import numpy as np
    from petsc4py import PETSc

    from rods.preflight import InputError

    found = tuple(int(p) for p in dolfinx.__version__.split(".")[:2] if p.isdigit())
    if found != DOLFINX_SERIES:
        need = ".".join(map(str, DOLFINX_SERIES))
        raise InputError("DOLFINx", dolfinx.__version__, f"rods needs DOLFINx {need}.x", STACK_REMEDY)
    scalar = np.dtype(PETSc.ScalarType)
    if scalar != np.float64:
        raise InputError("PETSc scalar type", scalar.name, "rods needs real float64 PETSc", STACK_REMEDY)
    if importlib.util.find_spec("slepc4py") is None:
        raise InputError("slepc4py", "not importable", "the stable step's eigenvalue solve needs SLEPc", STACK_REMEDY)
    _check_form_cache()


def _check_form_cache() -> None:
    """DOLFINx compiles the forms into its cache (``$XDG_CACHE_HOME/fenics``, default ``~/.cache/fenics``): one that
    does not exist and cannot be made (a read-only HOME on a cluster node) failed the set-up with a PermissionError,
    after the plan, naming no remedy."""
    import os
    from pathlib import Path

    from dolfinx.jit import get_options

    from rods.preflight import InputError

    cache = Path(get_options()["cache_dir"])
    probe = cache
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    if not cache.exists() and not os.access(probe, os.W_OK | os.X_OK):
        raise InputError(
            "DOLFINx's form cache", cache, f"cannot be made ({probe} is not writable): the models compile their forms "
            "there", "set XDG_CACHE_HOME to a writable folder (XDG_CACHE_HOME=/tmp/$USER-cache)",
        )  # fmt: skip
