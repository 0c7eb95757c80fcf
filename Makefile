# Every target bootstraps .venv by itself, so a fresh clone needs only `make`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
# The ROS side runs under the system Python that Debian's ROS 1 packages import under.
ROS_PYTHON ?= /usr/bin/python3
VENV_ROS   := .venv-ros
ROS_STAMP  := $(VENV_ROS)/.installed

DB      ?= reports/campaign.duckdb
OUT     ?=# the report's folder; empty: the store's folder
MUTANTS ?= 300
MISSION ?= missions/dala
SUTS    ?=
SEED    ?= 2012
JOBS    ?= 0
STRATEGY ?= random

.PHONY: venv ros test bench campaign analyze report paper clean

venv: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

# .venv-ros only where ROS is installed; elsewhere the ROS tests skip, saying why.
ros:
	@if $(ROS_PYTHON) -c 'import rospy, actionlib, genpy, rosmaster' 2>/dev/null; then \
		$(MAKE) --no-print-directory $(ROS_STAMP); \
	else echo "make ros: $(ROS_PYTHON) cannot import rospy/actionlib; ROS tests will skip (.ci/run installs them)"; fi

$(ROS_STAMP): pyproject.toml
	$(ROS_PYTHON) -m venv --system-site-packages $(VENV_ROS)
	$(VENV_ROS)/bin/python -m pip install --quiet -e .
	touch $(ROS_STAMP)

test: $(STAMP) ros
	$(PY) -m pytest

bench: $(STAMP) ros
	$(PY) bench/run.py

campaign: $(STAMP)
	$(PY) -m harness campaign --mission $(MISSION) --mutants $(MUTANTS) $(if $(SUTS),--sut $(SUTS)) --seed $(SEED) --strategy $(STRATEGY) --db $(DB) --jobs $(JOBS)

analyze: $(STAMP)
	$(PY) -m harness analyze --db $(DB)

report: $(STAMP)
	$(PY) -m harness report --db $(DB) $(if $(OUT),--out $(OUT))

clean:
	rm -rf $(VENV) $(VENV_ROS) reports/*.duckdb reports/*.html reports/*.csv reports/traces

# The paper's Tables II-IV beside ours, from a fresh default campaign (docs/paper.md).
PAPER_DB ?= reports/paper.duckdb
paper: $(STAMP)
	rm -f $(PAPER_DB)
	$(PY) -m harness campaign --db $(PAPER_DB) --seed $(SEED) --jobs $(JOBS)
	$(PY) -m harness.report.paper --db $(PAPER_DB) --out docs/paper.md
