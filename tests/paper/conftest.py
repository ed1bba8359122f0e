"""Stage data for the renderers' tests: today's record as JSON (tests/paper/data), and quick runs."""

from __future__ import annotations

import copy
import shutil
from pathlib import Path

import pytest

from rods import io

DATA = Path(__file__).resolve().parent / "data"
STAGES = ("table2.json", "table3.json", "fig4.json", "accuracy-cost.json", "contact-study.json")


@pytest.fixture(scope="session")
def _stages() -> dict[str, dict]:
    return {name: io.read_data(DATA / name) for name in STAGES}


@pytest.fixture
def stages(_stages) -> dict[str, dict]:
    """A fresh, editable copy of every stage's data."""
    return copy.deepcopy(_stages)


@pytest.fixture
def results(tmp_path) -> Path:
    """A results folder holding only the stage JSON files (no markdown, no CSV)."""
    for name in STAGES:
        shutil.copy(DATA / name, tmp_path / name)
    return tmp_path
