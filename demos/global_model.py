"""The global FE model from Python, with an observer of your own (serial or ``mpirun -n 2``).

    python demos/global_model.py
    mpirun -n 2 python demos/global_model.py

The explicit model is set-up + stepper + recorder + observers (``rods.fe``): ``ExplicitModel(scene)`` meshes the
two rods and assembles the stiffness, the lumped mass and the contact once; ``run`` marches the central-difference
scheme and calls each observer's ``after_step(step, t, state)`` after every step, where ``state.u`` and ``state.v``
are this rank's owned displacement u_n [m] and velocity v_{n+1/2} [m/s]. Here an observer records the axial
velocity of Rod 2's free end, a quantity the model does not record itself, and checks it against 1D bar theory:
the contact force F(t) sends into Rod 2 (impedance Z2 = ρ2 c2 A2) a pulse of particle velocity F/Z2, and at the free
end the incident and reflected waves add, so the end moves at v_end(t) = 2 F(t - L2/c2)/Z2 until the reflection
has crossed the rod and back (t < 3 L2/c2). The force is bounded by the impedance-bound force
P = s1 Z1 Z2/(Z1 + Z2) (``rods.scene.impedance_force``), so the end flies off at up to 2 P/Z2 (= s1, equal rods).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import rods.fe  # noqa: F401  (loads the PyPI wheel's dolfinx_solver shim where installed: before dolfinx/petsc4py)

# isort: split
from mpi4py import MPI

from rods import analytical
from rods.fe.model import ExplicitModel
from rods.fe.probes import PointProbes
from rods.scene import PAPER_SCENE, impedance_force, load_scene
from rods.study.figures import pyplot

ROOT = Path(__file__).resolve().parents[1]

# The paper's rods (Table 1: 12.7 mm A2 steel, a 35 mm tip onto a flat one) made short, so that the pulse reaches
# Rod 2's free end in 39 µs and the demo runs in seconds: 0.1 m onto 0.2 m at the paper's 2.197 m/s, 110 µs (its
# reflection returns to the free end at 3 L2/c2 = 117 µs).
OVERRIDES = ("rod1.length=0.1", "rod2.length=0.2", "simulation.end_time=1.1e-4")


class FreeEndVelocity:
    """Observer: the axial velocity [m/s] of Rod 2's free end on the axis at every step (collective: the point's
    owner holds the basis values, every rank sums its own entries' share, one Allreduce)."""

    def __init__(self, model: ExplicitModel):
        L2 = model.scene.rod2.length  # [m] Rod 2's apex is at z = 0, its free end at z = L2
        point = np.array([[0.0, L2]]) if model.scene["fe.kind"] == "axisymmetric" else np.array([[0.0, 0.0, L2]])
        self.P = PointProbes(model.V, point, model.axial).P[0]  # (P v) = v_z at the point, this rank's entries
        self.comm, self.t, self.v = model.comm, [], []

    def after_step(self, step: int, t: float, state) -> None:  # noqa: ARG002
        self.t.append(t + 0.5 * state.dt)  # v_{n+1/2} lives at the half step
        self.v.append(self.comm.allreduce(float((self.P @ state.v)[0]), op=MPI.SUM))


def main(out: Path = ROOT / "output" / "demos" / "global_model") -> dict:
    scene = load_scene(PAPER_SCENE, OVERRIDES)
    model = ExplicitModel(scene)  # collective: mesh, forms, lumped mass, contact, stable step
    end = FreeEndVelocity(model)
    result = model.run(observers=[end])  # run(out) would also write checkpoints and fields where asked
    reference = analytical.simulate(scene)  # the paper's 1D model, milliseconds

    rod2, s, h = scene.rod2, result.summary, result.history
    t, v = np.array(end.t), np.array(end.v)
    v_bar = 2.0 / rod2.impedance * np.interp(t - rod2.round_trip_time / 2, h["time"], h["contact_force"])
    v_max = 2.0 * impedance_force(scene.speed, scene.rod1, rod2) / rod2.impedance  # [m/s]
    numbers = {
        "peak_contact_force": s["peak_contact_force"],  # [N]
        "vs_analytical": s["peak_contact_force"] / reference.summary["peak_contact_force"] - 1.0,
        "energy_error": s["energy_error"],
        "free_end_peak_velocity": float(v.max()),  # [m/s]
        "free_end_bound": v_max,  # [m/s] 2 P/Z2
        # the FE end against the bar theory on the FE's own force, over the run, relative to 2 P/Z2 [-]
        "free_end_rms_vs_bar": float(np.sqrt(np.mean((v - v_bar) ** 2)) / v_max),
    }
    if MPI.COMM_WORLD.rank == 0:  # every rank holds the same numbers; one prints and writes
        print(f"{s['dofs']:,} DOFs, {s['steps']:,} steps of {s['dt']:.3g} s on {MPI.COMM_WORLD.size} rank(s)")
        print(
            f"peak contact force {numbers['peak_contact_force']:.1f} N ({numbers['vs_analytical']:+.3%} from the "
            f"analytical model), energy error {numbers['energy_error']:.1e}"
        )
        print(
            f"Rod 2's free end: up to {numbers['free_end_peak_velocity']:.4f} m/s (the bound 2 P/Z2: {v_max:.4f} m/s), "
            f"{numbers['free_end_rms_vs_bar']:.2%} RMS of it from 2 F(t - L2/c2)/Z2 on the FE's own force"
        )
        out.mkdir(parents=True, exist_ok=True)
        plt = pyplot()  # matplotlib Figures of their own, drawn by Agg when saved (files, no screen, no pyplot state)
        fig, ax = plt.subplots(figsize=(6, 3.5))
        ax.plot(t * 1e6, v, label="FE, Rod 2's free end (this observer)")
        ax.plot(t * 1e6, v_bar, "k--", lw=1, label="1D bars on the FE's force, 2 F(t - L2/c2)/Z2")
        ax.axhline(v_max, color="gray", ls=":", lw=1, label="the bound 2 P/Z2")
        ax.set(xlabel="t [µs]", ylabel="axial velocity [m/s]")
        ax.legend(loc="center left", fontsize=8)
        fig.tight_layout()
        fig.savefig(out / "free-end-velocity.png", dpi=120)
        plt.close(fig)
        print(f"wrote {out / 'free-end-velocity.png'}")
    return numbers


if __name__ == "__main__":
    main()
