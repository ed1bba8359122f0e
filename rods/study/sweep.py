"""Parameter sweeps: one CSV row per run, read from each run's summary.json by named keys.

Every row carries a ``key``: a hash of the code (``rods/``, ``workflows/``), the resolved scene and the
point's own parameters. ``workflows/Snakefile`` reads the committed record (``results/sweep-*.csv``) at
parse time and schedules only the points whose key is not in it; the table is then assembled from the
record's rows and the new runs (:func:`write_sweep_table`), into ``output/`` first and published to
``results/``. :func:`sync_text` keeps a sweep's key file, the rule's trigger, untouched while the keys are.
"""

from __future__ import annotations

import csv
import hashlib
import io as _io
import json
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from rods import io
from rods.preflight import InputError, distinct, short
from rods.scene import PAPER_SCENE  # the main job's scene, which its global meshes run on (the Snakefile's rules)

if TYPE_CHECKING:
    from rods.cost import Cost

__all__ = [
    "CONFIG_KEYS",
    "FIELDS",
    "FIELD_UNITS",
    "ConfigError",
    "check_config",
    "code_key",
    "gpu_choice",
    "point_cost",
    "point_key",
    "point_overrides",
    "read_record",
    "scene_key",
    "sync_text",
    "warning_key",
    "write_sweep_table",
]

# the columns of results/sweep-*.csv (after "path", before "key"): summary keys, SI units
FIELDS = (
    "model",
    "scene",  # the run's label: its scene and the point's settings (speed, kind, sizes, step fraction), SI units
    "impact_speed",
    "peak_contact_force",
    "contact_radius",
    "contact_duration",
    "midpoint_peak_speed",
    "midpoint_peak_strain",
    "wall_time",
    "dofs",
    "dt",
    "energy_error",
    "status",  # "ok" or "warnings": a row is only as good as its run's checks (rods.checks)
    "warnings",  # the keys the run's warnings name, "; "-separated (the texts are in its summary.json)
)
# the header's units, ``name [unit]`` as in every history CSV (rods.io.write_history); words and counts have none
FIELD_UNITS = {
    "impact_speed": "m/s",
    "peak_contact_force": "N",
    "contact_radius": "m",
    "contact_duration": "s",
    "midpoint_peak_speed": "m/s",
    "midpoint_peak_strain": "-",
    "wall_time": "s",
    "dofs": "-",
    "dt": "s",
    "energy_error": "-",
}


CONFIG_KEYS = (
    "scene", "speeds", "mesh_levels", "dt_fractions", "kinds", "fe_speed", "ranks", "mpi",
    "paper_levels", "paper_phase_levels", "paper_global_meshes", "gpu",
)  # fmt: skip


# where a config value comes from: the Snakefile's configfile, or one given with --configfile (a fuzz found every
# remedy naming workflows/sweep.yaml for a value from another file)
CONFIG_FILE = "workflows/sweep.yaml or your --configfile"


class ConfigError(ValueError):
    """A Snakemake config value (workflows/sweep.yaml or --config) that the sweeps cannot run."""

    def __init__(self, key: str, value: object, why: str, remedy: str = ""):
        remedy = remedy or f"{CONFIG_FILE}; override with --config {key}=..."
        super().__init__(f"config '{key}' = {short(value)}: {why} ({remedy})")


def check_config_file(path: str | Path) -> None:
    """Refuse (ConfigError) a config file Snakemake would misread: not YAML (Snakemake's own error names neither the
    line nor the column), not a mapping, or a key given twice in one mapping (YAML keeps the last, silently)."""
    import yaml

    class _Unique(yaml.SafeLoader):
        def construct_mapping(self, node, deep=False):
            seen = set()
            for key_node, _ in node.value:
                key = self.construct_object(key_node, deep=deep)
                if key in seen:
                    mark = key_node.start_mark
                    raise ConfigError(key, None, f"given twice in {path} (line {mark.line + 1})", "keep one")
                seen.add(key)
            return super().construct_mapping(node, deep)

    try:
        data = yaml.load(Path(path).read_text(encoding="utf-8"), Loader=_Unique)
    except (OSError, UnicodeDecodeError) as e:
        raise ConfigError("configfile", str(path), f"cannot be read ({e})", "a UTF-8 YAML file") from None
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        why = f"not valid YAML{where}: {getattr(e, 'problem', None) or e}"
        raise ConfigError("configfile", str(path), why, "fix that line (spaces, not tabs)") from None
    if not isinstance(data, dict):
        raise ConfigError("configfile", str(path), "must be a YAML mapping of the config's keys", "see sweep.yaml")


