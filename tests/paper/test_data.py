"""The runs later stages read (rods.paper.data): percentage cells, run specs."""

from __future__ import annotations

import math

from rods.paper import data


def test_percentage_cells():
    assert data.pct(1.0, 0.0) == "-" and data.pct(math.nan, 1.0) == "-"
    assert data.pct(1.0929, 1.093) == "-0.0%" and data.pct(1.0, math.nan) == "-"
    assert data.pct(1.0125, 1.0, 2) == "+1.25%"


def test_run_spec_keeps_equal_signs_in_the_label():
    label, folder = data.parse_run("driver (fe.penalty=8)=out/global")
    assert label == "driver (fe.penalty=8)" and str(folder) == "out/global"
    assert data.parse_run("out/global") == ("", type(folder)("out/global"))


def test_names_callers_imported_before_the_move_still_work(tmp_path):
    """A caller's script from before 2026-11-28 (Run, load, write_json, dump from here; Fig. 4 from rods.paper) runs
    unchanged on the same functions: rods.io's data files and rods.study.fig4."""
    from rods import io
    from rods.paper import fig4 as old_fig4
    from rods.paper.data import Run, dump, load, write_json
    from rods.study import fig4

    assert old_fig4 is fig4 and (Run, dump, load, write_json) == (io.Run, io.dumps, io.read_data, io.write_data)
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
    """rods.paper.data.STOPPED (the statuses a reading stage refuses; a literal, as rods.fe.guards loads PETSc) is
    exactly the statuses a guard's and an interrupt's stop write."""
    from rods.fe.guards import Interrupted, SimulationError

    assert set(data.STOPPED) == {SimulationError.status, Interrupted.status}
