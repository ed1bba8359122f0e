"""results/ holds renderings of its data: every committed table (markdown, CSV) is what its renderer makes of the
committed JSON beside it. A renderer changed without its table re-rendered, or a table rerun without its report,
left committed words that no data said (REPORT.md's energy error, accuracy-cost.md's GPU sentence, 2026-11-28)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from rods import io
from rods.paper import accuracy_cost, convergence, report, table2
from rods.study import fig4, table3, verification

from .conftest import benchmark

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"


def _data(name: str) -> dict:
    return io.read_data(RESULTS / name)


RENDERINGS: dict[str, Callable[[], str]] = {
    "REPORT.md": lambda: report.render(report.read(RESULTS, RESULTS / "contact-study.json")),
    "table2.md": lambda: table2.render_md(_data("table2.json")),
    "table2.csv": lambda: table2.render_csv(_data("table2.json")),
    "table3.md": lambda: table3.render_markdown(_data("table3.json")),
    "fig4.md": lambda: fig4.render_md(_data("fig4.json")),
    "accuracy-cost.md": lambda: accuracy_cost.render_md(_data("accuracy-cost.json")),
    "convergence.md": lambda: convergence.render_markdown(_data("convergence.json")),
    "verification.md": lambda: verification.render_markdown(_data("verification.json")),
    "contact-study.md": lambda: benchmark("contact_study").render_md(_data("contact-study.json")),
    "driver-study.md": lambda: benchmark("driver_study").render_md(_data("driver-study.json")),
    "edge-scatter.md": lambda: benchmark("edge_scatter").render_md(_data("edge-scatter.json")),
    "scene-probe.md": lambda: benchmark("scene_probe").render(_data("scene-probe.json")),
    "scene-probe-random.md": lambda: benchmark("scene_probe").render(_data("scene-probe-random.json")),
    "scene-probe-random-2026.md": lambda: benchmark("scene_probe").render(_data("scene-probe-random-2026.json")),
    "scene-probe-random-61206.md": lambda: benchmark("scene_probe").render(_data("scene-probe-random-61206.json")),
    "scene-probe-random-61207.md": lambda: benchmark("scene_probe").render(_data("scene-probe-random-61207.json")),
    "scene-probe-random-61208.md": lambda: benchmark("scene_probe").render(_data("scene-probe-random-61208.json")),
    "scene-probe-random-61209.md": lambda: benchmark("scene_probe").render(_data("scene-probe-random-61209.json")),
    "scene-probe-random-61223.md": lambda: benchmark("scene_probe").render(_data("scene-probe-random-61223.json")),
    "submodel-probe.md": lambda: benchmark("submodel_probe").render(_data("submodel-probe.json")),
    "submodel-probe-random.md": lambda: benchmark("submodel_probe").render(_data("submodel-probe-random.json")),
    "submodel-probe-random-1206.md": lambda: benchmark("submodel_probe").render(
        _data("submodel-probe-random-1206.json")
    ),
    "submodel-probe-random-61206.md": lambda: benchmark("submodel_probe").render(
        _data("submodel-probe-random-61206.json")
    ),
    "submodel-probe-random-61208.md": lambda: benchmark("submodel_probe").render(
        _data("submodel-probe-random-61208.json")
    ),
    "submodel-probe-random-61209.md": lambda: benchmark("submodel_probe").render(
        _data("submodel-probe-random-61209.json")
    ),
    "submodel-probe-random-61223.md": lambda: benchmark("submodel_probe").render(
        _data("submodel-probe-random-61223.json")
    ),
    "wave-probe-random.md": lambda: benchmark("wave_probe").render(_data("wave-probe-random.json")),
    "wave-probe-random-61206.md": lambda: benchmark("wave_probe").render(_data("wave-probe-random-61206.json")),
    "wave-probe-random-61207.md": lambda: benchmark("wave_probe").render(_data("wave-probe-random-61207.json")),
    "wave-probe-random-61208.md": lambda: benchmark("wave_probe").render(_data("wave-probe-random-61208.json")),
    "wave-probe-random-61223.md": lambda: benchmark("wave_probe").render(_data("wave-probe-random-61223.json")),
    "rod-end-compliance.md": lambda: benchmark("rod_end_compliance").render(_data("rod-end-compliance.json")),
}


@pytest.mark.parametrize("name", sorted(RENDERINGS))
def test_committed_table_is_the_rendering_of_its_data(name):
    committed = (RESULTS / name).read_text(encoding="utf-8")
    assert RENDERINGS[name]().splitlines() == committed.splitlines(), f"results/{name}: re-render it from its JSON"
