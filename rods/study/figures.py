"""The comparison stage's figures: Fig. 6 (σ_r at the integration points nearest the surface against Hertz)
and Fig. 5c (contact pressure at peak force), from the submodels' summaries (σ_r and p(r) profiles)."""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rods import compare, hertz, io
from rods.metrics import PICTURE_PATCHES

__all__ = ["fig5c", "fig6", "pyplot"]


class _Figures:
    """The two calls of matplotlib.pyplot the figures make (``subplots``, ``close``), on figures of their own
    (matplotlib.figure.Figure, drawn by Agg when saved): no pyplot state, no backend switched. ``matplotlib.use("Agg")``
    switched a notebook's backend for the rest of its session (a library user's fuzz, 2026-12-07)."""

    @staticmethod
    def subplots(*args: Any, figsize: tuple[float, float] | None = None, **kwargs: Any) -> tuple[Any, Any]:
        from matplotlib.figure import Figure

        fig = Figure(figsize=figsize)
        return fig, fig.subplots(*args, **kwargs)

    @staticmethod
    def close(fig: Any) -> None:  # noqa: ARG004  (a Figure of its own: nothing holds it but the caller)
        pass


def pyplot() -> _Figures:
    """The figures' drawing calls (:class:`_Figures`), imported at the first figure: matplotlib at module level cost
    every entry point 0.6 s at start, bad input included."""
    return _Figures()


