#!/usr/bin/env bash
# make test-cluster: a small sweep through Snakemake's SLURM executor on a one-node SLURM started here
# (scripts/slurm-localhost.sh), checked against the same sweep run locally.
#   sweep: the analytical model at 2 speeds (serial jobs) and the axisymmetric global FE model on a 4 x 1 mm
#   mesh at 2 time-step fractions, each FE job 2 MPI ranks launched by `srun --mpi=pmi2` (resources tasks=2)
# Runs in a temporary clone of the working tree (tracked files); prints sacct's view of the jobs.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)
py=$top/.venv/bin/python
snake=$top/.venv/bin/snakemake
"$py" -c 'import snakemake_executor_plugin_slurm' 2>/dev/null \
  || { echo "error: the SLURM executor plugin is missing: .venv/bin/pip install -e '.[cluster]'" >&2; exit 1; }
"$top/scripts/slurm-localhost.sh"

work=$(mktemp -d /tmp/rods-cluster.XXXXXX)
trap '[ "${KEEP:-0}" = 1 ] || rm -rf "$work"' EXIT  # KEEP=1: keep the clone and the logs
git clone -q "$top" "$work/rods"
(cd "$top" && git ls-files -z | xargs -0 cp -p --parents -t "$work/rods" 2>/dev/null || true)  # + the work tree
cd "$work/rods"
config=(--config 'speeds=[1.0,2.0]' 'mesh_levels={coarse: [4.0e-3, 1.0e-3]}' 'dt_fractions=[0.5,0.8]'
        'kinds=[axisymmetric]' ranks=2)
targets=(speed_sweep dt_sweep)

t0=$(date +%s)
"$snake" -s workflows/Snakefile --workflow-profile workflows/profiles/local --cores 2 "${targets[@]}" "${config[@]}" \
  > "$work/local.log" 2>&1 || { tail -30 "$work/local.log"; exit 1; }
t1=$(date +%s)
mkdir -p "$work/local" && cp results/sweep-speed.csv results/sweep-dt.csv "$work/local/"

# the same sweep again from scratch, through SLURM
rm -rf output .snakemake && git checkout -q -- results/
start=$(date '+%Y-%m-%dT%H:%M:%S')
"$snake" -s workflows/Snakefile --workflow-profile workflows/profiles/slurm --jobs 4 "${targets[@]}" \
  --default-resources slurm_partition=debug runtime=10 mem_mb=2000 --slurm-no-account \
  "${config[@]}" 'mpi=srun --mpi=pmi2' > "$work/slurm.log" 2>&1 || { tail -40 "$work/slurm.log"; exit 1; }
t2=$(date +%s)

echo "sacct (jobs of this run and their steps):"
sacct --starttime "$start" --format=JobID%16,JobName%28,State,NTasks,AllocCPUS
"$py" - "$work/local" results "$start" <<'PY'
import csv, math, subprocess, sys
local, slurm, start = sys.argv[1:4]
for name in ("sweep-speed.csv", "sweep-dt.csv"):
    a, b = (list(csv.DictReader(open(f"{d}/{name}"))) for d in (local, slurm))
    assert len(a) == len(b) == 2, (name, len(a), len(b))
    for ra, rb in zip(a, b):
        for k in ra:
            if k in ("wall_time", "key", "path") or ra[k] == "":
                continue
            try:
                x, y = float(ra[k]), float(rb[k])
            except ValueError:  # a text column (model, status, warnings): equal as written
                assert ra[k] == rb[k], (name, k, ra[k], rb[k])
                continue
            assert math.isclose(x, y, rel_tol=1e-9, abs_tol=1e-300), (name, k, x, y)
    print(f"{name}: local and SLURM rows equal (2 rows)")
# the FE jobs' MPI steps: 2 tasks each
out = subprocess.run(["sacct", "-P", "-n", "--starttime", start, "--format=JobID,JobName,NTasks"],
                     capture_output=True, text=True, check=True).stdout.split()
steps = [l.split("|") for l in out if "|python" in l or "|srun" in l or l.split("|")[1] == "python"]
mpi = [s for s in steps if s[2] == "2"]
assert len(mpi) >= 2, f"expected two 2-task MPI steps in sacct, got {steps}"
print(f"sacct: {len(mpi)} MPI steps with 2 tasks")
# each FE job asked SLURM for its own plan's time and memory (rods.study.jobs.request), not the defaults
from rods.scene import load_scene
from rods.study import jobs
want = set()
for dtf in (0.5, 0.8):
    sc = load_scene("workflows/scenes/paper.toml", ["impact.speed=2.197", "fe.kind=axisymmetric", "fe.axial_size=0.004",
                                                    "fe.radial_size=0.001", f"fe.dt_fraction={dtf}"])
    r = jobs.request([jobs.global_cost(sc, 2)])
    want.add((r["runtime"], r["mem_mb"]))
rows = subprocess.run(["sacct", "-P", "-n", "-X", "--starttime", start, "--format=JobID,AllocCPUS,Timelimit,ReqMem"],
                      capture_output=True, text=True, check=True).stdout.split()
def minutes(limit):  # sacct's [D-]HH:MM:SS
    days, _, hms = limit.rpartition("-")
    h, m, s = (int(x) for x in hms.split(":"))
    return int(days or 0) * 1440 + h * 60 + m + (s > 0)
def megabytes(mem):  # sacct's ReqMem: 2000M (older SLURM: 2000Mn, per node, or 2000Mc, per CPU), 2G
    import re
    number, unit = re.match(r"([\d.]+)([KMGT]?)", mem).groups()
    return round(float(number) * {"K": 2**-10, "": 1, "M": 1, "G": 2**10, "T": 2**20}[unit])
asked = {(minutes(t), megabytes(mem)) for _, cpus, t, mem in (r.split("|") for r in rows) if cpus == "2"}
assert asked == want, f"the FE jobs asked SLURM for {asked} (runtime [min], mem [MB]), their plans for {want}"
print(f"sacct: the FE jobs asked for their plans' time and memory {sorted(want)} (runtime [min], mem [MB])")
PY
echo "local run: $((t1 - t0)) s; SLURM run: $((t2 - t1)) s"
