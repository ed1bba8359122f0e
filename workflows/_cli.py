"""Shared command-line plumbing of the workflow scripts: --scene, --set, --out, and the one error path.

Every entry point runs its ``main`` through :func:`guarded`: bad input (rods.scene.SceneError,
rods.preflight.InputError, an argparse error, a missing input file) exits 2, a run that failed (a guard's
stop, any other error) exits 1, an interrupt (Ctrl-C, SIGTERM) exits 130; each with one line on stderr
(rank 0's, or the failing rank's under MPI), never a traceback (``RODS_TRACEBACK=1`` shows it). The
README's "When something goes wrong" lists the classes and their messages.
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import os
import re
import signal
import sys
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, NoReturn

from rods import interrupt
from rods.preflight import (  # noqa: F401  (for scripts)
    FolderClaim,
    InputError,
    default_folder,
    one_line,
    output_dir,
    output_file,
    safe_name,
    scene_folder,
    short,
)
from rods.scene import Scene, SceneError, load_scene, parse_override
from rods.study.console import progress_bar, rank0  # noqa: F401  (the entry points' console)

SCENES = Path(__file__).resolve().parent / "scenes"
EXIT_BAD_INPUT, EXIT_FAILED = 2, 1
EXIT_INTERRUPTED = interrupt.EXIT_INTERRUPTED


class _Parser(argparse.ArgumentParser):
    """argparse with whole option names only (an abbreviation such as --sce would pass unseen by code that looks
    for --scene) and one error line, rank 0's under MPI."""

    def __init__(self, **kw: Any):
        super().__init__(allow_abbrev=False, formatter_class=argparse.RawDescriptionHelpFormatter, **kw)
        # a negative number in exponent form (--dt -1e-8) is a value, so that its option names the range; Python
        # 3.13.0's argparse takes it for an unknown option ("unrecognized arguments")
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")

    def print_help(self, file: Any = None) -> None:  # rank 0's only under MPI
        if _is_rank0():
            super().print_help(file)

    def error(self, message: str) -> NoReturn:  # argparse exits 2 already; keep one line, one style
        quiet = not _is_rank0()
        self.exit(EXIT_BAD_INPUT, None if quiet else f"error: {one_line(message)} (see {self.prog} --help)\n")


def _number(kind: type, lo: float, closed: bool, unit: str) -> Callable[[str], float]:
    """An argparse type: a finite ``kind`` above ``lo`` (or at it when ``closed``), else an error naming the range."""

    def parse(text: str) -> float:
        try:
            v = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not {'an integer' if kind is int else 'a number'}") from None
        if v != v or v in (float("inf"), float("-inf")):
            raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
        if not (v >= lo if closed else v > lo):
            raise argparse.ArgumentTypeError(f"{text!r} must be {'>=' if closed else '>'} {lo:g}{unit}")
        return v

    return parse


class _Override(argparse.Action):
    """--set KEY=VALUE, repeatable (a key given again overrides the earlier value, as a later --set would in any
    order of composing defaults and changes): the syntax checked as it is read (rods.scene.parse_override)."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, text: Any, option: Any = None):
        try:
            parse_override(text)
        except SceneError as e:
            said = short(text)  # one line whatever the value's length (rods.preflight.MAX_VALUE)
            raise argparse.ArgumentError(self, f"{said}: {e.allowed}" + (f" ({e.hint})" if e.hint else "")) from None
        setattr(namespace, self.dest, [*(getattr(namespace, self.dest) or []), text])


positive = _number(float, 0.0, False, "")  # e.g. an element size [m], a time [s]
non_negative = _number(float, 0.0, True, "")
count = _number(int, 1, True, "")  # a step stride


def parser(
    description: str, default_scene: str = "paper.toml", dry_run: bool = False, out_help: str | None = None
) -> argparse.ArgumentParser:
    """The scene options (--scene, --set, --out, --force); ``dry_run``: also --dry-run (see :func:`afford`).
    ``description``: the script's docstring, shown as written (its usage lines included); ``out_help``: --out's
    help where it is not a run's folder (a file prefix)."""
    p = _Parser(description=description)
    p.add_argument("--scene", default=str(SCENES / default_scene), help="scene TOML file (default: %(default)s)")
    p.add_argument(
        "--set",
        dest="overrides",
        action=_Override,
        default=[],
        metavar="KEY=VALUE",
        help="override a scene value, e.g. --set impact.speed=1.848 (repeatable)",
    )
    p.add_argument(
        "--out",
        default=None,
        help=out_help or "output folder (default: output/<stage>/<scene name>, -<digest> appended with --set)",
    )
    p.add_argument(
        "--force", action="store_true", help="run above the step/history budgets (never above the free memory)"
    )
    if dry_run:
        p.add_argument(
            "--dry-run",
            action="store_true",
            help="check the input and --out, print the plan and the cost estimate, then exit 0 without running or "
            "writing anything",
        )
    return p


