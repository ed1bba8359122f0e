"""Result files (rods.io): strict JSON summaries, history CSVs that read back, atomic writes."""

import json
import math

import numpy as np
import pytest

from rods import io


def _strict(text: str) -> dict:
    """json.loads that refuses the non-standard NaN/Infinity constants."""

    def refuse(name: str) -> None:
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def _summary(**extra) -> dict:
    return {k: 1.0 for k in io.SUMMARY_KEYS} | {"model": "global", "scene": "paper"} | extra


def test_a_summary_is_strict_json_with_non_finite_numbers_null(tmp_path):
    """The kinematic contact's switching limit is inf: it was written as the string "inf" where readers expect a
    number (pandas, jq, a JavaScript viewer); a non-finite number is null now, numpy scalars and arrays are plain."""
    s = _summary(
        dt_contact_switching=math.inf,
        midpoint_peak_speed=float("nan"),
        dofs=np.int64(7),
        profile={"p": np.array([1.0, np.inf])},
        scene_values={"rod2": {"tip_radius": "inf"}},  # the scene's own record (Scene.as_dict) is kept as written
    )
    io.write_summary(tmp_path / "summary.json", s)
    back = _strict((tmp_path / "summary.json").read_text())
    assert back["dt_contact_switching"] is None and back["midpoint_peak_speed"] is None
    assert back["dofs"] == 7 and back["profile"]["p"] == [1.0, None]
    assert back["scene_values"]["rod2"]["tip_radius"] == "inf"


def test_a_summary_without_a_contract_key_is_refused_and_nothing_written(tmp_path):
    s = _summary()
    del s["contact_duration"]
    with pytest.raises(KeyError, match="contact_duration"):
        io.write_summary(tmp_path / "summary.json", s)
    assert list(tmp_path.iterdir()) == []


def test_a_history_reads_back_with_its_units_in_the_header(tmp_path):
    t = np.linspace(0.0, 1e-4, 7)
    cols = {"time": t, "contact_force": 5.6e3 * np.sin(t / 1e-4 * np.pi)}
    io.write_history(tmp_path / "h.csv", cols, {"time": "s", "contact_force": "N"})
    assert (tmp_path / "h.csv").read_text().splitlines()[0] == "time [s],contact_force [N]"
    back = io.read_history(tmp_path / "h.csv")
    assert list(back) == list(cols)
    for k in cols:
        np.testing.assert_allclose(back[k], cols[k], rtol=1e-10, atol=1e-300)
