"""Stage JSON: NaN survives the round trip as null; relative differences."""

from __future__ import annotations

import json
import math

import numpy as np

from rods.paper import data


def test_nan_is_written_as_null_and_read_back(tmp_path):
    d = {"a": math.nan, "b": [1.0, np.float64(math.inf)], "c": {"d": np.int64(3)}, "s": "x"}
    data.write_json(tmp_path / "x.json", d)
    raw = json.loads((tmp_path / "x.json").read_text())
    assert raw == {"a": None, "b": [1.0, None], "c": {"d": 3}, "s": "x"}
    back = data.load(tmp_path / "x.json")
    assert math.isnan(back["a"]) and math.isnan(back["b"][1]) and back["c"]["d"] == 3


def test_percentage_cells():
    assert data.pct(1.0, 0.0) == "-" and data.pct(math.nan, 1.0) == "-"
    assert data.pct(1.0929, 1.093) == "-0.0%" and data.pct(1.0, math.nan) == "-"
    assert data.pct(1.0125, 1.0, 2) == "+1.25%"


def test_run_spec_keeps_equal_signs_in_the_label():
    label, folder = data.parse_run("driver (fe.penalty=8)=out/global")
    assert label == "driver (fe.penalty=8)" and str(folder) == "out/global"
    assert data.parse_run("out/global") == ("", type(folder)("out/global"))
