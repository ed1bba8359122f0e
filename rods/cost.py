"""What a run will cost, estimated from the scene before anything heavy is allocated (no mesh is built).

:func:`fe_cost` counts the cells and DOFs the mesher will make from the requested sizes (the mesh modules'
own counting rules: :func:`rods.fe.layout.axial_spacing`, :func:`rods.fe.mesh3d.section_counts`), the steps
from the element step h_min/c_d, the recorded samples (one per output time, at most one per step), the memory and
the wall time; :func:`analytical_cost` the samples and memory of the analytical model. :func:`check` refuses
(:class:`rods.preflight.InputError`, exit 2) a run whose memory exceeds the machine's available memory
(always) or whose steps, DOF-steps or history values exceed the budgets below (``--force`` overrides those only).

Rates and sizes measured on this machine (2 cores, DOLFINx 0.11, the paper scene; docs/models.md, "Cost
estimates"):

* memory of one rank: 190 MB base (Python, DOLFINx, PETSc, gmsh) + 0.9 kB per DOF axisymmetric, 2.6 kB per DOF
  in 3D (fitted 2026-12-07 to the summed peak RSS of 2-rank runs of 19k to 4.9M DOFs, :data:`BASE_MEMORY`) + 9 bytes
  per step
  (the per-step force and the output mask) + the histories (:data:`BYTES_PER_VALUE`: the recorder's and the CSV
  writer's copies, the text written a chunk at a time);
* time step: Δt ≈ fe.dt_fraction x h_min / c_d (measured Δt / (h_min/c_d) = 0.80 at fe.dt_fraction 0.8),
  h_min ≈ 0.85 x the smallest requested size (the cap shortens the tip cells), times :data:`CAP_STEP_FACTOR`
  for a strongly curved axisymmetric tip (down to 0.47: its rim cells are the most distorted; a submodel's uniform
  mesh has its own :data:`SUBMODEL_CAP_STEP_FACTOR`, down to 0.51); under the penalty law the
  contact-switching limit 1/ω_c (rods.fe.explicit) when it is shorter: ω_c of the stiffest penalty pair computed as
  the set-up does, from the tip faces' nodes, areas and lumped masses as the mesher lays them (:func:`_switching_step`:
  a graded rod's coarse nodes over a thin rod's fine face are the stiffest pairs);
* time: set-up (mesh, assembly, the contact's data) + steps x (a fixed cost per step + DOFs / (rate x ranks)), a
  global's and a submodel's steps counted centrally: where the estimated stable step sets the step (it errs low for
  the checks), the run's is :data:`STEP_COUNT_BIAS` (:data:`SUBMODEL_STEP_COUNT_BIAS`) longer; a given step and the
  switching limit are the run's own (:func:`_march_step`).
  The fixed cost (contact, recorder, Python; the ghosts' exchange and the reductions under MPI; a submodel's cut
  driving: :data:`STEP_OVERHEAD`, :data:`MPI_STEP_OVERHEAD`, :data:`CUT_STEP_OVERHEAD`) dominates small models.
  The rate is the machine's, and it moves: the same 396k-DOF loop ran 9.9e7 DOF-steps/s on 2026-11-22, 3.3e7 on
  2026-11-27 and 6.1e7 on 2026-12-06, here. So the entry points scale it by :func:`machine_speed`
  (:func:`calibrated`): a sparse product of the run's own per-rank working set (:attr:`Cost.probe_rows`: in cache
  where the run's mesh is, out of it where it is not) timed on every rank at once (:data:`PROBE_MIN_SECONDS` for a
  small run, about 0.3 s at most; again when older than :data:`PROBE_MAX_AGE`), against
  :data:`PROBE_RATE_REFERENCE`: the reference rates :data:`DOF_STEPS_PER_SECOND` are the loop's where the probe
  reads that (idle: 3.5e7 axisymmetric, long runs serial and on 2 ranks, 2026-12-07 on an AMD EPYC, and 2.8e7
  past the cache, :func:`reference_rate`; 6.8e6 in 3D where the 3D-shaped probe reads its 7.2e6 rows/s, serial,
  2026-12-08 on an Intel Xeon: the 3D pair is measured on that machine only). Set-up 1.2e-5 s per DOF axisymmetric
  and 6e-5 in 3D over the ranks (measured serial: 0.42 s at 48k DOFs, 1.9 s at 199k; 3D 4.2 s at 132k on 2026-11-27,
  6.4 s on 2026-11-28: :data:`SETUP_SECONDS_PER_DOF`; 2026-12-06: 0.17 s at 23k, 3.9 s at 398k);
* time on a GPU (fe.backend "cupy", or "auto" serial where CuPy sees a device): set-up on the host per DOF and
  steps x (:data:`GPU_STEP_OVERHEAD` + DOFs / :data:`GPU_DOF_STEPS_PER_SECOND`), measured on an H200;
* cells and DOFs: the mesh modules' counts (3D: 38240 estimated and built for a 4 mm / 1 mm paper scene), 2 DOFs
  per node axisymmetric (rods.fe.layout.mesh_counts; 2.3 per cell before, 10% high on the paper mesh), 3 per node of
  the O-grid in 3D (exact: tests/test_cost.py); a 3D cell's step is :func:`_third_dimension` of the quadrilateral's (the
  estimate was 0.72 of the paper mesh's step without it, 0.88 with it; 3D coarse 1.05).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from rods import hertz
from rods.preflight import InputError
from rods.scene import BAND_ELEMENTS, Scene, SceneError, cut_records
from rods.stability import damping_factor, march_step, one_step_remedy, switching_step

__all__ = [
    "FRAME_BUDGET",
    "STEP_BUDGET",
    "VALUE_BUDGET",
    "WORK_BUDGET",
    "Cost",
    "analytical_cost",
    "analytical_steps",
    "available_disk",
    "available_memory",
    "calibrated",
    "check",
    "check_disk",
    "fe_cost",
    "local_memory",
    "machine_speed",
    "peak_memory",
    "products_cost",
    "total",
]

STEP_BUDGET = 2e7  # steps of one FE run (the paper's runs: 2e4 to 5e4; about 5 h at the paper mesh) [-]
WORK_BUDGET = 1e12  # DOF-steps of one FE run (the paper's finest submodel: 4e9; about 3 h on one rank, 14 h in 3D) [-]
VALUE_BUDGET = 5e7  # history values (samples x columns) of one run: about 1.2 GB of CSV [-]
# estimated wall time of one run (a day): the analytical model has no steps or DOFs, and 1 s of simulated time
# (the schema's largest end_time) is ~20 000 wave passes, 116 s on the paper rods, 103 s on 50 mm rods (measured) [s]
TIME_BUDGET = 86400.0
# analytical model: integration time per one-way pass L/c of a wave in the rod with the most (each reflection that
# lands in a contact restarts the delay equation's integration), per history value, and a fixed part (the first
# call's lazy imports and set-up: 0.55 s cold, 0.08 s warm on the paper scene to 0.3 ms). Refitted 2026-12-07 to
# fourteen warm runs of rods.study.stages.analytical (paper rods 1.5-100 ms, 50 mm and 1 m rods to 15-100 ms, output
# intervals 20 ns-1 µs, 0.5-1 mm rods, 0.05-20 m/s: least squares 0.18 s + 1.9 ms a pass + 0.68 µs a value + 89 µs
# a step, relative): the constants below plan them 0.78-1.9x (median 1.1); the ones before (10 ms a pass, 1 µs a
# value, 250 µs a step, no fixed part) had planned 2.0-6.8x (50 mm rods to 50 ms: 52 s for 7.7 s). Longer runs err
# high still: 50 mm rods to 0.2 s and 1 s (1 µs and 1 ms output) planned 47.6 s and 232 s for 29.4 s and 103 s run
# beside other work (a pass costs less once the rods have parted)
ANALYTICAL_SECONDS = 0.3  # [s]
SECONDS_PER_PASS = 2.2e-3  # [s]
SECONDS_PER_VALUE = 7e-7  # [s]
# ... and per step the contact's stiffness against the rods' impedance forces on the explicit DOP853: the
# linearised rate of the approach at the impedance-bounded force P = s/(1/Z1 + 1/Z2) is
# λ = (3/2) K^(2/3) s^(1/3) (1/Z1 + 1/Z2)^(2/3);
# accepted steps per λ t (measured 0.423-0.427 on paper rods of 20 µm to 0.1 mm diameter, 2e-4 s: 5.3k-45k steps),
# the time (fitted with the pass and value terms above) and the dense output's memory per step (measured
# 2026-11-25: 0.89 kB)
STEPS_PER_STIFFNESS = 0.45  # [-]
SECONDS_PER_STEP = 1.5e-4  # [s]
BYTES_PER_SOLVER_STEP = 1e3  # [B]
# [B] one rank's interpreter, DOLFINx, PETSc, gmsh, and [B] per DOF: fitted 2026-12-07 to the ranks' summed peak RSS
# (`mpirun -n 2 /usr/bin/time -f %M python workflows/global.py ... --set simulation.end_time=2e-6`, the set-up's
# peak): axisymmetric 19.3k / 49k / 1.24M / 4.88M DOFs 0.371 / 0.406 / 1.53 / 4.74 GB; 3D 132k / 255k / 1.61M
# (quarter) / 1.93M DOFs 0.708 / 1.04 / 4.41 / 5.38 GB. Before, 170 MB, 850 B and 2200 B had planned the 1.93M-DOF
# 3D run at 4.59 GB: a default 3D plan of 20.9 GB passed a 23 GB machine's 21 GB free, where ~24 GB would be used
# (a helper's audit)
BASE_MEMORY = 190e6  # [B]
# [B] the analytical model's process: the interpreter, numpy, scipy, mpi4py (109 MB max RSS on the paper scene,
# 2026-12-07; 60 MB had been planned)
ANALYTICAL_BASE_MEMORY = 105e6
BYTES_PER_DOF = {"axisymmetric": 900.0, "3d": 2600.0}  # [B]
BYTES_PER_STEP = 9.0  # [B] per-step force (float64) and output mask (bool)
# [B] a history value in memory: the recorder's column (8), the CSV writer's table (8) and its share of the heap's
# growth (the CSV's text is formatted a chunk at a time, rods.io.write_history: as one string it took 61 B a value, an
# audit's 200k rows 441 MB against 268 MB planned; 261 MB since, 2026-12-07)
BYTES_PER_VALUE = 33.0
# the time loop's rate per rank where the probe (machine_speed) at the loop's working set reads PROBE_RATE_REFERENCE
# [1/s]: the loop's rate x PROBE_RATE_REFERENCE / the probe's, measured 2026-12-06 on this idle machine, serial (the
# paper rods, coarsened, 600 steps, best of 2; the probe at each mesh's probe_rows, best of 5): axisymmetric 3.0e7
# at 23k DOFs, 2.8e7 at 103k, 2.1e7 at 299k, 2.3e7 at 398k (the loop 8.6e7, 6.9e7, 5.4e7, 6.1e7; the probe 101 to
# 117 M rows/s); 3D 6.7e6 at 132k, 6.8e6 at 83k (the loop 1.78e7, 1.81e7) at the 18-entry probe, which 3D no longer
# uses: its 6.8e6 is paired with PROBE_RATE_REFERENCE["3d"] since 2026-12-08. 2026-11-27: 3.3e7 and 8.5e6 at the
# 1M-row probe alone. Axisymmetric 3.5e7 since 2026-12-07: those 600-step runs carry the loop's one-off costs (first
# touches, the last step's output) in their steps, and the runs users make are long; the plans of long runs (1.3
# contact phases of drawn scenes, 5k-49k steps) came out 1.31x (seed 61213, 2 ranks, 2026-12-07) and 1.46x, 1.52x
# (seed 61214, 2 ranks and serial, the same day) of the measured global stage, median, at 2.5e7: the loop's rate
# there, x 4.0e7 / the probe's, was 4.3e7 serial (10 drawn scenes and the paper scene's default run; 2.9e7 for the
# 600-step runs of the same day) and 5.6e7 per rank on 2 ranks (the ranks' concurrent probe reads low). 3.5e7 puts
# those long runs near 1.1x and a short run near 0.8x
DOF_STEPS_PER_SECOND = {"axisymmetric": 3.5e7, "3d": 6.8e6}  # [1/s]
# the same where a rank's loop is past the last-level cache [1/s]: the probe scales the rate by a product of the run's
# working set, but the loop's rate over the probe's falls further out of cache. The paper rods at 398k DOFs (0.25 x
# 0.125 mm, uncoarsened, 4672 steps; 2026-12-07, idle): 2.73e7 serially and on 2 ranks (199k DOFs a rank), planned
# 0.85x and 0.76x of the measured run at 3.5e7; 496k DOFs (a helper's, 5.8k steps) 0.85x and 0.81x of its loop.
# Between IN_CACHE and OUT_OF_CACHE (the working set per rank over CACHE_BYTES) the rate goes log-linearly from
# DOF_STEPS_PER_SECOND to this; 3D keeps its one rate (its plans read 1.0-1.9x, none low)
OUT_OF_CACHE_DOF_STEPS_PER_SECOND = {"axisymmetric": 2.8e7}  # [1/s]
CACHE_BYTES = 32 * 2**20  # [B] this machine's last-level cache, where the rates were measured (AMD EPYC, 32 MiB L3)
IN_CACHE, OUT_OF_CACHE = 0.65, 1.6  # a rank's working set (LOOP_BYTES_PER_DOF x DOFs) over CACHE_BYTES [-]
# the probe (machine_speed): a banded CSR matrix, each row the 18 entries of an axisymmetric stiffness row (9 nodes x
# 2 components; a 3D run's: 81, below), y = A x, of as many rows as a run's per-rank working set (PROBE_ROWS_PER_DOF),
# rounded to a grid (PROBE_STEPS_PER_DOUBLING) so that a study's stages share probes, within PROBE_MIN_ROWS (a few ms
# with its build) and PROBE_ROWS (~0.22 GB, past any core's share of a cache: larger sets run at its rate)
PROBE_ROWS = 1_000_000  # [-]
PROBE_MIN_ROWS = 1 << 15  # [-] (7.7 MB of 18-entry rows)
PROBE_MIN_ROWS_3D = 1 << 13  # [-] (8.1 MB of 81-entry rows: a small 3D run's mesh in cache, as the axisymmetric one)
# the probe's sizes: the nearest 2^(k/4) rows, within 9% of the run's working set. The next power of two put it up to
# 2 x over, past a cache the run's mesh sits in: on the Intel Xeon (2026-12-08) the 3D probe read 3.0 x its reference
# at 40k rows, 1.3 x at 65,536, the 2^16 a 38.8k-DOF run was probed at (its plan 2.9 x the run), and 1.5-2.6 x at the
# next 2^(k/4), 46,341 (the cache's edge: rounding up kept it there)
PROBE_STEPS_PER_DOUBLING = 4
# the probe's products are repeated for at least this long [s]: near the cache's edge a product reaches its steady
# rate only after tens of repeats. On the Intel Xeon (2026-12-08, 2 ranks probing at once, 8 trials each) the best of
# 4-6 products at 155,872 rows (34 MB a rank) read 1.03-1.49 x the reference, of 0.1 s 1.32-2.28 x; the run it was
# probed for (a drawn scene at 130k DOFs a rank) looped at ~2.2 x, and its plan had read 2.14 x its time
PROBE_MIN_SECONDS = 0.1
# a DOF's traffic per step over a probe row's (18 entries of 8 + 4 B, the row pointer, x and y: 236 B): its row's
# entries, the row pointer and 48 B of vectors (rods.fe.backend), 268 B axisymmetric (18 entries), 1024 B in 3D (81)
LOOP_BYTES_PER_DOF = {"axisymmetric": 268.0, "3d": 1024.0}  # [B]
# a 3D run is probed with rows of its own shape (a hexahedral node's 27 neighbours x 3 components, 81 entries: 992 B a
# row), at most PROBE_ROWS_3D (~0.26 GB): the axisymmetric probe's 18-entry rows did not carry over between machines,
# the 3D loop per entry ran 0.76 x the 18-entry probe's rate on the AMD EPYC (32 MiB L3) where the rates were measured
# and 2.0 x on an Intel Xeon (480 MiB L3, 2026-12-08): its plans read 2.6-3.1 x the run there
PROBE_ROW_BYTES = {"axisymmetric": 236.0, "3d": 992.0}  # [B]
PROBE_ROWS_3D = 1 << 18  # [-]
PROBE_ROWS_PER_DOF = {kind: b / PROBE_ROW_BYTES[kind] for kind, b in LOOP_BYTES_PER_DOF.items()}  # [-]
# [rows/s] the probe's rate that DOF_STEPS_PER_SECOND is paired with, per kind. 3D, 2026-12-08 on the Intel Xeon,
# serial, idle, at the probe then sized to the next power of two (262,144 rows for both, the cap: 525k DOFs need 542k):
# the 3D loop at 132k and 525k DOFs (paper-3d-coarse, a quarter of the paper rods at 0.5 x 1 mm; 305 and 448 steps)
# 8.1e6 and 8.9e6 DOF-steps/s where the probe read 9.0e6 and 9.1e6 rows/s; a quarter of paper-3d-coarse (38.8k DOFs,
# in that machine's cache) 1.7e7-2.0e7 where the probe at its own size read 2.2e7. Not measured on the AMD EPYC
PROBE_RATE_REFERENCE = {"axisymmetric": 4.0e7, "3d": 7.2e6}
ESTIMATE_METHOD = "working-set probe"  # how calibrated estimates a run (the probe benchmarks record it) [-]
# [s] a probe older than this is measured again: one process planning many runs (the benchmarks, a notebook) tracks a
# machine whose memory-bound rate moves within the hour (2026-11-29, here: 0.3x to 1x of the reference in one hour)
PROBE_MAX_AGE = 60.0
# the plan's step count over the run's, centrally, per kind of global [-]: the estimated stable step errs low by design
# (TIP_STEP_FRACTION; the checks and the step budget keep that count), and the per-step costs below are per step run,
# so the time took the bias whole. Axisymmetric globals at auto sizes, 2026-12-07: 20 drawn scenes (scene_probe
# --random 10, seeds 61212 and 61213) 1.10-1.34, median 1.175; the verification matrix's six 1.11-1.13. 3D globals,
# 2026-12-07: 1.195-1.199 at the coarse scene's sizes (seven runs, full and quarter, serial and 2 ranks), 0.995-1.09
# at finer quarter models (four): 1.1 between, each within 10%
STEP_COUNT_BIAS = {"axisymmetric": 1.15, "3d": 1.1}
# the same for a submodel (driven at its cuts, its own uniform mesh), axisymmetric, 2026-12-07: 1.10-1.16 over the
# levels of four drawn studies (submodel_probe --random 4 --seed 61214: 13 levels, coarse to ultra-fine) and 1.09 on
# the paper scene's coarse, mid and fine; 3D submodels unmeasured: none
SUBMODEL_STEP_COUNT_BIAS = {"axisymmetric": 1.13}
# the fixed cost of one step [s]: contact, recorder, Python (serial); with the ghosts' exchange and the reductions
# under MPI; and a submodel's cut driving on top. Measured 2026-12-06, idle, the paper rods at 638 to 5.8k DOFs, 1500
# steps, best of 3: 40 to 108 µs serial, 60 to 112 µs on 2 ranks; 2 ranks' loops from 13.6k to 398k DOFs lie 40 to
# 130 µs over DOFs / rate at the calibrated rate (a small mesh's exchange costs more than its share of the product);
# the main job's submodels (2 ranks) 34 µs (23.7k DOFs) to 80 µs (93k) over globals of their size
STEP_OVERHEAD = 3.5e-5  # [s]
# a recorded row's (rods.fe.recorder.Recorder._record: energies, probes, the patch; ~40 small array operations) [s]:
# the coarse paper mesh to 10 ms, 40k rows against 1.0k, 1.69 s more (42 µs a row; 2026-12-07, idle; an audit on a
# loaded machine 125 µs), which the plan had left out (4.28 s planned for the 1k-row run's 2.27 s and the 40k's 3.96 s)
RECORD_ROW_SECONDS = 4e-5
MPI_STEP_OVERHEAD = 9e-5  # [s]
CUT_STEP_OVERHEAD = 5e-5  # [s]
# mesh, assembly, contact data and the step's eigenvalue, on one rank [s] (3D, 2026-11-27, serial: 2.9e-5 at 132k
# DOFs, 3.1e-5 at 983k, since the eigenvalue is solved to the step's need, rods.fe.explicit.EIGEN_TOL; 7.7e-5 and
# 1.6e-4 before). 3D, 2026-11-28, serial, quarter models of twelve drawn scenes (scene_probe.random_probes, seed 11,
# sizes d/8 across, d/4 along) and paper-3d-coarse: 3.4e-5 to 9.1e-5, median 6e-5, 18k to 2.19M DOFs (176 s at
# 2.19M, where 3e-5 said 66 s); the eigenvalue was 45-70% of it (its Krylov-Schur took 101 to 321 products)
SETUP_SECONDS_PER_DOF = {"axisymmetric": 1.2e-5, "3d": 6e-5}
# the time loop on one GPU (fe.backend = "cupy"; serial): a step = GPU_STEP_OVERHEAD + DOFs / GPU_DOF_STEPS_PER_SECOND,
# the line through the 3D coarse and paper meshes' closed-contact steps on an H200 (results/gpu-throughput.md,
# 2026-11-27: 1.899 ms at 132k DOFs, 4.040 ms at 7.58M; the medium mesh's 3.067 ms at 983k lies 43% above it, and
# a run's open-contact steps should be cheaper: the estimate is rough); set-up on that machine's CPU, 3D: 157 s at
# 7.58M DOFs with the device's eigenvalue solve to 1e-8 (before EIGEN_TOL; not remeasured)
# fe.operator = "matrix-free" on the CPU (NumPy, serial; rods.fe.matrixfree): the element kernel's product, measured
# 2026-11-28 on this 2-core machine, idle: 3D coarse (132k DOFs) 65.8 ms, 2.0e6 DOF-steps/s, 6.1x the CSR product
# (benchmarks/gpu_throughput.py --backend numpy); the axisymmetric paper mesh (48k DOFs, 4 x 4 Gauss points) 61.6 ms,
# 7.8e5, 25x the CSR product. On a GPU not measured: there the assembled rate below stands in for it. Axisymmetric
# whole runs, serial, idle: 1.03e6 (42.9k DOFs, 2026-12-06), 1.41e6 and 1.46e6 (19.3k and 40.2k, 2026-12-07): 1.0e6
MATRIX_FREE_CPU_DOF_STEPS_PER_SECOND = {"axisymmetric": 1.0e6, "3d": 2.0e6}  # [1/s]
GPU_STEP_OVERHEAD = 1.86e-3  # [s] the host's kernel launches and the contact's copy per step
GPU_DOF_STEPS_PER_SECOND = 3.5e9  # [1/s]
GPU_SETUP_SECONDS_PER_DOF = {"axisymmetric": 1.2e-5, "3d": 2.1e-5}  # [s] (axisymmetric: the CPU's, not measured)
# the submodel's cut driver: its weights and traction operator, built one colour of band nodes at a time
# (rods.fe.cut.node_colouring) [s per cut node] (measured 2026-11-24, 2 ranks, mixed driving: paper scene
# 0.056 s for 54 axisymmetric cut nodes, 0.049 s for 207; 4.3 s for 5250 in the 3D coarse model's full section,
# 730 s for those 5250 before, one interpolation per band node)
CUT_SECONDS_PER_NODE = {"axisymmetric": 1e-3, "3d": 1e-3}
# one checkpoint (fe.checkpoint_interval > 0: the state written and renamed per rank, the histories' new rows
# appended to its log, rods.fe.checkpoint) [s]: measured 2026-11-24 on the paper scene's 52.9k-DOF global, serial:
# 2.7-2.8 ms each, every step or every third; 2026-12-07, the coarse paper mesh (2.95k DOFs) to 6 ms every 1 µs:
# 5917 checkpoints 15.5 s (2.6 ms each, three fsyncs; with the histories rewritten whole, 21.6 s, growing with
# the run's length squared)
CHECKPOINT_SECONDS = 2.5e-3  # [s]
LOG_RECORD_BYTES = 256.0  # [B] a checkpoint's record in its rank's log besides its entries (two .npy headers)
CHECKPOINT_SECONDS_PER_DOF = 3.5e-8  # [s]
FRAME_BUDGET = 1e4  # field frames of one run (the paper's contact picture: 51) [-]
# a frame's time (projections, writes), measured on the paper scene's contact picture run (52 frames of 52.9k DOFs,
# 2 ranks): 0.82 s more than the same run without fields [s per DOF]
FIELD_SECONDS_PER_DOF = 3e-7  # [s]
# and a frame's time whatever its size (a file per frame, the gather, the ADIOS2 step): 3001 frames of 2.95k DOFs took
# 12.6 s more than the same run without fields (4.2 ms a frame against the 0.9 ms above; fields.xdmf rewritten
# geometrically, 2026-12-07; the plan had said 3.9 s for the whole run) [s]
FIELD_SECONDS_PER_FRAME = 3.3e-3
# a frame's files (XDMF/HDF5 and VTX: 7 fields, 2 vectors and 5 scalars, float64 on the nodes), measured 2026-12-06
# on the paper mesh (48k DOFs, serial: 25.1 MB for 5 frames, 51.8 MB for 11, both formats): 93 B per DOF a frame
# and 60 B per DOF once (the mesh, written with the first frame); 2026-11-24's contact picture run read 80 a frame
# (221 MB for 52 frames of 52.9k DOFs). Axisymmetric: 2 DOFs per node; 3D nodes carry 3, so it errs high there.
# Each frame also writes about 16 kB whatever the mesh (HDF5 headers, the XDMF and VTX indices: 387 kB a frame at
# the coarse paper mesh's 4.0k DOFs, 97 B per DOF)
FIELD_BYTES_PER_DOF = 93.0  # [B]
FIELD_MESH_BYTES_PER_DOF = 60.0  # [B]
FIELD_FRAME_BYTES = 16e3  # [B]
CSV_BYTES_PER_VALUE = 25.0  # [B] a history value as CSV text (BYTES_PER_VALUE's file part)
# a checkpoint's file (u and v_{n+1/2} in float64 with the histories so far; two on disk while the newer replaces the
# older, rods.fe.checkpoint): measured 790 kB at the paper mesh's 48k DOFs [B per DOF]
CHECKPOINT_BYTES_PER_DOF = 16.5  # [B]
# the submodels' cut record (rods.fe.cut.CutRecorder: u and v in float64 of every entry of the band, 2 BAND_ELEMENTS
# + 1 node rows around each cut plane, at every recorded step), held by the ranks through the run and written to
# cut.h5 by rank 0 (measured: 224 MB for 316 band nodes x 2 components x 22,160 records, the file's size exactly)
CUT_BYTES_PER_ENTRY_RECORD = 16.0  # [B]
# ... and rank 0 writes it from one ordered copy of u, then of v, each rank's part received in turn: copies of the
# record held at once at the write's peak [-] (measured 2026-12-06 with tracemalloc, the paper scene's driver at
# 0.1 mm across, serial: 690 MB at the write's peak against 56 MB before the record was allocated, 1.9 x its 331 MB
# file; 3.8 x while the write gathered u and v whole, concatenated and reordered them). The record counted here errs
# high, by the band's fifth row and the step estimate's margin, so this bounds the peak
CUT_RECORD_COPIES = 2.0  # [-]
DT_PER_ELEMENT_STEP = 1.0  # Δt / (fe.dt_fraction h_min / c_d) [-] (measured 0.80 / 0.8)
H_MIN_FRACTION = 0.85  # smallest cell / smallest requested size [-]
# a requested fe.dt above this x the estimated limit is refused before the set-up (the estimate lies at 0.68 to 1.05
# of the exact limit on the meshes measured, _tip_step; between the estimate and this, the set-up's exact limit
# decides)
DT_REFUSE_FACTOR = 2.0  # [-]
# the penalty pair's estimated switching limit (_switching_step) read 4% above the set-up's exact one on the paper
# scene (1.136e-8 against 1.0885e-8 s: a fuzz, 2026-12-07; since 2026-12-08 computed as the set-up does, at most 0.3%
# above it axisymmetric, 3.4% in 3D), so a given step above this fraction of it is only "valid as far as the plan can
# tell" [-]
SWITCHING_CAVEAT = 0.9
# the tip cells' estimated step (_tip_step) is this fraction of their thickness over the wave speed: that ratio read
# 0.76 to 1.03 of the set-up's exact step (the highest, 1.032, a uniform 0.25 mm submodel on a 10 mm tip), so the
# estimate errs low, as the bulk's (a stable given fe.dt is never refused) [-]
TIP_STEP_FRACTION = 0.95
# a near-hemispherical tip's butterfly cap (above rods.fe.layout.BUTTERFLY_ANGLE, 70°): Δt / the bulk's estimate
# above, against its rim angle asin(d/2r) [deg, -]; a one-block tip face below it is estimated from its own cells
# (_tip_step). Axisymmetric global, measured on the paper rods at the auto mesh, 2026-11-27 (tip radii 6.77 to 6.35
# mm), times 0.99
CAP_STEP_FACTOR = (
    (70.2, 0.47),
    (77.7, 0.56),
    (90.0, 0.68),
)
# the same for a radially graded butterfly (rods.fe.layout.graded_butterfly), measured 2026-11-29 at 0.1, 0.5 and
# 2.197 m/s (6.75, 6.5 and 6.35 mm tips, graded forced; the three speeds within 2%), 1.1x to 1.7x the uniform's
GRADED_CAP_STEP_FACTOR = (  # [deg, -]
    (70.2, 0.768),
    (77.7, 0.750),
    (90.0, 0.729),
)
# an axisymmetric submodel's butterfly (uniform size h, rods.fe.submodel.submodel_scene), measured at h = 0.25 and
# 0.125 mm (the same to 2%; the lower kept) on the paper rods
SUBMODEL_CAP_STEP_FACTOR = (  # [deg, -]
    (70.2, 0.51),
    (74.2, 0.57),
    (82.9, 0.62),
    (90.0, 0.64),
)
# the same, graded (rods.fe.submodel.submodel_grading), measured 2026-12-06 with grading forced at h = 0.25 and 0.125
# mm (the same to 3%), the lower of the two x 0.99
GRADED_SUBMODEL_CAP_STEP_FACTOR = (  # [deg, -]
    (70.2, 0.51),
    (74.2, 0.765),
    (90.0, 0.637),
)


@dataclass(frozen=True)
class Cost:
    """What one run will cost, estimated before anything heavy is allocated (:func:`fe_cost`, :func:`analytical_cost`):
    its size (cells, DOFs, steps, samples), memory [B] and files [B] of all ranks, and wall time [s] at the reference
    rates or, once :func:`calibrated`, at this machine's; :meth:`describe` is the plan's line, :func:`check` refuses
    a run above a budget or the available memory, naming the fields below that would lower it."""

    what: str
    cells: float
    dofs: float
    steps: float
    samples: float
    values: float  # history values, samples x columns
    memory: float  # [B] all ranks together
    wall_time: float  # [s] set-up and time loop
    ranks: int = 1
    setup_time: float = 0.0  # [s] the part of wall_time before the time loop
    frames: float = 0.0  # field frames written [-]
    field_bytes: float = 0.0  # [B] their files
    # the setting that chose this stage, named first in a refusal's remedy (a study's submodel level: the user set
    # no size for it, submodel.levels did) [-]
    remedy: str = ""
    # [s] the part of wall_time that scales with the machine's rate at the run's working set (machine_speed: memory
    # bandwidth for a large run, the cache's for a small one)
    memory_bound_time: float = 0.0
    speed: float | None = None  # [-] the machine_speed it was scaled by (None: the reference rates)
    probe_rows: int = 0  # [-] the probe's size for this run's working set per rank (probe_rows; 0: none, no CPU loop)
    probe_kind: str = "axisymmetric"  # the probe's row shape (the run's kind: machine_speed)
    file_bytes: float = 0.0  # [B] what the run writes: histories, field frames, checkpoints, the cut record
    # what the plan cannot settle and the set-up will (a given step above the estimated stable limit), said after
    # the cost so that a dry run does not pass it as valid [-]
    caveat: str = ""
    # the same model for less, named in a refusal's remedy after ``remedy`` (a 3D model's symmetric twin) [-]
    cheaper: str = ""
    # what the memory goes to and what would lower it (:func:`_memory_parts`), said when the memory refuses a run [-]
    memory_parts: str = ""
    # what gives fewer steps here, named when the step budget refuses a run (empty: the analytical model's) [-]
    step_remedy: str = ""
    # what more ranks would take here, named when the time budget refuses a run: the array backends and the
    # matrix-free operator run serially (a fuzz was told "more ranks" for a run that cannot have them) [-]
    ranks_remedy: str = "more ranks"

    def describe(self) -> str:
        if not (self.dofs or self.steps):  # a study's products (products_cost): rank 0's seconds, no model
            return f"cost of {self.what}: wall time about {_duration(self.wall_time)}"
        fields = f", {self.frames:.3g} field frames ({self.field_bytes / 1e9:.3g} GB)" if self.frames else ""
        machine = "" if self.speed is None else f" (this machine's probed rate {self.speed:.2f} x the reference's)"
        caveat = f"; {self.caveat}" if self.caveat else ""
        if self.cheaper and self.wall_time > CHEAPER_NOTE:  # a long full 3D run named its twin only when refused
            caveat += f"; for less: {self.cheaper}"
        # the analytical model's: the solver steps a stiff contact forces (analytical_steps), not all its steps
        mesh = (
            f"{self.cells:.3g} cells, {self.dofs:.3g} DOFs, {self.steps:.3g} steps"
            if self.dofs
            else f"{math.ceil(self.steps):.3g} solver steps the stiff contact forces"
        )
        return (
            f"cost of {self.what}: {mesh}, "
            f"{self.samples:.3g} samples ({self.values:.3g} history values){fields}, files {_size(self.file_bytes)}, "
            f"memory {self.memory / 1e9:.3g} GB on {self.ranks} rank(s), wall time about {_duration(self.wall_time)}"
            f"{machine}"
            f"{caveat}"
        )

    def at_speed(self, speed: float) -> Cost:
        """This cost on a machine whose rate at this run's working set is ``speed`` x the reference's: the loop's
        rate-bound part divided by it, the set-up and the per-step fixed cost as they are."""
        bound = self.memory_bound_time / speed
        wall = self.wall_time - self.memory_bound_time + bound
        return replace(self, wall_time=wall, memory_bound_time=bound, speed=speed)

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


CHEAPER_NOTE = 600.0  # [s] a plan above this names the same model for less (its ``cheaper``: a 3D run's twin)
# a study's products from its stages' results, written on rank 0 after them [s]: Table 3 with Figs. 5c/6 (a submodel
# study's comparison), Fig. 4 (the wave response's figure), the contact picture (the fields'). Each the study's wall
# time less its stages' set-up and loops (2026-12-07, idle, serial, the paper scene, one study each: 1.75 s with one
# coarse level, 0.75 s and 2.32 s), so the stages' hand-overs are in them; "cost in all" had left them out, and a
# one-level study took 1.6-2.3 x its plan (a helper's audit)
PRODUCT_SECONDS = {"the comparison": 1.5, "the wave figure": 0.6, "the contact picture": 2.0}


def products_cost(names: Sequence[str], ranks: int) -> Cost:
    """A study's products ``names`` (keys of :data:`PRODUCT_SECONDS`) as one more line of its plan: their seconds,
    no mesh, no steps; the memory an interpreter with the figures' libraries takes."""
    what = " and ".join([", ".join(names[:-1]), names[-1]] if len(names) > 2 else names)
    return Cost(what, 0, 0, 0, 0, 0, ANALYTICAL_BASE_MEMORY, sum(PRODUCT_SECONDS[n] for n in names), ranks=ranks)