def planning(analytical: Any) -> str:
    """The line said before a plan runs the analytical model to its first contact (its cost, ``analytical``: a
    rods.cost.Cost, the whole run's, an upper bound), so a long planning is announced rather than silent."""
    limit = f"at most about {analytical.wall_time:.3g} s of wall time"  # not a simulated time (a fuzz read it so)
    return f"planning: the analytical model to its first contact ({limit})"


def outlook(scene: Scene, log: Callable[..., None] = print, wave: bool = True, fe: bool = False) -> None:
    """Print, before the cost estimate, the checks a run of ``scene`` will likely fail (rods.outlook: foreseen from
    closed forms, before anything runs; nothing for a scene inside the models' range); ``wave``, ``fe``: as there."""
    from rods.outlook import outlook as foreseen

    for line in foreseen(scene, wave, fe):
        log(f"outlook: {line}")


def afford(
    args: argparse.Namespace, *costs: Any, log: Callable[..., None] = print, comm: Any = None, out: Path | None = None
) -> None:
    """Print each estimated cost (rods.cost) and refuse, exit 2, one above the free memory, all of them above the
    free disk where ``out`` is (rods.cost.check_disk) or, without --force, one above the step/history budgets;
    before anything heavy is allocated. A long run's time is this machine's (rods.cost.calibrated: measured by every
    rank of ``comm`` at once, the slowest taken by all). With --dry-run, stop here: exit 0, nothing run, nothing
    written (every rank alike)."""
    from rods import cost

    for c in costs:  # the memory first (--force never lifts it): no probe for a run that cannot start
        cost.check(c, force=True, comm=comm)
    if out is not None:  # nor the disk's room (rank 0's view: the ranks write into one folder)
        cost.check_disk(costs, out, comm)
    calibrated = cost.calibrated(costs, comm)
    for c in calibrated:
        cost.check(c, args.force, memory=False)  # the memory checked above, on every rank alike
        log(c.describe())
    if line := cost.total(calibrated):  # several stages: their sum, and the one that is most of it
        log(line)
    if note := cost.busy_note(max((c.ranks for c in costs), default=1)):  # the load is this machine's, now
        log(note)
    if getattr(args, "dry_run", False):
        unsettled = " as far as the plan can tell (the caveat above)" if any(c.caveat for c in costs) else ""
        log(f"dry run: the input and the output folder are valid{unsettled}; nothing was run or written")
        raise SystemExit(0)
    if out is not None:
        hold(out, comm)


def figure_file(path: str | Path, flag: str) -> None:
    """A figure's path names a format matplotlib writes (refused, exit 2, before anything is read or written: it
    failed at the figure, after the data beside it was written)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    formats = FigureCanvasAgg.get_supported_filetypes()
    suffix = Path(path).suffix.lstrip(".").lower()
    if suffix not in formats:
        raise InputError(flag, path, f"not a figure format ({', '.join(sorted(formats))})", "give a .png path")


def backend(scene: Scene, ranks: int) -> None:
    """The scene's fe.backend can run on ``ranks`` ranks (rods.fe.backend.select: serial only for numpy/cupy, CuPy
    importable): refused, exit 2, before any stage (the model's set-up would find it after a study's analytical
    stage had written its folder)."""
    from rods.fe.backend import select

    select(scene["fe.backend"], ranks, scene["fe.operator"])


def status(summary: Mapping[str, Any], rank: int = 0) -> None:
    """Rank 0 ends a run's console output with its warnings (stderr) and its status line (rods.checks)."""
    if rank != 0:
        return
    for w in summary.get("warnings", []):
        print(f"warning: {w}", file=sys.stderr)
    print(f"status: {summary.get('status', 'unknown')}", flush=True)