def fig6(out: Path, subs: Sequence[Mapping[str, Any]], nu: float) -> None:
    """σ_r against r at the Gauss points nearest the surface: FE levels and the closed form, out to PICTURE_PATCHES
    Hertz radii at the finest level's force."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for s in subs:
        prof = s.get("sigma_r_profile")
        if not prof:
            continue
        r, σ = np.asarray(prof["r"]), np.asarray(prof["sigma_r"])
        ax.plot(r * 1e3, σ / 1e6, ".", ms=3, label=f"FE {s['level']} (h = {s['element_size'] * 1e3:g} mm)")
    if subs:
        s = subs[-1]
        H = compare.stress_field_hertz(s)  # at the stored field's own force
        prof = s["sigma_r_profile"]
        r = np.asarray(prof["r"])
        z = np.asarray(prof["depth"])
        rr = np.linspace(1e-6, r.max(), 600)
        ax.plot(
            rr * 1e3,
            hertz.surface_radial_stress(rr, H["contact_radius"], H["peak_pressure"], nu) / 1e6,
            "k-",
            label=f"Hertz, surface (F = {H['force']:.0f} N)",
        )
        ax.plot(
            r * 1e3,
            hertz.subsurface_stresses(r, z, H["contact_radius"], H["peak_pressure"], nu)[0] / 1e6,
            "k--",
            lw=0.8,
            label=f"Hertz at the Gauss depth ({np.median(z) * 1e6:.1f} µm)",
        )
        ax.set_xlim(0, PICTURE_PATCHES * H["contact_radius"] * 1e3)  # a few patch radii (was 3 mm on every scene)
    ax.set_xlabel("r [mm]")
    ax.set_ylabel("σ_r [MPa]")
    ax.set_title("Fig. 6: σ_r at the integration points nearest the surface, peak force", fontsize=10)
    ax.grid(alpha=0.3)
    if subs:
        ax.legend(fontsize=8)
    else:  # the globals sample no σ_r: say so on the figure rather than leave an empty frame
        note = "no submodel level given: σ_r is sampled by the submodels"
        ax.text(0.5, 0.5, note, ha="center", transform=ax.transAxes)
    fig.tight_layout()
    fig.savefig(out / "fig6-sigma-r.png", dpi=150)
    plt.close(fig)


def fig5c(out: Path, s: Mapping[str, Any], E_star: float, R_star: float) -> None:
    """Contact pressure on the Rod-1 tip at peak force: a map of it on the tip (pyvista, off-screen; the
    axisymmetric p(r) revolved, a 3D run's nodes as they lie, its symmetry model mirrored whole) and p against
    the distance from the patch's centre with Hertz at the same force (matplotlib), both out to PICTURE_PATCHES
    Hertz radii at that force (they showed 2.5 mm, the paper's patch, on every scene). A 3D run's centre is its
    contact centroid (an offset or tilted impact's patch lies off Rod 1's axis, from which its profile's r runs)."""
    x, y, p = tip_pressure(s)
    c = (float(s.get("contact_centroid_x") or 0.0), float(s.get("contact_centroid_y") or 0.0))  # [m] axisymmetric: 0
    r = np.hypot(x - c[0], y - c[1])  # [m] from the patch's centre
    H = hertz.at_force(s["peak_contact_force"], E_star, R_star)
    R_disc = PICTURE_PATCHES * H["contact_radius"]  # [m] shown radius: a few patch radii, whatever the scene's
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    order = np.argsort(r)
    three_d = "x" in s["pressure_profile"]
    style = dict(marker="o", ms=2, ls="none" if three_d else "-")  # 3D: nodes at every angle, no line through them
    ax.plot(r[order] * 1e3, p[order] / 1e9, **style, label=f"FE {s.get('level', 'global')}")
    rr = np.linspace(0, R_disc, 500)
    ax.plot(
        rr * 1e3, hertz.pressure(rr, H["contact_radius"], H["peak_pressure"]) / 1e9, "k--", label="Hertz, same force"
    )
    ax.set_xlim(0, R_disc * 1e3)
    ax.set_xlabel("distance from the patch's centre [mm]" if three_d else "r [mm]")
    ax.set_ylabel("p [GPa]")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "fig5c-profile.png", dpi=150)
    plt.close(fig)
    keep = r <= R_disc
    _pressure_map(out / "fig5c-pressure.png", x[keep] * 1e3, y[keep] * 1e3, p[keep], s["peak_contact_force"])


def tip_pressure(s: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x [m], y [m], p [Pa]) on the Rod-1 tip at peak force, from a summary's ``pressure_profile``: the
    axisymmetric p(r) revolved (every 2°, the axis once), a 3D run's nodes with its symmetry model mirrored whole
    (half: about y = 0; quarter: about x = 0 and y = 0; rods.fe.mesh3d.QUADRANTS)."""
    prof = s["pressure_profile"]
    r, p = np.asarray(prof["r"], dtype=float), np.asarray(prof["p"], dtype=float)
    if "x" not in prof:
        th = np.linspace(0, 2 * np.pi, 180, endpoint=False)
        on_axis = r == 0
        x = np.r_[r[on_axis], np.outer(r[~on_axis], np.cos(th)).ravel()]
        y = np.r_[r[on_axis] * 0, np.outer(r[~on_axis], np.sin(th)).ravel()]
        return x, y, np.r_[p[on_axis], np.repeat(p[~on_axis], th.size)]
    x, y = np.asarray(prof["x"], dtype=float), np.asarray(prof["y"], dtype=float)
    symmetry = s.get("symmetry", "full")
    for flip, planes in (((1, -1), ("half", "quarter")), ((-1, 1), ("quarter",))):
        if symmetry in planes:
            x, y, p = np.r_[x, flip[0] * x], np.r_[y, flip[1] * y], np.r_[p, p]
    _, first = np.unique(np.round(np.c_[x, y], 12), axis=0, return_index=True)  # nodes on a plane once
    return x[first], y[first], p[first]


def _pressure_map(png: Path, x: np.ndarray, y: np.ndarray, p: np.ndarray, force: float) -> None:
    """Fig. 5c's map: p [Pa] at points (``x``, ``y``) [mm] on the tip, triangulated (pyvista, off-screen; matplotlib
    where VTK cannot render), titled with the ``force`` [N] it was taken at."""
    title = f"Fig. 5c: contact pressure on the Rod-1 tip at peak force ({force:.0f} N)"
    fmt = io.bar_format(float(np.abs(p).max(initial=0.0)) / 1e9)
    try:
        pv = io.offscreen_pyvista()
        surface = pv.PolyData(np.c_[x, y, np.zeros_like(x)]).delaunay_2d()
        surface.point_data["p [GPa]"] = p / 1e9  # delaunay_2d keeps the points and their order
        pl = pv.Plotter(off_screen=True, window_size=(900, 760))
        # the bar stands at the right, clear of the axes' labels (at the bottom it sat on the x labels)
        bar = dict(title="p [GPa]\n", vertical=True, position_x=0.85, position_y=0.2, width=0.06, height=0.55, fmt=fmt)
        pl.add_mesh(surface, scalars="p [GPa]", cmap="jet", show_edges=False, scalar_bar_args=bar)
        pl.show_bounds(xtitle="x [mm]", ytitle="y [mm]", font_size=12, location="outer")
        pl.view_xy()
        pl.camera.parallel_projection = True
        pl.camera.zoom(0.8)  # room for the axes' titles and the bar
        pl.add_text(title, font_size=10)
        pl.screenshot(str(png))
        pl.close()
    except Exception as e:  # no GL here: matplotlib fallback
        print(f"fig5c: pyvista rendering failed ({type(e).__name__}: {e}); matplotlib fallback", file=sys.stderr)
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(6, 5.5))
        pc = ax.tripcolor(x, y, p / 1e9, cmap="jet", shading="gouraud")
        fig.colorbar(pc, label="p [GPa]")
        ax.set(aspect="equal", xlabel="x [mm]", ylabel="y [mm]")
        fig.suptitle(f"{title}\n(matplotlib: VTK could not render)", fontsize=9)
        fig.tight_layout()
        fig.savefig(png, dpi=150)
        plt.close(fig)