DEAREST_SHARE = 0.5  # a stage above this share of a run's estimated wall time is named in its total [-]


def total(costs: Sequence[Cost]) -> str | None:
    """The line under several stages' costs: their wall time in all and, where one stage is above
    :data:`DEAREST_SHARE` of it and a setting chose it (its ``remedy``: a study's submodel level), that stage's share
    and how to leave it out: a small contact patch puts a study's auto levels down to ultra-fine, each level about
    8 x the one above it (2D: 4 x the cells, 2 x the steps), so that one level can be most of the study. None for a
    single stage."""
    if len(costs) < 2:
        return None
    wall = sum(c.wall_time for c in costs)  # [s]
    line = f"cost in all: wall time about {_duration(wall)} on {max(c.ranks for c in costs)} rank(s)"
    dearest = max(costs, key=lambda c: c.wall_time)
    share = dearest.wall_time / wall if wall > 0 else 0.0
    if share > DEAREST_SHARE and dearest.remedy:
        line += f", {share:.0%} of it {dearest.what} (to leave it out: {dearest.remedy})"
    return line


def _size(b: float) -> str:
    """``b`` [B] in kB, MB or GB, three digits."""
    for unit, scale in (("GB", 1e9), ("MB", 1e6)):
        if b >= scale:
            return f"{b / scale:.3g} {unit}"
    return f"{b / 1e3:.3g} kB"


