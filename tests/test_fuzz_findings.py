"""What a fuzz of the entry points found (2026-12-07: ~8,800 generated inputs to analytical.py, global.py, run.py,
submodel.py, verify.py, view.py and rods.scene.load_scene, in-process, each bounded to 20 s), pinned: each case
failed before its mend. tests/test_fuzz_cli.py is the standing harness.

* nesting: a scene file or --set nesting lists/tables deeper than Python's recursion: exit 1 "RecursionError"
* lock: a .rods-lock in --out this process cannot open (another user's stale lock, a folder): exit 1, an OSError
* sizes: schema-valid extreme sizes: the plan's own counting took minutes and gigabytes (MemoryError, exit 1)
* mesh first: run.py --dry-run / global.py --driver --dry-run on a µm rod: the analytical planning ran minutes
  before the FE mesh (refused for memory in seconds) was looked at
* level: submodel.py --level too coarse for the rods: the refusal named --size, never given
* fields: global.py --out DIR removed DIR/fields/ whole, whatever it held (exit 0)
* view: workflows/view.py: a name over 255 bytes, or a series without frames: a traceback
* verify: verify.py --case X: a refusal's remedy ran every case and named another case's refusal instead
"""

from __future__ import annotations

import importlib
import resource
import sys
import time
import types

import pytest

from .conftest import PAPER, in_process, set_args

TINY = ["fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=2e-5"]


def refused(p, out=None) -> str:
    """The one error line of an exit-2 refusal (no traceback, no output folder)."""
    errors = [line for line in p.stderr.splitlines() if line.startswith("error")]
    assert p.returncode == 2, (p.returncode, p.stderr[-2000:])
    assert len(errors) == 1 and "Traceback" not in p.stderr, p.stderr[-2000:]
    assert out is None or not out.exists(), "an output folder after exit 2"
    return errors[0]


# nesting --------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("depth", [40, 600, 5000])
def test_deeply_nested_set_is_refused_naming_the_key(tmp_path, depth):
    value = "[" * depth + "]" * depth
    p = in_process("analytical.py", "--set", f"effects={value}", "--dry-run", "--out", str(tmp_path / "o"),
                   cwd=tmp_path)  # fmt: skip
    assert "effects" in refused(p, tmp_path / "o")


DEEP = ["x = " + "[" * 1000 + "]" * 1000, "[" + ".".join(["t"] * 500) + "]", "x = " + "{a = " * 400 + "1" + "}" * 400]


@pytest.mark.parametrize("tail", DEEP)
def test_deeply_nested_scene_file_is_refused_naming_the_file(tmp_path, tail):
    scene = tmp_path / "deep.toml"
    scene.write_text(PAPER.read_text() + "\n" + tail + "\n")
    p = in_process("analytical.py", "--scene", str(scene), "--dry-run", "--out", str(tmp_path / "o"), cwd=tmp_path)
    assert "deep.toml" in refused(p, tmp_path / "o")


def test_load_scene_raises_scene_error_only_on_deep_nesting(tmp_path):
    from rods.scene import SceneError, load_scene

    scene = tmp_path / "deep.toml"
    scene.write_text(PAPER.read_text() + "\n[" + ".".join(["t"] * 500) + "]\n")
    with pytest.raises(SceneError):
        load_scene(scene)
    with pytest.raises(SceneError):
        load_scene(PAPER, ["effects=" + "[" * 800 + "]" * 800])


# lock -----------------------------------------------------------------------------------------------------------------
def test_lock_that_is_a_folder_is_refused(tmp_path):
    out = tmp_path / "o"
    (out / ".rods-lock").mkdir(parents=True)
    p = in_process("analytical.py", *set_args(["simulation.end_time=1e-4"]), "--out", str(out), cwd=tmp_path)
    line = refused(p)
    assert ".rods-lock" in line and "remove" in line
    assert sorted(q.name for q in out.iterdir()) == [".rods-lock"]  # nothing written


def test_lock_file_of_another_user_is_opened_read_only(tmp_path, monkeypatch):
    """A stale 0644 lock of another user: O_RDWR is denied, flock on a read-only descriptor holds the folder."""
    from rods import preflight

    out = tmp_path / "o"
    out.mkdir()
    (out / ".rods-lock").write_text("")
    real_open = preflight.os.open

    def os_open(path, flags, *mode):
        if str(path).endswith(".rods-lock") and flags & preflight.os.O_RDWR:
            raise PermissionError(13, "Permission denied", str(path))
        return real_open(path, flags, *mode)

    monkeypatch.setattr(preflight.os, "open", os_open)
    claim = preflight.FolderClaim(out)
    with pytest.raises(preflight.InputError, match="another run is writing"):
        preflight.FolderClaim(out)  # the read-only lock holds it
    claim.release()


