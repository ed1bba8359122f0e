"""Bad input found before anything runs: one-line messages, output folders checked, names made safe.

Every entry point (``workflows/_cli.py``) turns an :class:`InputError` (or a :class:`rods.scene.SceneError`)
into exit code 2 and one line on stderr that names the argument or file, the value and the remedy.

* :func:`short` — a value as it appears in a message, cut to :data:`MAX_VALUE` characters (a 200k-entry
  list must not echo megabytes);
* :func:`output_dir` — an output folder is usable: not a file, its nearest existing ancestor a writable
  folder (nothing is created here: a refused run leaves no folder);
* :func:`input_dir` — a folder a stage reads: it exists and holds the files named;
* :func:`safe_name` — a scene name as a folder name: no separators, no leading dots (``../../x`` stays
  under ``output/``), at most :data:`MAX_FOLDER_NAME` characters;
* :func:`scene_folder` — the default folder name of a run: the safe scene name, and where ``--set`` changed the
  scene a digest of its resolved values, so a run with other values never overwrites the plain scene's;
* :func:`default_folder` — a run's folder without ``--out``: ``output/<stage>/<scene folder>``;
* :class:`FolderClaim` — an output folder held by one run while it writes there: a second run into it is refused.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import hashlib
import json
import os
import re
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = [
    "MAX_VALUE",
    "FolderClaim",
    "InputError",
    "distinct",
    "input_dir",
    "one_line",
    "output_dir",
    "output_file",
    "output_names",
    "safe_name",
    "default_folder",
    "scene_folder",
    "short",
]

MAX_VALUE = 120  # characters of a value shown in a message [-]
MAX_MESSAGE = 1000  # characters of a whole message line [-]
MAX_FOLDER_NAME = 100  # characters of a folder named after a scene [-]
NAME_MAX = 255  # [B] of one file or folder name
PATH_MAX = 4000  # [B] of a whole path (Linux: 4096, less the file names a run adds)


def short(value: Any, limit: int = MAX_VALUE) -> str:
    """``repr(value)`` cut to ``limit`` characters, the cut marked with its full length."""
    text = repr(value)
    if len(text) <= limit:
        return text
    return f"{text[: limit - 30]}... ({len(text)} characters)"


ANSI_ESCAPE = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")  # a terminal colour code (ADIOS2 colours its exceptions' text)


def one_line(message: str, limit: int = MAX_MESSAGE) -> str:
    """``message`` on one line (terminal colour codes dropped, whitespace runs collapsed), cut to ``limit``
    characters."""
    text = " ".join(ANSI_ESCAPE.sub("", message).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


class InputError(ValueError):
    """A command-line argument or an input file that cannot be used: ``what`` (the argument or file), its
    ``value``, the ``problem`` and the ``remedy``."""

    def __init__(self, what: str, value: Any, problem: str, remedy: str = ""):
        self.what, self.value, self.problem, self.remedy = what, value, problem, remedy
        msg = f"{what} = {short(str(value) if isinstance(value, Path) else value)}: {problem}"
        super().__init__(msg + (f"; {remedy}" if remedy else ""))


def output_dir(path: str | Path, what: str = "--out") -> Path:
    """``path`` as an output folder, checked without creating anything: not an existing file, and the
    folder itself (if it exists) or its nearest existing ancestor a writable, searchable folder."""
    if str(path) == "":
        raise InputError(what, "", "is empty", "give a folder path")
    p = Path(path)
    if p.parts and p.parts[0].startswith("~"):  # `--out=~/x`: the shell expands no ~ after '=' (a folder named '~')
        raise InputError(
            what, p, "starts with a '~' the shell did not expand",
            "give the full path (the shell expands '~' at a word's start: a space after the option, not '='; a "
            "folder named so: ./~x)",
        )  # fmt: skip
    _name_lengths(p, what)  # before exists(), which raises on such a name
    if p.exists() and not p.is_dir():
        raise InputError(what, p, "is an existing file, not a folder", "give a folder path")
    probe = p
    while not probe.exists():
        if probe.is_symlink():  # a link to a purged scratch folder, or a loop: the run failed at its end (exit 1)
            raise InputError(
                what, p, f"{probe} is a link to {os.readlink(probe)}, which does not resolve to a folder",
                "create its target, or give another folder",
            )  # fmt: skip
        probe = probe.parent
    if not probe.is_dir():
        raise InputError(what, p, f"{probe} is a file, so the folder cannot be created", "give another path")
    if not (os.access(probe, os.W_OK | os.X_OK) and _can_create(probe)):
        raise InputError(what, p, f"folder {probe} is not writable", "give a folder you can write to")
    if p.is_dir():
        _blocked_names(p, what)
    return p


REMOVE = "remove it, or give another folder"  # the remedy of a name in the way

# what the stages write into their folder (files) and a study into its own (stage folders): an entry of that name of
# the other kind failed the run at its first write (IsADirectoryError, exit 1, a history.csv without its summary)
RUN_FILES = ("summary.json", "history.csv", "pressure_profile.csv", "sigma_r.csv", "axis_stress.csv", "cut.h5",
             "fields.xdmf", "checkpoint.json")  # fmt: skip
STAGE_FOLDERS = ("analytical", "global", "driver", "submodel")


def _blocked_names(p: Path, what: str) -> None:
    """No entry of ``p`` named as a run's file (:data:`RUN_FILES`) is a folder, none named as a study's stage
    folder (:data:`STAGE_FOLDERS`) a file."""
    output_names(p, RUN_FILES, what)
    for name in STAGE_FOLDERS:
        q = p / name
        if q.exists() and not q.is_dir():
            raise InputError(what, p, f"{q} is in the way: a run writes a folder of that name there", REMOVE)


def output_file(path: str | Path, what: str = "--out") -> Path:
    """``path`` as a file to write (or a prefix of files): not empty, not an existing folder, its folder usable
    (:func:`output_dir`)."""
    if str(path) == "":
        raise InputError(what, "", "is empty", "give a file path")
    p = Path(path)
    if p.is_dir():
        raise InputError(what, p, "is an existing folder, not a file", "give a file path inside it")
    output_dir(p.parent, what)
    return p


def output_names(folder: str | Path, names: Sequence[str], what: str = "--out") -> None:
    """The files a stage will write into ``folder`` (``names``) can be written: none of them is a folder or other
    non-file (a stage that met one failed at that write, exit 1, after writing the files before it)."""
    for name in names:
        q = Path(folder) / name
        if q.exists() and not q.is_file():
            raise InputError(what, folder, f"{q} is in the way: a run writes a file of that name there", REMOVE)


def distinct(values: Sequence[Any], what: str) -> None:
    """Each of a repeatable option's ``values`` given once: a run given twice is counted twice (a table row, a
    convergence level, a case run twice into one folder)."""
    seen = set()
    for v in values:
        key = str(Path(v).resolve()) if isinstance(v, Path) else v
        if key in seen:
            raise InputError(what, v, "given more than once", f"give each {what} once")
        seen.add(key)


def _name_lengths(p: Path, what: str) -> None:
    """Each name in ``p`` within NAME_MAX (255 bytes on Linux and macOS file systems): a longer one fails when the
    first file is written, after the run."""
    if len(os.fsencode(str(p.absolute()))) > PATH_MAX:
        raise InputError(what, p, f"a path over the file system's {PATH_MAX} bytes", "give a shorter path")
    for part in p.parts:
        if len(os.fsencode(part)) > NAME_MAX:
            raise InputError(what, p, f"a folder name of {len(os.fsencode(part))} bytes exceeds the file system's "
                             f"{NAME_MAX}", "give shorter names (a long scene name: --out DIR)")  # fmt: skip


def _can_create(folder: Path) -> bool:
    """A file can be created in ``folder`` (also for root on a read-only file system); removed at once."""
    try:
        fd, name = tempfile.mkstemp(dir=folder, prefix=".rods-preflight-")
    except OSError:
        return False
    os.close(fd)
    os.unlink(name)
    return True


def input_dir(path: str | Path, files: tuple[str, ...], what: str, remedy: str) -> Path:
    """``path`` as a folder a stage reads: exists and holds ``files``; an empty path is no folder (Path("") is
    the working folder, which the refusal named '.')."""
    if str(path) == "":
        raise InputError(what, "", "is empty", remedy)
    p = Path(path)
    if not p.is_dir():
        raise InputError(what, p, "a file, not a folder" if p.exists() else "no such folder", remedy)
    for f in files:
        if not (p / f).is_file():
            why = f"its {f} is not a file" if (p / f).exists() else f"has no {f}"
            raise InputError(what, p, why, remedy)
    return p


def safe_name(name: str) -> str:
    """A scene name usable as one folder name: characters outside [A-Za-z0-9._=-] become '_', leading
    dots are dropped (no '..', no hidden folder), a name above MAX_FOLDER_NAME characters is cut and marked with
    its hash; empty -> 'scene'."""
    text = re.sub(r"[^A-Za-z0-9._=-]", "_", name).lstrip(".")
    if len(text) > MAX_FOLDER_NAME:  # a long name is cut, its hash keeps it apart from others cut alike
        text = f"{text[: MAX_FOLDER_NAME - 9]}-{hashlib.sha1(name.encode()).hexdigest()[:8]}"
    return text or "scene"


OUTPUT = Path("output")  # where a run without --out writes, under the folder it runs from (ignored by git)


def default_folder(stage: str, scene: Any, overridden: bool) -> Path:
    """A run's folder without --out: output/<stage>/<:func:`scene_folder`> (``stage``: analytical, global, driver,
    run, submodel/<level>, compare, ...), relative to the folder the command runs from."""
    return OUTPUT / stage / scene_folder(scene, overridden)


def scene_folder(scene: Any, overridden: bool) -> str:
    """The default folder name of a run of ``scene`` (rods.scene.Scene): :func:`safe_name` of its name, and when
    ``overridden`` (``--set`` given) "-" and 8 hex digits of the SHA-1 of its resolved values (Scene.as_dict,
    keys sorted, with what changes no result at its default: Scene.result_values(default=True); the same scene
    whatever the order of the overrides), e.g. ``paper-3f1c09a2``."""
    name = safe_name(scene.name)
    if not overridden:
        return name
    values = scene.result_values(default=True)  # a restart may turn checkpoints on: the same folder
    digest = hashlib.sha1(json.dumps(values, sort_keys=True).encode()).hexdigest()[:8]
    return f"{name[: MAX_FOLDER_NAME - 9]}-{digest}"


LOCK = ".rods-lock"  # the file a run holds locked in its output folder while it writes there
LOCK_TRIES = 5  # locks of the lock file before a claim gives up on one held or replaced [-]
LOCK_WAIT = 0.05  # [s] between two (another claim's probe holds it shared for microseconds)
LOCK_DEPTH = 2  # folder levels below a run's folder whose locks a claim checks (a study's stage folders) [-]
BUSY = (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES)  # a non-blocking flock's errors where another process holds it


def _nested_locks(out: Path) -> list[Path]:
    """The lock files above ``out`` and up to :data:`LOCK_DEPTH` levels below it."""
    out = Path(out).absolute()
    above = [q / LOCK for q in out.parents]
    below = [f for depth in range(1, LOCK_DEPTH + 1) for f in out.glob("/".join(["*"] * depth) + "/" + LOCK)]
    return [f for f in (*above, *below) if f.is_file()]


def _held(lock: Path) -> bool:
    """Whether a running process holds ``lock`` (a file left by a killed one is not held)."""
    try:
        fd = os.open(lock, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError as e:
        return e.errno in BUSY
    finally:
        os.close(fd)  # drops the shared lock taken
    return False


class FolderClaim:
    """An output folder held by this process while its run writes there: an exclusive, non-blocking ``flock`` on its
    :data:`LOCK` file, so that a second run into the folder is refused (:class:`InputError`, naming ``what``) instead
    of mixing its files with the first's (a fuzz, 2026-12-07: two runs into one folder, both exit 0, one's
    summary.json over the other's history.csv in 2 of 20 tries; a study's fields deleted under another). The
    operating system drops the lock with the process, however it ends, so a lock file left by a killed run stops
    nobody. Where the file system has no locks (ENOLCK, some network mounts) the folder is not held.
    :meth:`release` unlocks, removes the file and the folders the claim made that are still empty (a run refused
    after its claim leaves nothing)."""

    def __init__(self, out: Path, what: str = "--out"):
        out = Path(out)
        self.made = [q for q in (out, *out.parents) if not q.exists()]  # deepest first
        out.mkdir(parents=True, exist_ok=True)
        self.path, self.fd = out / LOCK, None
        self._lock(out, what)
        for other in _nested_locks(out):  # after its own: two claims at once refuse each other, never both pass
            if _held(other):
                self.release()
                raise InputError(
                    what, out, f"another run is writing {other.parent} (it holds {LOCK} there), which this run's "
                    "folder is inside or holds", "wait for it to end, or give a folder outside it",
                )  # fmt: skip

    def _lock(self, out: Path, what: str) -> None:
        """The exclusive lock on :attr:`path`: again where the file was replaced between the open and the lock (a run
        ending removes its file), or briefly held shared (another claim's probe, :func:`_held`)."""
        for _ in range(LOCK_TRIES):
            fd = self._open(out, what)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError as e:
                os.close(fd)
                if e.errno == errno.EBADF:  # a read-only descriptor (:meth:`_open`) where flock is byte-range (NFS)
                    self.release()
                    raise InputError(
                        what, out, f"its {LOCK} is another user's and cannot be locked through a read-only descriptor "
                        "on this file system", f"remove {self.path} (no run holds it when none is writing there), or "
                        "give another folder",
                    ) from None  # fmt: skip
                if e.errno not in BUSY:  # no locks on this file system: not held
                    with contextlib.suppress(OSError):
                        self.path.unlink()
                    return
                time.sleep(LOCK_WAIT)
                continue
            with contextlib.suppress(OSError):
                if os.fstat(fd).st_ino == os.stat(self.path).st_ino:
                    self.fd = fd
                    return
            os.close(fd)  # removed (or replaced) between the open and the lock: again
        self.release()  # held, or replaced under every try: another run is busy there either way, never unheld
        raise InputError(
            what, out, f"another run is writing this folder (it holds {LOCK} there)",
            "wait for it to end, or give another folder",
        )  # fmt: skip

    def _open(self, out: Path, what: str) -> int:
        """The lock file's descriptor: created, or an earlier one opened (flock needs no write access: a lock file left
        by another user's run, 0644, is opened read-only; a fuzz found it, and a folder of that name, ending the run
        with exit 1 and an OSError's text after its plan)."""
        try:
            return os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        except PermissionError:
            with contextlib.suppress(OSError):
                return os.open(self.path, os.O_RDONLY)
        except OSError:
            pass
        self.release()  # the folders the claim made (none: the lock's folder exists)
        raise InputError(
            what, out, f"its {LOCK} cannot be opened to hold the folder (not a file, or not readable by this user)",
            f"remove {self.path} (no run holds it when none is writing there), or give another folder",
        )  # fmt: skip

    def release(self) -> None:
        """Unlock and remove the lock file, then the folders the claim made where nothing else was written."""
        if self.fd is not None:
            with contextlib.suppress(OSError):  # gone already (the folder removed under the run)
                self.path.unlink()
            os.close(self.fd)
            self.fd = None
        for q in self.made:
            with contextlib.suppress(OSError):
                q.rmdir()  # only an empty one