def _duration(s: float) -> str:
    return f"{s:.3g} s" if s < 120 else (f"{s / 60:.3g} min" if s < 7200 else f"{s / 3600:.3g} h")


def _mesh_axisymmetric(scene: Scene, h_r: float, h: float, g: float) -> tuple[float, float]:
    """(cells, DOFs) of ``scene``'s axisymmetric mesh (a global's, or a submodel's region, :func:`_submodel_region`)
    at sizes ``h_r``, ``h`` [m] and tip grading ``g``: the mesh module's own counts of both rods, as the mesher reads
    the scene (fe.radial_grading, its bar size and core along: rods.scene.Scene.bar_axial_size, axial_core;
    fe.radial_coarsening: rods.fe.layout.coarsening_start), 2 DOFs
    per node."""
    from rods.fe.layout import coarsening_start, mesh_counts

    radial, core, h_bar, along = scene["fe.radial_grading"], scene.graded_core, scene.bar_axial_size, scene.axial_core
    start = coarsening_start(scene)
    counts = [mesh_counts(rod, h_r, h, g, core, radial, h_bar, along, start) for rod in scene.rods]
    return float(sum(c for c, _ in counts)), 2.0 * sum(n for _, n in counts)


def _submodel_region(scene: Scene, size: float, axial_size: float | None) -> Scene:
    """The submodel's own scene at ``size`` across and ``axial_size`` along [m] (rods.fe.submodel.submodel_scene:
    rods cut to fe.submodel_length, its grading): what its mesh and step are counted on, as the mesher builds them."""
    from rods.fe.submodel import submodel_scene

    return submodel_scene(scene, size, axial_size)