def test_a_lock_flock_cannot_take_is_refused_not_removed(tmp_path, monkeypatch):
    """Where flock is byte-range (NFS) an exclusive lock through a read-only descriptor fails with EBADF: that is no
    file system without locks, so the other user's lock file stays and the claim is refused (a review, 2026-12-07)."""
    import errno

    from rods import preflight

    out = tmp_path / "o"
    out.mkdir()
    (out / ".rods-lock").write_text("")

    def flock(fd, op):
        raise OSError(errno.EBADF, "Bad file descriptor")

    monkeypatch.setattr(preflight.fcntl, "flock", flock)
    with pytest.raises(preflight.InputError, match="read-only descriptor"):
        preflight.FolderClaim(out)
    assert (out / ".rods-lock").exists()


# sizes ----------------------------------------------------------------------------------------------------------------
def _quick_refusal(tmp_path, script: str, overrides: list[str], seconds: float, megabytes: float) -> str:
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # [kB]
    t0 = time.monotonic()
    p = in_process(script, *set_args(overrides), "--dry-run", "--out", str(tmp_path / "o"), cwd=tmp_path)
    took, grew = time.monotonic() - t0, (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1e3
    line = refused(p, tmp_path / "o")
    assert took < seconds and grew < megabytes, (took, grew, line)
    return line


def test_a_mesh_of_5e7_elements_across_is_refused_at_once(tmp_path):
    big = ["rod1.diameter=1.0", "rod2.diameter=1.0", "rod1.length=20", "rod2.length=20", "rod1.tip_radius=10"]
    line = _quick_refusal(tmp_path, "global.py", [*big, "fe.radial_size=1e-8"], seconds=15, megabytes=500)
    assert "fe.radial_size" in line  # was: 134 s, > 5 GB, exit 1 "MemoryError"


def test_a_micrometre_rod_global_is_refused_without_gigabytes(tmp_path):
    _quick_refusal(tmp_path, "global.py", ["rod2.diameter=1e-6"], seconds=15, megabytes=500)  # was 8.5 s, 2 GB


# mesh first -----------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("script", "flags"), [("run.py", []), ("global.py", ["--driver"])])
def test_plans_on_a_micrometre_rod_refuse_before_the_analytical_planning(tmp_path, script, flags):
    """The mesh (8e6 GB) is refused before the analytical model plans the contact phase (it ran past 120 s)."""
    import signal

    def too_long(*_):
        raise TimeoutError("the dry run took over 30 s")

    old = signal.signal(signal.SIGALRM, too_long)
    signal.alarm(30)
    try:
        p = in_process(script, *flags, *set_args(["rod2.diameter=1e-6"]), "--dry-run", "--out", str(tmp_path / "o"),
                       cwd=tmp_path)  # fmt: skip
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    assert "memory" in refused(p, tmp_path / "o")


# level ----------------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def driver(tmp_path_factory):
    out = tmp_path_factory.mktemp("driver") / "d"
    p = in_process("global.py", "--driver", *set_args(["fe.axial_size=2e-3", "fe.radial_size=5e-4"]), "--out",
                   str(out), cwd=out.parent)  # fmt: skip
    assert p.returncode == 0, p.stderr[-2000:]
    return out


def test_a_level_too_coarse_for_the_rods_names_the_level(tmp_path, driver):
    p = in_process("submodel.py", "--global", str(driver), "--level", "ultra-coarse-x64", "--dry-run", "--out",
                   str(tmp_path / "s"), cwd=tmp_path)  # fmt: skip
    line = refused(p, tmp_path / "s")
    assert line.startswith("error: --level = 'ultra-coarse-x64'") and "--level" in line.split(";")[-1], line


# fields ---------------------------------------------------------------------------------------------------------------
def test_a_users_fields_folder_in_out_is_kept(tmp_path):
    out = tmp_path / "project"
    (out / "fields").mkdir(parents=True)
    (out / "fields" / "thesis.dat").write_text("mine")
    p = in_process("global.py", *set_args(TINY), "--out", str(out), cwd=tmp_path)
    assert p.returncode == 0, p.stderr[-2000:]
    assert (out / "fields" / "thesis.dat").read_text() == "mine"


def test_a_series_of_an_earlier_run_is_still_removed(tmp_path):
    out = tmp_path / "g"
    p = in_process("global.py", *set_args([*TINY, "fe.field_interval=5e-6"]), "--out", str(out), cwd=tmp_path)
    assert p.returncode == 0 and (out / "fields" / "mesh.h5").exists(), p.stderr[-2000:]
    p = in_process("global.py", *set_args(TINY), "--out", str(out), cwd=tmp_path)
    assert p.returncode == 0 and not (out / "fields").exists() and not (out / "fields.xdmf").exists()


# view -----------------------------------------------------------------------------------------------------------------
@pytest.fixture
def view(monkeypatch):
    """workflows/view.py with a stand-in ParaView whose readers see no time step (a series listing no frame)."""

    class Reader:
        TimestepValues: list = []
        PointData: dict = {}

        def UpdatePipeline(self, t=None):
            pass

    simple = types.SimpleNamespace(Xdmf3ReaderS=lambda **kw: Reader(), XDMFReader=lambda **kw: Reader())
    monkeypatch.setitem(sys.modules, "paraview", types.SimpleNamespace(simple=simple))
    monkeypatch.setitem(sys.modules, "paraview.simple", simple)
    return importlib.import_module("view")


@pytest.mark.parametrize("extra", [["--check"], ["--png", "x.png"]])
def test_view_refuses_a_series_without_frames(tmp_path, view, capsys, extra):
    (tmp_path / "fields.xdmf").write_text('<?xml version="1.0"?><Xdmf Version="3.0"><Domain/></Xdmf>\n')
    assert view.main([str(tmp_path), *extra]) == 2  # was: --check exit 0; --png ValueError from max()
    assert capsys.readouterr().err.startswith("error: ")


def test_view_refuses_a_name_over_255_bytes(view, capsys):
    assert view.main(["x" * 300]) == 2  # was: OSError (File name too long), a traceback
    assert capsys.readouterr().err.count("\n") == 1


# verify ---------------------------------------------------------------------------------------------------------------
def test_verify_refusal_names_a_case_that_was_asked_for(tmp_path):
    """--case paper with a too-short end time and a speed of its own: the remedy's end time is computed over the
    cases asked for (it ran every case, and speed-1.0 refused the speed: the line named a case never asked for)."""
    p = in_process("verify.py", "--case", "paper", *set_args(["simulation.end_time=1e-4", "impact.speed=2.0"]),
                   "--dry-run", "--out", str(tmp_path / "v"), cwd=tmp_path)  # fmt: skip
    line = refused(p, tmp_path / "v")
    assert "simulation.end_time" in line and "speed-1.0" not in line, line


# echo -----------------------------------------------------------------------------------------------------------------
def test_a_long_malformed_set_is_echoed_cut(tmp_path):
    """A malformed --set of 600 characters: the refusal quotes it cut (rods.preflight.short), one short line."""
    p = in_process("analytical.py", "--set", "impact.speed=[1," + "2," * 300, "--dry-run", cwd=tmp_path)
    line = refused(p)
    assert "(618 characters)" in line and len(line) < 400, line


# scene files ----------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("table", ["[simulaton]", "[rod1.materal]", "[fe.contact_law]"])
def test_an_empty_unknown_table_is_refused(tmp_path, table):
    """An unknown table with no keys (a misspelt [simulation] whose keys were not yet written) vanished: the scene ran
    without a word. Now refused as an unknown key; an empty known table ([fe], [rod1.material]) still reads."""
    from rods.scene import SceneError, load_scene

    f = tmp_path / "s.toml"
    f.write_text(f'base = "{PAPER}"\n{table}\n', encoding="utf-8")
    with pytest.raises(SceneError, match=rf"'{table[1:-1]}'.*unknown"):
        load_scene(f)
    f.write_text(f'base = "{PAPER}"\n[fe]\n[rod1.material]\n', encoding="utf-8")
    assert load_scene(f)["impact.speed"] == 2.197


def test_no_overrides_may_be_given_as_none():
    """load_scene(path, None) raised TypeError ('NoneType' is not iterable): None means no overrides, as ()."""
    from rods.scene import load_scene

    assert load_scene(PAPER, None) == load_scene(PAPER)


def test_a_summarys_scene_takes_overrides_as_load_scene_does():
    """scene_from_summary: None is no overrides (a TypeError), one string is one override (it was split into letters:
    "scene key 'i' = None"), as load_scene and scene_from_dict take them."""
    from rods.scene import load_scene, scene_from_summary

    values = load_scene(PAPER).as_dict(json_safe=True)
    assert scene_from_summary(values, None) == scene_from_summary(values)
    assert scene_from_summary(values, "impact.speed=1.0")["impact.speed"] == 1.0
    assert scene_from_summary(values, given="impact.speed=2.197").overrides == ("impact.speed=2.197",)