def fail(message: str) -> NoReturn:
    """Exit 2 with one line (rank 0's under MPI: input checks run on every rank alike)."""
    if _is_rank0():
        print(f"error: {one_line(message)}", file=sys.stderr, flush=True)
    raise SystemExit(EXIT_BAD_INPUT)


def load(args: argparse.Namespace) -> Scene:
    """Load and validate the scene; any problem exits 2 before anything runs."""
    try:
        return load_scene(args.scene, args.overrides)
    except SceneError as e:
        _refuse(str(e) + _scene_remedy(e, args))  # one rank's alone (its view of the file): every rank aborted


def _scene_remedy(e: SceneError, args: argparse.Namespace) -> str:
    """The remedy of a scene value refused without one of its own (a range, a choice): where the value came from,
    the --set that gave it or the scene file, to be given within what is allowed."""
    if e.hint or not e.allowed.startswith("must"):
        return ""
    keys = [parse_override(t)[0] for t in args.overrides or ()]  # read once by _Override already
    # a key inside a --set table or list (station[3].position in --set station=[...]) came from that --set
    given = next((k for k in keys if e.key == k or e.key.startswith((f"{k}[", f"{k}."))), None)
    where = f"{e.key} in {args.scene}" if given is None else f"--set {e.key}=VALUE" if given == e.key else (
        f"{e.key} in --set {given}=..."
    )  # fmt: skip
    return f" (remedy: {where}, a value as allowed)"


def out_dir(args: argparse.Namespace, model: str, scene: Scene) -> Path:
    """--out, or output/<model>/<scene folder> (rods.preflight.scene_folder: the scene's name, with a digest of its
    values where --set changed it); checked usable (rods.preflight) and, for a stage that writes a summary.json,
    not holding another kind of run's (rods.study.runs.check_reuse)."""
    from rods.study.runs import check_owner, check_reuse, stage_kind

    default = default_folder(model, scene, _overridden(args, scene))
    out = output_dir(args.out if args.out is not None else default)
    if (kind := stage_kind(model)) is not None:
        check_reuse(out, kind)
    if args.out is None:  # a folder named by the scene's name: not another scene file's of that name
        check_owner(out, scene)
    return out


def scene_default(args: argparse.Namespace, stage: str, scene: Scene) -> Path:
    """A side tool's default output folder, output/<stage>/<scene folder> as a run's (rods.preflight.default_folder):
    one per scene, so that a tool run on another scene's runs does not overwrite the paper's tables (a fuzz)."""
    return default_folder(stage, scene, _overridden(args, scene))


_HELD: list[FolderClaim] = []  # the output folder this process's run holds (rank 0's), released by guarded()
_HOLDING: list[Path] = []  # the folder held, on every rank (the same decisions on all)
_AGREE: list[Any] = []  # a duplicate of MPI's world, made as a command starts under MPI: see _refused_by_all
# [s] how long a rank refusing input waits for the others to refuse too (they check the same input at the same point,
# milliseconds apart) before it takes its refusal for its own and aborts them all
AGREE_WAIT = 5.0


def hold(out: Path, comm: Any = None) -> None:
    """Hold ``out`` for this run from here to its end (rods.preflight.FolderClaim, rank 0's): a second run into the
    folder is refused on every rank, exit 2, before it writes anything; from here on a missing file is a failed run
    (exit 1), not a path given wrong. Held already (a restart holds it before reading its checkpoint): kept."""
    if _HOLDING and _HOLDING[-1] == Path(out).absolute():
        return
    _release()  # an earlier run's in this process (a caller of main without guarded(): it has ended)
    _HOLDING.append(Path(out).absolute())
    if comm is None and (mpi := _mpi()) is not None:  # a script that loaded MPI without passing its communicator
        comm = mpi.COMM_WORLD
    refusal = None
    if comm.rank == 0 if comm is not None else _is_rank0():  # a script without MPI: the launcher's rank 0
        try:
            _HELD.append(FolderClaim(out))
        except InputError as e:
            refusal = (e.what, e.value, e.problem, e.remedy)
    if comm is not None and comm.size > 1:
        refusal = comm.bcast(refusal, root=0)
    if refusal is not None:
        raise InputError(*refusal)