def _mesh_3d(scene: Scene, h_r: float, h: float, g: float, lengths: tuple[float, float]) -> tuple[float, float]:
    """(cells, DOFs) of the 3D mesh: each rod's O-grid section (rods.fe.mesh3d.section_size) extruded in its
    axial layers, 3 DOFs per node."""
    from rods.fe.layout import axial_spacing
    from rods.fe.mesh3d import section_size

    cells = dofs = 0.0
    for rod, L in zip(scene.rods, lengths, strict=True):
        sec_cells, sec_nodes = section_size(rod.diameter / 2, h_r, scene["fe.symmetry"])
        sp = axial_spacing(_with_length(rod, L), h, g)
        layers = sp.n
        cells, dofs = cells + sec_cells * layers, dofs + 3 * sec_nodes * (layers + 1)
    return cells, dofs


def _cut_nodes(scene: Scene, h: float) -> int:
    """Nodes on the submodel's two cut planes at size ``h`` [m]: a row across each rod's radius (axisymmetric) or
    each O-grid section (3D)."""
    if scene["fe.kind"] == "3d":
        from rods.fe.mesh3d import section_size

        return sum(section_size(r.diameter / 2, h, scene["fe.symmetry"])[1] for r in scene.rods)
    return sum(math.ceil(r.diameter / 2 / h - 1e-9) + 1 for r in scene.rods)


def _with_length(rod: Any, L: float) -> Any:
    from dataclasses import replace

    return rod if L == rod.length else replace(rod, length=L)


def fe_cost(
    scene: Scene,
    ranks: int = 1,
    *,
    what: str = "global FE model",
    size: float | None = None,
    axial_size: float | None = None,
    end_time: float | None = None,
    dt: float | str = "auto",
    remedy: str = "",
    record_until: float | None = None,
    record_every: int = 1,
    record_flags: bool = False,
    cut_record_bytes: float | None = None,
) -> Cost:
    """The cost of the FE model of ``scene`` on ``ranks`` ranks; a submodel with ``size`` [m] across and
    ``axial_size`` along (uniform, or graded outside the patch as rods.fe.submodel.submodel_grading), rods cut to
    fe.submodel_length, to ``end_time`` [s] at its own step ``dt`` [s] ("auto": the stable one; the global's is
    fe.dt). ``remedy``: :attr:`Cost.remedy`. ``record_until`` [s]: a global recording the submodels' cut band to
    that time every ``record_every`` steps (its memory and its file, :func:`_cut_record_bytes`; ``record_flags``: the
    user set them, workflows/global.py --record-cut's --record-every and --record-until, and a remedy may name
    them: a driver and a study record their contact phase every step). A submodel reads its
    driver's cut record whole on every rank (rods.fe.cut.CutDriver): ``cut_record_bytes`` [B], that file's size where
    it is at hand, else the record the scene's driving global writes to ``end_time`` (:func:`_driver_record_bytes`;
    a fuzz measured 704 MB against a 191 MB plan that left it out)."""
    kind = scene["fe.kind"]
    (h_r, h, g), region, cells, dofs = _fe_mesh(scene, size, axial_size, what, remedy)
    end = scene.end_time if end_time is None else end_time
    # the step given, by the key that gave it: a global's fe.dt, a submodel's own --dt (not its global's fe.dt)
    given = ("fe.dt" if scene["fe.dt"] != "auto" else None) if size is None else ("--dt" if dt != "auto" else None)
    dt, caveat, bias = _march_step(scene, h_r, h, g, size, dt, region)
    # a global's end: the scene's, or a study's contact phase in it (below a step only if it is); a submodel's: its
    # own (workflows/submodel.py --end-time: 1 ns against a 9 ns step planned one step)
    _check_one_step(end, dt, scene.end_time if size is None else end, given)
    steps = math.ceil(end / dt)
    # the recorder keeps the step nearest each output time, once (rods.fe.recorder.output_steps): at most one row per
    # step, step 0 included (the paper scene every 0.1 ns was refused for 1.5e7 samples; it records 4.8e4)
    samples = min(math.floor(end / min(scene.output_interval, end)) + 1, steps + 1)
    values = samples * (12 + 2 * len(scene.stations) + (4 if kind == "3d" else 0))
    parts = _memory_of(scene, ranks, dofs, steps, values, size)
    if size is not None:  # [B] on every rank
        parts.update(_driver_record_memory(scene, ranks, end, cut_record_bytes))
    setup, loop, bound = _fe_time(scene, ranks, steps / bias, dofs, size is not None, samples)
    if size is not None:  # the submodel's cut driver: the recorded band located at each cut node
        setup += _cut_nodes(scene, h_r) * CUT_SECONDS_PER_NODE[kind]
    frames, field_bytes, files, writing = _fe_files(scene, ranks, dt, steps, dofs, values, size is not None)
    wall = setup + loop + writing
    if record_until is not None:
        cut = _cut_record_bytes(scene, dt, steps, record_until, record_every)
        files += cut
        flags = ", a larger --record-every or an earlier --record-until" if record_flags else ""
        parts["the cut record"] = (CUT_RECORD_COPIES * cut, f"coarser sizes (fewer cut nodes, a larger step){flags}")
    memory = sum(b for b, _ in parts.values())
    return Cost(
        what, cells, dofs, steps, samples, values, memory, wall, ranks, setup, frames, field_bytes, remedy, bound,
        file_bytes=files, probe_rows=probe_rows(kind, dofs, ranks) if bound > 0 else 0, probe_kind=kind, caveat=caveat,
        cheaper=_symmetry_remedy(scene), memory_parts=_memory_parts(parts), step_remedy=_step_remedy(scene, size),
        ranks_remedy=_ranks_remedy(scene),
    )  # fmt: skip


def _memory_of(
    scene: Scene, ranks: int, dofs: float, steps: int, values: float, size: float | None
) -> dict[str, tuple[float, str]]:
    """What an FE run's memory goes to [B], each with what would lower it (:func:`_memory_parts`): the ranks'
    interpreters, the mesh and its operators, the per-step force and output mask, the histories."""
    return {
        "the ranks' interpreters and libraries": (ranks * BASE_MEMORY, "fewer ranks"),
        "the mesh": (BYTES_PER_DOF[scene["fe.kind"]] * dofs, "coarser sizes"),
        "the per-step force": (
            ranks * BYTES_PER_STEP * steps,
            f"fewer steps ({_step_remedy(scene, size)}, a shorter end_time)",
        ),
        "the histories": (BYTES_PER_VALUE * values, "a larger simulation.output_interval, fewer stations"),
    }


