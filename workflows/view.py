"""Open a run's fields in ParaView (pvpython): warp by displacement, colour by von Mises around the contact.

    pvpython workflows/view.py output/g                       # list frames and fields (both XDMF readers)
    xvfb-run -a pvpython workflows/view.py output/g --png contact.png [--time 3e-5] [--scale 50]

RUN is a run folder with ``fields.xdmf`` (written by the FE models when the scene asks for fields, see
``rods.fe.fields``) or the file itself. Without ``--time`` the frame with the largest contact pressure is
shown (the peak-force frame of the field series), 2.5 contact radii of the run (its summary.json) either
side. ``--reader legacy`` uses ParaView's XDMF (2) reader instead of the Xdmf3 one; both read the file.
``--check`` exits 1 unless every frame has every field.
Runs under ParaView's own Python (Debian: ``apt-get install paraview python3-paraview``), not the venv.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path
from typing import NoReturn

FIELDS = ("displacement", "velocity", "sigma_zz", "sigma_rr", "sigma_tt", "von_mises", "contact_pressure")
# half-width of the view around the contact point (the tips touch at the origin) in contact radii [-]: the run's
# (rods.metrics.PICTURE_PATCHES, kept here as this runs without the project's packages; a test ties the two)
PICTURE_PATCHES = 2.5


def _summary(run: Path) -> dict:
    """The run's summary.json beside its fields; {} where there is none (a run stopped before it) or unreadable."""
    folder = run if run.is_dir() else run.parent
    try:
        s = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return s if isinstance(s, dict) else {}


def _number(s: dict, key: str) -> float:
    """``s[key]`` as a finite float, else NaN (absent, null)."""
    try:
        v = float(s[key])
    except (KeyError, TypeError, ValueError):
        return math.nan
    return v if math.isfinite(v) else math.nan


def window(run: Path, bounds: tuple[float, ...]) -> float:
    """Half-width of the view [m]: PICTURE_PATCHES x the run's contact radius (its summary.json beside the fields),
    else (a run stopped before its summary) the mesh's half-width across, the whole tip (``bounds``: the data's)."""
    a = _number(_summary(run), "contact_radius")
    return PICTURE_PATCHES * a if a > 0 else max(abs(bounds[0]), abs(bounds[1]))


def centre(run: Path) -> float:
    """x [m] of the patch's centre on the section y = 0, where the view is centred: a 3D run's force-weighted contact
    centroid at peak force (summary.json's contact_centroid_x, rods.fe.contact.PATCH_KEYS; an offset or tilted
    impact's patch lies off the axis, beyond a few contact radii of it for an offset of a few radii), else 0: on the
    axis (axisymmetric runs, centric impacts, a run stopped before its summary)."""
    x = _number(_summary(run), "contact_centroid_x")
    return x if math.isfinite(x) else 0.0


def open_fields(path: Path, legacy: bool):
    from paraview import simple as pv

    xdmf = path / "fields.xdmf" if path.is_dir() else path
    if legacy:
        return pv.XDMFReader(FileNames=[str(xdmf)])
    return pv.Xdmf3ReaderS(FileName=[str(xdmf)])


def frames(reader) -> list[tuple[float, list[str], float]]:
    """(time [s], point fields, largest contact pressure [Pa]) of every frame."""
    out = []
    for t in reader.TimestepValues:
        reader.UpdatePipeline(t)
        names = sorted(reader.PointData.keys())
        p = reader.PointData["contact_pressure"].GetRange()[1] if "contact_pressure" in names else 0.0
        out.append((float(t), names, p))
    return out


def contact_motion(reader, t: float) -> list[float]:
    """The mean displacement [m] of the nodes in contact at time ``t`` (contact pressure > 0; zero where none): the
    rods' common motion, which the picture takes out before it warps (else ``scale`` x the rigid motion carried the
    contact out of the view: 38 µm x 50 against a 3 mm window, an audit, 2026-12-07)."""
    import numpy as np
    from paraview import servermanager
    from paraview.vtk.util.numpy_support import vtk_to_numpy

    reader.UpdatePipeline(t)
    data = servermanager.Fetch(reader)
    blocks = data.IsA("vtkMultiBlockDataSet")
    grids = [data.GetBlock(i) for i in range(data.GetNumberOfBlocks())] if blocks else [data]
    u, p = [], []
    for g in grids:
        if g is not None and g.GetPointData().GetArray("contact_pressure") is not None:
            u.append(vtk_to_numpy(g.GetPointData().GetArray("displacement")))
            p.append(vtk_to_numpy(g.GetPointData().GetArray("contact_pressure")))
    if not p:
        return [0.0, 0.0, 0.0]
    u, p = np.concatenate(u), np.concatenate(p)
    return [float(c) for c in u[p > 0].mean(axis=0)] if (p > 0).any() else [0.0, 0.0, 0.0]


