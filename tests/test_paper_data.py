"""The paper's tables are read by name from one data file and agree with the trial scenes."""

from __future__ import annotations

import math

import pytest

from rods import paper_data
from rods.scene import load_scene
from tests.conftest import SCENES


def test_every_trial_scene_has_its_row_and_speed():
    data = paper_data.load()
    assert set(data.trials) == {p.stem for p in SCENES.glob("trial-*.toml")}
    for name, row in data.trials.items():
        assert load_scene(SCENES / f"{name}.toml").speed == pytest.approx(row.impact_speed, rel=1e-12)


def test_fe_trial_and_units():
    data = paper_data.load()
    exp = data.fe_experiment
    assert exp.impact_speed == 2.197 and exp.experimental_radius == pytest.approx(1.109e-3)
    # Table 3's printed experimental area is π a² of the Table-2 radius to three digits
    assert data.experimental_area == pytest.approx(math.pi * exp.experimental_radius**2, rel=2e-3)
    assert data.table3_submodel("fine").force == 5492.0 and data.table3_submodel("extra-fine") is None
    assert math.isnan(data.trials["trial-1-1"].experimental_peak_speed)


def test_table1_is_the_paper_scene_and_decides_which_scenes_are_the_papers():
    """Table 1 in the data file and workflows/scenes/paper.toml state the same rods; the trials are the paper's
    rods, only the FE trial's speed is the FE scene; changing any rod value makes another scene."""
    data = paper_data.load()
    paper = load_scene(SCENES / "paper.toml")
    assert data.same_rods(paper) and data.is_fe_scene(paper)
    trial = load_scene(SCENES / "trial-2-5.toml")
    assert data.same_rods(trial) and not data.is_fe_scene(trial)
    for override in (
        "rod1.tip_radius=0.02",
        "rod2.tip_radius=0.035",
        "rod2.length=0.35",
        "rod2.material.youngs_modulus=114e9",
        "rod1.material.poisson_ratio=0.29",
    ):
        assert not data.is_fe_scene(paper.with_overrides(override)), override
