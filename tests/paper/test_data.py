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
