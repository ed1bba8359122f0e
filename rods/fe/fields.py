"""Field output of an explicit run: every field on one dataset per frame, at exactly the requested times.

Frames: t_k = k x ``fe.field_interval`` for every t_k within the run, plus the final state (t = steps Δt,
unless it is within a step of the last requested time). Frame k is formed at the nearest step n = round(t_k/Δt), with
τ = t_k - t_n in [-Δt/2, Δt/2], on the scheme's own trajectory (:mod:`rods.fe.explicit`): u is piecewise
linear between steps with slope v_{n±½}, so u(t_k) = u_n + τ v_{n+½} (τ >= 0) or u_n + τ v_{n-½} (τ < 0),
exact; v(t_k) is the linear interpolation of v_{n-½} and v_{n+½} at their half-step times (at t = 0: v_0).
Stresses are evaluated at u(t_k); the contact pressure is the contact law's force at the frame's step
(``slave_forces``: the penalty law's at u(t_k), the kinematic law's the impulse per step of the step that ended
there, whatever u, so the t = 0 frame holds the apex ring's first impulse).

Fields (all P1, point data, one grid per frame): ``displacement``, ``velocity`` (3 components: r, z, 0
axisymmetric; x, y, z in 3D), ``sigma_zz``, ``sigma_rr``, ``sigma_tt`` (σ_θθ) in each rod's cylindrical
frame (3D: about the rod's own axis, Rod 1's placed one when tilted or offset), ``von_mises``, and
``contact_pressure`` on both tip surfaces (Rod 1: p_s = F_s / a_s of the contact law; Rod 2: its nodal
reaction Wᵀ F over its tributary area; 0 elsewhere). Stresses are nodal averages, the lumped L² projection
σ_i = ∫ N_i σ w dx / ∫ N_i w dx (w: the volume weight; Gauss points are interior, so r > 0 in 3D).

Files in the run folder:

* ``fields.xdmf`` + ``fields/mesh.h5`` + ``fields/frame-<k>.h5``: XDMF 3 with one temporal collection of
  uniform grids, each grid carrying all attributes (ParaView's Xdmf3 readers, VTK's legacy ``vtkXdmfReader``
  and meshio read it). Each frame is its own HDF5 file, closed before the XML is replaced atomically, so a
  killed run leaves every frame written so far readable, and a restart keeps the frames before its
  restart step and appends after them.
* ``fields.bp`` (ADIOS2, DOLFINx's VTXWriter, written in parallel; ParaView's ADIOS2VTXReader): the same
  functions and frames; a restart writes its frames to ``fields-restart-<step>.bp`` (VTXWriter cannot append);
  not written where DOLFINx was built without ADIOS2.

A run afresh (not a restart) removes an earlier run's field files in its folder first (:func:`discard`), asked
for fields or not: a series left there would sit beside the new run's summary.json as if it were its own.
``fields/mesh.h5`` carries the scene values of the run that wrote the series (attribute ``scene_values``, JSON):
:func:`check_run` refuses a series that is not the run's beside it (:func:`render_contact`,
workflows/contact_picture.py).

MPI: the XDMF is written by rank 0 from arrays gathered in global node order (one gather per frame).
"""

from __future__ import annotations

import contextlib
import json
import math
import shutil
import sys
import time
from pathlib import Path

import dolfinx
import dolfinx.fem.petsc
import dolfinx.io
import numpy as np
import ufl

from rods import io
from rods.fe import forms
from rods.fe.explicit import CentralDifference
from rods.metrics import PICTURE_PATCHES
from rods.preflight import InputError
from rods.scene import scene_from_summary, value_differences

__all__ = [
    "FIELD_NAMES",
    "FieldOutput",
    "XdmfSeries",
    "check_run",
    "contact_picture",
    "damaged_file",
    "discard",
    "frame_count",
    "frame_schedule",
    "series_scene",
    "surface_edges",
]

XML_INTERVAL = 2.0  # [s] longest wall time between two rewrites of fields.xdmf during a run (XdmfSeries)
XML_LAG = 0.1  # frames fields.xdmf may leave unlisted during a run, per frame it lists [-] (XdmfSeries)
FIELD_NAMES = ("displacement", "velocity", "sigma_zz", "sigma_rr", "sigma_tt", "von_mises", "contact_pressure")
# a run folder's field files (module docstring; fields.h5: an older version's XDMF data), removed by a run afresh
SERIES_FILES = ("fields.xdmf", "fields.h5", "fields", "fields.bp", "fields-restart-*.bp", ".fields.xdmf.*.tmp")
# what a series writes into its fields/ folder, each through a temporary .<name>.tmp (XdmfSeries._write_h5)
FOLDER_FILES = ("mesh.h5", "frame-*.h5")