def _checkpoints(scene: Scene, ranks: int, dt: float, steps: int, dofs: float, values: float) -> tuple[float, float]:
    """(seconds [s], bytes on disk [B]) of a global's periodic checkpoints at fe.checkpoint_interval > 0 (the model's
    stride, rods.fe.checkpoint.stride): two states on disk while the newer replaces the older, and each rank's log of
    the histories and the per-step force (rods.fe.checkpoint.Appended). Without the interval a run
    writes one only when stopped (Ctrl-C, SIGTERM), and a finished run removes it: (0, 0)."""
    if scene["fe.checkpoint_interval"] <= 0:
        return 0.0, 0.0
    from rods.fe.checkpoint import stride

    every = stride(scene["fe.checkpoint_interval"], dt)
    seconds = steps / every * (CHECKPOINT_SECONDS + CHECKPOINT_SECONDS_PER_DOF * dofs / ranks)
    log = (8.0 * (values + steps) + LOG_RECORD_BYTES * steps / every) * ranks  # [B] rows, force, a record a save
    return seconds, 2 * CHECKPOINT_BYTES_PER_DOF * dofs + log


def _ranks_remedy(scene: Scene) -> str:
    """What running on more ranks takes: the PETSc path (the MPI path); the NumPy and CuPy backends and the
    matrix-free operator are serial (rods.fe.backend)."""
    serial = [f"fe.{k}='{v}'" for k, v in (("operator", "assembled"), ("backend", "petsc"))
              if (k == "operator" and scene["fe.operator"] == "matrix-free")
              or (k == "backend" and scene["fe.backend"] in ("numpy", "cupy"))]  # fmt: skip
    return f"{' and '.join(serial)} on more ranks" if serial else "more ranks"


def _step_remedy(scene: Scene, size: float | None) -> str:
    """What gives a run fewer steps: coarser sizes (a larger stable step), the step itself where it was given below
    its limit or at a fraction of it; a step above the stable limit is refused, so 'a larger fe.dt' is no remedy
    of an 'auto' step at fe.dt_fraction 1."""
    if size is not None:
        return "a larger submodel element size (a larger stable step)"
    if scene["fe.dt"] != "auto":
        return "a larger fe.dt (up to the stable limit), coarser sizes"
    if scene["fe.dt_fraction"] < 1.0:
        return "coarser sizes (a larger stable step), a larger fe.dt_fraction (at most 1)"
    return "coarser sizes (a larger stable step)"


MEMORY_SHARE = 0.2  # a part of a run's memory above this share is named, with its remedy, in a refusal [-]


def _memory_parts(parts: Mapping[str, tuple[float, str]]) -> str:
    """The parts of a run's memory above :data:`MEMORY_SHARE` of it, largest first, each with what lowers it: a
    refusal names the remedies that work (a fuzz: a driving global refused for 31.2 GB, 30.9 GB its cut record, was
    told a larger output interval, which changed nothing)."""
    total = sum(b for b, _ in parts.values())
    big = sorted(((b, name, fix) for name, (b, fix) in parts.items() if b > MEMORY_SHARE * total), reverse=True)
    return "; ".join(f"{name} {b / 1e9:.3g} GB: {fix}" for b, name, fix in big)


STEP_ESTIMATE_MARGIN = 1.1  # the estimated stable step over the exact one, at most (0.68-1.05 measured) [-]


def _driver_record_memory(scene: Scene, ranks: int, end: float, known: float | None) -> dict[str, tuple[float, str]]:
    """A submodel's memory part [B] for its driver's cut record, read whole by every rank: the file's size where it is
    ``known``, else the record the scene's driving global writes to ``end`` [s] (:func:`_driver_record_bytes`)."""
    record = _driver_record_bytes(scene, end) if known is None else known
    return {"the driver's cut record, read by every rank": (ranks * record, "fewer ranks, or a driver recorded at "
                                                              "coarser sizes")}  # fmt: skip


def _fe_files(
    scene: Scene, ranks: int, dt: float, steps: int, dofs: int, values: int, submodel: bool
) -> tuple[int, float, float, float]:
    """An FE run's files: the field frames, their bytes [B], every file's bytes [B] (fields, histories and a global's
    periodic checkpoints) and the seconds [s] writing the fields and checkpoints takes (a submodel writes neither)."""
    frames = 0 if submodel else _field_frames(scene, dt, steps)
    field_bytes = frames * FIELD_FRAME_BYTES + (frames * FIELD_BYTES_PER_DOF + FIELD_MESH_BYTES_PER_DOF) * dofs
    field_bytes = field_bytes if frames else 0.0
    seconds = frames * (FIELD_SECONDS_PER_FRAME + dofs * FIELD_SECONDS_PER_DOF)
    files = field_bytes + CSV_BYTES_PER_VALUE * values
    if not submodel:
        written_seconds, written = _checkpoints(scene, ranks, dt, steps, dofs, values)
        seconds, files = seconds + written_seconds, files + written
    return frames, field_bytes, files, seconds


def _check_one_step(end: float, dt: float, shown: float, given: str | None) -> None:
    """Refuse (exit 2) a run to ``end`` [s] shorter than one step ``dt`` [s], as the set-up would (rods.fe.timestep)
    but before it: a step ``given`` by a key (fe.dt, a submodel's --dt) exactly, an estimated step (None) only where
    it is below it by :data:`STEP_ESTIMATE_MARGIN` (a dry run passed a 1 ps end time that the set-up then refused).
    ``shown`` [s]: the end time the user gave (the scene's, or a submodel's own)."""
    if end * (1.0 if given else STEP_ESTIMATE_MARGIN) < dt:
        raise SceneError(
            "simulation.end_time", shown,
            f"must be >= one time step, {f'{given} = ' if given else 'about '}{dt:.3g} s on this mesh",
            one_step_remedy(given or False),
        )  # fmt: skip


def _symmetry_remedy(scene: Scene) -> str:
    """A 3D run's cheaper symmetric twin, where the impact allows one (rods.scene: a quarter model needs no offset
    and no tilt, a half one is cut along the plane of both): part of a refusal's remedy ("" where none). A fuzz,
    2026-12-06: a full 3D model refused for memory named coarser sizes only, where its quarter ran in half the time
    on a quarter of the DOFs."""
    if scene["fe.kind"] != "3d":
        return ""
    if scene["fe.symmetry"] != "quarter" and not scene.misaligned:
        return "fe.symmetry = 'quarter' (a centric impact: a quarter of the DOFs)"
    if scene["fe.symmetry"] == "full":
        return "fe.symmetry = 'half' (the impact's offset and tilt lie in one plane: half the DOFs)"
    return ""


def _fe_mesh(
    scene: Scene, size: float | None, axial_size: float | None, what: str = "the submodel", remedy: str = ""
) -> tuple[tuple[float, float, float], Scene | None, float, float]:
    """The sizes (across, along [m], tip grading), the region (an axisymmetric submodel's own scene, on which its
    mesh and step are counted; else ``scene`` or, in 3D, None), cells and DOFs of :func:`fe_cost`'s mesh (``what``,
    ``remedy``: a submodel's, as :func:`fe_cost`'s, for :func:`_check_across`)."""
    if size is None:
        h_r, h, g = scene["fe.radial_size"], scene["fe.axial_size"], scene.tip_grading
        lengths = (scene.rod1.length, scene.rod2.length)
    else:
        h_r, h, g = size, axial_size or size, 1.0
        lengths = (scene["fe.submodel_length"],) * 2
    if scene["fe.kind"] == "3d":
        return (h_r, h, g), None, *_mesh_3d(scene, h_r, h, g, lengths)
    region = scene if size is None else _submodel_region(scene, size, axial_size)
    _check_across(region, h_r, size, what, remedy)
    return (h_r, h, g), region, *_mesh_axisymmetric(region, h_r, h, g)


# [-] most elements across a rod's radius the plan counts: its layout (rods.fe.layout: the 3:1 merges' groups, the tip
# row) walks every element across, in Python and in arrays, before the memory is checked. A fuzz: 1 m rods at
# fe.radial_size = 1e-8 (5e7 across, every value in the schema's range) took 134 s and over 5 GB in the dry run, then
# exit 1 (MemoryError). At 1e6 across the counting takes about a second and the mesh (its tip zone alone at least
# 1e6 x its rows) is beyond any one machine's memory.
MAX_ACROSS = 1_000_000


def _check_across(region: Scene, h_r: float, size: float | None, what: str = "the submodel", remedy: str = "") -> None:
    """Refuse (exit 2, before any per-element counting) an axisymmetric mesh of more than :data:`MAX_ACROSS`
    elements across a rod's radius: its columns' counts (rods.fe.layout.scene_columns) are a few numbers each. A
    submodel's refusal names the stage ``what`` and its caller's ``remedy`` (a study's level is no --size of its)."""
    from rods.fe.layout import scene_columns

    across = max(sum(c.n for c in columns) for columns in scene_columns(region))
    if across > MAX_ACROSS:
        if size is None:
            what, remedy = "fe.radial_size", "a larger fe.radial_size"
        raise InputError(
            what, h_r, f"{across:.3g} elements across a rod's radius, above {MAX_ACROSS:.0e} (a mesh no machine's "
            "memory holds)", f"{remedy or 'a coarser level'}, or fe.radial_grading = 'graded' (fine only around the "
            "patch)",
        )  # fmt: skip


def _fe_time(
    scene: Scene, ranks: int, steps: float, dofs: float, cut: bool, rows: int = 0
) -> tuple[float, float, float]:
    """The set-up, the time loop and the loop's rate-bound part [s] of ``steps`` steps (the run's, centrally:
    :func:`_march_step`'s bias) on ``dofs`` DOFs (``cut``: a submodel's, driven at its cuts) recording ``rows`` rows:
    on a device its own rate (not the host's probe, so no bound), else the CPU's per rank: assembled at the reference
    probe's rate (the bound part), matrix-free at its own (no bound), and the fixed costs per step and per row."""
    kind = scene["fe.kind"]
    recording = rows * RECORD_ROW_SECONDS
    if _on_gpu(scene, ranks):
        setup = dofs * GPU_SETUP_SECONDS_PER_DOF[kind]
        return setup, steps * (GPU_STEP_OVERHEAD + dofs / GPU_DOF_STEPS_PER_SECOND) + recording, 0.0
    fixed = (MPI_STEP_OVERHEAD if ranks > 1 else STEP_OVERHEAD) + (CUT_STEP_OVERHEAD if cut else 0.0)
    setup = dofs * SETUP_SECONDS_PER_DOF[kind] / ranks
    if scene["fe.operator"] == "matrix-free":  # gathers and small products, not the sparse product the probe times:
        # at its measured rate, unscaled (42.9k axisymmetric DOFs, 2026-12-06: 1.03e6 DOF-steps/s, where 7.8e5 x
        # the probe's 2.91 planned 66.6 s for a 151 s run)
        return setup, steps * (fixed + dofs / (MATRIX_FREE_CPU_DOF_STEPS_PER_SECOND[kind] * ranks)) + recording, 0.0
    bound = steps * dofs / (reference_rate(kind, dofs / ranks) * ranks)
    return setup, steps * fixed + recording + bound, bound