def check_config(config: Mapping[str, object], local_cpus: int | None = None) -> None:
    """Refuse, before any job, a config the sweeps cannot run: unknown keys, a scene that does not load, speeds,
    mesh sizes, time-step fractions, model kinds, ranks and levels outside the scene schema's ranges (each value
    is checked as the scene override it becomes), an entry given twice (the same run twice, or one folder given
    twice to a stage that refuses it), a gpu that is not auto/true/false; ``local_cpus`` (the machine's CPUs where
    the jobs run on it, None on a cluster executor): more ranks per run than that."""
    from rods.scene import SceneError, load_scene

    _keys(config)
    try:
        load_scene(str(config["scene"]))
    except SceneError as e:  # the scene file itself is the config's value: not said as a --scene option
        why = f"{e.allowed}" + (f" ({e.hint})" if e.hint else "") if e.key == "--scene" else str(e)
        raise ConfigError("scene", config["scene"], why) from None

    def each(key: str, kind: type, overrides, scene: str | Path | None = None) -> None:
        values = config[key]
        if not isinstance(values, kind) or not values:
            raise ConfigError(key, values, f"must be a non-empty {'list' if kind is list else 'mapping'}")
        for v in values:
            try:
                load_scene(str(scene or config["scene"]), overrides(v))
            except (SceneError, TypeError, ValueError, KeyError, IndexError) as e:
                raise ConfigError(key, values, f"entry {short(v)}: {e}") from None
        if kind is list:
            _once(key, values, [_number(v) if key in ("speeds", "dt_fractions") else v for v in values])
        elif key == "mesh_levels":  # two names, one pair of sizes: the same run twice, two equal rows (an audit)
            sizes = {k: tuple(_number(x) for x in v) for k, v in values.items()}
            for k, v in sizes.items():
                if (first := next(n for n, w in sizes.items() if w == v)) != k:
                    why = f"levels {first!r} and {k!r} have the same sizes {list(v)}: one run twice"
                    raise ConfigError(key, values, why, "give each pair of sizes once")

    each("speeds", list, lambda v: [f"impact.speed={_number(v)!r}"])
    each("mesh_levels", dict, lambda k: _mesh_level(config["mesh_levels"][k]))
    each("dt_fractions", list, lambda v: [f"fe.dt_fraction={_number(v)!r}"])
    each("kinds", list, lambda v: [f"fe.kind={v!r}"])
    # the main job runs its global meshes on the paper scene (rule paper_global), whatever the sweeps' scene
    each("paper_global_meshes", dict, lambda k: _overrides(config["paper_global_meshes"][k]), PAPER_SCENE)
    _folder_names(config)
    if "coarse" not in config["mesh_levels"]:
        raise ConfigError("mesh_levels", config["mesh_levels"], "must hold 'coarse' (the time-step sweep's mesh)")
    try:
        load_scene(str(config["scene"]), [f"impact.speed={_number(config['fe_speed'])!r}"])
    except (SceneError, TypeError, ValueError) as e:
        raise ConfigError("fe_speed", config["fe_speed"], str(e)) from None
    _ranks(config, local_cpus)
    gpu_choice(config["gpu"])
    _paper_levels(config)