def discard(out: str | Path, comm) -> None:
    """Remove an earlier run's field files (:data:`SERIES_FILES`) from ``out`` (collective: rank 0 removes, then a
    barrier): a run afresh writes its own series or none, and an earlier one left beside its summary.json would be
    read as this run's (a later run without fields reused the folder). The XML goes first: a kill in between
    leaves no series that lists missing frames. A restart keeps them (it appends its frames)."""
    if comm.rank == 0:
        for pattern in SERIES_FILES:
            for old in sorted(Path(out).glob(pattern)):
                if old.name == "fields" and old.is_dir() and not old.is_symlink():
                    _discard_series_folder(old)
                elif old.is_dir() and not old.is_symlink():
                    shutil.rmtree(old, ignore_errors=True)
                else:
                    old.unlink(missing_ok=True)
    comm.barrier()


def _discard_series_folder(folder: Path) -> None:
    """Remove the files a series writes into ``fields/`` (mesh.h5, frame-<k>.h5, their temporaries) and the folder
    where nothing else is left: an --out given a folder of the user's that holds a ``fields/`` of theirs keeps it (a
    fuzz: global.py --out DIR removed DIR/fields/ whole, whatever it held, with exit 0)."""
    for pattern in (*FOLDER_FILES, *(f".{name}.tmp" for name in FOLDER_FILES)):
        for p in folder.glob(pattern):
            if p.is_file() or p.is_symlink():
                p.unlink(missing_ok=True)
    with contextlib.suppress(OSError):
        folder.rmdir()  # only an empty one


def series_scene(folder: str | Path) -> dict | None:
    """The scene values (nested, as summary.json's ``scene_values``) of the run that wrote the field series in
    ``folder`` (its fields/mesh.h5), or None: written before they were recorded, or unreadable."""
    import h5py

    try:
        with h5py.File(Path(folder) / "fields" / "mesh.h5", "r") as f:
            text = f.attrs.get("scene_values")
        return json.loads(text) if text is not None else None
    except (OSError, ValueError, TypeError):
        return None


def damaged_file(folder: str | Path) -> tuple[Path, str] | None:
    """(the first file of the field series in ``folder`` that does not read, why) or None: fields.xdmf not XML or
    naming no frame, or an HDF5 file it names (fields/mesh.h5, a frame) missing or unreadable (truncated, its
    bytes damaged)."""
    import xml.etree.ElementTree as ET

    import h5py

    folder = Path(folder)
    xdmf = folder / "fields.xdmf"
    try:
        items = [e.text or "" for e in ET.parse(xdmf).getroot().iter("DataItem") if e.get("Format") == "HDF"]
    except (ET.ParseError, OSError) as e:
        return xdmf, f"is not a readable XDMF file ({type(e).__name__})"
    datasets: dict[str, list[str]] = {}  # file -> the datasets the XDMF reads from it, files in order
    for text in filter(None, (t.strip() for t in items)):
        name, _, dataset = text.partition(":")
        datasets.setdefault(name, []).append(dataset)
    if not datasets:
        return xdmf, "names no mesh or frame"
    for name, names in datasets.items():
        f = folder / name
        if not f.is_file():
            return f, "is missing"
        try:
            with h5py.File(f, "r") as h:
                for dataset in names:
                    h[dataset].shape  # noqa: B018  (reading the header finds a damaged object table)
        except (OSError, KeyError, ValueError):
            return f, "is not a readable HDF5 file (truncated or damaged)"
    return None


def check_run(folder: str | Path, what: str = "--fields") -> None:
    """Refuse (:class:`InputError`, exit 2 at the entry points) a field series in ``folder`` that is damaged
    (:func:`damaged_file`) or that the summary.json beside it does not describe: written by another run (another
    scene: an earlier run's series that a later one left behind, the study's restart excepted), or with no record of
    its run (an older version's files). Without a summary.json there is nothing to mislabel: accepted."""
    folder = Path(folder)
    remedy = "rerun this run with fields (fe.field_interval > 0), or give the folder of the run that wrote them"
    try:
        summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    except FileNotFoundError:
        return
    except (OSError, ValueError) as e:
        raise InputError(what, folder, f"unreadable summary.json ({type(e).__name__})", remedy) from None
    ours = summary.get("scene_values") if isinstance(summary, dict) else None
    if (damage := damaged_file(folder)) is not None:  # exit 1 with h5py's or the XML parser's words before (a fuzz)
        path, why = damage
        fix = "rerun the run with fields into an empty folder (a stopped one: --restart repairs its series)"
        raise InputError(what, folder, f"its field series is damaged: {path.relative_to(folder)} {why}", fix)
    theirs = series_scene(folder)
    if theirs is None:
        raise InputError(what, folder, "its field series carries no record of the run that wrote it", remedy)
    diffs = value_differences(ours, theirs)
    if diffs:
        key, mine, other = diffs[0]
        why = f"its field series was written by another run ({key} = {other!r} there, {mine!r} in summary.json)"
        raise InputError(what, folder, why, remedy)