def _refused_by_all() -> bool:
    """Whether every rank refuses the input too (each reaches a barrier on :data:`_AGREE` within
    :data:`AGREE_WAIT`): refusals are decided on every rank alike, but one taken by one rank alone (its node's free
    memory, its view of a file) left the others waiting in their next collective, a hang (an audit, 2026-12-07).
    True without several ranks. On a duplicate communicator: the barrier never meets the command's own collectives.
    A signal while it waits stops the command (exit 130)."""
    if not _AGREE:
        return True
    request, deadline = _AGREE[0].Ibarrier(), time.monotonic() + AGREE_WAIT
    try:
        while not request.Test():
            if time.monotonic() > deadline:
                return False
            time.sleep(0.01)
    except KeyboardInterrupt:
        _interrupted()
    return True


def _refuse(message: str) -> int:
    """Exit 2 with one line where every rank refuses alike (:func:`fail`), else this rank's line and every rank
    aborted (:func:`_refused_by_all`)."""
    if not _refused_by_all():  # this rank's alone: the others must not wait for it
        return _abort(message, EXIT_BAD_INPUT)
    fail(message)


def _release() -> None:
    """Release the folder this process's run holds (:func:`hold`), on every rank."""
    while _HELD:
        _HELD.pop().release()
    _HOLDING.clear()


def _overridden(args: argparse.Namespace, scene: Scene) -> bool:
    """Whether --set changed the scene's values: a run whose overrides repeat the file's values (`--set
    impact.speed=2.197` on paper.toml), or change only what changes no result (rods.scene.RESULT_NEUTRAL: checkpoints
    turned on for a restart), is the file's scene and shares its default folder."""
    if not args.overrides:
        return False
    try:
        return load_scene(args.scene).result_values() != scene.result_values()
    except SceneError:  # the file alone is not a valid scene: the overrides made it one
        return True


def _mpi():
    mpi = sys.modules.get("mpi4py.MPI")
    return mpi if mpi is not None and mpi.Is_initialized() and not mpi.Is_finalized() else None


# the rank a launcher gives each process (MPICH's hydra, Open MPI, PMIx, SLURM's srun), read where MPI is not loaded
# [s] between a rank's error line and its MPI_Abort: hydra forwards a rank's stderr through its proxy, which the
# abort tears down, and on a loaded machine the line was lost (once, in the suite's abort test under load; MPICH's
# own issues report the same), leaving the user an abort without its reason
ABORT_GRACE = 0.2
# [s] how long the main thread waits where the watcher's stop came first (rods.interrupt.stopping): it ends the
# process at once; the wait only keeps the main thread from a second line and a second release of the folder
STOP_WAIT = 10.0
LAUNCHER_RANKS = ("PMI_RANK", "OMPI_COMM_WORLD_RANK", "PMIX_RANK", "SLURM_PROCID")


def _is_rank0() -> bool:
    """Whether this process speaks for the run: MPI's rank 0, or, in a script that never loads MPI (compare.py,
    report.py, ...) started under a launcher, the launcher's rank 0 (each rank printed the same error line)."""
    mpi = _mpi()
    if mpi is not None:
        return mpi.COMM_WORLD.rank == 0
    rank = next((os.environ[k] for k in LAUNCHER_RANKS if k in os.environ), "0")
    return rank.strip() in ("0", "")


def _stopped(e: BaseException) -> int | None:
    """Exit code of a guard's collective stop (every rank raised it): 130 interrupted, 1 failed."""
    guards = sys.modules.get("rods.fe.guards")
    if guards is None or not isinstance(e, guards.SimulationError):
        return None
    mpi = _mpi()
    if mpi is None or mpi.COMM_WORLD.rank == 0:
        from rods.study.console import end_bar

        end_bar()  # the line after the bar, not on it
        if isinstance(e, guards.Interrupted) and e.checkpointed:
            tail = "the histories up to the stop and a checkpoint are written: the same command with --restart resumes"
            print(f"error: interrupted: {one_line(str(e))}; {tail}", file=sys.stderr)
        elif isinstance(e, guards.Interrupted):  # a driver's cut record, which no checkpoint holds: a rerun
            print(f"error: interrupted: {one_line(str(e))}; the histories up to the stop are written", file=sys.stderr)
        else:
            print(f"error: run stopped: {one_line(str(e))}; the histories up to the stop are written", file=sys.stderr)
    return EXIT_INTERRUPTED if isinstance(e, guards.Interrupted) else EXIT_FAILED


