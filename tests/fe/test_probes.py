"""Point probes (rods.fe.probes): the linear map P reproduces a field the Q1 space holds exactly, and the
stations sit where the scene puts them."""

from __future__ import annotations

import shutil
import subprocess
from types import SimpleNamespace

import dolfinx
import numpy as np
import pytest
from mpi4py import MPI

from rods.fe.probes import PointProbes, station_points

from ..conftest import MPIRUN, PY, ROOT


def _sheared_mesh(gdim: int):
    """A unit box (2D: square) of Q1 cells under an affine map (shear and stretch): every cell a parallelogram
    (parallelepiped), so a field bilinear in the reference coordinates is bilinear in x too."""
    if gdim == 2:
        msh = dolfinx.mesh.create_unit_square(MPI.COMM_SELF, 5, 7, dolfinx.mesh.CellType.quadrilateral)
        A = np.array([[0.02, 0.004], [0.0, 0.3]])  # [m]: r in [0, 24] mm, z sheared
    else:
        msh = dolfinx.mesh.create_unit_cube(MPI.COMM_SELF, 3, 4, 5, dolfinx.mesh.CellType.hexahedron)
        A = np.array([[0.02, 0.0, 0.003], [0.0, 0.02, 0.0], [0.001, 0.0, 0.3]])  # [m]
    x = msh.geometry.x
    x[:, :gdim] = x[:, :gdim] @ A.T
    return msh, A


@pytest.mark.parametrize("gdim", [2, 3])
def test_probe_reproduces_a_field_linear_in_z_exactly(gdim):
    """u_z = a + b z + c x_0 (linear, held exactly by Q1 on affine cells): at random points inside the sheared
    mesh, (P u)[2i] = u_z(X_i) and (P u)[2i + 1] = ∂u_z/∂z = b to round-off, the other components ignored."""
    msh, A = _sheared_mesh(gdim)
    V = dolfinx.fem.functionspace(msh, ("Lagrange", 1, (gdim,)))
    a, b, c = 1e-4, -3e-3, 2e-3  # [m], [-], [-]
    u = dolfinx.fem.Function(V)
    axial = gdim - 1
    u.interpolate(
        lambda x: np.vstack([7.0 * x[0] + 1.0, *([5.0 * x[2]] if gdim == 3 else []), a + b * x[axial] + c * x[0]])
    )
    rng = np.random.default_rng(11)
    X = rng.uniform(0.05, 0.95, size=(9, gdim)) @ A.T  # [m]: random points inside the cells
    P = PointProbes(V, X, axial).P
    n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
    values = P @ u.x.array[:n]
    exact = a + b * X[:, axial] + c * X[:, 0]
    assert np.abs(values[0::2] - exact).max() <= 1e-12 * np.abs(exact).max()
    assert np.abs(values[1::2] - b).max() <= 1e-10 * abs(b)


@pytest.mark.parametrize("gdim", [2, 3])
def test_a_probe_on_a_node_takes_the_mean_of_its_cells(gdim, comm=MPI.COMM_SELF):
    """u_z = z² on a 2 x 8 strip (3D: 2 x 2 x 8 block) of unit Q1 cells: at a node between cells the one-sided
    strains of the interpolant are 2z - 1 and 2z + 1; the probe reads their mean 2z (the exact strain) whatever the
    partition (the first cell found on the lowest rank was taken: 6.6% of the column's largest strain between 1 and
    2 ranks, a fuzz, 2026-12-07); inside a cell, the cell's own. The MPI case below runs this on 2 ranks."""
    if gdim == 2:
        box, cell = [[0.0, 0.0], [2.0, 8.0]], dolfinx.mesh.CellType.quadrilateral
        msh = dolfinx.mesh.create_rectangle(comm, box, [2, 8], cell)
    else:
        box, cell = [[0.0, 0.0, 0.0], [2.0, 2.0, 8.0]], dolfinx.mesh.CellType.hexahedron
        msh = dolfinx.mesh.create_box(comm, box, [2, 2, 8], cell)
    V = dolfinx.fem.functionspace(msh, ("Lagrange", 1, (gdim,)))
    u = dolfinx.fem.Function(V)
    u.interpolate(lambda x: np.vstack([*([0.0 * x[0]] * (gdim - 1)), x[gdim - 1] ** 2]))
    z = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 2.5])  # nodes (4 or 8 cells around one), then a cell's middle
    P = PointProbes(V, np.column_stack([np.full((z.size, gdim - 1), 1.0), z]), gdim - 1).P
    n = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
    values = comm.allreduce(P @ u.x.array[:n], op=MPI.SUM)
    assert values[0::2] == pytest.approx(np.where(z % 1 == 0, z**2, 6.5), rel=1e-12)  # the interpolant's values
    assert values[1::2] == pytest.approx(2 * z, rel=1e-12)  # nodes: the mean of 2z -/+ 1; z = 2.5: the cell's 5


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which(str(MPIRUN)) is None, reason="no mpirun")
def test_a_probe_on_a_node_takes_the_mean_of_its_cells_on_two_ranks():
    """The case above on MPI.COMM_WORLD under `mpirun -n 2`: the strip's nodes lie on the ranks' boundary."""
    code = (
        "import rods.fe\nfrom mpi4py import MPI\nfrom tests.fe.test_probes import "
        "test_a_probe_on_a_node_takes_the_mean_of_its_cells as t\nt(2, MPI.COMM_WORLD)\nt(3, MPI.COMM_WORLD)\n"
    )
    p = subprocess.run(
        [str(MPIRUN), "-n", "2", str(PY), "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120
    )
    assert p.returncode == 0, p.stderr[-2000:]


def test_a_probe_outside_the_mesh_is_refused():
    V = dolfinx.fem.functionspace(_sheared_mesh(2)[0], ("Lagrange", 1, (2,)))
    with pytest.raises(ValueError, match="outside the mesh"):
        PointProbes(V, np.array([[0.5, 5.0]]), 1)  # [m]: z far beyond the 0.3 m box


def test_stations_sit_on_the_surface_at_their_distance_from_the_tip(scene_with):
    """Axisymmetric: (d/2, +x) on Rod 2, (d/2, -x) on Rod 1; 3D quarter model: the stations at y = 0 and Rod 2's
    midpoint pair, whose -x member is mirrored to +x (the quarter holds x >= 0 only)."""
    sc = scene_with()
    pts, keys = station_points(sc, None, three_d=False)
    assert keys == [(f"{s.name}_velocity", f"{s.name}_strain") for s in sc.stations]
    for s, p in zip(sc.stations, pts, strict=True):
        rod = sc.rods[s.rod - 1]
        assert p.tolist() == [rod.diameter / 2, s.position if s.rod == 2 else -s.position]
    quarter = SimpleNamespace(symmetry="quarter", placement=SimpleNamespace(apply=lambda p: p))
    pts3, keys3 = station_points(sc, quarter, three_d=True)
    assert len(pts3) == len(sc.stations) + 2 and keys3[-1] == ("rod2_mid_velocity_minus_x", "rod2_mid_strain_minus_x")
    R2, mid = sc.rod2.diameter / 2, sc.rod2.length / 2  # [m]
    assert pts3[-2].tolist() == pts3[-1].tolist() == [R2, 0.0, mid]
    half = SimpleNamespace(symmetry="half", placement=quarter.placement)
    assert station_points(sc, half, three_d=True)[0][-1].tolist() == [-R2, 0.0, mid]
