"""The paper's analytical model (Section 2.1) on one scene.

    python workflows/analytical.py --scene workflows/scenes/paper.toml --set impact.speed=1.848 --out DIR

Writes DIR/history.csv (contact force, compression, contact radius, peak pressure, velocity and
strain at every station) and DIR/summary.json; prints the plan first and the summary last.
"""

from __future__ import annotations

import json
import sys
import warnings
from collections.abc import Sequence

import _cli
from rods import io
from rods.analytical import simulate
from rods.hertz import YieldWarning


def main(argv: Sequence[str] | None = None) -> int:
    args = _cli.parser(__doc__.splitlines()[0]).parse_args(argv)
    # parameters
    scene = _cli.load(args)
    out = _cli.out_dir(args, "analytical", scene)
    print(
        f"plan: analytical model (1D waves + Hertz), scene '{scene.name}', s1 = {scene.speed} m/s, "
        f"t_end = {scene.end_time:g} s every {scene.output_interval:g} s, rtol = {scene['analytical.rtol']:g}; "
        f"stations: {', '.join(s.name for s in scene.stations)} -> {out}"
    )
    # solve
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", YieldWarning)
        result = simulate(scene)
    for w in caught:
        print(f"warning: {w.message}", file=sys.stderr)
    result.summary["yield_warnings"] = [str(w.message) for w in caught]
    result.summary["scene_values"] = scene.as_dict()
    # output
    io.write_history(out / "history.csv", result.history, result.units)
    io.write_summary(out / "summary.json", result.summary)
    keys = [*io.SUMMARY_KEYS[2:], "rigid_velocity_rod1", "rigid_velocity_rod2"]
    print(json.dumps({k: result.summary[k] for k in keys}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(_cli.guarded(main)())
