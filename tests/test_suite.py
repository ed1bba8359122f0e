"""The suite's own rules (tests/conftest.py): a case marked ``mpi`` or ``alone`` sits in a file that spells the mark,
so that `make test`'s one-at-a-time part, which collects the files a grep for the marks finds, runs it."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from tests.conftest import pytest_collection_modifyitems


def _item(path, marker: str | None):
    return SimpleNamespace(
        path=path, nodeid=f"{path.name}::case", get_closest_marker=lambda name: object() if name == marker else None
    )


def test_a_marked_case_in_a_file_that_does_not_spell_the_mark_is_refused(tmp_path):
    spelled, hidden, plain = tmp_path / "test_a.py", tmp_path / "test_b.py", tmp_path / "test_c.py"
    spelled.write_text("import pytest\n\n@pytest.mark.mpi\ndef test_x(): ...\n")
    hidden.write_text("import pytest\n\nMPI = pytest.mark.mpi  # spelled here too\n")
    plain.write_text("MARKS = [getattr(__import__('pytest').mark, 'alone')]\n")  # a mark the grep cannot see
    pytest_collection_modifyitems(None, [_item(spelled, "mpi"), _item(hidden, "mpi"), _item(plain, None)])
    with pytest.raises(pytest.UsageError, match=r"test_c.py::case: marked mpi or alone"):
        pytest_collection_modifyitems(None, [_item(plain, "alone")])
