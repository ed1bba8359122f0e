"""Shared command-line plumbing of the workflow scripts: --scene, --set, --out; exit code 2 on bad input."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import NoReturn

from rods.scene import Scene, SceneError, load_scene
from rods.study.console import progress_bar, rank0  # noqa: F401  (the entry points' console)

SCENES = Path(__file__).resolve().parent / "scenes"


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:  # argparse exits 2 already; keep one message style
        self.print_usage(sys.stderr)
        self.exit(2, f"error: {message}\n")


def parser(description: str, default_scene: str = "paper.toml") -> argparse.ArgumentParser:
    p = _Parser(description=description)
    p.add_argument("--scene", default=str(SCENES / default_scene), help="scene TOML file (default: %(default)s)")
    p.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override a scene value, e.g. --set impact.speed=1.848 (repeatable)",
    )
    p.add_argument("--out", default=None, help="output folder (default: output/<stage>/<scene name>)")
    return p


def fail(message: str) -> NoReturn:
    print(f"error: {message}", file=sys.stderr)
    raise SystemExit(2)


def load(args: argparse.Namespace) -> Scene:
    """Load and validate the scene; any problem exits 2 before anything runs."""
    try:
        return load_scene(args.scene, args.overrides)
    except SceneError as e:
        fail(str(e))


def out_dir(args: argparse.Namespace, model: str, scene: Scene) -> Path:
    return Path(args.out) if args.out else Path("output") / model / scene.name


def guarded(main: Callable[[Sequence[str] | None], int]) -> Callable[[Sequence[str] | None], int]:
    """Turn SceneError anywhere in ``main`` into exit code 2 with one clean line. Under MPI, any other
    failure on one rank prints its message with the rank and aborts all ranks (never a hang in a
    collective the failed rank will not reach)."""

    def run(argv: Sequence[str] | None = None) -> int:
        try:
            return main(argv)
        except SceneError as e:
            fail(str(e))
        except Exception as e:
            mpi = sys.modules.get("mpi4py.MPI")
            if mpi is None or mpi.COMM_WORLD.size == 1:
                raise
            import traceback

            rank = mpi.COMM_WORLD.rank
            traceback.print_exc()
            print(f"error on rank {rank}: {type(e).__name__}: {e}; aborting all ranks", file=sys.stderr, flush=True)
            mpi.COMM_WORLD.Abort(1)
            raise

    return run
