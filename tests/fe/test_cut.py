"""The cut band's graph helpers (rods.fe.cut): the node graph of the band cells and its distance colouring, on
which the cut weights and the traction operator are built one colour at a time. The recording and the driving
themselves run in tests/fe/test_submodel.py and tests/fe/test_traction.py (they need a global run)."""

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rods.fe.cut import band_adjacency, node_colouring


def quads(nx: int, ny: int) -> np.ndarray:
    """Cells (4 nodes each) of a structured nx x ny quadrilateral grid, nodes numbered row by row."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    n0 = (j * (nx + 1) + i).ravel()
    return np.stack([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1], axis=1)


def test_adjacency_links_exactly_the_nodes_that_share_a_cell():
    """Two quadrilaterals side by side (6 nodes): a corner node sees its own cell's 4, a middle node all 6."""
    A = band_adjacency(quads(2, 1), 6).toarray()
    assert np.array_equal(A, A.T) and np.all(np.diag(A) == 1)
    assert A.sum(axis=1).tolist() == [4, 6, 4, 4, 6, 4]
    assert A[0, 2] == 0 and A[0, 4] == 1


@settings(max_examples=20, deadline=None)
@given(nx=st.integers(1, 7), ny=st.integers(1, 7), hops=st.integers(1, 2))
def test_nodes_within_the_reach_differ_in_colour(nx, ny, hops):
    """Any two nodes within ``hops`` cell-sharing steps get different colours (what lets one interpolation or one
    traction projection serve a whole colour), and no more colours than a node's reach holds, (2 hops + 1)² on
    a structured quad grid: 9 at one hop, 25 at two (the greedy colouring's bound, its degree + 1)."""
    cells = quads(nx, ny)
    n = (nx + 1) * (ny + 1)
    A = band_adjacency(cells, n)
    R = A if hops == 1 else (A @ A)
    colour = node_colouring(A, hops)
    rows, cols = R.nonzero()
    off = rows != cols
    assert colour.min() == 0
    assert np.all(colour[rows[off]] != colour[cols[off]])
    assert colour.max() + 1 <= (2 * hops + 1) ** 2


@pytest.mark.parametrize("hops", [1, 2])
def test_colouring_is_the_same_from_the_same_cells(hops):
    """Every rank colours the band it was given in the same order: the colours are the greedy ones in index order
    (node j takes the smallest colour no node i < j within ``hops`` of it holds), a function of the cells alone, not
    of the process (a review: a colouring in a per-process random order passed the old same-process comparison)."""
    import scipy.sparse.csgraph

    cells = quads(5, 3)
    colour = node_colouring(band_adjacency(cells, 24), hops)
    hops_apart = scipy.sparse.csgraph.shortest_path(band_adjacency(cells, 24), unweighted=True)
    for j in range(24):
        near = [i for i in range(j) if hops_apart[i, j] <= hops]
        assert colour[j] == min(set(range(25)) - {int(colour[i]) for i in near}), j


@pytest.mark.parametrize("flattened", [False, True])
def test_record_products_equal_the_product_of_each_record(flattened):
    """rods.fe.cut.record_products: one sparse product over every record equals A U_k record by record, for A on the
    band nodes per component (W: (n_rec, n_cut, gdim)) and on the flattened records (T: (n_rec, n_cut gdim)) (their
    interpolation in time: tests/fe/test_submodel.py, test_cut_displacement_matches_recorded_at_coincident_nodes)."""
    import scipy.sparse

    from rods.fe.cut import record_products

    rng = np.random.default_rng(4)
    n_rec, n_nodes, gdim, n_rows = 7, 30, 3, 11
    U = rng.normal(size=(n_rec, n_nodes, gdim))
    A = scipy.sparse.random(n_rows, n_nodes * gdim if flattened else n_nodes, density=0.2, random_state=5, format="csr")
    P = record_products(A, U)
    for k in range(n_rec):
        expected = A @ U[k].ravel() if flattened else A @ U[k]
        np.testing.assert_allclose(P[k], expected, rtol=1e-13, atol=1e-13)
    assert P.flags.c_contiguous and P.shape == ((n_rec, n_rows) if flattened else (n_rec, n_rows, gdim))
