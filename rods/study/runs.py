"""The runs later stages read, checked as bad input (:func:`read_summary`: the folder, its summary, the kind of run,
its scene; :func:`read_run`: a :class:`rods.io.Run`); percentage cells. The data files themselves: :mod:`rods.io`."""

from __future__ import annotations

import json
import math
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from rods import io
from rods.compare import percent
from rods.plan import scene_difference, submodel_end
from rods.preflight import InputError, input_dir
from rods.scene import Scene, SceneError, scene_from_summary, value_differences

__all__ = [
    "check_driven_by",
    "check_owner",
    "check_reuse",
    "driver_end",
    "parse_run",
    "pct",
    "read_driver",
    "read_run",
    "read_summary",
    "run_kind",
    "verify_folder",
]


def pct(ours: float, ref: float, digits: int = 1) -> str:
    """:func:`rods.compare.percent` as a signed percentage cell, '-' where a value is missing."""
    if not (math.isfinite(ours) and math.isfinite(ref)) or ref == 0:
        return "-"
    return f"{percent(ours, ref):+.{digits}f}%"


def run_kind(summary: Mapping[str, Any]) -> str:
    """The kind of run a summary.json comes from, by its ``model``: "analytical", "global" (``fe-axisymmetric``,
    ``fe-3d``), "submodel" (``fe-submodel-<level>``), "study" (``workflow``), else "unknown"."""
    model = str(summary.get("model", ""))
    if model.startswith("fe-submodel"):
        return "submodel"
    if model.startswith("fe-"):
        return "global"
    return {"analytical": "analytical", "workflow": "study"}.get(model, "unknown")


# the kind of run (run_kind) each entry point's stage writes, by the stage's folder name under output/ (a submodel's:
# submodel/<level>); a stage not listed writes no summary.json of its own
STAGE_KINDS = {
    "analytical": "analytical",
    "global": "global",
    "driver": "global",
    "run": "study",
    "submodel": "submodel",
    "verify": "verification",  # no summary.json of its own: its folder holds case folders of runs (verify_folder)
}


def stage_kind(stage: str) -> str | None:
    """The run kind of an entry point's stage (:data:`STAGE_KINDS`), None for one without a summary.json."""
    return STAGE_KINDS.get(stage.split("/")[0])


def verify_folder(out: str | Path) -> bool:
    """Whether ``out`` is a verification matrix's folder or one of its cases' (each case runs a global 2 x finer,
    ``global-finer``, which no other entry point writes)."""
    p = Path(out)
    return (p / "global-finer").is_dir() or any(c.is_dir() for c in p.glob("*/global-finer"))


def check_owner(out: str | Path, scene: Scene, flag: str = "--scene") -> None:
    """Refuse (:class:`InputError` naming ``flag``) a scene's default output folder ``out`` that holds a run of
    another scene file of the same name: the folder is named by the scene's name (rods.preflight.scene_folder), so
    a copy of paper.toml at 4 m/s that kept ``name = "paper"`` wrote over the paper scene's run (a fuzz, 2026-12-07).
    A rerun of the same file, edited or not, replaces its run as before; a run that recorded no scene file is not
    checked."""
    ours = scene.scene_file
    try:
        theirs = json.loads((Path(out) / "summary.json").read_text(encoding="utf-8")).get("scene_file")
    except (OSError, ValueError, AttributeError):  # none, or not a run's: nothing to protect
        return
    if ours is None or theirs is None or ours == theirs:
        return
    why = f"its default folder {out} holds a run of another scene file of the name {scene.name!r} ({theirs})"
    raise InputError(flag, ours, why, 'give --out, or give this scene file a name of its own (name = "...")')


def check_reuse(out: str | Path, kind: str, flag: str = "--out") -> None:
    """Refuse (:class:`InputError`) an output folder that holds another kind of run's summary.json: rerunning a
    stage into its own folder replaces it, but a global written over a study's folder (or a study over a
    global's) would leave the other's files beside a summary that no longer describes them."""
    if kind != "verification" and verify_folder(out):  # a case's runs, or the matrix of them (a fuzz, 2026-12-06:
        # a study into a case folder replaced its analytical and global, its finer global left beside them)
        why = f"holds a verification matrix's runs (workflows/verify.py) rather than this {kind} run's"
        raise InputError(flag, out, why, "give another --out")
    f = Path(out) / "summary.json"
    try:
        theirs = run_kind(json.loads(f.read_text(encoding="utf-8")))
    except (OSError, ValueError, AttributeError):  # none, or not a run's: nothing to protect
        return
    if theirs not in (kind, "unknown"):
        why = f"holds another kind of run ({theirs}: its summary.json) than this {kind} run"
        raise InputError(flag, out, why, "give another --out")


