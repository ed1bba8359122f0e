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