def _requested(interval: float, dt: float, steps: int) -> tuple[int, bool]:
    """(index of the last requested frame, whether the final state is a frame of its own: it lies a step or more
    past the last requested time; a run ends at the first step at or past its end time, and a frame closer than
    that would repeat the last one)."""
    end = steps * dt
    n_req = int(math.floor(end / interval * (1 + 1e-12)))
    return n_req, end - n_req * interval >= dt * (1 - 1e-9)


def frame_count(interval: float, dt: float, steps: int) -> int:
    """The number of frames :func:`frame_schedule` makes, without building it (rods.cost counts them)."""
    n_req, final = _requested(interval, dt, steps)
    return n_req + 1 + final


def frame_schedule(interval: float, dt: float, steps: int) -> dict[int, list[tuple[int, float]]]:
    """Step n -> [(frame index k, time t_k [s])]: t_k = k x ``interval`` (to 14 digits: a product's last-digit noise
    dropped) <= steps Δt at n = round(t_k/Δt),
    then the final state (k = last + 1, t = steps Δt) where :func:`_requested` says so."""
    n_req, final = _requested(interval, dt, steps)
    sched: dict[int, list[tuple[int, float]]] = {}
    for k in range(n_req + 1):
        t = float(f"{k * interval:.14g}")  # [s] 6e-05, not k x interval's 6.000000000000001e-05 (a fuzz)
        sched.setdefault(min(steps, round(t / dt)), []).append((k, t))
    if final:
        sched.setdefault(steps, []).append((n_req + 1, steps * dt))
    return sched


class _Stresses:
    """σ_zz, σ_rr, σ_θθ, von Mises of ``u`` as P1 nodal averages (lumped L² projection, module docstring)."""

    def __init__(self, model, u: dolfinx.fem.Function, Q: dolfinx.fem.FunctionSpace):
        msh, kind = model.rm.mesh, model.kind
        x = ufl.SpatialCoordinate(msh)
        σ = forms.stress(forms.strain(u, x, kind), model.mat.λ, model.mat.μ)
        if kind == "3d":
            e_z, e_r, e_t = _cylindrical_frame(model, x)
            comps = [ufl.dot(e, ufl.dot(σ, e)) for e in (e_z, e_r, e_t)]
        else:  # (r, θ, z) ordering of rods.fe.forms
            comps = [σ[2, 2], σ[0, 0], σ[1, 1]]
        s = ufl.dev(σ)
        comps.append(ufl.sqrt(1.5 * ufl.inner(s, s)))
        q, w = ufl.TestFunction(Q), forms.measure_weight(x, kind)
        dx = ufl.dx(metadata={"quadrature_degree": 2})
        self.forms = [dolfinx.fem.form(c * q * w * dx) for c in comps]
        self.n = Q.dofmap.index_map.size_local
        self.inv_weight = 1.0 / self._assemble(dolfinx.fem.form(q * w * dx))

    def _assemble(self, form) -> np.ndarray:
        return forms.assemble_owned(form, self.n)

    def evaluate(self) -> list[np.ndarray]:
        """Owned nodal values [Pa] of σ_zz, σ_rr, σ_θθ, von Mises at the current ``u``."""
        return [self._assemble(f) * self.inv_weight for f in self.forms]


def _cylindrical_frame(model, x):
    """3D: (e_z, e_r, e_θ) of each rod's cylindrical frame as UFL vectors; the axis a and a point c on it are
    cellwise (DG0): Rod 2 along z through the origin, Rod 1 placed (R_y(θ) e_z through its apex)."""
    msh, pl = model.rm.mesh, model.rm.placement
    Q3 = dolfinx.fem.functionspace(msh, ("DG", 0, (3,)))
    a, c = dolfinx.fem.Function(Q3), dolfinx.fem.Function(Q3)
    for rod, axis, centre in (
        ("rod1", (math.sin(pl.tilt), 0.0, math.cos(pl.tilt)), (pl.offset, 0.0, pl.dz)),
        ("rod2", (0.0, 0.0, 1.0), (0.0, 0.0, 0.0)),
    ):
        cells = model.rm.cell_tags.find(model.tags[rod])
        for f, val in ((a, axis), (c, centre)):
            f.x.array.reshape(-1, 3)[cells] = val
    a.x.scatter_forward()
    c.x.scatter_forward()
    d = x - c
    d_perp = d - ufl.dot(d, a) * a
    ρ = ufl.sqrt(ufl.dot(d_perp, d_perp) + (1e-9 * model.scene.rod2.diameter) ** 2)  # Gauss points: ρ > 0
    e_r = d_perp / ρ
    return a, e_r, ufl.cross(a, e_r)