def _keys(config: Mapping[str, object]) -> None:
    """Every key known (an unknown one named with the nearest known one) and given."""
    from rods.scene import nearest_key

    unknown = sorted(set(config) - set(CONFIG_KEYS))
    if unknown:
        near = nearest_key(unknown[0], CONFIG_KEYS)
        hint = f"did you mean '{near}'?; " if near else ""
        fix = f"{CONFIG_FILE}; spell it --config {near}=..." if near else f"{CONFIG_FILE}; remove it"
        raise ConfigError(unknown[0], config[unknown[0]], f"unknown key; {hint}known: {', '.join(CONFIG_KEYS)}", fix)
    missing = [k for k in CONFIG_KEYS if k not in config]
    if missing:
        why = "missing: a config replacing sweep.yaml (--replace-workflow-config) states every key, the main job's too"
        raise ConfigError(missing[0], None, why, "copy workflows/sweep.yaml and edit the copy")


def _ranks(config: Mapping[str, object], local_cpus: int | None) -> None:
    """``ranks`` a count >= 1, at most ``local_cpus`` (:func:`check_config`); ``mpi`` a launcher command."""
    ranks = config["ranks"]
    if isinstance(ranks, bool) or not isinstance(ranks, int) or ranks < 1:
        raise ConfigError("ranks", ranks, "must be an integer >= 1 (MPI ranks per FE run)")
    if local_cpus is not None and ranks > local_cpus:
        why = f"more MPI ranks per FE run than the {local_cpus} CPUs the jobs may use here (the machine's, --cores)"
        fix = f"--config ranks={local_cpus} or fewer, more --cores, or a cluster (workflows/profiles/slurm)"
        raise ConfigError("ranks", ranks, why, fix)
    if config["mpi"] is not None and not isinstance(config["mpi"], str):  # --config mpi= gives None
        raise ConfigError("mpi", config["mpi"], "must be a launcher command ('' = the venv's mpirun)")


def _paper_levels(config: Mapping[str, object]) -> None:
    """The main job's submodel levels: known, each once, at least one; its phase levels among them."""
    from rods.scene import SUBMODEL_LEVELS

    for key in ("paper_levels", "paper_phase_levels"):
        levels = config[key]
        if not isinstance(levels, list) or not all(isinstance(v, str) and v in SUBMODEL_LEVELS for v in levels):
            raise ConfigError(key, levels, f"must be a list of submodel levels: {', '.join(SUBMODEL_LEVELS)}")
        _once(key, levels, levels)
    if not config["paper_levels"]:
        why = "must name at least one submodel level (the main job's contact-patch study and its convergence)"
        raise ConfigError("paper_levels", config["paper_levels"], why)
    if extra := [v for v in config["paper_phase_levels"] if v not in config["paper_levels"]]:  # dropped silently
        why = f"level {extra[0]!r} is not among paper_levels {config['paper_levels']}: the main job does not run it"
        raise ConfigError("paper_phase_levels", config["paper_phase_levels"], why)


def _once(key: str, values: object, keys: list) -> None:
    """Each entry of the list ``values`` (compared as ``keys``: numbers by value) given once (rods.preflight.distinct):
    twice would run one point twice, or give its folder twice to a stage that refuses that, hours into the job."""
    try:
        distinct(keys, key)
    except InputError as e:
        raise ConfigError(key, values, f"entry {short(e.value)} given more than once; give each once") from None


