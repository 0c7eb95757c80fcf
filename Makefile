# Every target bootstraps .venv by itself, so a fresh clone needs only `make`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

DB      ?= reports/campaign.duckdb
OUT     ?= reports
MUTANTS ?= 300
SUTS    ?= genom,bip-a,bip-b
SEED    ?= 2012
JOBS    ?= 0

.PHONY: venv test bench campaign analyze report clean

venv: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

test: $(STAMP)
	$(PY) -m pytest

bench: $(STAMP)
	$(PY) bench/run.py

campaign: $(STAMP)
	$(PY) -m harness campaign --mutants $(MUTANTS) --sut $(SUTS) --seed $(SEED) --db $(DB) --jobs $(JOBS)

analyze: $(STAMP)
	$(PY) -m harness analyze --db $(DB)

report: $(STAMP)
	$(PY) -m harness report --db $(DB) --out $(OUT)

clean:
	rm -rf $(VENV) reports/*.duckdb reports/*.html reports/*.csv reports/traces
