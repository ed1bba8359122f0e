"""The runs later stages read (rods.study.runs): percentage cells, run specs."""

from __future__ import annotations

import math

from rods.study import runs as data


def test_percentage_cells():
    assert data.pct(1.0, 0.0) == "-" and data.pct(math.nan, 1.0) == "-"
    assert data.pct(1.0929, 1.093) == "-0.0%" and data.pct(1.0, math.nan) == "-"
    assert data.pct(1.0125, 1.0, 2) == "+1.25%"


def test_run_spec_keeps_equal_signs_in_the_label():
    label, folder = data.parse_run("driver (fe.penalty=8)=out/global")
    assert label == "driver (fe.penalty=8)" and str(folder) == "out/global"
    assert data.parse_run("out/global") == ("", type(folder)("out/global"))


def test_names_callers_imported_before_the_move_still_work(tmp_path):
    """A caller's script from before 2026-11-28 (Run, load, write_json, dump from rods.paper.data; Fig. 4 from
    rods.paper) and one from before 2026-12-07 (this module's names from rods.paper.data) run unchanged on the same
    functions: rods.io's data files, rods.study.fig4 and this module."""
    from rods import io
    from rods.paper import data as old_data
    from rods.paper import fig4 as old_fig4
    from rods.paper.data import Run, dump, load, write_json
    from rods.study import fig4

    assert old_fig4 is fig4 and (Run, dump, load, write_json) == (io.Run, io.dumps, io.read_data, io.write_data)
    names = [*data.__all__, "DRIVER_REMEDY", "RERUN_DRIVER", "STAGE_KINDS", "STOPPED", "stage_kind"]
    assert all(getattr(old_data, n) is getattr(data, n) for n in names)
    write_json(tmp_path / "x.json", {"a": math.nan})
    assert math.isnan(load(tmp_path / "x.json")["a"])


def test_each_stage_writes_the_run_kind_its_folder_is_kept_for(tmp_path):
    """An entry point's stage name gives the kind of run it writes (a driver is a global, a submodel level a submodel,
    run.py a study; compare writes none), and check_reuse refuses a folder that holds another kind's summary."""
    import json

    import pytest

    from rods.preflight import InputError

    kinds = {s: data.stage_kind(s) for s in ("analytical", "global", "driver", "run", "submodel/fine", "compare")}
    assert kinds == {"analytical": "analytical", "global": "global", "driver": "global", "run": "study",
                     "submodel/fine": "submodel", "compare": None}  # fmt: skip
    (tmp_path / "summary.json").write_text(json.dumps({"model": "fe-submodel-fine"}))
    data.check_reuse(tmp_path, data.stage_kind("submodel/mid"))  # a submodel over a submodel: its own kind
    with pytest.raises(InputError, match="another kind of run"):
        data.check_reuse(tmp_path, data.stage_kind("driver"))


def test_a_stopped_run_is_named_by_the_statuses_the_guards_write():
    """rods.study.runs.STOPPED (the statuses a reading stage refuses; a literal, as rods.fe.guards loads PETSc) is
    exactly the statuses a guard's and an interrupt's stop write."""
    from rods.fe.guards import Interrupted, SimulationError

    assert set(data.STOPPED) == {SimulationError.status, Interrupted.status}


def _driver_folder(path, values: dict, cut_values: dict, times=(0.0, 2.4e-4), status: str = "ok"):
    """A driving global's folder as a submodel reads it: summary.json and a cut record's times and scene."""
    import json

    import h5py

    path.mkdir()
    summary = {"scene_values": values, "dt": 3e-8, "contact_phase": 2.4e-4, "status": status}
    (path / "summary.json").write_text(json.dumps(summary))
    with h5py.File(path / "cut.h5", "w") as f:
        f["times"] = list(times)
        f.attrs["scene_values"] = json.dumps(cut_values)
    return path


def test_a_driver_is_read_only_when_finished_and_its_record_is_its_own(tmp_path):
    """read_driver: a finished driver's folder gives its summary, scene and record end; a stopped one, a cut.h5
    recorded by another scene (other sizes: not the bodies alone), a missing or empty record are refused, each
    naming --global."""
    import pytest

    from rods.preflight import InputError
    from rods.scene import load_scene
    from tests.conftest import PAPER

    paper = load_scene(PAPER).as_dict()
    other = load_scene(PAPER, ("fe.axial_size=5e-4",)).as_dict()
    gdir, summary, scene, recorded = data.read_driver(_driver_folder(tmp_path / "ok", paper, paper))
    assert gdir == tmp_path / "ok" and scene.as_dict() == paper and recorded == 2.4e-4 and summary["dt"] == 3e-8
    for name, values, cut, status, words in (
        ("stopped", paper, paper, "interrupted", "did not finish"),
        ("other", other, paper, "ok", "cut.h5 was recorded by another scene"),
    ):
        with pytest.raises(InputError, match=f"--global.*{words}"):
            data.read_driver(_driver_folder(tmp_path / name, values, cut, status=status))
    _driver_folder(tmp_path / "empty", paper, paper, times=())
    with pytest.raises(InputError, match="--global.*cut.h5 unreadable or empty"):
        data.read_driver(tmp_path / "empty")
    with pytest.raises(InputError, match="--global.*no such folder"):
        data.read_driver(tmp_path / "none")


def test_a_driven_submodel_ends_within_its_record(tmp_path):
    """driver_end: the asked end, else the driver's contact phase; past the record refused, named by --end-time
    where the user gave it and by the driver's folder where its own phase outlasts its record."""
    import pytest

    from rods.preflight import InputError
    from rods.scene import load_scene
    from tests.conftest import PAPER

    scene, summary = load_scene(PAPER), {"contact_phase": 2.4e-4}
    assert data.driver_end(scene, summary, 2.4e-4, None, tmp_path) == pytest.approx(2.4e-4)
    assert data.driver_end(scene, summary, 2.4e-4, 1e-4, tmp_path) == 1e-4
    with pytest.raises(InputError, match=r"--end-time = 0.0003: .*beyond the driving global's cut record"):
        data.driver_end(scene, summary, 2.4e-4, 3e-4, tmp_path)
    with pytest.raises(InputError, match="--global.*the driver's contact phase; .*give --end-time 1e-05 or less"):
        data.driver_end(scene, summary, 1e-5, None, tmp_path)