def reference_rate(kind: str, dofs_per_rank: float) -> float:
    """The loop's rate per rank [DOF-steps/s] where the probe reads PROBE_RATE_REFERENCE, at ``dofs_per_rank``: the
    in-cache rate up to IN_CACHE x CACHE_BYTES of working set, the out-of-cache one from OUT_OF_CACHE x, log-linear in
    the working set between (:data:`OUT_OF_CACHE_DOF_STEPS_PER_SECOND`)."""
    rate, far = DOF_STEPS_PER_SECOND[kind], OUT_OF_CACHE_DOF_STEPS_PER_SECOND.get(kind)
    share = LOOP_BYTES_PER_DOF[kind] * dofs_per_rank / CACHE_BYTES
    if far is None or share <= IN_CACHE:
        return rate
    w = min(1.0, math.log(share / IN_CACHE) / math.log(OUT_OF_CACHE / IN_CACHE))
    return rate ** (1.0 - w) * far**w


def probe_rows(kind: str, dofs: float, ranks: int) -> int:
    """The probe's rows for a loop over ``dofs`` DOFs on ``ranks`` ranks of ``kind`` (:data:`PROBE_ROWS_PER_DOF`):
    the nearest 2^(k/:data:`PROBE_STEPS_PER_DOUBLING`), within :data:`PROBE_MIN_ROWS` and :data:`PROBE_ROWS`
    (:data:`PROBE_MIN_ROWS_3D` and :data:`PROBE_ROWS_3D` in 3D)."""
    least, most = (PROBE_MIN_ROWS_3D, PROBE_ROWS_3D) if kind == "3d" else (PROBE_MIN_ROWS, PROBE_ROWS)
    rows = max(PROBE_ROWS_PER_DOF[kind] * dofs / ranks, least)
    rounded = 2.0 ** (round(PROBE_STEPS_PER_DOUBLING * math.log2(rows)) / PROBE_STEPS_PER_DOUBLING)
    return min(max(round(rounded), least), most)


def _driver_record_bytes(scene: Scene, until: float) -> float:
    """The cut record [B] the driving global of ``scene`` writes to ``until`` [s] every step, at its own mesh and step
    (:func:`_cut_record_bytes`): what a submodel planned before its driver ran will read."""
    (h_r, h, g), region, _, _ = _fe_mesh(scene, None, None)
    dt = _march_step(scene, h_r, h, g, None, scene["fe.dt"], region)[0]
    return _cut_record_bytes(scene, dt, math.ceil(until / dt), until, 1)


def _cut_record_bytes(scene: Scene, dt: float, steps: int, until: float, every: int) -> float:
    """The cut record's size [B] (:data:`CUT_BYTES_PER_ENTRY_RECORD`): the band's entries, at most 2 BAND_ELEMENTS + 1
    node rows across each rod at its cut plane (2 BAND_ELEMENTS where the plane falls inside an element, as on five
    drivers measured: 316, 272, 252, 464 and 132 nodes, 4/5 of this count) of the global's columns
    (rods.fe.layout.scene_columns; 3D: the O-grid section's nodes), times the records to ``until`` [s] every ``every``
    steps (rods.scene.cut_records)."""
    rows = 2 * BAND_ELEMENTS + 1
    if scene["fe.kind"] == "3d":  # the O-grid sections at the global's size, as a submodel's cut planes
        entries = 3 * rows * _cut_nodes(scene, scene["fe.radial_size"])
    else:
        from rods.fe.layout import scene_columns

        entries = 2 * rows * sum(sum(c.n for c in columns) + 1 for columns in scene_columns(scene))
    records = cut_records(scene, dt, steps, until, every)
    return CUT_BYTES_PER_ENTRY_RECORD * entries * records


def _field_frames(scene: Scene, dt: float, steps: int) -> int:
    """Field frames the global run writes at fe.field_interval with step ``dt`` [s] over ``steps``; a SceneError
    where the interval is below half a step (frames between two steps interpolate the same two states)."""
    if not scene.field_interval > 0:
        return 0
    from rods.fe.fields import frame_count

    if scene.field_interval < 0.5 * dt:
        raise SceneError(
            "fe.field_interval", scene.field_interval, f"below half the time step (about {dt:.3g} s here): "
            "frames between two steps are interpolations of the same two states", "an interval of a step or more",
        )  # fmt: skip
    return frame_count(scene.field_interval, dt, steps)


def _march_step(
    scene: Scene, h_r: float, h: float, g: float, size: float | None, dt: float | str, region: Scene | None
) -> tuple[float, str, float]:
    """The step [s] the model will march at, as rods.fe.timestep: fe.dt_fraction of the estimated stable step, at
    most the switching limit, or the given one (the global's fe.dt, a submodel's ``dt``), refused (exit 2) when it
    is far above the estimated limit (``region``: :func:`_step_limits`); a caveat where a given step is above
    the estimate but not that far: the set-up's exact limit decides (empty otherwise); and the run's step over it,
    centrally [-]: the estimated stable step errs low by design (:data:`STEP_COUNT_BIAS`,
    :data:`SUBMODEL_STEP_COUNT_BIAS`), so where it sets the step the run's is that much longer, where the switching
    limit (estimated as the set-up computes it: 0.966 to 1.003 x on 39 scenes, 2026-12-08) or a given step sets it, 1 (a
    bias on those read the time of a penalty run or of a given fe.dt 1.15 x low)."""
    stable, switching = _step_limits(scene, h_r, h, g, size, region)
    limit = min(stable, switching)
    key, given = ("fe.dt", scene["fe.dt"]) if size is None else ("--dt", dt)
    if given == "auto":
        fraction = scene["fe.dt_fraction"]
        bias = (STEP_COUNT_BIAS if size is None else SUBMODEL_STEP_COUNT_BIAS).get(scene["fe.kind"], 1.0)
        step = march_step(fraction, stable, switching)
        return step, "", march_step(fraction, bias * stable, switching) / step
    if given > DT_REFUSE_FACTOR * limit:
        raise (SceneError if size is None else InputError)(  # a scene key, or the submodel's --dt
            key,
            given,
            f"must be <= the stable limit, about {limit:.3g} s on this mesh (estimated from its smallest element; "
            "the set-up computes it exactly)",
            "fe.dt = 'auto' takes fe.dt_fraction of it" if size is None else "--dt auto takes fe.dt_fraction of it",
        )
    caveat = ""
    if given > limit:
        caveat = (
            f"{key} = {given:.3g} s is above the estimated stable limit {limit:.3g} s: the set-up computes the exact "
            "limit (the estimate errs low) and refuses a step above it"
        )
    elif switching <= stable and given > SWITCHING_CAVEAT * switching:  # this estimate can err high
        caveat = (
            f"{key} = {given:.3g} s is within {1 - SWITCHING_CAVEAT:.0%} of the penalty's estimated switching limit "
            f"{switching:.3g} s, which can read a few % above the exact one: the set-up computes it and refuses a "
            "step above it"
        )
    return given, caveat, 1.0


def _on_gpu(scene: Scene, ranks: int) -> bool:
    """The time loop runs on a GPU: fe.backend "cupy", or "auto" serial where CuPy sees a device."""
    from rods.fe.backend import resolve

    return resolve(scene["fe.backend"], ranks) == "cupy"


def _step_limits(
    scene: Scene, h_r: float, h: float, g: float, size: float | None, region: Scene | None = None
) -> tuple[float, float]:
    """(stable step, contact switching limit) [s] estimated. The first is the smaller of the bulk's, from the smallest
    element asked for (:data:`DT_PER_ELEMENT_STEP`, :data:`H_MIN_FRACTION`; a hexahedron's in 3D; a butterfly cap's
    by its table, :func:`_butterfly_step_factor`), and, on the axisymmetric mesh, the tip faces' own cells
    (:func:`_tip_step`); the second under the penalty law only (inf for the kinematic contact). An axisymmetric
    submodel is read off its ``region`` (:func:`_submodel_region`; built here where not given), a global off
    ``scene`` (whose own sizes ``h_r``, ``h``, ``g`` are). A 3D mesh's bulk takes the lower third-dimension factor of
    its tip's cells (h_r, g h) and its body's (h_r, h): a graded tip's cubes had hidden the body's long cells, where
    the highest mode sits, along the O-grid's core corners (x = y = s, rods.fe.mesh3d.CORE; a power iteration on the
    paper rods' 0.3 x 1 mm quarter model), and the estimate read 1.17x (that mesh) to 1.21x (the paper's auto 3D
    mesh) the exact step (2026-12-06)."""
    c_d = max(r.material.dilatational_wave_speed for r in scene.rods)  # [m/s]
    stable = DT_PER_ELEMENT_STEP * H_MIN_FRACTION * min(h_r, g * h) / c_d
    if scene["fe.kind"] == "3d":
        stable *= min(_third_dimension(h_r, g * h), _third_dimension(h_r, h))  # the tip's cells and the body's
        region = scene
    else:
        region = scene if size is None else region or _submodel_region(scene, h_r, h)
        stable *= _butterfly_step_factor(region, submodel=size is not None)
    stable = min(stable, _tip_step(region, h_r, h, g))
    stable *= damped_step_factor(scene)
    if scene["fe.contact"] != "penalty":
        return stable, math.inf
    factor = scene["fe.penalty"] if size is None else scene.submodel_penalty(h_r)
    return stable, _switching_step(region, factor, h_r, h, g)


def damped_step_factor(scene: Scene) -> float:
    """The stable step with the bulk viscosity ξ = fe.bulk_viscosity over the undamped one (the scheme's
    rods.stability.damping_factor). Without it a run at ξ = 0.99 marched 2.4x the steps estimated (17822 against
    7.4e3, paper driver)."""
    return damping_factor(scene["fe.bulk_viscosity"])


def _third_dimension(a: float, b: float) -> float:
    """Step of a hexahedron (a x a across, b along) over that of the quadrilateral a x b: a cell's highest mode
    scales as ω² ∝ Σ 1/h_i² (a cube: sqrt(2/3) of a square's step). Measured: see :data:`DT_PER_ELEMENT_STEP`."""
    return math.sqrt((1 / a**2 + 1 / b**2) / (2 / a**2 + 1 / b**2))


def _tip_step(region: Scene, h_r: float, h: float, g: float) -> float:
    """[s] The stable step of the cells under the rods' curved tip faces (a butterfly's aside; inf where there are
    none): their smallest thickness (rods.fe.layout.altitudes of :func:`_tip_cells`, the mesher's own corners, no
    mesh built) over their rod's dilatational wave speed, in 3D with their edge along the rim as the third dimension
    (:func:`_third_dimension`), x :data:`TIP_STEP_FRACTION`. A curved face's rim cells are the thinnest of a mesh:
    the face slopes there and the cap takes (its height)/(the block's length) of their column, which depends on the
    rods' diameters against the patch, so no table of the paper rods carries it over (that one read 1.24x to 1.49x
    the exact step on 30 to 38 mm rods and at 15 m/s; 3D had no tip term: an 8 mm tip's run took 1.63x the steps
    planned). Their thickness over the wave speed against the set-up's exact limit, 2026-12-06: 0.76 to 0.98 over the
    paper rods' tips of 50 to 6.8 mm (graded or not, meshes to 0.25 x 0.125 mm; deeper caps lower) and 48
    scene-probe scenes (benchmarks/scene_probe.py's named and three random draws), a submodel's (0.25 mm, tips of 35
    to 6.76 mm) 0.83 to 1.03; the whole estimate then 0.72 to 0.91 on those globals, 0.79 to 0.98 on the submodels,
    0.80 to 0.87 on four curved 3D tips (0.68 on a hemisphere)."""
    from rods.fe.layout import altitudes

    steps = [math.inf]
    for rod, cells, along_rim in _tip_cells(region, h_r, h, g):
        a = float(altitudes(cells).min())  # [m]
        third = _third_dimension(along_rim, a) if along_rim > 0 else 1.0
        steps.append(a / rod.material.dilatational_wave_speed * third)
    return TIP_STEP_FRACTION * DT_PER_ELEMENT_STEP * min(steps)


