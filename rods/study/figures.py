"""The comparison stage's figures: Fig. 6 (σ_r at the integration points nearest the surface against Hertz)
and Fig. 5c (contact pressure at peak force), from the submodels' summaries (σ_r and p(r) profiles)."""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rods import hertz, io
from rods.metrics import PICTURE_PATCHES

__all__ = ["fig5c", "fig6", "pyplot"]


def pyplot():
    """matplotlib.pyplot on the Agg backend (files, no screen), imported at the first figure: at module level it
    cost every entry point 0.6 s at start, bad input included."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


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
        H = s["hertz_at_own_force"]
        prof = s["sigma_r_profile"]
        r = np.asarray(prof["r"])
        z = np.asarray(prof["depth"])
        rr = np.linspace(1e-6, r.max(), 600)
        ax.plot(
            rr * 1e3,
            hertz.surface_radial_stress(rr, H["contact_radius"], H["peak_pressure"], nu) / 1e6,
            "k-",
            label=f"Hertz, surface (F = {s['peak_contact_force']:.0f} N)",
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
    """Contact pressure on the Rod-1 tip at peak force: the axisymmetric p(r) revolved into a disc (pyvista,
    off-screen), and p(r) against Hertz at the same force (matplotlib), both out to PICTURE_PATCHES Hertz radii
    at that force (they showed 2.5 mm, the paper's patch, on every scene)."""
    plt = pyplot()
    r, p = np.asarray(s["pressure_profile"]["r"]), np.asarray(s["pressure_profile"]["p"])
    H = hertz.at_force(s["peak_contact_force"], E_star, R_star)
    R_disc = PICTURE_PATCHES * H["contact_radius"]  # [m] shown radius: a few patch radii, whatever the scene's
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(r * 1e3, p / 1e9, "o-", ms=2, label=f"FE {s.get('level', 'global')}")
    rr = np.linspace(0, r.max(), 500)
    ax.plot(
        rr * 1e3, hertz.pressure(rr, H["contact_radius"], H["peak_pressure"]) / 1e9, "k--", label="Hertz, same force"
    )
    ax.set_xlim(0, R_disc * 1e3)
    ax.set_xlabel("r [mm]")
    ax.set_ylabel("p [GPa]")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "fig5c-profile.png", dpi=150)
    plt.close(fig)
    keep = r <= R_disc
    _pressure_disc(out / "fig5c-pressure.png", r[keep], p[keep], s["peak_contact_force"])


def _pressure_disc(png: Path, r: np.ndarray, p: np.ndarray, force: float) -> None:
    """Fig. 5c's disc: the axisymmetric p(r) [Pa] at radii ``r`` [m] revolved about the axis (pyvista, off-screen;
    matplotlib where VTK cannot render), titled with the ``force`` [N] it was taken at."""
    th = np.linspace(0, 2 * np.pi, 181)
    title = f"Fig. 5c: contact pressure on the Rod-1 tip at peak force ({force:.0f} N)"
    fmt = io.bar_format(float(np.abs(p).max(initial=0.0)) / 1e9)
    try:
        pv = io.offscreen_pyvista()
        X, Y = np.outer(r, np.cos(th)) * 1e3, np.outer(r, np.sin(th)) * 1e3
        grid = pv.StructuredGrid(X, Y, np.zeros_like(X))
        grid.point_data["p [GPa]"] = np.tile(p / 1e9, th.size)  # points in Fortran order: r fastest
        pl = pv.Plotter(off_screen=True, window_size=(900, 760))
        # the bar stands at the right, clear of the axes' labels (at the bottom it sat on the x labels)
        bar = dict(title="p [GPa]\n", vertical=True, position_x=0.85, position_y=0.2, width=0.06, height=0.55, fmt=fmt)
        pl.add_mesh(grid, scalars="p [GPa]", cmap="jet", show_edges=False, scalar_bar_args=bar)
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
        T, Rg = np.meshgrid(th, r)
        fig, ax = plt.subplots(figsize=(6, 5.5))
        P = np.repeat(p[:, None] / 1e9, th.size, 1)
        pc = ax.pcolormesh(Rg * np.cos(T) * 1e3, Rg * np.sin(T) * 1e3, P, cmap="jet", shading="gouraud")
        fig.colorbar(pc, label="p [GPa]")
        ax.set(aspect="equal", xlabel="x [mm]", ylabel="y [mm]")
        fig.suptitle(f"{title}\n(matplotlib: VTK could not render)", fontsize=9)
        fig.tight_layout()
        fig.savefig(png, dpi=150)
        plt.close(fig)
