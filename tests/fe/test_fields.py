"""Field output (rods.fe.fields): every field on one grid at exactly the requested times plus the final state,
read back by meshio and VTK's legacy XDMF reader; serial and 2-rank files equal; a killed run leaves its frames
readable and a restart keeps them and appends the rest, equal to an uninterrupted run's."""

from __future__ import annotations

import json
import shutil
import signal
import subprocess
import time

import h5py
import meshio
import numpy as np
import pytest

from rods.fe.fields import FIELD_NAMES, frame_count, frame_schedule

from ..conftest import MPIRUN, ROOT, run_workflow, set_args

SPEED = 2.197  # [m/s] the paper scene's impact speed
# coarse axisymmetric paper rods (4 mm x 1 mm); Rod 1's far end is reached by the first wave at L/c ~ 49 µs
COARSE = ["fe.axial_size=4e-3", "fe.radial_size=1e-3"]


def _frames(out) -> list[tuple[float, dict[str, np.ndarray]]]:
    with meshio.xdmf.TimeSeriesReader(str(out / "fields.xdmf")) as r:
        points, _ = r.read_points_cells()
        return points, [r.read_data(k)[:2] for k in range(r.num_steps)]


def _run(out, extra, ranks=1):
    p = run_workflow("global.py", [*set_args([*COARSE, *extra]), "--out", str(out)], ranks, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    return json.loads((out / "summary.json").read_text())


def test_schedule_requested_times_at_the_nearest_step_and_the_final_state():
    dt = 0.3e-6  # [s]
    sched = frame_schedule(1e-6, dt, 10)  # end 3.0 µs: requested 0, 1, 2, 3 µs; 3 µs is the final state
    assert [(n, k) for n, fr in sorted(sched.items()) for k, _ in fr] == [(0, 0), (3, 1), (7, 2), (10, 3)]
    sched = frame_schedule(1e-6, dt, 11)  # end 3.3 µs: the final state is a frame of its own
    assert sched[11] == [(4, pytest.approx(3.3e-6))]
    sched = frame_schedule(1e-6, 0.301e-6, 10)  # end 3.01 µs, a fraction of a step past 3 µs: no repeat frame
    assert [(n, k) for n, fr in sorted(sched.items()) for k, _ in fr] == [(0, 0), (3, 1), (7, 2), (10, 3)]
    for args in [(1e-6, 0.3e-6, 10), (1e-6, 0.3e-6, 11), (1e-6, 0.301e-6, 10), (5e-6, 3.3e-8, 7607), (1e-9, 1e-7, 5)]:
        assert frame_count(*args) == sum(map(len, frame_schedule(*args).values())), args  # what rods.cost counts
    # the times a reader sees are the requested ones, not a product's last-digit noise (3 x 2e-5 = 6.000000000000001e-5)
    times = [t for fr in frame_schedule(2e-5, 1e-7, 1000).values() for _, t in fr]
    assert times[3] == 6e-5 and times[:6] == [0.0, 2e-5, 4e-5, 6e-5, 8e-5, 1e-4]


def test_every_field_on_one_grid_at_the_requested_times(tmp_path):
    """Before the first wave reaches Rod 1's far end it moves rigidly: u_z = s1 t and v_z = s1 at the frame
    times to 1e-6 and 5e-4 (the scheme's dispersive precursor, excited by the first closing pair's impulse
    under the kinematic contact: measured 4e-8 and 1.6e-4). u is interpolated on the scheme's
    own trajectory: at the nearest step only, u_z would be off by up to Δt/2t ~ 1e-3. The tip pressure peaks
    near the summary's peak pressure; von Mises peaks near the contact."""
    s = _run(tmp_path, ["simulation.end_time=3.3e-5", "fe.field_interval=1e-5"])
    points, frames = _frames(tmp_path)
    times = [t for t, _ in frames]
    assert times == pytest.approx([0.0, 1e-5, 2e-5, 3e-5, s["steps"] * s["dt"]], rel=1e-12, abs=1e-18)
    far = np.argmin(points[:, 1])  # Rod 1's far end (z = -L1)
    for t, d in frames:
        assert sorted(d) == sorted(FIELD_NAMES)
        assert d["displacement"].shape == d["velocity"].shape == (len(points), 3)
        assert d["displacement"][far, 1] == pytest.approx(SPEED * t, rel=1e-6, abs=1e-18)
        assert d["velocity"][far, 1] == pytest.approx(SPEED, rel=5e-4)
        assert np.all(d["von_mises"] >= 0) and np.all(d["contact_pressure"] >= 0)
    from rods.io import file_mode

    for f in [tmp_path / "fields.xdmf", *(tmp_path / "fields").iterdir()]:  # readable by a group (ParaView server)
        assert f.stat().st_mode & 0o777 == file_mode(), f
    p_max = max(d["contact_pressure"].max() for _, d in frames)
    assert p_max == pytest.approx(s["peak_contact_pressure"], rel=0.05)
    vm = frames[-1][1]["von_mises"][:, 0]
    assert np.argmax(vm) in np.flatnonzero(np.hypot(points[:, 0], points[:, 1]) < 2e-3)  # near the contact


def test_legacy_xdmf_reader_sees_all_fields(tmp_path):
    vtk = pytest.importorskip("vtk")
    s = _run(tmp_path, ["simulation.end_time=1e-5", "fe.field_interval=5e-6"])
    r = vtk.vtkXdmfReader()  # VTK's (and ParaView's) legacy XDMF reader, which crashed on DOLFINx's XDMF
    r.SetFileName(str(tmp_path / "fields.xdmf"))
    r.UpdateInformation()
    times = r.GetOutputInformation(0).Get(vtk.vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    assert s["steps"] * s["dt"] - 1e-5 < s["dt"]  # the run ends within a step of its last requested frame:
    assert times == pytest.approx([0.0, 5e-6, 1e-5], abs=1e-18)  # no near-repeat of it as the final state
    r.Update()
    pd = r.GetOutputDataObject(0).GetPointData()
    assert sorted(pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())) == sorted(FIELD_NAMES)


@pytest.mark.mpi
@pytest.mark.skipif(shutil.which(str(MPIRUN)) is None, reason="no mpirun")
@pytest.mark.parametrize("kind", ["axisymmetric", pytest.param("3d", marks=pytest.mark.slow)])  # 3D: 19 s
def test_fields_do_not_depend_on_the_rank_count(tmp_path, kind):
    extra = ["simulation.end_time=1e-5", "fe.field_interval=5e-6"]
    if kind == "3d":  # short rods, tilted: σ_rr in each rod's own cylindrical frame
        extra += ["fe.kind='3d'", "rod1.length=0.05", "rod2.length=0.1", "impact.tilt=0.02"]
    _run(tmp_path / "1", extra)
    _run(tmp_path / "2", extra, ranks=2)
    (p1, f1), (p2, f2) = _frames(tmp_path / "1"), _frames(tmp_path / "2")
    o1, o2 = (np.lexsort(np.round(p, 9).T[::-1]) for p in (p1, p2))  # global numbering depends on the partition
    np.testing.assert_allclose(p1[o1], p2[o2], rtol=0, atol=1e-15)  # [m]
    assert [t for t, _ in f1] == pytest.approx([t for t, _ in f2], rel=1e-9)  # Δt: SLEPc to round-off
    for (_, a), (_, b) in zip(f1, f2, strict=True):
        for name in FIELD_NAMES:
            scale = max(np.abs(a[name]).max(), 1e-300)
            np.testing.assert_allclose(b[name][o2], a[name][o1], rtol=0, atol=1e-9 * scale, err_msg=name)


@pytest.mark.slow  # 11 s; the killed run's restart is in the default suite (tests/fe/test_guards_restart.py)
def test_killed_run_keeps_its_frames_and_a_restart_appends(tmp_path):
    extra = ["simulation.end_time=2e-4", "fe.field_interval=1e-5", "fe.checkpoint_interval=5e-5"]
    ref, cut = tmp_path / "ref", tmp_path / "cut"
    _run(ref, extra)
    cmd = [str(MPIRUN.parent / "python"), "workflows/global.py", *set_args([*COARSE, *extra])]
    p = subprocess.Popen([*cmd, "--out", str(cut)], cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    t0, ck = time.time(), cut / "checkpoint.json"
    while not ck.exists() or json.loads(ck.read_text())["time"] < 1e-4:
        assert p.poll() is None, "run ended before it could be killed"
        assert time.time() - t0 < 120
        time.sleep(0.02)
    p.send_signal(signal.SIGKILL)
    p.wait()
    _, before = _frames(cut)  # readable after kill -9: every frame the XML lists
    assert len(before) >= 10 and not (cut / "summary.json").exists()
    for f in (cut / "fields").glob("frame-*.h5"):
        with h5py.File(f, "r") as h:
            assert sorted(h) == sorted(FIELD_NAMES)
    r = subprocess.run([*cmd, "--out", str(cut), "--restart"], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    (_, a), (_, b) = _frames(ref), _frames(cut)
    assert [t for t, _ in b] == [t for t, _ in a]  # the frames before the restart are kept, none doubled
    for (_, da), (_, db) in zip(a, b, strict=True):
        for name in FIELD_NAMES:
            np.testing.assert_allclose(db[name], da[name], rtol=0, atol=1e-10 * max(np.abs(da[name]).max(), 1e-300))


def test_a_run_afresh_leaves_no_earlier_series_and_the_picture_refuses_a_foreign_one(tmp_path):
    """A run without fields reused the folder of a run with fields: fields.xdmf and its 11 frames of the 2.197 m/s
    run stayed beside the new 1.0 m/s summary, and contact_picture.py drew the old run's peak labelled with the
    new scene. Now a run afresh removes an earlier run's series (XML, frames, ADIOS2 folders), and a series
    written by another run than the summary.json beside it (copied in, or an older version's left behind; one
    without a record of its run) is refused, exit 2, one line, before the picture's folder is made."""
    from rods.fe.fields import check_run, render_contact
    from rods.preflight import InputError

    out, old = tmp_path / "gf", tmp_path / "old"
    _run(out, ["simulation.end_time=1e-4", "fe.field_interval=1e-5"])
    assert len(list((out / "fields").glob("frame-*.h5"))) == 11 and (out / "fields.bp").is_dir()
    check_run(out)  # its own series
    shutil.copytree(out, old)
    s = _run(out, ["simulation.end_time=5e-5", "impact.speed=1.0"])  # no fields asked
    assert s["impact_speed"] == 1.0
    assert sorted(p.name for p in out.iterdir()) == ["history.csv", "pressure_profile.csv", "summary.json"]
    picture = tmp_path / "cp" / "x"
    p = run_workflow("contact_picture.py", ["--fields", str(out), "--out", str(picture)])
    assert p.returncode == 2 and "has no fields.xdmf" in p.stderr, p.stderr[-2000:]
    for name in ("fields", "fields.xdmf"):  # the old run's series beside the new summary
        (shutil.copytree if (old / name).is_dir() else shutil.copy)(old / name, out / name)
    p = run_workflow("contact_picture.py", ["--fields", str(out), "--out", str(picture)])
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1, p.stderr[-2000:]
    assert lines[0].startswith("error: --fields") and "written by another run" in lines[0] and "rerun" in lines[0]
    assert not picture.parent.exists()
    with pytest.raises(InputError, match="another run"):
        render_contact(out / "fields.xdmf", tmp_path / "x.png")
    with h5py.File(old / "fields" / "mesh.h5", "a") as f:  # an older version's series: no record of its run
        del f.attrs["scene_values"]
    with pytest.raises(InputError, match="no record"):
        check_run(old)

    # a damaged series, each named by its file in one line (a fuzz: exit 1 with h5py's or the XML parser's words);
    # the damage is found before the series is matched to its summary
    def truncate(f, n: int) -> None:
        f.write_bytes(f.read_bytes()[:n])

    frame = sorted((out / "fields").glob("frame-*.h5"))[4].name
    for damage, words in (
        (lambda d: truncate(d / "fields" / frame, 1000), f"{frame} is not a readable HDF5"),
        (lambda d: (d / "fields" / frame).unlink(), f"{frame} is missing"),
        (lambda d: truncate(d / "fields" / "mesh.h5", 100), "mesh.h5 is not a readable HDF5"),
        (lambda d: truncate(d / "fields.xdmf", 300), "fields.xdmf is not a readable XDMF"),
        (lambda d: (d / "fields.xdmf").write_text("<Xdmf/>"), "fields.xdmf names no mesh or frame"),
    ):
        damaged = tmp_path / "damaged"
        shutil.rmtree(damaged, ignore_errors=True)
        shutil.copytree(out, damaged)
        damage(damaged)
        with pytest.raises(InputError, match=f"--fields.*its field series is damaged: .*{words}"):
            check_run(damaged)


class _Killed(Exception):
    """Stands for kill -9 right after a checkpoint is on disk."""


def test_a_checkpoint_implies_its_frames_are_on_disk(tmp_path, monkeypatch, capfd):
    """The kill window the subprocess test above cannot aim at: the process dies just after a checkpoint
    at step c is written. The restart resumes at c + 1, so every frame up to step c must already be written
    (fields before checkpoints in the observer order); otherwise a frame goes missing for good."""
    from rods.fe import checkpoint
    from rods.fe.model import ExplicitModel
    from rods.scene import load_scene

    from ..conftest import PAPER

    sc = load_scene(
        PAPER, [*COARSE, "simulation.end_time=4e-5", "fe.field_interval=1e-5", "fe.checkpoint_interval=2e-5"]
    )
    model = ExplicitModel(sc)
    save = checkpoint.Checkpoints.save_now

    def save_then_die(self, step, t):
        save(self, step, t)
        raise _Killed

    monkeypatch.setattr(checkpoint.Checkpoints, "save_now", save_then_die)
    (tmp_path / "summary.json").write_text('{"status": "ok"}')  # an earlier run's, finished, in this folder
    with pytest.raises(_Killed):
        model.run(tmp_path)
    # a run afresh removed it: killed, the folder reads as unfinished, not as the earlier run beside a partial series
    assert not (tmp_path / "summary.json").exists()
    t_ck = json.loads((tmp_path / "checkpoint.json").read_text())["time"]
    _, frames = _frames(tmp_path)
    assert t_ck == pytest.approx(2e-5, rel=0.02)
    assert [t for t, _ in frames] == pytest.approx([0.0, 1e-5, 2e-5], rel=1e-9, abs=1e-18)
    # a frame deleted before the restart cannot come back: the restart names it and lists the frames found
    monkeypatch.undo()
    (tmp_path / "fields" / "frame-000001.h5").unlink()
    capfd.readouterr()
    model.run(tmp_path, restart=True)
    err = capfd.readouterr().err
    assert "1 frame(s) before the restart are missing" in err and "t = 10 µs" in err, err
    _, frames = _frames(tmp_path)
    assert [t for t, _ in frames] == pytest.approx([0.0, 2e-5, 3e-5, 4e-5], rel=1e-9, abs=1e-18)


def test_contact_picture_off_screen_without_x_warnings(tmp_path, capfd, monkeypatch):
    from rods.fe.fields import render_contact

    _run(tmp_path, ["simulation.end_time=2e-5", "fe.field_interval=1e-5"])
    monkeypatch.delenv("DISPLAY", raising=False)
    t = render_contact(tmp_path / "fields.xdmf", tmp_path / "contact.png")
    _, frames = _frames(tmp_path)
    assert t == max(frames, key=lambda f: f[1]["contact_pressure"].max())[0]  # the peak-pressure frame
    assert (tmp_path / "contact.png").stat().st_size > 20_000
    assert "X server" not in capfd.readouterr().err
    # the main job's picture and its data (workflows/contact_picture.py), rendered into REPORT.md
    p = run_workflow("contact_picture.py", ["--fields", str(tmp_path), "--out", str(tmp_path / "cf")])
    assert p.returncode == 0, p.stderr[-2000:]
    cf = json.loads((tmp_path / "cf.json").read_text())
    d = next(f for tf, f in frames if tf == t)
    assert cf["time"] == t and cf["peak_contact_pressure"] == d["contact_pressure"].max()
    from rods.paper.report import contact_fields_section

    text = "\n".join(contact_fields_section(cf))
    assert f"t = {t * 1e6:.2f} µs" in text and "![contact region at peak contact pressure](cf.png)" in text
    # a run killed before its summary.json (its series complete): pictured, named by the series' own scene (it was
    # refused as "a run without fields": an audit, 2026-12-07)
    (tmp_path / "summary.json").unlink()
    p = run_workflow("contact_picture.py", ["--fields", str(tmp_path), "--out", str(tmp_path / "killed")])
    assert p.returncode == 0, p.stderr[-2000:]
    killed = json.loads((tmp_path / "killed.json").read_text())
    assert killed["time"] == t and killed["model"] is None and killed["scene"].endswith("(no summary.json)")


@pytest.mark.slow  # 10 s; the axisymmetric picture off screen is in the default suite
def test_contact_picture_of_a_half_3d_model_with_an_offset(tmp_path):
    """3D fields of a half model (its plane y = 0 is the symmetry boundary): the picture's section is that plane's
    quadrilaterals, each once, and its window is centred on the off-axis patch. Before, VTK's slice of the
    warped boundary plane was empty and contact_picture.py stopped with KeyError 'von Mises [MPa]' (exit 1)."""
    from rods.fe.fields import read_fields, render_contact, section_y0

    extra = ["fe.kind='3d'", "fe.symmetry='half'", "impact.offset=2e-3", "fe.tip_grading=0.25"]
    short = ["rod1.length=0.06", "rod2.length=0.06"]  # the contact region only: 12 cm of rods, 30 µs, 7 frames
    _run(tmp_path, [*extra, *short, "simulation.end_time=3e-5", "fe.field_interval=5e-6"])
    points, hexes, frames = read_fields(tmp_path / "fields.xdmf")
    quads = section_y0(points, hexes)
    assert len(quads) == len(np.unique(np.sort(quads, axis=1), axis=0)) > 0
    assert set(np.unique(quads)) == set(np.flatnonzero(np.abs(points[:, 1]) < 1e-12))  # the whole plane
    t = render_contact(tmp_path / "fields.xdmf", tmp_path / "contact.png")
    assert t == max(frames, key=lambda f: f[1]["contact_pressure"].max())[0]
    assert (tmp_path / "contact.png").stat().st_size > 20_000
    p = run_workflow("contact_picture.py", ["--fields", str(tmp_path), "--out", str(tmp_path / "cf")])
    assert p.returncode == 0, p.stderr[-2000:]


def test_the_paraview_script_names_the_fields_the_model_writes():
    """workflows/view.py runs under ParaView's own Python, without this project's packages, so it keeps its own list
    of the field names; it must be the writer's (rods.fe.fields.FIELD_NAMES), or pvpython would colour by a field
    the files do not hold. Read from the script's text: importing it needs nothing but the standard library."""
    import ast
    from pathlib import Path

    from rods.fe.fields import FIELD_NAMES
    from rods.metrics import PICTURE_PATCHES

    tree = ast.parse((Path(__file__).resolve().parents[2] / "workflows" / "view.py").read_text())
    names = {n.targets[0].id: n.value for n in tree.body if isinstance(n, ast.Assign)}
    assert ast.literal_eval(names["FIELDS"]) == FIELD_NAMES
    assert ast.literal_eval(names["PICTURE_PATCHES"]) == PICTURE_PATCHES  # and frames the patch as the library


def test_the_paraview_view_frames_the_runs_patch(tmp_path):
    """view.py's half-width: PICTURE_PATCHES contact radii of the run (summary.json beside fields.xdmf; it was 3 mm
    on every scene); a folder or file whose run has no summary (stopped before it) or no contact: the mesh's
    half-width across."""
    import importlib
    import json

    from rods.metrics import PICTURE_PATCHES

    view = importlib.import_module("view")  # stdlib only at import: ParaView is imported where it renders
    bounds = (0.0, 6.35e-3, -0.1, 0.2, 0.0, 0.0)  # [m] an axisymmetric mesh's data bounds: r, z
    assert view.window(tmp_path, bounds) == 6.35e-3
    (tmp_path / "summary.json").write_text(json.dumps({"contact_radius": 4e-3}))
    assert view.window(tmp_path, bounds) == pytest.approx(PICTURE_PATCHES * 4e-3)
    assert view.window(tmp_path / "fields.xdmf", bounds) == pytest.approx(PICTURE_PATCHES * 4e-3)
    (tmp_path / "summary.json").write_text(json.dumps({"contact_radius": None}))
    assert view.window(tmp_path, bounds) == 6.35e-3


@pytest.mark.parametrize("a", [0.1e-3, 1.09e-3, 6e-3])  # [m] a small rod's patch, the paper's, a 100 mm rod's
def test_the_contact_picture_frames_the_patch_whatever_its_size(a):
    """The picture's half-width is PICTURE_PATCHES contact radii of the frame it draws (it was 2.5 mm on every
    scene: the paper's patch, where a 6 mm patch fell outside and a 0.1 mm one was a few pixels): axisymmetric from
    the axis, 3D from the loaded nodes' centre (an offset patch); no node loaded: the mesh's half-width."""
    from rods.fe.fields import PICTURE_PATCHES, picture_window

    r = np.linspace(0.0, 20 * a, 401)
    axi = np.column_stack([r, np.zeros_like(r), np.zeros_like(r)])
    p = np.where(r <= a, 1e9 * np.sqrt(np.clip(1 - (r / a) ** 2, 0, None)) + 1.0, 0.0)
    assert picture_window(axi, p, three_d=False) == pytest.approx(PICTURE_PATCHES * a)
    e = 3 * a  # an offset patch in 3D: measured from its own centre, not the axis
    xy = np.array(
        [[e + a * np.cos(t), a * np.sin(t), 0.0] for t in np.linspace(0, 2 * np.pi, 16, endpoint=False)] + [[e, 0, 0]]
    )
    hexes_pts = np.vstack([xy, [[-20 * a, 0, 0], [20 * a, 0, 0]]])
    p3 = np.r_[np.ones(len(xy)), 0.0, 0.0]
    assert picture_window(hexes_pts, p3, three_d=True) == pytest.approx(PICTURE_PATCHES * a)
    assert picture_window(axi, np.zeros_like(p), three_d=False) == pytest.approx(20 * a)


def test_the_paraview_view_is_centred_on_an_off_axis_patch(tmp_path):
    """view.py centres a 3D run's section on the patch (it looked at the axis: a 3 mm offset's 1 mm patch fell
    outside the 2.5 mm window): the run's force-weighted contact centroid at peak force, the summary key the
    library writes (rods.fe.contact.PATCH_KEYS); on the axis without a summary or a centroid."""
    import importlib
    import json

    from rods.fe.contact import PATCH_KEYS

    view = importlib.import_module("view")
    assert view.centre(tmp_path) == 0.0
    (tmp_path / "summary.json").write_text(json.dumps({PATCH_KEYS[0]: 3.1e-3, "contact_radius": 1e-3}))
    assert view.centre(tmp_path) == 3.1e-3 and view.centre(tmp_path / "fields.xdmf") == 3.1e-3
    assert view.window(tmp_path, (0.0, 1.0)) == pytest.approx(view.PICTURE_PATCHES * 1e-3)
    (tmp_path / "summary.json").write_text(json.dumps({PATCH_KEYS[0]: None}))
    assert view.centre(tmp_path) == 0.0
    (tmp_path / "summary.json").write_text("[1, 2]")  # not a summary: on the axis, the mesh's width
    assert view.centre(tmp_path) == 0.0 and view.window(tmp_path, (-2e-3, 5e-3)) == 5e-3


def test_the_pressure_is_drawn_on_the_section_boundary_without_the_axis():
    """rods.fe.fields.surface_edges: the contact picture draws the nodal contact pressure (a surface traction) along
    the section's boundary edges, not interpolated into the cells beside the faces. A 2 x 2 block of quadrilaterals
    at 0 <= r <= 2: 8 boundary edges, 2 of them on the axis r = 0 (no surface of an axisymmetric model)."""
    from rods.fe.fields import surface_edges

    r, z = np.meshgrid([0.0, 1.0, 2.0], [0.0, 1.0, 2.0])
    points = np.stack([r.ravel(), z.ravel(), np.zeros(9)], axis=1)
    quads = np.array([[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]])  # counter-clockwise
    edges = {tuple(e) for e in surface_edges(points, quads).tolist()}
    assert edges == {(0, 1), (1, 2), (2, 5), (5, 8), (7, 8), (6, 7)}  # bottom, right, top; not (0, 3), (3, 6)
    assert {tuple(e) for e in surface_edges(points + [1.0, 0.0, 0.0], quads).tolist()} >= {(0, 3), (3, 6)}


def test_a_dolfinx_without_adios2_writes_the_xdmf_series_alone(tmp_path, monkeypatch, capfd):
    """DOLFINx 0.11 built without ADIOS2 (``dolfinx.common.has_adios2`` false: no ``dolfinx.io.VTXWriter``; some
    conda and source builds) runs with fields: the XDMF series has every frame, no ``fields.bp``, and one note
    says why."""
    import dolfinx

    from rods.fe.model import ExplicitModel
    from rods.scene import load_scene

    from ..conftest import PAPER

    monkeypatch.setattr(dolfinx.common, "has_adios2", False)
    monkeypatch.delattr(dolfinx.io, "VTXWriter")  # as such a build has none
    ExplicitModel(load_scene(PAPER, [*COARSE, "simulation.end_time=2e-5", "fe.field_interval=1e-5"])).run(tmp_path)
    _, frames = _frames(tmp_path)
    assert [t for t, _ in frames] == pytest.approx([0.0, 1e-5, 2e-5], rel=1e-9, abs=1e-18)
    assert not list(tmp_path.glob("*.bp"))
    assert "this DOLFINx has no ADIOS2" in capfd.readouterr().err


def test_the_series_xml_is_rewritten_geometrically_not_after_every_frame(tmp_path, monkeypatch):
    """Rewritten after every frame, fields.xdmf's writes grew with the square of the frames (3002 frames: 37.8 s and
    ~8 GB); now once the unlisted frames are a tenth of the listed (or 2 s on), and whole at flush."""
    from rods import io
    from rods.fe import fields

    writes = []
    real = io.atomic_write_text
    monkeypatch.setattr(io, "atomic_write_text", lambda path, text: (writes.append(len(text)), real(path, text)))
    monkeypatch.setattr(fields, "XML_INTERVAL", 1e9)  # [s] the count alone
    points, cells = np.zeros((3, 3)), np.array([[0, 1, 2]])
    s = fields.XdmfSeries(tmp_path, points, cells, "Triangle", -np.inf, "{}")
    for k in range(1000):
        s.write(k, k * 1e-6, {"velocity": np.zeros((3, 3))})
    assert len(writes) < 80 and sum(writes) < 12 * writes[-1]  # O(log n) rewrites, O(n) bytes (not 1000, n²/2)
    s.flush()
    assert (tmp_path / "fields.xdmf").read_text().count('<Grid Name="frame"') == 1000
