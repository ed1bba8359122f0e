"""Study stages (rods.study.stages): what a restart keeps, mesh-free."""

from __future__ import annotations

from mpi4py import MPI

from rods import io
from rods.study.stages import GLOBAL_IGNORES, SUBMODEL_IGNORES, finished


def _finished_run(folder, scene, status="ok", until=None):
    folder.mkdir(parents=True, exist_ok=True)
    summary = dict.fromkeys(io.SUMMARY_KEYS, 0.0) | {"model": "global", "scene": scene.label, "status": status}
    io.write_summary(folder / "summary.json", summary | {"scene_values": scene.as_dict()})
    end = scene.end_time if until is None else until  # [s] the history's last sample
    io.write_history(folder / "history.csv", {"time": [0.0, end], "contact_force": [0.0, 1.0]}, {"time": "s"})


def test_a_restart_keeps_a_stage_finished_for_the_same_scene_only(scene_with, tmp_path):
    """Kept: the same scene's finished run (its summary and history read back). Not kept: another mesh or end
    time, an interrupt's partial summary, a missing history. Keys the stage does not read (another submodel
    level, the submodels' own contact and driving for a global, the checkpoint interval) do not stop it being kept."""
    sc = scene_with("effects=['contact_patch']", "submodel.levels=['coarse']", "simulation.end_time=3e-4")
    _finished_run(tmp_path / "g", sc)
    kept = finished("global", tmp_path / "g", sc, MPI.COMM_SELF)
    assert kept is not None and kept.kept and kept.history["contact_force"][-1] == 1.0
    for other in ("fe.axial_size=5e-3", "simulation.end_time=2e-4", "impact.speed=2.0"):
        assert finished("global", tmp_path / "g", sc.with_overrides(other), MPI.COMM_SELF) is None, other
    more = sc.with_overrides("submodel.levels=['coarse', 'mid']", "submodel.driving='traction'")
    assert finished("global", tmp_path / "g", more, MPI.COMM_SELF) is None  # compared whole unless told
    assert finished("global", tmp_path / "g", more, MPI.COMM_SELF, ignore=GLOBAL_IGNORES) is not None
    assert finished("sub", tmp_path / "g", more, MPI.COMM_SELF, ignore=SUBMODEL_IGNORES) is None  # driving: read
    saved = sc.with_overrides("fe.checkpoint_interval=1e-4")  # checkpoints save the state, never change it
    for ignore in (GLOBAL_IGNORES, SUBMODEL_IGNORES):
        assert finished("global", tmp_path / "g", saved, MPI.COMM_SELF, ignore=ignore) is not None
    _finished_run(tmp_path / "i", sc, status="interrupted")
    assert finished("global", tmp_path / "i", sc, MPI.COMM_SELF) is None
    (tmp_path / "g" / "history.csv").unlink()
    assert finished("global", tmp_path / "g", sc, MPI.COMM_SELF) is None
    # a history cut short (damaged from outside) is not a finished run: Fig. 4 read it over its first 74 µs (a fuzz)
    _finished_run(tmp_path / "short", sc, until=7.4e-5)
    assert finished("global", tmp_path / "short", sc, MPI.COMM_SELF) is None


def test_cut_options_are_checked_by_the_library_as_by_global_py():
    """check_cut_options: a window or spacing without a record of the user's, a window past the end or shorter than
    one step, a restart of a recording run are refused, each naming its option; a record within the run passes."""
    import pytest

    from rods.preflight import InputError
    from rods.scene import load_scene
    from rods.study.stages import check_cut_options
    from tests.conftest import PAPER

    sc = load_scene(PAPER, ["simulation.end_time=1e-4"])
    check_cut_options(sc, record_cut=True, record_until=5e-5, record_every=2, step=3e-8)
    for kw, words in (
        ({"record_until": 5e-5}, "--record-until/--record-every.*go with --record-cut"),
        ({"driver": True, "record_every": 2}, "the driver records the contact phase"),
        ({"record_cut": True, "record_until": 2e-4}, "--record-until = 0.0002: beyond the run's end"),
        ({"record_cut": True, "record_until": 1e-9, "step": 3e-8}, "shorter than one time step.*t = 0 alone"),
        ({"driver": True, "restart": True}, "--restart.*not checkpointed"),
    ):
        with pytest.raises(InputError, match=words):
            check_cut_options(sc, **kw)


def test_a_submodel_without_an_axis_profile_leaves_none_from_an_earlier_run(tmp_path):
    """A submodel with no axis profile (flat tips, a tilted or offset impact) removes an earlier run's
    axis_stress.csv from its reused folder; one with a profile writes it (rods.study.stages.write_submodel_files)."""
    from types import SimpleNamespace

    from rods.study.stages import write_submodel_files

    profile = {"depth": [0.0, 1e-4], "r": [0.0, 0.0], "sigma_r": [1.0, 2.0], "sigma_z": [3.0, 4.0], "tau": [1.0, 1.0]}
    summary = dict.fromkeys(io.SUMMARY_KEYS, 0.0) | {"axis_profile": profile}
    result = SimpleNamespace(history={"time": [0.0, 1e-6]}, units={"time": "s"}, pressure_profile={"r": [0.0]})
    sr = SimpleNamespace(result=result, sigma_r={"r": [0.0], "depth": [0.0], "sigma_r": [0.0]}, summary=summary)
    write_submodel_files(sr, tmp_path)
    assert io.read_history(tmp_path / "axis_stress.csv")["tau"].tolist() == [1.0, 1.0]
    sr.summary = summary | {"axis_profile": None}
    write_submodel_files(sr, tmp_path)
    assert not (tmp_path / "axis_stress.csv").exists() and (tmp_path / "summary.json").is_file()


def test_a_library_callers_bad_folder_level_or_size_is_refused_before_any_set_up(scene_with, tmp_path):
    """The stages as a script calls them: an existing file, or None, as the output folder, an unknown submodel level
    and a size of 0 are refused (InputError naming the argument) before a mesh is built (a file had failed with
    NotADirectoryError after the set-up, a level with a bare KeyError; a size of 0 had run the level's own)."""
    import pytest

    from rods.preflight import InputError
    from rods.study import stages

    sc = scene_with("fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=2e-5")
    (tmp_path / "a-file").write_text("")
    for out in (tmp_path / "a-file", str(tmp_path / "a-file"), None):
        with pytest.raises(InputError, match=r"^out = "):
            stages.global_model(sc, out)
    cut = tmp_path / "cut.h5"  # never read: the refusals come first
    with pytest.raises(InputError, match=r"^level = 'superfine': is no submodel level; give one of "):
        stages.submodel(sc, cut, tmp_path / "s", level="superfine")
    for size in (0.0, -1e-3, float("nan")):
        with pytest.raises(InputError, match=r"^size = .*: must be a positive element size"):
            stages.submodel(sc, cut, tmp_path / "s", size=size)
    assert not (tmp_path / "s").exists()


def test_a_model_set_up_with_comm_none_runs_on_the_world(scene_with):
    """``ExplicitModel(scene, None)``, as its signature allows (the stages' comm=None): on MPI.COMM_WORLD (it raised
    an AttributeError on None.size)."""
    from rods.fe.model import ExplicitModel

    m = ExplicitModel(scene_with("fe.axial_size=4e-3", "fe.radial_size=1e-3", "simulation.end_time=2e-5"), None)
    assert m.comm is MPI.COMM_WORLD and m.steps > 0
