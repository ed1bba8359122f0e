"""rods.study.figures: figures drawn without pyplot's global state."""

from __future__ import annotations

import subprocess
import sys


def test_drawing_a_figure_leaves_the_callers_matplotlib_as_it_was(tmp_path):
    """A notebook's backend (here svg, set by the caller) and pyplot's figure list are the caller's: the figures'
    matplotlib.use("Agg") switched the backend for the rest of the session. The PNG is still written (Agg draws a
    figure of its own when it is saved)."""
    code = f"""
import matplotlib
matplotlib.use("svg")
from rods.study.figures import pyplot
plt = pyplot()
fig, ax = plt.subplots(1, 2, figsize=(4, 3), sharex=True)
ax[0].plot([0, 1], [0, 1])
fig.tight_layout()
fig.savefig({str(tmp_path / "f.png")!r}, dpi=50)
plt.close(fig)
import sys
print(matplotlib.get_backend(), "matplotlib.pyplot" in sys.modules)
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
    assert p.stdout.split() == ["svg", "False"]
    assert (tmp_path / "f.png").read_bytes()[:4] == b"\x89PNG"