def _abort(message: str, code: int, at_once: bool = False) -> int:
    """One line naming the rank; under MPI with several ranks, abort them all (none hangs in a collective).
    ``at_once``: one process ends here too, without the teardown (a writer whose file failed throws again as it is
    destroyed: ADIOS2's on a full disk ended the process by SIGABRT, exit 134, after the line)."""
    if not interrupt.stopping() and threading.current_thread() is threading.main_thread():
        time.sleep(STOP_WAIT)  # the watcher's stop came first (it took this one's raise for lost): it ends the process
    mpi = _mpi()
    if os.environ.get("RODS_TRACEBACK") and sys.exc_info()[0] is not None:
        import traceback

        traceback.print_exc()
    if mpi is None or mpi.COMM_WORLD.size == 1:
        print(f"error: {one_line(message)}", file=sys.stderr, flush=True)
        if at_once:
            _release()
            sys.stdout.flush()
            os._exit(code)
        return code
    rank = mpi.COMM_WORLD.rank
    if rank and code == EXIT_INTERRUPTED:  # a signal reaches every rank: rank 0's line and abort first, one line
        time.sleep(2 * ABORT_GRACE)
    print(f"error on rank {rank}: {one_line(message)}; aborting all ranks", file=sys.stderr, flush=True)
    _release()  # the folder's lock (rank 0's): the abort skips the teardown that releases it
    time.sleep(ABORT_GRACE)
    mpi.COMM_WORLD.Abort(code)
    return code


# the errors of a full disk or quota, and of a file over its size limit (ulimit -f), by number and by the text that
# a C++ library's exception carries (ADIOS2: "errno = 28: No space left on device")
DISK_FULL = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


def _disk_full(e: BaseException) -> str | None:
    """The line for an error of a full disk (:data:`DISK_FULL`), naming the file where the error does; else None."""
    texts = [os.strerror(n) for n in DISK_FULL]
    if isinstance(e, OSError) and e.errno in DISK_FULL:
        where, why = e.filename, os.strerror(e.errno)
    elif any(t in str(e) for t in texts):
        where, why = None, next(t for t in texts if t in str(e))
    else:
        return None
    held = f" in {_HELD[0].path.parent}" if _HELD else ""
    return (
        f"{where or 'writing the results' + held}: {why.lower()}; free space (or raise the quota or ulimit -f), then "
        "run again, or with --restart where the run wrote checkpoints"
    )


def _interrupted() -> int:
    """Ctrl-C/SIGTERM outside the time loop (set-up, writing) or a second one inside it (rods.interrupt): stop at
    once, every rank, exit 130, without the
    extensions' exit handlers (they would report the interrupted call again)."""
    code = _abort(
        "interrupted (in the set-up, the writing, or by a second signal: nothing partial to write)", EXIT_INTERRUPTED
    )
    _release()  # the folder's lock, and the folder where the run wrote nothing yet (os._exit skips the teardown)
    sys.stderr.flush()
    sys.stdout.flush()
    os._exit(code)


def _start_gmsh() -> None:
    """gmsh started before the interrupt's handlers go in, as PETSc is, on rank 0, which meshes: its initialize puts
    its own SIGTERM handler in place for ~2 ms (rods.fe.mesh.start_gmsh puts ours back after it), which in the set-up
    ended a rank with 15, no line (one in ~15 SLURM-style stops at the set-up's start: a review, 2026-12-07).
    Started here, the mesh finds it started (rods.fe.mesh.gmsh_to_dolfinx) and the window lies before any handler of
    ours. It also sets SIGSEGV, SIGFPE, SIGBUS and SIGILL to the default, as meshing always did on rank 0: the other
    ranks keep PETSc's crash handlers."""
    import gmsh

    from rods.fe.mesh import start_gmsh

    if _is_rank0() and not gmsh.isInitialized():  # the ranks that mesh: the others keep PETSc's crash handlers
        start_gmsh()