def render(reader, t: float, scale: float, png: str, run: Path) -> None:
    """Warp by ``scale`` x the displacement relative to the contact (:func:`contact_motion`), colour by von Mises at
    time ``t``, camera on the contact (3D: the section y = 0, seen from -y, on :func:`centre`; axisymmetric: the
    (r, z) plane), :func:`window` either side; labelled with the time and the warp factor."""
    from paraview import simple as pv

    bounds = reader.GetDataInformation().GetBounds()
    three_d = bounds[5] - bounds[4] > 0
    u_c = contact_motion(reader, t)
    source = pv.Slice(Input=reader, SliceType="Plane") if three_d else reader
    if three_d:  # a hair off the symmetry plane: a series written before rods.fe.mesh3d.SNAP has its nodes at
        # y = ±1e-19 there, and a cut at 0 dropped the rim's cells
        source.SliceType.Origin, source.SliceType.Normal = [0, 1e-12, 0], [0, 1, 0]
    relative = pv.Calculator(Input=source, ResultArrayName="relative_displacement")
    relative.Function = f"displacement - ({u_c[0]!r}*iHat + {u_c[1]!r}*jHat + {u_c[2]!r}*kHat)"
    warp = pv.WarpByVector(Input=relative, Vectors=["POINTS", "relative_displacement"], ScaleFactor=scale)
    view = pv.CreateRenderView()
    view.ViewSize = [1200, 800]
    view.ViewTime = t
    view.OrientationAxesVisibility = 0
    shown = pv.Show(warp, view)
    pv.ColorBy(shown, ("POINTS", "von_mises"))
    shown.RescaleTransferFunctionToDataRange(False, True)
    shown.SetScalarBarVisibility(view, True)
    pv.GetScalarBar(pv.GetColorTransferFunction("von_mises"), view).Title = "von Mises [Pa]"
    x_c = centre(run) if three_d else 0.0  # [m] the patch's centre (axisymmetric: r = 0, on the axis)
    view.CameraPosition = [x_c, -1, 0] if three_d else [0, 0, 1]
    view.CameraFocalPoint, view.CameraViewUp = [x_c, 0, 0], [0, 0, 1] if three_d else [0, 1, 0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = window(run, bounds)
    label = pv.Text(Text=f"von Mises, t = {t * 1e6:.3g} µs, displacement relative to the contact x {scale:g}")
    pv.Show(label, view).FontSize = 14
    pv.SaveScreenshot(png, view, ImageResolution=[1200, 800])


def _bad(message: str) -> int:
    """Bad input: one line, exit 2 (the entry points' convention, workflows/_cli.py)."""
    print(f"error: {message}", file=sys.stderr)
    return 2


class _Parser(argparse.ArgumentParser):
    """argparse with the entry points' one error line (its own printed the usage block first)."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"error: {message} (see {self.prog} --help)\n")


def _finite(text: str) -> float:
    """An argparse type: a finite number (float() takes 'nan' and 'inf')."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} must be a finite number")
    return value


def main(argv: list[str] | None = None) -> int:
    # plain argparse: this runs under ParaView's pvpython, without the venv's workflows/_cli.py helpers
    ap = _Parser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", type=Path, help="run folder (with fields.xdmf) or the .xdmf file")
    ap.add_argument("--reader", choices=("xdmf3", "legacy"), default="xdmf3")
    ap.add_argument("--time", type=_finite, help="frame time [s] (default: the largest contact pressure)")
    ap.add_argument("--scale", type=_finite, default=1.0, help="displacement warp factor [-]")
    ap.add_argument("--png", help="save a screenshot (needs a display: xvfb-run -a pvpython ...)")
    ap.add_argument("--check", action="store_true", help="exit 1 unless every frame has every field")
    a = ap.parse_args(argv)
    try:  # a name over the file system's 255 bytes raises here (a fuzz: a traceback, exit 1)
        xdmf = a.run / "fields.xdmf" if a.run.is_dir() else a.run
        found = xdmf.is_file()
    except OSError as e:
        return _bad(f"{str(a.run)[:120]}: {e.strerror or e}; give a run folder or its fields.xdmf")
    if not found:
        return _bad(f"{xdmf}: no such file (a run writes fields.xdmf when its scene asks for fields; README "
                    "'Looking at fields')")  # fmt: skip
    try:
        import paraview.simple  # noqa: F401
    except ImportError as e:
        return _bad(f"ParaView's Python is not importable ({e}); run this script with pvpython, not the venv's python")
    reader = open_fields(a.run, a.reader == "legacy")
    series = frames(reader)
    if not series:  # a series whose XML lists no frame (a run stopped before its first), or not one ParaView reads:
        # --check passed it and --png ended in max()'s ValueError (a fuzz, with a stand-in reader)
        return _bad(f"{xdmf}: no frames that ParaView reads; give the fields.xdmf of a run that wrote frames")
    for t, names, p in series:
        print(f"t = {t:.6g} s  p_max = {p:.4g} Pa  {' '.join(names)}")
    if a.check and any(sorted(FIELDS) != names for _, names, _ in series):
        print("fields missing", file=sys.stderr)
        return 1
    if a.png:
        t = a.time if a.time is not None else max(series, key=lambda f: f[2])[0]
        render(reader, t, a.scale, a.png, a.run)
        print(f"wrote {a.png} (t = {t:.6g} s)")
    return 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    # skip the interpreter's teardown: with Mesa GLX on a virtual display (xvfb-run) the render window's
    # destructor fails (GLXBadContext) after the screenshot is written, which would turn the exit code to 1
    os._exit(code)
