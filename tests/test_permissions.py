"""Result files get the mode ``open()`` would give (0666 less the umask), never mkstemp's private 0600."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest

from rods import io


@pytest.fixture(params=[0o022, 0o027, 0o002])
def umask(request):
    old = os.umask(request.param)
    yield request.param
    os.umask(old)


def _mode(p) -> int:
    return stat.S_IMODE(os.stat(p).st_mode)


def test_result_files_honour_the_umask(tmp_path, umask):
    summary = dict.fromkeys(io.SUMMARY_KEYS, 1.0)
    io.write_summary(tmp_path / "summary.json", summary)
    io.write_history(tmp_path / "history.csv", {"time": [0.0, 1.0]}, {"time": "s"})
    io.write_data(tmp_path / "table3.json", {"a": 1})
    io.atomic_write_text(tmp_path / "table3.md", "x\n")
    want = 0o666 & ~umask
    for name in ("summary.json", "history.csv", "table3.json", "table3.md"):
        assert _mode(tmp_path / name) == want, name
    assert io.file_mode() == want
    (tmp_path / "plain").write_text("x")  # what open() gives: the reference
    assert _mode(tmp_path / "plain") == want


def test_checkpoint_files_are_readable_by_the_group(tmp_path, umask):
    from mpi4py import MPI

    from rods.fe import checkpoint

    checkpoint.save(tmp_path, 10, 1e-6, {"u": np.zeros(3)}, MPI.COMM_SELF, "key")
    want = 0o666 & ~umask
    assert _mode(tmp_path / checkpoint.MANIFEST) == want
    assert _mode(tmp_path / "checkpoint-10-r0.npz") == want


def test_a_path_this_user_cannot_reach_is_bad_input(tmp_path):
    """A folder on an --out or --global path that this user cannot search: exit 2 naming the path (it was exit 1,
    PermissionError). As root, run without the override capabilities (setpriv), as a user would be."""
    import shutil
    import subprocess

    from .conftest import PY, ROOT

    prefix = []
    if os.geteuid() == 0:
        if shutil.which("setpriv") is None:
            pytest.skip("root without setpriv: permissions are not enforced")
        prefix = ["setpriv", "--bounding-set", "-dac_override,-dac_read_search", "--"]
    closed = tmp_path / "closed"
    (closed / "inner").mkdir(parents=True)
    closed.chmod(0)
    try:
        for script, args in (("analytical.py", ["--out", str(closed / "inner" / "x")]),
                             ("compare.py", ["--global", str(closed / "inner")])):  # fmt: skip
            p = subprocess.run([*prefix, str(PY), str(ROOT / "workflows" / script), *args], capture_output=True,
                               text=True, timeout=120)  # fmt: skip
            assert p.returncode == 2 and "permission denied" in p.stderr and str(closed) in p.stderr, p.stderr
    finally:
        closed.chmod(0o755)
