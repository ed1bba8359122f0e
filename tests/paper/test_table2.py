"""Table 2: rendered from its data, the paper's values taken by name, the average-peak-speed offset computed."""

from __future__ import annotations

import dataclasses

import pytest

from rods import paper_data
from rods.paper import table2
from tests.conftest import ROOT, SCENES


def test_csv_renders_the_committed_table_from_its_json(stages):
    assert table2.render_csv(stages["table2.json"]) == (ROOT / "results" / "table2.csv").read_text()


def test_markdown_prose_follows_the_data(stages):
    t2 = stages["table2.json"]
    before = table2.render_md(t2)
    assert "5,543 N" in before and "1.0912 m/s (-1.25% from the paper's 1.105)" in before
    t2["paper_analytical_force"] = 5600.0
    table2.fe_row(t2)["paper_peak_speed"] = 1.0912
    after = table2.render_md(t2)
    assert "5,600 N" in after and "(-0.8%)" in after and "5,543" not in after
    assert "(+0.00% from the paper's 1.091)" in after


@pytest.fixture(scope="module")
def computed(tmp_path_factory):
    """compute() on a copy of the paper data with two values changed (bands skipped: they cost seconds)."""
    paper = paper_data.load()
    t = paper.trials["trial-2-4"]
    trials = paper.trials | {"trial-2-4": dataclasses.replace(t, analytical_radius=1.2e-3, circularity=0.5e-3)}
    changed = dataclasses.replace(paper, trials=trials)
    band = {q: {"nominal": 1.0, "uncertainty": 0.0} for q in ("radius", "peak_speed")}
    mp = pytest.MonkeyPatch()
    mp.setattr(table2, "_bands", lambda scene: band)
    yield table2.compute(SCENES, tmp_path_factory.mktemp("t2"), changed)
    mp.undo()


def test_paper_values_come_from_the_data_file_by_name(computed):
    row = next(r for r in computed["trials"] if r["name"] == "trial-2-4")
    assert row["paper_radius"] == 1.2e-3 and row["circularity"] == 0.5e-3
    assert row["experimental_radius"] == paper_data.load().trials["trial-2-4"].experimental_radius
    assert "1.200" in table2.render_csv(computed).splitlines()[3]


def test_peak_speed_with_the_papers_threshold(computed):
    """Issue 13 item 5: with the paper's fixed 1.0 m/s the model gives 1.0912 m/s at 2.197 m/s, -1.25% from the
    paper's 1.105, so the threshold does not explain the offset (an independent solver gives 1.0911)."""
    fe = table2.fe_row(computed)
    assert fe["peak_speed_at_paper_threshold"] == pytest.approx(1.0912, abs=1e-4)
    assert fe["peak_speed_at_paper_threshold"] / fe["paper_peak_speed"] - 1 == pytest.approx(-0.0125, abs=5e-4)
    slow = next(r for r in computed["trials"] if r["impact_speed"] / 2 < 1.0)
    assert slow["peak_speed_at_paper_threshold"] != slow["peak_speed_at_paper_threshold"]  # NaN: never reaches 1 m/s
    assert "unexplained" in table2.peak_speed_offset(computed)


def test_the_papers_peak_speeds_scale_with_the_plateau_maxima(computed):
    """The other reading of "average peak speed", the mean of the five plateaus' maxima (1.1147 m/s at 2.197 m/s),
    overshoots the paper as ours undershoots it; the paper's values are one scale of it (0.9906-0.9913) on all five
    quoted trials, while against our plateau means they spread over 1.0114-1.0126."""
    fe = table2.fe_row(computed)
    assert fe["mean_plateau_maximum"] == pytest.approx(1.1147, abs=1e-4)
    quoted = [r for r in computed["trials"] if r["paper_peak_speed"] > 0]
    scale = [r["paper_peak_speed"] / r["mean_plateau_maximum"] for r in quoted]
    assert len(quoted) == 5 and 0.990 < min(scale) and max(scale) < 0.992 and max(scale) - min(scale) < 1e-3
    assert "0.9906 to 0.9913 of that mean" in table2.peak_speed_offset(computed)