def read_summary(
    folder: str | Path,
    flag: str,
    kinds: tuple[str, ...] = ("global", "submodel"),
    scene: Scene | None = None,
    files: tuple[str, ...] = ("summary.json",),
    other_scene: str = "give --scene/--set of that run, or a run of this scene",
    whole_contact: bool = False,
) -> dict[str, Any]:
    """The summary.json of the run in ``folder`` that a later stage reads, checked before anything is computed
    (:class:`InputError` naming ``flag``, exit 2): the folder holds ``files``, the summary parses, the run is one
    of ``kinds`` and not a stopped one, given ``scene`` its bodies and impact are the scene's (a run of another
    scene gives a table of differences between two scenes that says nothing), and with ``whole_contact`` its
    first contact ended before its end time (Table 3's global row is that contact's peak: a 20 µs global read
    -20%)."""
    remedy = f"give the folder of a finished {' or '.join(kinds)} run"  # "finished" takes no article
    d = input_dir(folder, files, flag, remedy)
    try:
        summary = json.loads((d / "summary.json").read_text(encoding="utf-8"))
        kind = run_kind(summary) if isinstance(summary, dict) else "unknown"
        values = _scene_values(summary, kind) if scene is not None and kind != "study" else None
        theirs = scene_from_summary(values, source=str(d)) if values is not None else None
    except SceneError as e:
        raise InputError(flag, d, f"summary.json's scene_values are not a scene ({e})", "rerun that stage") from None
    except (ValueError, OSError, TypeError, AttributeError) as e:
        raise InputError(flag, d, f"unreadable summary.json ({type(e).__name__}: {e})", "rerun that stage") from None
    if kind not in kinds:
        model = summary.get("model") if isinstance(summary, dict) else None
        article = "an" if kinds[0][0] in "aeiou" else "a"
        why = f"a run of model {model!r} ({kind}), not {article} {' or '.join(kinds)} run"
        raise InputError(flag, d, why, remedy)
    if summary.get("status") in STOPPED:  # a guard's or an interrupt's partial histories, not a result
        why = f"a stopped run (status {summary['status']!r}): its histories end where it stopped"
        raise InputError(
            flag, d, why, "run it to its end (--restart resumes a run that wrote checkpoints; a driving or "
            "cut-recording global, not checkpointed, reruns into an empty folder)",
        )  # fmt: skip
    if whole_contact and summary.get("contact_duration") is None:
        end = summary.get("scene_values", {}).get("simulation", {}).get("end_time")
        why = f"its first contact has not ended by its end time ({end} s): its peak force may be still to come"
        fix = "give a run through the contact phase: workflows/global.py --driver"
        if kind == "submodel":  # ended early only by --end-time: its default end is the driver's contact phase
            fix = "rerun the submodel without --end-time (it ends at its driver's contact phase)"
        raise InputError(flag, d, why, fix)
    diff = scene_difference(scene, theirs, cut=False) if theirs is not None else None
    if diff is not None:
        key, ours, other = diff
        why = f"a run of another scene: {key} = {other!r} there, {ours!r} in this one"
        raise InputError(flag, d, why, other_scene)
    return summary


STOPPED = ("failed", "interrupted")  # summary.json status of a run a guard or an interrupt stopped


def _scene_values(summary: Any, kind: str) -> Mapping[str, Any] | None:
    """The scene values a run's bodies and impact are checked by: a submodel's driving global's (its own are the
    cut region's, rods L_s long: rods.study.stages.submodel writes both), read from the cut record it names for a
    summary written before that; None where neither is at hand (not checked)."""
    if not isinstance(summary, dict):
        raise TypeError("summary.json holds no object")
    if kind != "submodel":
        return summary.get("scene_values")
    if "driver_scene_values" in summary:
        return summary["driver_scene_values"]
    cut = summary.get("cut_file")
    if cut and Path(cut).is_file():
        from rods.fe.cut import recorded_until

        return recorded_until(cut)[1]
    return None


def read_run(
    folder: str | Path,
    label: str = "",
    flag: str = "--run",
    kinds: tuple[str, ...] = ("analytical", "global", "submodel"),
    scene: Scene | None = None,
    other_scene: str = "give --scene/--set of that run, or a run of this scene",
    whole_contact: bool = False,
) -> io.Run:
    """The run in ``folder`` (history.csv, summary.json: :func:`read_summary`, ``other_scene`` its remedy for a
    run of another scene, ``whole_contact`` as there); the label defaults to the summary's model. A history.csv
    without columns of two or more samples is refused as unreadable."""
    folder = Path(folder)
    summary = read_summary(folder, flag, kinds, scene, ("summary.json", "history.csv"), other_scene, whole_contact)
    try:
        with warnings.catch_warnings():  # numpy warns of an empty file before the check below names it
            warnings.simplefilter("ignore", UserWarning)
            history = io.read_history(folder / "history.csv")
        if not history or min(np.size(v) for v in history.values()) < 2:
            raise ValueError("no columns with two or more samples")
    except (ValueError, OSError, IndexError, TypeError) as e:
        raise InputError(flag, folder, f"unreadable history.csv ({e})", "rerun that stage") from None
    return io.Run(label or summary.get("model", folder.name), history, summary)


