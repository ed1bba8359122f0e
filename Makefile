# rods: every target creates or refreshes .venv itself (idempotent, see .ci/ensure-venv).
PY := .venv/bin/python
NPROC ?= 2

.PHONY: venv paper test test-slow bench lint clean

venv:
	@./.ci/ensure-venv

## The main job: reproduce the paper (today: the analytical model, Table 2 and Fig. 4) into results/.
paper: venv
	$(PY) workflows/paper.py

## The default test suite (no slow cases); what CI runs.
test: venv
	$(PY) -m pytest -m "not slow" -q

## The long cases (stability matrix, paper-resolution FE validation).
test-slow: venv
	$(PY) -m pytest -m "slow" -q

## Benchmarks (not tests): write their tables and figures to results/.
bench: venv
	$(PY) benchmarks/analytical_vs_ddeint.py
	@if [ -f benchmarks/fe_throughput.py ]; then $(PY) benchmarks/fe_throughput.py; fi

lint: venv
	.venv/bin/ruff format --check rods workflows tests benchmarks
	.venv/bin/ruff check rods workflows tests benchmarks

clean:
	rm -rf output .pytest_cache