def _folder_names(config: Mapping[str, object]) -> None:
    """The names of mesh levels and of the main job's global meshes: each becomes a folder and a shell word."""
    for key in ("mesh_levels", "paper_global_meshes"):
        for name in config[key]:
            if not (isinstance(name, str) and re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", name)):
                raise ConfigError(key, name, "a name must be letters, digits, '_', '.' or '-' (it names a folder)")


def gpu_choice(value: object) -> bool | str:
    """The config's ``gpu`` as True, False or "auto" (YAML gives booleans, ``--config gpu=true`` a string)."""
    choice = {"auto": "auto", "true": True, "false": False}.get(str(value).lower())
    if choice is None:
        raise ConfigError("gpu", value, "must be auto, true or false (the paper's 3D mesh on a GPU)")
    return choice


def _overrides(value: object) -> list[str]:
    """A list of ``KEY=VALUE`` scene overrides (a string would be read character by character)."""
    if not isinstance(value, list) or not all(isinstance(o, str) for o in value):
        raise TypeError(f"{short(value)} is not a list of KEY=VALUE overrides")
    return value


def _mesh_level(sizes: object) -> list[str]:
    """A mesh level's [axial, radial] sizes [m] as scene overrides."""
    if not isinstance(sizes, list) or len(sizes) != 2:
        raise TypeError(f"{short(sizes)} is not [axial size, radial size] in metres")
    return [f"fe.axial_size={_number(sizes[0])!r}", f"fe.radial_size={_number(sizes[1])!r}"]


def point_overrides(config: Mapping[str, object], point: Mapping[str, object]) -> list[str]:
    """A sweep point's overrides of the sweep's scene (``config["scene"]``): its impact speed and, for a global FE
    point (one with a ``kind``), its model kind, its mesh level's sizes and its time-step fraction."""
    overrides = [f"impact.speed={point['speed']}"]
    if "kind" in point:
        sizes = _mesh_level(config["mesh_levels"][point["level"]])
        overrides += [f"fe.kind={point['kind']}", *sizes, f"fe.dt_fraction={point['dtf']}"]
    return overrides


def point_cost(config: Mapping[str, object], point: Mapping[str, object]) -> Cost:
    """The plan of a sweep point (rods.cost): the analytical model's at its speed, or its global FE run's on the
    config's ranks, the costs its entry point prints."""
    from rods import cost
    from rods.scene import load_scene
    from rods.study import jobs

    scene = load_scene(config["scene"], point_overrides(config, point))
    if "kind" not in point:
        return cost.analytical_cost(scene)
    return jobs.global_cost(scene, int(config["ranks"]))


def _number(v: object) -> float:
    """A config number: a YAML int or float, or a numeric string (--config 'speeds=[1.0,2.0]' gives strings)."""
    if isinstance(v, bool) or not isinstance(v, int | float | str):
        raise TypeError(f"{short(v)} is not a number")
    try:
        return float(v)
    except ValueError:
        raise TypeError(f"{short(v)} is not a number") from None


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def code_key(paths: Iterable[str | Path]) -> str:
    """Hash of the contents of ``paths`` (sorted by name): any change to the code reruns every point."""
    h = hashlib.sha256()
    for p in sorted(str(p) for p in paths):
        h.update(p.encode() + b"\0" + Path(p).read_bytes() + b"\0")
    return h.hexdigest()[:16]


def library_differs(checkout: str | Path = "rods") -> bool:
    """Whether the ``rods`` this interpreter imports holds other code than the checkout's ``checkout`` folder, whose
    files the points' keys hash (a venv shared by two clones ran the other clone's code: an audit, 2026-12-07); the
    same code installed elsewhere (a wheel) is no difference."""
    import rods

    imported, here = Path(rods.__file__).resolve().parent, Path(checkout).resolve()
    if imported == here:
        return False
    ours, theirs = (sorted(p.relative_to(d) for p in d.rglob("*.py")) for d in (here, imported))
    return ours != theirs or any((here / f).read_bytes() != (imported / f).read_bytes() for f in ours)


def scene_key(path: str | Path) -> str:
    """Hash of the resolved scene (bases merged, defaults filled): an edit that changes no value reruns nothing."""
    from rods.scene import load_scene

    return _sha(json.dumps(load_scene(path).as_dict(), sort_keys=True))


def point_key(code: str, scene: str, **params) -> str:
    """The key of one sweep point: code and scene hashes and the point's parameters (values as text, a number's
    as its float: --config's "4.0e-3" arrives as a string and is the yaml's 0.004, one point, not two)."""
    return _sha(json.dumps([code, scene, {k: _number_text(v) for k, v in sorted(params.items())}]))


def folder_text(v: object) -> str:
    """A config number as a point's folder spells it: through float (``2`` and ``2.0`` one point, one folder; a run
    under speed-2.0/ was run again under speed-2/: an audit, 2026-12-07)."""
    return repr(_number(v))


def _number_text(v: object) -> str:
    """``v`` as text, through float where it reads as a number (nested lists item by item)."""
    if isinstance(v, list | tuple):
        return "[" + ", ".join(_number_text(x) for x in v) + "]"
    try:
        return repr(float(v)) if not isinstance(v, bool) else str(v)
    except (TypeError, ValueError):
        return str(v)


def _cell(summary: Mapping[str, object], key: str) -> object:
    """A sweep table's cell of ``key`` from a run's summary: its warnings as the keys they name."""
    if key == "warnings":
        return "; ".join(warning_key(str(w)) for w in summary.get("warnings") or [])
    return summary.get(key)


def warning_key(text: str) -> str:
    """The key a warning names ("key: why"; rods.checks), "yield" for the elastic yield criterion's (a sentence
    of its own, rods.hertz), "other" for any other sentence."""
    head = text.split(":", 1)[0]
    if head and ":" in text and not any(c.isspace() for c in head):
        return head
    return "yield" if "S_y" in text else "other"


def read_record(path: str | Path) -> dict[str, dict[str, str]]:
    """Rows of a published table by key, by the columns' bare names (units stripped from the header; {} for a
    missing file or a table from before keys)."""
    p = Path(path)
    if not p.exists():
        return {}
    with p.open(newline="") as f:
        reader = csv.reader(f)
        names = [h.split(" [")[0] for h in next(reader, [])]
        rows = (dict(zip(names, r, strict=False)) for r in reader)
        return {row["key"]: row for row in rows if row.get("key")}


def sync_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` only if it differs (its mtime then marks a change for Snakemake)."""
    p = Path(path)
    if not p.exists() or p.read_text() != text:
        io.atomic_write_text(p, text)


def sync_keys(path: str | Path, points: Sequence[tuple[str, str]], record: str | Path) -> None:
    """A sweep's trigger ``path``: its points' (summary path, key) lines (:func:`sync_text`), and touched where the
    published ``record`` holds other keys while the trigger is no newer than it. Another config's invocation (a dry
    run, one refused by Snakemake's lock) rewrites the trigger at parse time; the table published after it was still
    the first config's, and under ``--rerun-triggers mtime`` the second config then ran nothing (an audit,
    2026-12-07). Touched, the trigger reassembles the table under any trigger until the record is this config's."""
    p, r = Path(path), Path(record)
    sync_text(p, "".join(f"{k} {s}\n" for s, k in points))
    if r.exists() and set(read_record(r)) != {k for _, k in points} and p.stat().st_mtime <= r.stat().st_mtime:
        os.utime(p)


def write_sweep_table(
    path: str | Path,
    points: Sequence[tuple[str | Path, str]],
    record: Mapping[str, Mapping[str, str]] | None = None,
    fields: Sequence[str] = FIELDS,
) -> None:
    """Write ``path``: one row per (summary path, key) of ``points``, in order: the ``record``'s row of that
    key where it has one, else ``fields`` read from the summary (empty if absent). The header names each
    column's SI unit (:data:`FIELD_UNITS`)."""
    record = record or {}
    buf = _io.StringIO()
    names = ["path", *fields, "key"]
    csv.writer(buf, lineterminator="\r\n").writerow(
        [f"{n} [{FIELD_UNITS[n]}]" if n in FIELD_UNITS else n for n in names]
    )
    w = csv.DictWriter(buf, fieldnames=names, lineterminator="\r\n", extrasaction="ignore")
    for p, key in points:
        if key in record:
            w.writerow(record[key])
            continue
        s = json.loads(Path(p).read_text())
        w.writerow({"path": str(p), **{k: _cell(s, k) for k in fields}, "key": key})
    io.atomic_write_text(path, buf.getvalue())
