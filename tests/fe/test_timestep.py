"""The step's limits (rods.fe.timestep) under MPI: the Gershgorin bound's stiffness rows are whole rows on every
rank (the closed-form and eigenvalue checks of the limits are in tests/fe/test_stability.py and test_explicit.py)."""

from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pytest

from tests.conftest import MPIRUN, PAPER, PY, ROOT

# Σ_ij |K_ij| over the owned rows, summed over the ranks, and the bound's step, printed by rank 0 (JSON)
ROW_SUMS = f"""
import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)
import json, numpy as np
from mpi4py import MPI
from rods.scene import load_scene
from rods.fe.model import ExplicitModel
from rods.fe.timestep import stiffness_row_sums
sc = load_scene({str(PAPER)!r}, ["fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=2e-5"])
m = ExplicitModel(sc)
total = MPI.COMM_WORLD.allreduce(float(np.sum(stiffness_row_sums(m))))
if MPI.COMM_WORLD.rank == 0:
    print(json.dumps({{"total": total, "dt_gershgorin": m.dt_gershgorin}}))
"""


def _row_sums(ranks: int) -> dict:
    cmd = [str(MPIRUN), "-n", str(ranks), str(PY), "-c", ROW_SUMS]
    p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which(str(MPIRUN)) is None, reason="no mpirun")
def test_gershgorin_rows_are_whole_on_every_rank():
    """On 2 ranks the owned rows' Σ_j |K_ij| sum to the serial total (rel 1e-12): a row on the partition boundary
    holds the other rank's cells' part too (DOLFINx's matrix needs its ghost rows scattered into their owners; a
    partial row could put the 'safe' bound under ω_max²), and the bound's step is the serial one."""
    from mpi4py import MPI

    from rods.fe.model import ExplicitModel
    from rods.fe.timestep import stiffness_row_sums
    from rods.scene import load_scene

    sc = load_scene(PAPER, ["fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=2e-5"])
    m = ExplicitModel(sc, MPI.COMM_SELF)  # serial, in this process
    serial = {"total": float(np.sum(stiffness_row_sums(m))), "dt_gershgorin": m.dt_gershgorin}
    parallel = _row_sums(2)
    assert parallel["total"] == pytest.approx(serial["total"], rel=1e-12)
    assert parallel["dt_gershgorin"] == pytest.approx(serial["dt_gershgorin"], rel=1e-12)
