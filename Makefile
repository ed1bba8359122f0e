# rods: every target creates or refreshes .venv itself (idempotent, see .ci/ensure-venv).
PY := .venv/bin/python
NPROC ?= 2

.PHONY: venv paper paper-full sweep verify test test-slow bench lint clean

venv:
	@./.ci/ensure-venv

SNAKE := .venv/bin/snakemake -s workflows/Snakefile --workflow-profile workflows/profiles/local --cores $(NPROC)

## The main job: the whole paper into results/ (REPORT.md links every table and figure); reruns only what changed.
paper: venv
	$(SNAKE) paper

## The main job plus the ultra-fine level's four other phase members (4 runs of 41-53 min each on 2 cores, measured 2026-11-27/28: about 3 h more).
paper-full: venv
	$(SNAKE) paper --config 'paper_phase_levels=[coarse,mid,fine,extra-fine,ultra-fine]'

## Parameter sweeps (impact speed, mesh level, time-step fraction): results/sweep-*.csv
sweep: venv
	$(SNAKE) speed_sweep mesh_sweep dt_sweep

## Verification matrix (global FE at default settings vs analytical on six scenes): results/verification.{md,json}
verify: venv
	.venv/bin/mpirun -n $(NPROC) $(PY) workflows/verify.py --tables results

## The default test suite (no slow cases); what CI runs. The serial cases run on NPROC workers (pytest-xdist, a
## worker that runs out of cases takes some of the other's: one long case last no longer idles the other core);
## the MPI cases (their own ranks) and the wall-time measurements (marker alone) after them, one at a time, collected
## from the files that mark them (tests/conftest.py refuses a marked case elsewhere): collecting all takes ~8 s more.
MARKED := $(shell grep -rlE --include='test_*.py' 'mark\.(mpi|alone)' tests | sort)
test: venv
	@rc=0; $(PY) -m pytest -m "not slow and not mpi and not alone" -q -n $(NPROC) --dist worksteal || rc=$$?; \
	$(PY) -m pytest -m "not slow and (mpi or alone)" -q $(MARKED) || rc=$$?; exit $$rc

## The long cases (stability matrix, paper-resolution FE validation), in the two parts of `make test`.
test-slow: venv
	@rc=0; $(PY) -m pytest -m "slow and not mpi and not alone" -q -n $(NPROC) --dist worksteal || rc=$$?; \
	$(PY) -m pytest -m "slow and (mpi or alone)" -q $(MARKED) || rc=$$?; exit $$rc

## The SLURM path (not in the default suite; root): a one-node SLURM here (scripts/slurm-localhost.sh), a small
## sweep through Snakemake's SLURM executor with 2-rank MPI jobs, checked against the local run (~3 min measured).
test-cluster: venv
	$(PY) -m pip install --quiet --disable-pip-version-check -e '.[cluster]'
	scripts/test-cluster.sh

## Benchmarks (not tests): write their tables and figures to results/.
bench: venv
	$(PY) benchmarks/analytical_vs_ddeint.py
	@if [ -f benchmarks/fe_throughput.py ]; then $(PY) benchmarks/fe_throughput.py; fi
	.venv/bin/mpirun -n $(NPROC) $(PY) benchmarks/scene_probe.py
	.venv/bin/mpirun -n $(NPROC) $(PY) benchmarks/submodel_probe.py

lint: venv
	.venv/bin/ruff format --check rods workflows tests benchmarks demos
	.venv/bin/ruff check rods workflows tests benchmarks demos

clean:
	rm -rf output .pytest_cache