def _tip_cells(region: Scene, h_r: float, h: float, g: float) -> list[tuple[Any, Any, float]]:
    """Each curved tip's cells under its face, as (rod, corners (n, 4, 2) in (r, depth), edge along the rim [m] in
    3D, else 0): on the axisymmetric mesh the row on a one-block face (rods.fe.layout.tip_row; a butterfly has its
    table), in 3D the first layer's thinnest rim cell (rods.fe.mesh3d.tip_rim_cell) at sizes ``h_r``, ``h``, ``g``."""
    if region["fe.kind"] == "3d":
        from rods.fe.mesh3d import tip_rim_cell

        return [(rod, *tip_rim_cell(rod, h_r, h, g)) for rod in region.rods if math.isfinite(rod.tip_radius)]
    from rods.fe.layout import rod_layouts, tip_row

    return [(lay.rod, tip_row(lay), 0.0) for lay in rod_layouts(region) if lay.butterfly is None]


def _butterfly_step_factor(region: Scene, submodel: bool) -> float:
    """The butterfly cap's factor on the bulk's step (1 where no tip is one), interpolated linearly in its rim angle:
    a ``submodel``'s (``region`` its own scene, :func:`_submodel_region`) from :data:`SUBMODEL_CAP_STEP_FACTOR` or,
    graded, :data:`GRADED_SUBMODEL_CAP_STEP_FACTOR`, a global's from :data:`CAP_STEP_FACTOR` or, graded,
    :data:`GRADED_CAP_STEP_FACTOR`."""
    from rods.fe.layout import rod_layouts

    tables = (
        (SUBMODEL_CAP_STEP_FACTOR, GRADED_SUBMODEL_CAP_STEP_FACTOR)
        if submodel
        else (CAP_STEP_FACTOR, GRADED_CAP_STEP_FACTOR)
    )
    factors = [1.0]
    for layout in rod_layouts(region):
        if layout.butterfly is not None:
            rod = layout.rod
            phi = math.degrees(math.asin(min(1.0, rod.diameter / 2 / rod.tip_radius)))
            angles, values = zip(*tables[len(layout.columns) > 1], strict=True)
            factors.append(float(np.interp(phi, angles, values)))
    return min(factors)


def _switching_step(region: Scene, factor: float, h_r: float, h: float, g: float) -> float:
    """The penalty pair's switching limit (rods.stability.switching_step) at ω_c of the stiffest pair, as the
    set-up's rods.fe.contact.PenaltyContact.pair_frequency: ω_s² = k_s (1/m_s + Σ_j W_sj²/m_j), k_s = ε a_s, from the
    faces' nodes as the mesher lays them at sizes ``h_r``, ``h``, ``g`` (no mesh built). Axisymmetric
    (rods.fe.layout.tip_faces): the tributary areas a_i = ∫ N_i r ds along each face, the lumped masses ρ ∫ N_i r dA
    over the row of cells under them, ε = factor x E*/h_tip and W linear in r, as the set-up pairs them. Where a
    slave is coarser than the master it lies over (a graded rod's nodes outside its core over a thin rod's uniform
    face), its spring pulls on masters lighter than it: the equal-mesh estimate 2 factor E* (1/ρ_1 + 1/ρ_2)/h_n² read
    0.97 to 1.80 x the exact limit on 29 drawn scenes (five above 1.2 x); now 0.9999 to 1.0000 x on them and 0.966
    to 1.003 x on ten more (butterflies, near-hemispherical masters, submodels; 2026-12-08). 3D (equal O-grid sections
    at h_r on both faces): ω² = 2 ε/cos θ_1 (1/(ρ_1 t_1) + (A_1/A_2)/(ρ_2 t_2)) over the radii both faces share,
    t_i the first layer there (rods.fe.mesh3d.first_layer: a curved tip's rim cells are thin), A_i the O-grids' cells
    (the slave's spring over the master's mass) and θ_1 the slave face's slope (its area over its projection): 0.930 to
    1.034 x on fourteen quarter models (curved tips low), where the equal-mesh estimate read up to 1.66 x (a 7 mm tip
    on the paper rods) and the first layer without the areas 1.16 x (a 6 mm rod onto a 12.7 mm one)."""
    E_star = hertz.contact_constants(region.rod1, region.rod2)[0]  # [Pa]
    ω2 = _pair_frequency_3d if region["fe.kind"] == "3d" else _pair_frequency_axisymmetric
    return switching_step(math.sqrt(ω2(region, factor * E_star, h_r, h, g)))


def _pair_frequency_3d(region: Scene, stiffness: float, h_r: float, h: float, g: float) -> float:
    """ω_c² [1/s²] of the stiffest 3D pair (:func:`_switching_step`) at ``stiffness`` = factor x E* [Pa]:
    2 ε/cos θ_1 (1/(ρ_1 t_1) + (A_1/A_2)/(ρ_2 t_2)) over the radii both faces share, A_i each O-grid's cells there
    (rods.fe.mesh3d.section_cell_area: a thin slave's ring cells over a thick master's core)."""
    from rods.fe.layout import axial_spacing
    from rods.fe.mesh3d import first_layer, section_cell_area, section_radius

    ε = stiffness / min(axial_spacing(rod, h, g).h_tip for rod in region.rods)  # [Pa/m]
    rho = np.linspace(0.0, min(section_radius(rod.diameter / 2, h_r) for rod in region.rods), 257)  # [m]
    cos = np.sqrt(np.maximum(1.0 - (rho / region.rod1.tip_radius) ** 2, 1e-12))  # the slave face's slope
    (t1, t2), (ρ1, ρ2) = ((first_layer(r, h, g, rho) for r in region.rods), (r.material.density for r in region.rods))
    A1, A2 = (section_cell_area(r.diameter / 2, h_r, rho) for r in region.rods)  # [m^2]
    return float(np.max(2.0 * ε / cos * (1.0 / (ρ1 * t1) + A1 / A2 / (ρ2 * t2))))


def _pair_frequency_axisymmetric(region: Scene, stiffness: float, *_: float) -> float:
    """ω_c² [1/s²] of the stiffest axisymmetric pair (:func:`_switching_step`) at ``stiffness`` = factor x E* [Pa]:
    each slave over the master face on the spring ε a_s, against its lumped mass and its masters' weighted by W²."""
    from rods.fe.layout import tip_faces

    slave, master = tip_faces(region)
    ρ1, ρ2 = (rod.material.density for rod in region.rods)
    ε = stiffness / min(slave.h_tip, master.h_tip)  # [Pa/m]
    j = np.clip(np.searchsorted(master.r, slave.r, side="right") - 1, 0, master.r.size - 2)
    t = np.clip((slave.r - master.r[j]) / (master.r[j + 1] - master.r[j]), 0.0, 1.0)
    inv_m = 1.0 / (ρ2 * master.volume)  # [2π/kg] the masters' inverse lumped masses
    pair = 1.0 / (ρ1 * slave.volume) + (1.0 - t) ** 2 * inv_m[j] + t**2 * inv_m[j + 1]
    over = slave.r <= master.r[-1] * (1.0 + 1e-12)  # the slaves over the master face
    return float(np.max(ε * slave.area * pair, where=over, initial=0.0))


def analytical_cost(scene: Scene) -> Cost:
    """The analytical model's recorded samples, memory and time: :data:`ANALYTICAL_SECONDS`, :data:`SECONDS_PER_PASS`
    per one-way wave pass L/c of the rod with the most (each reflection restarts the delay equation's integration),
    :data:`SECONDS_PER_VALUE` per history value, and the solver steps a stiff contact forces
    (:func:`analytical_steps`), each with its time and stored dense output."""
    samples = math.floor(scene.end_time / scene.output_interval) + 1
    values = samples * (5 + 2 * len(scene.stations))
    passes = scene.end_time * max(r.material.wave_speed / r.length for r in scene.rods)  # [-]
    steps = analytical_steps(scene)
    wall = ANALYTICAL_SECONDS + SECONDS_PER_PASS * passes + SECONDS_PER_VALUE * values + SECONDS_PER_STEP * steps
    memory = ANALYTICAL_BASE_MEMORY + 3 * BYTES_PER_VALUE * values + BYTES_PER_SOLVER_STEP * steps
    return Cost("analytical model", 0, 0, steps, samples, values, memory, wall, file_bytes=CSV_BYTES_PER_VALUE * values)


def analytical_steps(scene: Scene) -> float:
    """Steps of the explicit DOP853 where the contact is stiff against the rods' impedance (thin rods: the rate
    grows as d^(-4/3)): :data:`STEPS_PER_STIFFNESS` x λ x end_time (constants above; at most a few hundred on
    centimetre rods, where accuracy, not stability, sets the step)."""
    P = scene.impedance_force  # [N]
    k = hertz.tangent_stiffness(P, *hertz.contact_constants(scene.rod1, scene.rod2))  # [N/m] dF/dδ at P
    λ = k * scene.speed / P  # [1/s] d(K δ^1.5 (1/Z1 + 1/Z2))/dδ at K δ^1.5 = P, as (1/Z1 + 1/Z2) = s1/P
    return STEPS_PER_STIFFNESS * λ * scene.end_time


def check_mesh(scene: Scene, ranks: int = 1, comm: Any = None, what: str = "the global") -> None:
    """Refuse (exit 2) a global FE model of ``scene`` whose mesh alone (its DOFs and the ranks' interpreters) exceeds
    the available memory: what a plan checks before it runs the analytical model to its first contact (a study's
    dry run, a driver's phase), which on a micrometre rod takes minutes (a fuzz: run.py --dry-run --set
    rod2.diameter=1e-6 planned 'at most about 1830 s' and ran past 120 s, where the mesh's 8e6 GB is refused in
    seconds once counted). The whole run's memory and budgets are checked after the plan, as before."""
    _, _, _, dofs = _fe_mesh(scene, None, None)
    memory = sum(b for b, _ in _memory_of(scene, ranks, dofs, 0, 0.0, None).values())  # [B] no steps, no histories
    free = available_memory(comm)
    if memory > free:
        raise InputError(
            what, f"{memory / 1e9:.3g} GB", f"its mesh alone needs more memory than available ({free / 1e9:.3g} GB): "
            f"{dofs:.3g} DOFs", "coarser sizes (fe.radial_size, fe.axial_size), or thicker rods",
        )  # fmt: skip


def available_memory(comm: Any = None) -> float:
    """MemAvailable of /proc/meminfo [B] (inf where unknown); with ``comm``, the least of its ranks' (a collective:
    every rank then refuses alike; one rank refused alone, on a node with less free memory, left the others waiting
    in the next collective, a hang: an audit, 2026-12-07)."""
    free = local_memory()
    return min(comm.allgather(free)) if comm is not None and comm.size > 1 else free


def local_memory() -> float:
    """MemAvailable of this process's /proc/meminfo [B] (inf where unknown)."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return float(line.split()[1]) * 1024
    except OSError:
        pass
    return math.inf


def peak_memory(comm: Any = None) -> float:
    """The peak resident memory of this process so far [B] (``ru_maxrss``: kB on Linux, bytes on macOS), summed over
    ``comm``'s ranks (collective where given): what :data:`BASE_MEMORY` and :data:`BYTES_PER_DOF` were fitted to, so
    a run's summary sets it beside its plan's :attr:`Cost.memory`. A process that ran other work first (a study's
    stages, a test session) reports that work's peak where it was higher."""
    import resource
    import sys

    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * (1 if sys.platform == "darwin" else 1024)
    return float(comm.allreduce(rss) if comm is not None else rss)


