"""Field output of an explicit run: an XDMF time series of u, v (P1) and σ_zz, σ_rr (σ_xx in 3D),
von Mises (DG0), written collectively every ``every`` steps (an observer, :mod:`rods.fe.observers`)."""

from __future__ import annotations

from pathlib import Path

import dolfinx
import dolfinx.io
import ufl

from rods.fe import forms
from rods.fe.explicit import CentralDifference

__all__ = ["DEFAULT_FIELD_INTERVAL", "FieldOutput"]

DEFAULT_FIELD_INTERVAL = 10e-6  # [s] when "fields" is requested without fe.field_interval


class FieldOutput:
    """Observer: writes ``out/fields.xdmf`` at t_n with u_n and v_{n+½} every ``every`` steps (P1 only:
    XDMF needs the fields on the linear geometry)."""

    def __init__(self, model, out: Path, every: int):
        V, msh, kind = model.V, model.rm.mesh, model.kind
        self.every, self.n = max(1, every), model.n_local
        self.uf = dolfinx.fem.Function(V, name="displacement")
        self.vf = dolfinx.fem.Function(V, name="velocity")
        Q = dolfinx.fem.functionspace(msh, ("DG", 0))
        x = ufl.SpatialCoordinate(msh)
        σ = forms.stress(forms.strain(self.uf, x, kind), model.mat.λ, model.mat.μ)
        s = ufl.dev(σ)
        exprs = {
            "sigma_zz": σ[2, 2],
            "sigma_xx" if kind == "3d" else "sigma_rr": σ[0, 0],
            "von_mises": ufl.sqrt(1.5 * ufl.inner(s, s)),
        }
        self.derived = [
            (dolfinx.fem.Function(Q, name=name), dolfinx.fem.Expression(e, Q.element.interpolation_points))
            for name, e in exprs.items()
        ]
        self.xdmf = dolfinx.io.XDMFFile(msh.comm, str(Path(out) / "fields.xdmf"), "w")
        self.xdmf.write_mesh(msh)

    def after_step(self, step: int, t: float, state: CentralDifference) -> None:
        if step % self.every:
            return
        self.uf.x.array[: self.n] = state.u
        self.vf.x.array[: self.n] = state.v
        for f in (self.uf, self.vf):
            f.x.scatter_forward()
            self.xdmf.write_function(f, t)
        for fq, e in self.derived:
            fq.interpolate(e)
            self.xdmf.write_function(fq, t)

    def finish(self) -> None:
        self.xdmf.close()
