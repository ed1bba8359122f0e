"""Mesh-free toy systems for the FE unit tests: two spring-mass bodies meeting through one penalty pair."""

from __future__ import annotations

import numpy as np
import scipy.sparse
from mpi4py import MPI
from petsc4py import PETSc

from rods.fe.contact import PenaltyContact, TipNodes
from rods.fe.explicit import CentralDifference
from rods.fe.recorder import Recorder

K_SPRING = 1.0e6  # [N/m]
MASS = 1.0  # [kg]
K_CONTACT = 2.0e6  # penalty stiffness ε a of the contact pair [N/m]
SPEED = 1.0  # [m/s]


def petsc_matrix(K: np.ndarray) -> PETSc.Mat:
    """A serial AIJ matrix with the entries of the dense ``K``."""
    n = K.shape[0]
    A = PETSc.Mat().createAIJ((n, n), nnz=n, comm=PETSc.COMM_SELF)
    A.setUp()
    A.setValues(range(n), range(n), K.ravel())
    A.assemble()
    return A


def tip(local: int, area: float) -> TipNodes:
    """One tip node at r = z = 0 with tributary area ``area`` [m^2] at owned entry ``local``."""
    return TipNodes(np.zeros(1), np.zeros(1), np.array([area]), np.array([local]), np.zeros(1, dtype=np.int64))


def bodies() -> tuple[np.ndarray, np.ndarray, PenaltyContact]:
    """Two bodies of two masses and one spring each (entries 0-1 and 2-3), touching at entries 1 and 2:
    K [N/m], the lumped masses [kg] and the penalty contact (slave entry 1, master entry 2)."""
    k = K_SPRING * np.array([[1.0, -1.0], [-1.0, 1.0]])
    K = np.zeros((4, 4))
    K[:2, :2], K[2:, 2:] = k, k
    ε, area = K_CONTACT / 1e-4, 1e-4  # [Pa/m], [m^2]
    pairing = (np.zeros((1, 1), dtype=np.int64), np.ones((1, 1)), np.ones(1, dtype=bool))
    contact = PenaltyContact(tip(1, area), tip(2, area), ε, MPI.COMM_SELF, pairing)
    return K, np.full(4, MASS), contact


def omega_max(K: np.ndarray, mass: np.ndarray) -> float:
    """Largest ω [rad/s] of M^-1 K (lumped M)."""
    d = 1.0 / np.sqrt(mass)
    return float(np.sqrt(np.linalg.eigvalsh(d[:, None] * K * d[None, :]).max()))


def impact(dt: float, steps: int, β: float = 0.0, sources=()) -> tuple[CentralDifference, Recorder, np.ndarray]:
    """Stepper and recorder (every step recorded) of the two bodies, body 1 moving at SPEED toward body 2."""
    K, mass, contact = bodies()
    v0 = np.array([SPEED, SPEED, 0.0, 0.0])
    stepper = CentralDifference(petsc_matrix(K), mass, 1.0 / mass, dt, v0, β, contact)
    P = scipy.sparse.csr_matrix(([1.0], ([0], [0])), shape=(2, 4))  # a probe on entry 0: value, no gradient
    rec = Recorder(contact, (P, [("p0_velocity", "p0_strain")]), mass, np.arange(steps + 1), steps, dt,
                   MPI.COMM_SELF, 1, sources)  # fmt: skip
    return stepper, rec, K