class XdmfSeries:
    """Rank 0's XDMF time series (module docstring): ``mesh.h5`` once (with ``scene_values``, the JSON of the run's
    scene values, :func:`check_run`), one HDF5 file per frame, the XML replaced atomically once the frames it does not
    list are :data:`XML_LAG` of those it does, or :data:`XML_INTERVAL` seconds after its last rewrite, and at
    :meth:`flush` (rewritten after every frame, the XML's writes grew with the square of the frames: an audit's 3002
    frames spent 37.8 s and ~8 GB of writes on it; geometric rewrites keep them in proportion). A kill between two
    rewrites leaves an XML without the last frames' grids (at most a tenth of them; a restart lists every frame file
    it finds).
    ``keep_before``: frames with t below it survive (a restart)."""

    def __init__(
        self,
        out: Path,
        points: np.ndarray,
        cells: np.ndarray,
        cell_type: str,
        keep_before: float,
        scene_values: str = "",
    ):
        import h5py

        self.h5py, self.xml = h5py, Path(out) / "fields.xdmf"
        self.dir = Path(out) / "fields"
        self.cell_type, self.shape = cell_type, (len(points), len(cells), cells.shape[1])
        self.frames: list[tuple[str, float, dict[str, int]]] = []
        self.grids: dict[str, str] = {}  # frame file -> its <Grid> element, formatted once
        self.written, self.listed = -math.inf, 0  # [s] time.monotonic() of the last XML rewrite, the frames it lists
        if self.dir.exists():
            self.frames = [f for f in self._read_frames() if f[1] < keep_before]
            for p in self.dir.glob("frame-*.h5"):
                if p.name not in {f[0] for f in self.frames}:
                    p.unlink()
        self.dir.mkdir(parents=True, exist_ok=True)
        self._write_h5("mesh.h5", {"points": points, "cells": cells}, attrs={"scene_values": scene_values})
        self._write_xml()

    def _read_frames(self) -> list[tuple[str, float, dict[str, int]]]:
        frames = []
        for p in sorted(self.dir.glob("frame-*.h5")):
            try:
                with self.h5py.File(p, "r") as f:
                    frames.append((p.name, float(f.attrs["time"]), {k: f[k].shape[1] for k in f}))
            except (OSError, KeyError):  # a frame cut short by a kill: dropped (it is rewritten)
                continue
        return sorted(frames, key=lambda f: f[1])

    def _write_h5(self, name: str, data: dict[str, np.ndarray], time: float | None = None, attrs=None) -> None:
        tmp = self.dir / f".{name}.tmp"
        with self.h5py.File(tmp, "w") as f:
            for k, v in data.items():
                f.create_dataset(k, data=v)
            if time is not None:
                f.attrs["time"] = time
            f.attrs.update({k: v for k, v in (attrs or {}).items() if v})
        tmp.chmod(io.file_mode())
        tmp.replace(self.dir / name)

    def write(self, k: int, t: float, data: dict[str, np.ndarray]) -> None:
        """Frame ``k`` at time ``t`` [s]: ``data`` name -> (n_points, n_comp) in global node order."""
        name = f"frame-{k:06d}.h5"
        self._write_h5(name, data, t)
        self.frames = [f for f in self.frames if f[0] != name and f[1] < t] + [
            (name, t, {n: v.shape[1] for n, v in data.items()})
        ]
        self.grids.pop(name, None)  # a restart's frame of that number: its time may differ
        behind = len(self.frames) - self.listed  # frames the XML does not list yet
        if behind >= XML_LAG * self.listed or time.monotonic() - self.written >= XML_INTERVAL:
            self._write_xml()

    def flush(self) -> None:
        """The XML of every frame written (the run's end, or its stop)."""
        self._write_xml()

    def _grid(self, name: str, t: float, comps: dict[str, int]) -> str:
        """The <Grid> element of frame file ``name`` at ``t`` [s] with its fields' component counts ``comps``."""
        n_pts, n_cells, per_cell = self.shape
        topo = f'<DataItem Dimensions="{n_cells} {per_cell}" NumberType="Int" Precision="8" Format="HDF">'
        geo = f'<DataItem Dimensions="{n_pts} 3" NumberType="Float" Precision="8" Format="HDF">'
        attrs = "".join(
            f'<Attribute Name="{a}" AttributeType="{"Vector" if nc == 3 else "Scalar"}" Center="Node">'
            f'<DataItem Dimensions="{n_pts} {nc}" NumberType="Float" Precision="8" Format="HDF">'
            f"fields/{name}:/{a}</DataItem></Attribute>"
            for a, nc in comps.items()
        )
        return (
            f'<Grid Name="frame" GridType="Uniform"><Time Value="{t!r}"/>'
            f'<Topology TopologyType="{self.cell_type}" NumberOfElements="{n_cells}">{topo}'
            f"fields/mesh.h5:/cells</DataItem></Topology>"
            f'<Geometry GeometryType="XYZ">{geo}fields/mesh.h5:/points</DataItem></Geometry>{attrs}</Grid>\n'
        )

    def _write_xml(self) -> None:
        for name, t, comps in self.frames:
            if name not in self.grids:
                self.grids[name] = self._grid(name, t, comps)
        io.atomic_write_text(
            self.xml,
            '<?xml version="1.0"?>\n<Xdmf Version="3.0"><Domain>\n'
            '<Grid Name="fields" GridType="Collection" CollectionType="Temporal">\n'
            f"{''.join(self.grids[name] for name, _, _ in self.frames)}</Grid></Domain></Xdmf>\n",
        )
        self.written, self.listed = time.monotonic(), len(self.frames)


