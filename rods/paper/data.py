"""The runs later stages read lived here until 2026-12-07; they are :mod:`rods.study.runs` now (a study's stage read
them from the paper package, a floor above it). Their names stay importable from here, the same objects, for callers'
scripts; so do the data files' writer and reader and the run record, which lived here before :mod:`rods.io` took them
(2026-11-28)."""

from rods import io
from rods.study.runs import *  # noqa: F403
from rods.study.runs import DRIVER_REMEDY, RERUN_DRIVER, STAGE_KINDS, STOPPED, stage_kind  # noqa: F401  (not in its __all__)

Run, dump, load, write_json = io.Run, io.dumps, io.read_data, io.write_data
