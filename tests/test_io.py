"""Result files (rods.io): strict JSON summaries, history CSVs that read back, atomic writes."""

import json
import math
from pathlib import Path

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


def test_stage_data_writes_nan_as_null_and_reads_it_back(tmp_path):
    """A stage's data file (write_data/read_data): NaN and inf as null, numpy scalars as numbers, text as UTF-8
    whatever the locale (µ and ✗ in the tables' labels), and every null back as NaN."""
    d = {"a": math.nan, "b": [1.0, np.float64(math.inf)], "c": {"d": np.int64(3)}, "s": "µ ✗"}
    io.write_data(tmp_path / "x.json", d)
    raw = json.loads((tmp_path / "x.json").read_text(encoding="utf-8"))
    assert raw == {"a": None, "b": [1.0, None], "c": {"d": 3}, "s": "µ ✗"}
    back = io.read_data(tmp_path / "x.json")
    assert math.isnan(back["a"]) and math.isnan(back["b"][1]) and back["c"]["d"] == 3


def test_result_files_are_utf8_under_an_ascii_locale(tmp_path):
    """Markdown tables and JSON labels carry µ, σ and ✗: written as UTF-8 whatever the locale. A plain open() in an
    ASCII locale (LC_ALL=C without Python's UTF-8 coercion, as on some cluster nodes) raised UnicodeEncodeError."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "LC_ALL": "C", "PYTHONUTF8": "0", "PYTHONCOERCECLOCALE": "0"}
    code = (
        "import locale, sys; from rods import io; assert locale.getpreferredencoding(False) != 'UTF-8'; "
        "io.write_data(sys.argv[1] + '/x.json', {'s': '\\u00b5 \\u03c3 \\u2717'}); "
        "io.atomic_write_text(sys.argv[1] + '/x.md', '| \\u00b5m |')"
    )
    r = subprocess.run([sys.executable, "-c", code, str(tmp_path)], env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert io.read_data(tmp_path / "x.json")["s"] == "µ σ ✗"
    assert (tmp_path / "x.md").read_text(encoding="utf-8") == "| µm |"


def test_a_summary_records_what_produced_it(tmp_path):
    """summary.json carries its provenance: the versions, and in a git checkout the commit (read from .git's files,
    no git process under MPI), as `git rev-parse HEAD` gives it."""
    import shutil
    import subprocess

    from rods.io import SUMMARY_KEYS, write_summary

    write_summary(tmp_path / "summary.json", dict.fromkeys(SUMMARY_KEYS, 1.0))
    p = json.loads((tmp_path / "summary.json").read_text())["provenance"]
    assert p["rods"] and p["numpy"] == np.__version__ and p["python"]
    root = Path(__file__).resolve().parents[1]
    if (root / ".git").is_dir() and shutil.which("git"):
        head = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], capture_output=True, text=True)
        assert p["git_commit"] == head.stdout.strip()


def test_the_commit_is_read_from_loose_and_packed_refs_and_a_detached_head(tmp_path):
    from rods.io import _git_commit

    git = tmp_path / ".git"
    (git / "refs" / "heads").mkdir(parents=True)
    (git / "HEAD").write_text("ref: refs/heads/main\n")
    (git / "packed-refs").write_text("# pack-refs with: peeled\n" + "a" * 40 + " refs/heads/main\n")
    assert _git_commit(git) == "a" * 40
    (git / "refs" / "heads" / "main").write_text("b" * 40 + "\n")  # a loose ref wins over the packed one
    assert _git_commit(git) == "b" * 40
    (git / "HEAD").write_text("c" * 40 + "\n")  # detached
    assert _git_commit(git) == "c" * 40
    assert _git_commit(tmp_path / "none") is None


def test_colour_bars_keep_three_significant_digits_at_any_magnitude():
    """Field pictures' bars (the contact picture, Fig. 5c's disc): GPa of a steel patch, MPa of a soft scene's,
    fractions of one; a bar of zeros (nothing loaded) without decimals."""
    assert [io.bar_format(v) for v in (2228.0, 45.0, 3.2, 0.047, 0.0)] == ["%.0f", "%.1f", "%.2f", "%.4f", "%.0f"]
    assert (io.bar_format(2.23) % 2.2284) == "2.23" and (io.bar_format(0.463) % 0.4629) == "0.463"


def test_a_history_is_written_a_chunk_at_a_time_and_reads_back_whole(tmp_path, monkeypatch):
    """The CSV's text one chunk of rows at a time (as one string it took ~4x the file's size in memory): every row,
    in order, at 11 significant digits, whatever the chunk's size against the rows."""
    from rods import io

    monkeypatch.setattr(io, "HISTORY_CHUNK_ROWS", 7)
    t = np.linspace(0.0, 1e-3, 50)  # [s]
    io.write_history(tmp_path / "h.csv", {"time": t, "contact_force": np.sin(t * 1e4)}, {"time": "s"})
    lines = (tmp_path / "h.csv").read_text().splitlines()
    assert lines[0] == "time [s],contact_force [-]" and len(lines) == 51
    back = io.read_history(tmp_path / "h.csv")
    np.testing.assert_allclose(back["time"], t, rtol=1e-10)
    np.testing.assert_allclose(back["contact_force"], np.sin(t * 1e4), rtol=1e-10, atol=1e-300)