class FieldOutput:
    """Observer: the frames of :func:`frame_schedule` (module docstring) into ``out``; ``state`` is the
    stepper before its first step of this run (v_0, or v_{step0-½} after a restart at ``step0``)."""

    def __init__(self, model, out: Path, interval: float, state: CentralDifference, step0: int = 0):
        V, msh = model.V, model.rm.mesh
        self.comm, self.dt, self.bs, self.contact = model.comm, model.dt, model.bs, model.contact
        self.scene_values = model.scene.as_dict()  # as the run's summary.json holds them
        self.sched = frame_schedule(interval, model.dt, model.steps)
        self.v_prev = state.v.copy()  # v_{n-½} of the next frame step n
        self.uf = dolfinx.fem.Function(V, name="displacement")
        self.vf = dolfinx.fem.Function(V, name="velocity")
        Q = dolfinx.fem.functionspace(msh, ("Lagrange", 1))
        if not np.array_equal(Q.dofmap.list, V.dofmap.list):  # node i of V is dof i of Q (DOLFINx's P1 layout)
            raise RuntimeError("scalar and vector P1 dof layouts differ: fields cannot share nodes")
        self.scalars = {name: dolfinx.fem.Function(Q, name=name) for name in FIELD_NAMES[2:]}
        self.stresses = _Stresses(model, self.uf, Q)
        self.n_nodes = Q.dofmap.index_map.size_local
        self.vtx = _vtx(msh.comm, Path(out), [self.uf, self.vf, *self.scalars.values()], step0)
        self.series, self.order = self._xdmf(V, Path(out), (step0 - 0.5) * model.dt if step0 else -math.inf)
        if self.series is not None and step0:
            self._note_missing(Path(out), step0)

    def _note_missing(self, out: Path, step0: int) -> None:
        """Rank 0, a restart: the frames before ``step0`` that the interrupted run wrote and that are gone now
        (deleted or cut short by the kill) are named on stderr; the series lists only the frames found, and no
        later step can rewrite them."""
        found = {name for name, _, _ in self.series.frames}
        kept = (step0 - 0.5) * self.dt  # [s] the frames the series keeps (XdmfSeries' keep_before)
        gone = [(k, t) for f in self.sched.values() for k, t in f if t < kept and f"frame-{k:06d}.h5" not in found]
        if gone:
            ts = ", ".join(f"{t * 1e6:.6g}" for _, t in gone[:5]) + (", ..." if len(gone) > 5 else "")
            sys.stderr.write(
                f"note: fields: {len(gone)} frame(s) before the restart are missing from {out / 'fields'} "
                f"(t = {ts} µs); fields.xdmf lists the {len(found)} found. For a complete series, rerun without "
                "--restart\n"
            )

    def _xdmf(self, V, out: Path, keep_before: float) -> tuple[XdmfSeries | None, np.ndarray | None]:
        """Rank 0's series and the permutation of the gathered owned nodes into global order."""
        imap, msh = V.dofmap.index_map, V.mesh
        gid = imap.local_to_global(np.arange(imap.size_local, dtype=np.int32))
        pts = V.tabulate_dof_coordinates()[: imap.size_local]
        n_cells = msh.topology.index_map(msh.topology.dim).size_local
        ct = msh.topology.cell_type
        perm = dolfinx.cpp.io.perm_vtk(ct, V.dofmap.list.shape[1])
        cells = imap.local_to_global(V.dofmap.list[:n_cells].ravel()).reshape(n_cells, -1)[:, perm]
        parts = self.comm.gather((gid, pts, cells), root=0)
        if self.comm.rank != 0:
            return None, None
        order = np.argsort(np.concatenate([p[0] for p in parts]))
        points = np.vstack([p[1] for p in parts])[order]
        cell_type = {"quadrilateral": "Quadrilateral", "hexahedron": "Hexahedron"}[ct.name]
        scene = json.dumps(self.scene_values)  # whose series it is (check_run)
        series = XdmfSeries(out, points, np.vstack([p[2] for p in parts]), cell_type, keep_before, scene)
        return series, order

    def after_step(self, step: int, t: float, state: CentralDifference) -> None:  # noqa: ARG002
        for k, t_k in self.sched.get(step, ()):
            self._frame(k, t_k, step, state)
        if step + 1 in self.sched:
            self.v_prev[:] = state.v  # v_{n-½} of the frame step n = step + 1

    def _frame(self, k: int, t_k: float, n: int, state: CentralDifference) -> None:
        """u, v at t_k on the scheme's trajectory (module docstring), then everything derived from u."""
        τ = t_k - n * self.dt  # [s], |τ| <= Δt/2
        u = state.u + τ * (state.v if τ >= 0 else self.v_prev)
        v = self.v_prev + (τ / self.dt + 0.5 if n else 2 * τ / self.dt) * (state.v - self.v_prev)
        n_own = u.size
        for f, a in ((self.uf, u), (self.vf, v)):
            f.x.array[:n_own] = a
            f.x.scatter_forward()
        values = [*self.stresses.evaluate(), self._contact_pressure(u)]
        for f, a in zip(self.scalars.values(), values, strict=True):
            f.x.array[: self.n_nodes] = a
            f.x.scatter_forward()
        if self.vtx is not None:
            self.vtx.write(t_k)
        pad = np.zeros((self.n_nodes, 3 - self.bs))
        data = {
            "displacement": np.hstack([u.reshape(-1, self.bs), pad]),
            "velocity": np.hstack([v.reshape(-1, self.bs), pad]),
        }
        data.update({name: a[:, None] for name, a in zip(self.scalars, values, strict=True)})
        parts = self.comm.gather(data, root=0)
        if self.series is not None:
            self.series.write(k, t_k, {name: np.vstack([p[name] for p in parts])[self.order] for name in data})

    def _contact_pressure(self, u: np.ndarray) -> np.ndarray:
        """Owned nodal contact pressure [Pa] (collective): the slave forces F_s of the contact law
        (:meth:`rods.fe.contact.PenaltyContact.slave_forces` at ``u``; the kinematic law's are its last step's,
        whatever ``u``) per tributary area on Rod 1's tip, their reaction Wᵀ F per tributary area on Rod 2's."""
        c = self.contact
        F = c.slave_forces(u)  # [N]
        F_m = np.bincount(c.J.ravel(), (c.W * F[:, None]).ravel(), c.nm)  # [N]
        p = np.zeros(self.n_nodes)
        for tip, Fk in ((c.slave, F), (c.master, F_m)):
            area = tip.area[tip.pos]
            p[tip.local // self.bs] = np.where(area > 0, Fk[tip.pos] / np.where(area > 0, area, 1.0), 0.0)
        return p

    @property
    def collective(self) -> bool:
        """Whether :meth:`finish` is collective (the ADIOS2 writer closes on every rank together)."""
        return self.vtx is not None and self.comm.size > 1

    def finish(self) -> None:
        self.finish_alone()
        if self.vtx is not None:
            self.vtx.close()

    def finish_alone(self) -> None:
        """Rank 0's XML of every frame written (also where this rank stops alone: the ADIOS2 close is collective)."""
        if self.series is not None:
            self.series.flush()


def _vtx(comm, out: Path, funcs: list, step0: int):
    """The ADIOS2 copy of the frames (``fields.bp``, or ``fields-restart-<step0>.bp`` after a restart: VTX cannot
    append), or None where this DOLFINx was built without ADIOS2 (``dolfinx.common.has_adios2``; some conda and
    source builds): the XDMF series is then the only one, and rank 0 says so once."""
    if not dolfinx.common.has_adios2:
        if comm.rank == 0:
            sys.stderr.write(
                "note: fields: this DOLFINx has no ADIOS2, so no fields.bp; fields.xdmf holds the frames\n"
            )
        return None
    name = "fields.bp" if step0 == 0 else f"fields-restart-{step0}.bp"  # afresh: the model discarded the old
    reuse = dolfinx.io.VTXMeshPolicy.reuse  # the mesh once, not with every frame
    return dolfinx.io.VTXWriter(comm, out / name, funcs, "BP4", mesh_policy=reuse)


def read_fields(xdmf: str | Path) -> tuple[np.ndarray, np.ndarray, list[tuple[float, dict[str, np.ndarray]]]]:
    """Points, cells and the frames [(t [s], field name -> point values)] of a ``fields.xdmf`` (meshio); a series
    whose data do not read (damage :func:`damaged_file` does not see: bytes inside a dataset) is refused as
    :class:`InputError` naming its folder."""
    import meshio

    try:
        with meshio.xdmf.TimeSeriesReader(str(xdmf)) as r:
            points, cells = r.read_points_cells()
            frames = [r.read_data(k)[:2] for k in range(r.num_steps)]
    except (OSError, KeyError, ValueError, IndexError, meshio.ReadError) as e:
        why = f"its field series does not read ({type(e).__name__}: {e})"
        raise InputError("--fields", Path(xdmf).parent, why, "rerun the run with fields into an empty folder") from None
    return points, cells[0].data, frames


def section_y0(points: np.ndarray, hexes: np.ndarray) -> np.ndarray:
    """The quadrilaterals of a hexahedral mesh's plane y = 0 (a full model's interior O-grid plane, a half or
    quarter model's symmetry boundary), each once, ordered around its centre in (x, z): the exact section,
    where VTK's slice of a boundary plane (or of one the displacement moved) left part of it or none."""
    scale = float(np.abs(points).max()) or 1.0
    on = np.abs(points[:, 1]) <= 1e-9 * scale
    hexes = hexes[on[hexes].sum(axis=1) == 4]
    quads = np.array([h[on[h]] for h in hexes], dtype=np.int64).reshape(-1, 4)
    quads = np.unique(np.sort(quads, axis=1), axis=0)
    xz = points[quads][:, :, [0, 2]]
    angle = np.arctan2(*(xz - xz.mean(axis=1, keepdims=True)).transpose(2, 0, 1)[::-1])
    return np.take_along_axis(quads, np.argsort(angle, axis=1), axis=1)


def picture_window(points: np.ndarray, p: np.ndarray, three_d: bool) -> float:
    """The contact picture's half-width [m]: :data:`PICTURE_PATCHES` x the frame's contact radius, the farthest
    loaded node (``p`` > 0) from the patch's centre across the rods (axisymmetric: r, the centre on the axis; 3D:
    in the x-y plane, from the loaded nodes' mean); where no node is loaded, the mesh's half-width (the whole tip)."""
    loaded = p > 0
    if not loaded.any():
        return float(np.abs(points[:, :1]).max())
    across = points[:, :2] - points[loaded, :2].mean(axis=0) if three_d else points[:, :1]  # [m] from the centre
    return PICTURE_PATCHES * float(np.linalg.norm(across[loaded], axis=1).max())


def render_contact(xdmf: str | Path, png: str | Path, window: float | None = None) -> float:
    """Off-screen picture (pyvista on EGL: no X server) of the contact region at the frame of the largest
    contact pressure: von Mises on the deformed mesh (left), the contact pressure along the tip faces (right),
    in the (r, z) plane (3D: the section y = 0), ``window`` [m] either side of the patch's centre (default
    :func:`picture_window`: a few contact radii, whatever the scene's patch). Displacements relative to the
    contact centre are scaled so that the largest within the window is 5% of it (said in the title). The
    frame's time [s]. A series that is not the run's of the summary.json beside it is refused first
    (:func:`check_run`)."""
    check_run(Path(xdmf).parent)
    points, cells, frames = read_fields(xdmf)
    t, d = _peak_frame(frames)
    _draw(points, cells, t, d, png, window)
    return float(t)


def _peak_frame(frames: list[tuple[float, dict[str, np.ndarray]]]) -> tuple[float, dict[str, np.ndarray]]:
    """The frame (time [s], fields) of the largest contact pressure."""
    return max(frames, key=lambda f: f[1]["contact_pressure"].max())


def surface_edges(points: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """The edges (node pairs) of a quadrilateral section's boundary, each once, without the axis r = 0 (an
    axisymmetric mesh's boundary that is no surface): within the contact picture's window, the two tips' faces,
    where the contact pressure, a surface traction, lives. ``quads``: nodes in order around each cell."""
    edges = np.sort(np.stack([quads, np.roll(quads, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
    pairs, count = np.unique(edges, axis=0, return_counts=True)
    pairs = pairs[count == 1]  # an interior edge borders two cells
    on_axis = np.abs(points[:, 0]) <= 1e-9 * (float(np.abs(points).max()) or 1.0)
    return pairs[~on_axis[pairs].all(axis=1)]


def _draw(points: np.ndarray, cells: np.ndarray, t: float, d: dict, png: str | Path, window: float | None) -> None:
    """:func:`render_contact`'s picture of the frame ``d`` at time ``t`` [s] on the series' ``points`` and ``cells``:
    von Mises on the section's cells; the contact pressure, a nodal traction on the tip faces, along those faces
    (:func:`surface_edges`) over the grey mesh, not smeared into the cells beside them."""
    from rods.io import bar_format, offscreen_pyvista

    pv = offscreen_pyvista()
    p = d["contact_pressure"][:, 0]
    u_c = d["displacement"][p > 0].mean(axis=0) if (p > 0).any() else np.zeros(3)
    du, x_c = d["displacement"] - u_c, 0.0  # x_c: the contact centre (axisymmetric: on the axis, r = 0)
    window = picture_window(points, p, cells.shape[1] == 8) if window is None else window
    if cells.shape[1] == 8:  # 3D: the section y = 0 drawn as the (x, z) plane
        cells = section_y0(points, cells)
        points, du = points[:, [0, 2, 1]] * [1, 1, 0], du[:, [0, 2, 1]] * [1, 1, 0]
        x_c = float(points[p > 0, 0].mean()) if (p > 0).any() else 0.0  # an offset impact's patch is off the axis
    near = np.linalg.norm(points - [x_c, 0.0, 0.0], axis=1) < window
    factor = 0.05 * window / max(np.linalg.norm(du[near], axis=1).max(initial=0.0), 1e-300)
    box = (x_c - window, x_c + window, -window, window, -1.0, 1.0)
    grid = pv.UnstructuredGrid({pv.CellType.QUAD: cells}, points + factor * du)
    grid.point_data["von Mises [MPa]"] = d["von_mises"][:, 0] / 1e6
    grid = grid.clip_box(box, invert=False)
    faces = pv.UnstructuredGrid({pv.CellType.LINE: surface_edges(points, cells)}, points + factor * du)
    faces.point_data["p [MPa]"] = p / 1e6
    faces = faces.clip_box(box, invert=False)
    pl = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(1600, 800))
    for col, (name, title, field) in enumerate(
        (("von Mises [MPa]", "von Mises", grid), ("p [MPa]", "contact pressure on the tip faces", faces))
    ):
        pl.subplot(0, col)
        fmt = bar_format(float(np.abs(field.point_data[name]).max(initial=0.0)))
        bar = dict(title=name, vertical=True, position_x=0.84, position_y=0.15, width=0.06, height=0.7, fmt=fmt)
        if col == 1:  # the section in grey under the faces' pressure
            pl.add_mesh(grid, color="lightgray", show_edges=True, edge_color="gray")
        pl.add_mesh(
            field,
            scalars=name,
            cmap="turbo",
            show_edges=col == 0,
            edge_color="gray",
            line_width=8 if col == 1 else None,  # [px] the faces as thick lines; the mesh edges thin
            scalar_bar_args=bar,
        )
        pl.add_text(f"{title}, t = {t * 1e6:.2f} µs, deformation x {factor:.3g}", font_size=10)
        pl.view_xy()
        pl.camera.parallel_projection = True
        _clear_of_the_bar(pl.camera)
    pl.link_views()
    pl.screenshot(str(png))
    pl.close()


def _clear_of_the_bar(camera) -> None:
    """Zoom out to 80% and move the picture left by a tenth of the panel: a 3D section's square window filled the
    panel and ran under the colour bar at its right (from 84% of the width on)."""
    camera.zoom(0.8)
    shift = 0.2 * camera.parallel_scale  # [m] a tenth of the visible width (square panels: 2 x the half-height)
    camera.focal_point = np.add(camera.focal_point, (shift, 0.0, 0.0))
    camera.position = np.add(camera.position, (shift, 0.0, 0.0))


def _run_summary(run: Path) -> dict:
    """What the picture's data names of ``run``: its summary.json, or for a run killed before it wrote one (its
    series complete to its last frame) the series' own scene (fields/mesh.h5), its model and mesh unknown (None)."""
    if (run / "summary.json").is_file():
        return json.loads((run / "summary.json").read_text(encoding="utf-8"))
    values = series_scene(run)
    if values is None:
        raise InputError("--fields", run, "has no summary.json and its series records no scene", "give a run's folder")
    name = f"{scene_from_summary(values).name}, its values as its field series records them (no summary.json)"
    return {"model": None, "scene": name, "mesh": None, "scene_values": values}


def contact_picture(run: str | Path, out: str | Path) -> dict:
    """The contact picture of ``run``'s fields (:func:`render_contact`) as ``out``.png, and its data as ``out``.json
    (the frame: time, peak contact pressure and von Mises, the run's model, scene and mesh; REPORT.md renders it):
    workflows/contact_picture.py and a study's ``fields`` effect (rods.study.pipeline). The data."""
    run, out = Path(run), Path(out)
    check_run(run)
    points, cells, frames = read_fields(run / "fields.xdmf")  # once: the picture and its data
    t, d = _peak_frame(frames)
    _draw(points, cells, t, d, out.with_suffix(".png"), None)
    s = _run_summary(run)
    data = {
        "png": out.with_suffix(".png").name,
        "time": float(t),
        "peak_contact_pressure": float(d["contact_pressure"].max()),  # either tip face's (summary.json: Rod 1's)
        "von_mises_max": float(d["von_mises"].max()),
        "model": s["model"],
        "scene": s["scene"],
        "mesh": s["mesh"],
        "field_interval": scene_from_summary(s["scene_values"]).field_interval,  # [s] the fields effect's default too
    }
    io.write_data(out.with_suffix(".json"), data)
    return data
