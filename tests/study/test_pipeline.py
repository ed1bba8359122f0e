"""rods.study.pipeline.run_study from Python: the entry point's own refusals, before anything runs or is written."""

from __future__ import annotations

import json

import pytest

from rods.preflight import InputError
from rods.scene import SceneError
from rods.study.pipeline import run_study


def test_a_library_study_refuses_what_run_py_refuses(scene_with, tmp_path):
    """Levels no submodel would use, a file as its folder, another kind of run's folder: refused before anything
    runs (the library ran a useless submodel, raised NotADirectoryError, and left a global's histories beside the
    study's summary: a library user's fuzz, 2026-12-07); nothing written."""
    with pytest.raises(SceneError, match="given, but effects"):
        run_study(scene_with("submodel.levels=['fine']"), tmp_path / "a")
    (tmp_path / "afile").write_text("x")
    with pytest.raises(InputError, match="is an existing file"):
        run_study(scene_with(), tmp_path / "afile")
    (tmp_path / "g").mkdir()
    (tmp_path / "g" / "summary.json").write_text(json.dumps({"model": "fe-axisymmetric"}))
    with pytest.raises(InputError, match="holds"):
        run_study(scene_with(), str(tmp_path / "g"))
    assert not (tmp_path / "a").exists() and sorted(p.name for p in (tmp_path / "g").iterdir()) == ["summary.json"]