def parse_run(spec: str, flag: str = "--run") -> tuple[str, Path]:
    """``LABEL=FOLDER`` (or a bare folder) from the command line; the label may itself contain '='. No folder
    (``''``, ``LABEL=``) is refused naming ``flag``: Path("") is the working folder, which the refusal named '.'."""
    label, _, folder = spec.rpartition("=")
    if not folder:
        raise InputError(flag, spec, "names no folder", f"give {flag} DIR or {flag} LABEL=DIR")
    return label, Path(folder)


DRIVER_REMEDY = "give the folder of a workflows/global.py --driver run (its cut.h5 and summary.json)"
RERUN_DRIVER = "rerun workflows/global.py --driver into an empty folder"


def read_driver(folder: str | Path, flag: str = "--global") -> tuple[Path, dict[str, Any], Scene, float]:
    """(folder, summary, scene, the end of its cut record [s]) of the driving global in ``folder`` that a submodel
    reads, checked before anything runs (:class:`InputError` naming ``flag``): its cut.h5 and summary.json readable,
    the run finished (a stopped run's cut.h5 may be an earlier run's), and the cut record written by that same
    scene in every value, not the bodies and impact alone (a record left by an earlier run of other sizes drove a
    submodel "ok" under the newer run's label: a fuzz, 2026-12-06)."""
    from rods.fe.cut import recorded_until  # h5py, read only here

    gdir = input_dir(folder, ("cut.h5", "summary.json"), flag, DRIVER_REMEDY)
    try:
        summary = json.loads((gdir / "summary.json").read_text(encoding="utf-8"))
        driver = scene_from_summary(summary["scene_values"], (), str(gdir))
        summary["dt"]
    except (ValueError, KeyError, TypeError) as e:
        why = f"summary.json unreadable or not a global run's ({e})"
        raise InputError(flag, gdir, why, DRIVER_REMEDY) from None
    try:
        recorded, values = recorded_until(gdir / "cut.h5")  # [s], the recording global's scene
        recorder = scene_from_summary(values, (), str(gdir / "cut.h5"))
    except (OSError, KeyError, IndexError, ValueError, TypeError) as e:
        raise InputError(flag, gdir, f"cut.h5 unreadable or empty ({e})", DRIVER_REMEDY) from None
    if summary.get("status") not in ("ok", "warnings"):
        why = f"summary.json's status is {summary.get('status')!r}: the driving global did not finish"
        raise InputError(flag, gdir, why, RERUN_DRIVER)
    diffs = value_differences(driver.as_dict(), recorder.as_dict())
    if diffs:
        key, ours, theirs = scene_difference(driver, recorder) or diffs[0]  # bodies and impact named first
        why = f"cut.h5 was recorded by another scene than summary.json's ({key} = {theirs!r} there, {ours!r})"
        raise InputError(flag, gdir, why, RERUN_DRIVER)
    return gdir, summary, driver, recorded


def driver_end(
    scene: Scene,
    summary: Mapping[str, Any],
    recorded: float,
    end_time: float | None,
    folder: str | Path,
    flag: str = "--global",
) -> float:
    """A driven submodel's end [s]: ``end_time`` as asked (``--end-time``), else the library's rule
    (:func:`rods.plan.submodel_end`, the driver's contact phase); refused past the driver's cut record
    (``recorded`` [s]), never cut short silently, named by ``--end-time`` where the user gave it and by ``flag``
    (the driver's ``folder``) where the driver's own contact phase outlasts its record."""
    end = end_time if end_time is not None else submodel_end(scene, summary)
    if end <= recorded * (1 + 1e-9):
        return end
    why = f"the submodel's end {end:.6g} s is beyond the driving global's cut record (to {recorded:.6g} s)"
    if end_time is None:
        why += ", the driver's contact phase; its record stops short of it"
        fix = f"give --end-time {recorded:.6g} or less, or a driver recorded over its contact phase"
        fix += " (global.py --driver)"
        raise InputError(flag, folder, why, fix)
    raise InputError("--end-time", end, why, f"--end-time {recorded:.6g} or less, or a driver recorded longer")


def check_driven_by(folder: str | Path, summary: Mapping[str, Any], driver: str | Path) -> None:
    """A submodel level (``summary``, in ``folder``) was driven by the cut record of the global in ``driver`` (its
    summary's ``cut_record``, the record's own id: rods.io.cut_identity), else bad input naming ``--submodel`` or
    ``--global``: Table 3 would call another global its driver (a fuzz, 2026-12-06, had a contact-only global with
    no cut record labelled "drives the submodels"). A level written before the id was recorded is not checked."""
    recorded = summary.get("cut_record")
    if recorded is None:
        return
    cut = Path(driver) / "cut.h5"
    if not cut.is_file():
        why = "records no cut (no cut.h5): it drove no submodel"
        raise InputError("--global", driver, why, f"give the global that drove them ({summary.get('cut_file')})")
    if io.cut_identity(cut) != recorded:
        why = f"driven by another global's cut record ({summary.get('cut_file')}), not by --global {driver}'s"
        raise InputError("--submodel", folder, why, "give --global the run that drove it, or rerun it from this one")