def guarded(
    main: Callable[[Sequence[str] | None], int], ignore_after: bool = False
) -> Callable[[Sequence[str] | None], int]:
    """``main`` with the one error path (module docstring): exit 2 bad input, 1 failed run, 130 interrupt;
    ``ignore_after`` (the command, :func:`entry`): Ctrl-C and SIGTERM ignored from its end on, else the previous
    handlers back (a caller in-process)."""

    def run(argv: Sequence[str] | None = None) -> int:
        # a closed reader (`| head`) ends the process quietly, as for any command-line tool (PETSc's handler
        # printed a "Caught signal number 13 Broken Pipe" error block and called MPI_Abort); PETSc installs its
        # handlers when it initialises, so an FE entry point (rods.fe loaded) initialises it first, and the
        # interrupt's handlers go in after it (else a SIGTERM before the time loop, e.g. in the analytical
        # planning, printed PETSc's "Caught signal number 15" block and MPI_Abort(59) instead of exit 130)
        if "rods.fe" in sys.modules:
            from petsc4py import PETSc  # noqa: F401

            with contextlib.suppress(Exception):  # a gmsh that cannot start fails in the mesh, with its own line
                _start_gmsh()
        previous = interrupt.install(stop=lambda message, code: _abort(message, code, at_once=True))
        pipe = signal.signal(signal.SIGPIPE, signal.SIG_DFL)
        if (mpi := _mpi()) is not None and mpi.COMM_WORLD.size > 1 and not _AGREE:  # every rank starts here
            _AGREE.append(mpi.COMM_WORLD.Dup())  # kept for the process: freeing it is collective too
        try:
            return main(argv)
        except (SceneError, InputError) as e:
            return _refuse(str(e))
        except FileNotFoundError as e:
            if not _HOLDING:  # an input path given wrong; in a run (a file removed under it) a failure, below
                return _refuse(f"{e.filename or e}: no such file or folder (check the path)")
            return _abort(f"{e.filename or e}: removed while the run used it (run again)", EXIT_FAILED)
        except PermissionError as e:
            if not _HOLDING:  # a path given that this user cannot reach (a folder on it not searchable)
                return _refuse(f"{e.filename or e}: permission denied (a folder on its path cannot be read or "
                               "searched by this user); give a path you can reach")  # fmt: skip
            return _abort(f"PermissionError: {e} (RODS_TRACEBACK=1 shows where)", EXIT_FAILED)
        except KeyboardInterrupt:
            return _interrupted()
        except Exception as e:
            if isinstance(e, OSError) and e.errno == errno.ENAMETOOLONG:  # a path given (--scene, --global, base)
                return _refuse(f"{short(str(e.filename))}: a name in this path is longer than the file system allows "
                               "(give a shorter one)")  # fmt: skip
            code = _stopped(e)
            if code is not None:
                return code
            if (full := _disk_full(e)) is not None:
                return _abort(full, EXIT_FAILED, at_once=True)
            if interrupt.requested():  # a signal inside a C extension (SLEPc, gmsh) surfaces as another error
                return _interrupted()
            return _abort(f"{type(e).__name__}: {e} (RODS_TRACEBACK=1 shows where)", EXIT_FAILED)
        finally:  # the command: ignored at once, no default SIGTERM between (a repeat killed a rank with 15)
            _release()
            interrupt.uninstall({s: signal.SIG_IGN for s in previous} if ignore_after else previous)
            signal.signal(signal.SIGPIPE, pipe)

    return run


def entry(main: Callable[[Sequence[str] | None], int]) -> NoReturn:
    """Run ``main`` as the command (an entry point's ``__main__``): :func:`guarded`, then exit with its code. A Ctrl-C
    or SIGTERM after ``main`` returned (its files written, its status printed) is ignored: in the interpreter's and
    MPI's teardown it raised KeyboardInterrupt, a traceback, and hydra's mpirun reported the rank killed by signal 2
    as "EXIT CODE: 2", the bad-input code."""
    for stream in (sys.stdout, sys.stderr):  # an ASCII console (PYTHONIOENCODING=ascii, LC_ALL=C): 'µs', 'Δt' and a
        if hasattr(stream, "reconfigure"):  # scene's non-ASCII name escaped, not a UnicodeEncodeError's exit 1
            stream.reconfigure(errors="backslashreplace")
    sys.exit(guarded(main, ignore_after=True)())


def bare_parser(description: str, **kw: Any) -> argparse.ArgumentParser:
    """A parser without the scene options (the paper's rendering scripts, the benchmarks), with the one-line
    errors."""
    return _Parser(description=description, **kw)


def tool(main: Callable[[], int | None]) -> NoReturn:
    """Run a benchmark's ``main()`` (it parses sys.argv itself) as a command (:func:`entry`): bad input one line and
    exit 2, as every entry point's."""
    entry(lambda argv=None: main() or 0)