def available_disk(folder: str | Path) -> float:
    """Free space [B] of the file system that ``folder`` (or its nearest existing parent) is on; inf where unknown."""
    import shutil

    p = Path(folder).absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    try:
        return float(shutil.disk_usage(p).free)
    except OSError:
        return math.inf


def check_disk(costs: Sequence[Cost], out: str | Path, comm: Any = None) -> None:
    """Refuse (always: --force does not make room) runs whose files (:attr:`Cost.file_bytes`, all ``costs``
    together) exceed the free space where ``out`` is: a full disk stopped a run part-way, its files half-written.
    Under MPI rank 0 of ``comm`` looks and every rank takes its figure, so all refuse alike."""
    need = sum(c.file_bytes for c in costs)  # [B]
    free = available_disk(out) if comm is None or comm.rank == 0 else None
    free = free if comm is None else comm.bcast(free, root=0)
    if need > free:
        fields = sum(c.field_bytes for c in costs)
        said = f"{fields / 1e9:.3g} GB of it field frames" if fields else "histories, checkpoints and cut records"
        raise InputError(
            "--out", str(out), f"the run writes about {need / 1e9:.3g} GB of files ({said}) where {free / 1e9:.3g} GB"
            " are free", "a larger fe.field_interval or simulation.output_interval, a shorter end_time, or an --out "
            "on a larger disk",
        )  # fmt: skip


_probes: dict[tuple[str, int], tuple[float, float]] = {}  # (kind, rows) -> (_clock() of the probe, its speed)
_clock = time.monotonic  # [s]


def probe_is_stale(rows: int = PROBE_ROWS, kind: str = "axisymmetric") -> bool:
    """Whether :func:`machine_speed` at ``rows`` would measure again (none yet, or older than :data:`PROBE_MAX_AGE`)."""
    return (kind, rows) not in _probes or _clock() - _probes[kind, rows][0] > PROBE_MAX_AGE


def machine_speed(rows: int = PROBE_ROWS, refresh: bool | None = None, kind: str = "axisymmetric") -> float:
    """This machine's rate at a working set of ``rows`` over the reference's [-]: the best of at least four products
    (and :data:`PROBE_MIN_SECONDS` of them) y = A x of a banded CSR matrix (``rows`` rows of a ``kind`` stiffness
    row's entries, the axisymmetric 18 or the 3D 81, spread as a structured mesh's: in a core's cache where a small
    run's mesh is, past it at :data:`PROBE_ROWS`, ~0.22 GB, ~0.3 s with the build), in rows/s over
    :data:`PROBE_RATE_REFERENCE` of ``kind``.
    Measured again where the last probe of this size is older than :data:`PROBE_MAX_AGE` (``refresh`` overrides:
    under MPI one rank decides for all, :func:`calibrated`); 1.0 where the memory for it is not available."""
    if refresh is None:
        refresh = probe_is_stale(rows, kind)
    if refresh or (kind, rows) not in _probes:
        _probes[kind, rows] = (_clock(), _probe(rows, kind))
    return _probes[kind, rows][1]


def _probe(rows: int, kind: str = "axisymmetric") -> float:
    """One measurement of :func:`machine_speed` (no memory: 1.0)."""
    import scipy.sparse

    if kind == "3d":  # a hexahedral node's 27 neighbours, 40 x 40 nodes a mesh layer, 3 components per node
        step = np.array([-1, 0, 1])
        nodes = (step[:, None, None] * 1600 + step[None, :, None] * 40 + step[None, None, :]).ravel()
        offsets = (3 * nodes[:, None] + np.arange(3)).ravel()  # [-]
    else:  # a quadrilateral node's 9, 500 nodes a mesh row, 2 components per node
        nodes = np.array([-501, -500, -499, -1, 0, 1, 499, 500, 501])
        offsets = (2 * nodes[:, None] + np.arange(2)).ravel()  # [-]
    n, k = rows, offsets.size
    if local_memory() < 4 * n * k * 12:  # values (8 B) and column indices (4 B), with room to spare
        return 1.0
    columns = ((np.arange(n)[:, None] + offsets) % n).astype(np.int32).ravel()
    a = scipy.sparse.csr_matrix((np.ones(n * k), columns, np.arange(0, n * k + 1, k, dtype=np.int32)), shape=(n, n))
    x, best, start, repeats = np.ones(n), math.inf, time.perf_counter(), 0
    # a small product is short against the clock's jitter, and one near the cache's edge reaches its steady rate late
    # (PROBE_MIN_SECONDS): at least max(4, PROBE_ROWS // n) of them, for at least PROBE_MIN_SECONDS
    while repeats < max(4, PROBE_ROWS // n) or time.perf_counter() - start < PROBE_MIN_SECONDS:
        t0 = time.perf_counter()
        a @ x
        best, repeats = min(best, time.perf_counter() - t0), repeats + 1
    return n / best / PROBE_RATE_REFERENCE[kind]


def calibrated(costs: Sequence[Cost], comm: Any = None) -> list[Cost]:
    """``costs`` at this machine's rate (:func:`machine_speed`) at each one's working set per rank
    (:attr:`Cost.probe_rows`: a small run's in cache, as its mesh is, at milliseconds' cost); those without a CPU
    loop (the analytical model, a GPU's) as they are. Under MPI every rank of ``comm`` probes at once, as the run's
    ranks will share a node's cache and memory bandwidth, and all take the slowest. Every rank must call it with the
    same costs (they follow from the scene alone), so every rank plans and refuses alike."""
    sizes = sorted({(c.probe_kind, c.probe_rows) for c in costs if c.memory_bound_time > 0 and c.probe_rows > 0})
    if comm is None or comm.size == 1:
        speeds = {(kind, rows): machine_speed(rows, kind=kind) for kind, rows in sizes}
    else:  # rank 0 says which probes are stale, so that every rank probes at once or none does
        stale = comm.bcast([probe_is_stale(rows, kind) for kind, rows in sizes] if comm.rank == 0 else None, root=0)
        speeds = {}
        for (kind, rows), refresh in zip(sizes, stale, strict=True):
            comm.Barrier()
            speeds[kind, rows] = min(comm.allgather(machine_speed(rows, refresh, kind)))
    return [c.at_speed(speeds[key]) if (key := (c.probe_kind, c.probe_rows)) in speeds else c for c in costs]


def _analytical_memory_remedy(cost: Cost) -> str:
    """The analytical model's remedy for memory, its larger part first: the history (an output interval far below
    the scene's times) or the solver's dense output (a contact stiff against thin rods)."""
    steps = f"thicker rods (a contact this stiff against their impedance takes {cost.steps:.3g} solver steps)"
    if 3 * BYTES_PER_VALUE * cost.values >= 10 * BYTES_PER_SOLVER_STEP * cost.steps:  # the history alone: no rods
        return "a larger simulation.output_interval or a shorter end_time"  # (65 steps had been named: an audit)
    if 3 * BYTES_PER_VALUE * cost.values >= BYTES_PER_SOLVER_STEP * cost.steps:
        return f"a larger simulation.output_interval, a shorter end_time, or {steps}"
    return f"{steps}, a larger simulation.output_interval or a shorter end_time"


def busy_note(ranks: int, load: float | None = None, cores: int | None = None) -> str:
    """A line for the plan where other work already holds the cores (``load``: the 1-minute load average, ``cores``:
    those this process may use; default the machine's): the estimate is an idle machine's, and beside other jobs a
    run took 3-11 x it on 2 ranks (a fuzz at load 3.4-6.9 on 2 cores, ranks spin-waiting on each other); empty
    where the load leaves this run's ranks their cores."""
    import os

    if load is None:
        try:
            load = os.getloadavg()[0]
        except OSError:  # no load average on this platform: nothing to say
            return ""
    if cores is None:
        cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if load + ranks <= cores + 0.5:
        return ""
    return (
        f"note: this machine is busy (load average {load:.1f} on {cores} cores, {ranks} rank(s) of this run on "
        "top): the wall time above is an idle machine's estimate; beside other jobs a run can take several times it"
    )


def check(
    cost: Cost, force: bool = False, memory: bool = True, forced_by: str | None = "--force", comm: Any = None
) -> Cost:
    """Refuse ``cost`` above the available memory (where ``memory``: this machine runs it; a cluster job's memory is
    its node's, asked of the scheduler) or the step, work, frame, value and time budgets (unless ``force``; the
    remedy names ``forced_by``, the option that lifts them, where there is one). Under MPI pass ``comm`` (every rank
    calls it): the memory is then the least of the ranks' (:func:`available_memory`), the budgets follow from the
    cost, alike on every rank."""
    free = available_memory(comm) if memory else math.inf
    fe = cost.dofs > 0  # else the analytical model, whose steps a contact stiff against thin rods sets
    first = "".join(f"{r}, " for r in (cost.remedy, cost.cheaper) if r)
    if memory and cost.memory > free:
        raise InputError(
            cost.what, f"{cost.memory / 1e9:.3g} GB", f"needs more memory than available ({free / 1e9:.3g} GB): "
            f"{cost.dofs:.3g} DOFs, {cost.steps:.3g} steps, {cost.values:.3g} history values",
            (f"{first}{cost.memory_parts}" if cost.memory_parts else
             f"{first}coarser sizes, a larger simulation.output_interval, or a shorter end_time") if fe else
            _analytical_memory_remedy(cost),
        )  # fmt: skip
    steps_remedy = (cost.step_remedy or "coarser sizes") if fe else "thicker rods (a contact less stiff against them)"
    budgets = (  # (budget's name, amount, budget, the amount as said, the budget as said, what it would mean, remedy)
        ("step", cost.steps, STEP_BUDGET, f"{cost.steps:.3g} steps", f"{STEP_BUDGET:.3g} steps",
         f"this run: about {_duration(cost.wall_time)}", f"{steps_remedy}, a shorter end_time"),
        ("work", cost.dofs * cost.steps, WORK_BUDGET, f"{cost.dofs * cost.steps:.3g} DOF-steps",
         f"{WORK_BUDGET:.3g} DOF-steps", f"this run: about {_duration(cost.wall_time)} on {cost.ranks} rank(s)",
         "coarser sizes, a shorter end_time"),
        ("frame", cost.frames, FRAME_BUDGET, f"{cost.frames:.3g} field frames", f"{FRAME_BUDGET:.3g} frames",
         f"this run: {cost.field_bytes / 1e9:.3g} GB of files", "a larger fe.field_interval, a shorter end_time"),
        ("history", cost.values, VALUE_BUDGET, f"{cost.values:.3g} history values", f"{VALUE_BUDGET:.3g} values",
         f"this run: {cost.samples:.3g} samples", "a larger simulation.output_interval, fewer stations"),
        ("time", cost.wall_time, TIME_BUDGET, f"about {_duration(cost.wall_time)}", _duration(TIME_BUDGET),
         "the estimated wall time", f"a shorter end_time, coarser sizes, {cost.ranks_remedy}"),
    )  # fmt: skip
    for name, amount, budget, said, limit, meaning, remedy in budgets:
        if not force and amount > budget:
            why = f"above the {name} budget of {limit} ({meaning})"
            raise InputError(cost.what, said, why, f"{first}{remedy}" + (f", or {forced_by}" if forced_by else ""))
    return cost
