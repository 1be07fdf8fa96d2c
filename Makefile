# earl-m2t: the two entry points are `make demo` and `make test`; both set up what they need.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
SAMPLE := samples/pick_and_place/pick_and_place.uml
STAMP := $(VENV)/.installed

.PHONY: demo test campaign prefixes setup bytecode wheel-check bench fuzz clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet -e '.[test]'
	@touch $(STAMP)

# The package's bytecode, written now: CI jobs often run with PYTHONDONTWRITEBYTECODE=1, and
# without .pyc files every start would compile earl-m2t's modules again. (pip compiles a
# wheel's modules when it installs them; an editable install leaves that to the first run.)
bytecode: $(STAMP)
	@$(PY) -m compileall -q earl_m2t

setup: bytecode

demo: bytecode
	$(VENV)/bin/earl-m2t check $(SAMPLE)
	$(VENV)/bin/earl-m2t show $(SAMPLE)
	$(VENV)/bin/earl-m2t report $(SAMPLE) -o build/report

# Orocos RTT and OCL for the orocos target's tests, and ROS 2 Jazzy for the ros2 target's: found,
# or built once into a cache, the two builds side by side (the ROS 2 one waits on PyPI for part of
# its time). A failed build does not stop here: those tests then fail with the build log's tail.
prefixes:
	@$(PYTHON) tests/support/orocos.py ensure >/dev/null & orocos=$$!; \
	  $(PYTHON) tests/support/ros2.py ensure >/dev/null || true; wait $$orocos || true

# The loaded campaigns (a sample under a CPU hog per core): the suite makes each campaign's
# `suite` runs of tests/support/campaigns.toml, the fewest that still catch its known-bad variant;
# `make campaign` runs the campaign modules alone with their `full` runs (tests/support/campaign.py).
SUITE_RUNS ?= suite
CAMPAIGN_RUNS ?= full
CAMPAIGNS := tests/test_sample_runs.py tests/test_two_arm_runs.py tests/test_harmoniser_runs.py tests/test_gen_ros2.py \
	tests/test_gen_ros.py tests/test_gen_orocos.py tests/test_ros_switch_runs.py tests/test_orocos_switch_runs.py \
	tests/test_ros2_hosts.py tests/test_ros2_switch_runs.py tests/test_differential_switching.py
# Two phases: the tests that are not loaded on every core at once (pytest-xdist; each module on
# one worker, the ROS 2 modules on one worker together), then the loaded ones (a CPU hog per core)
# one at a time. Both write JUnit XML, from which tests/support/suite_time.py prints where the time
# went (per area, per module, the slowest tests), also when tests failed; the exit status is that
# of the first phase that failed.
TEST_JOBS ?= $(shell nproc)
RESULTS := build/test-results
test: bytecode prefixes
	@rm -f $(RESULTS)/parallel.xml $(RESULTS)/loaded.xml; status=0; \
	  EARL_CAMPAIGN_RUNS=$(SUITE_RUNS) $(PY) -m pytest -q -n $(TEST_JOBS) --dist loadgroup -m "not loaded" \
	    --junitxml=$(RESULTS)/parallel.xml || status=$$?; \
	  EARL_CAMPAIGN_RUNS=$(SUITE_RUNS) $(PY) -m pytest -q -m loaded --junitxml=$(RESULTS)/loaded.xml \
	    || { loaded=$$?; [ $$status -ne 0 ] || status=$$loaded; }; \
	  $(PYTHON) tests/support/suite_time.py $(RESULTS)/parallel.xml $(RESULTS)/loaded.xml || true; exit $$status

campaign: bytecode prefixes
	EARL_CAMPAIGN_RUNS=$(CAMPAIGN_RUNS) $(PY) -m pytest -q -s $(CAMPAIGNS)

wheel-check: $(STAMP)
	$(PY) -m pytest -q tests/packaging

bench: bytecode
	$(PY) bench/run.py

# The long fuzz campaign (tests/fuzz/runner.py, docs/untrusted-models.md): every command, the
# properties (round trip, clean check then gen, memory bound); failing inputs go to
# tests/fuzz/regressions/. FUZZ_BOUND: the seconds of CPU time an input may take.
FUZZ_INPUTS ?= 100000
FUZZ_SEED ?= 1
FUZZ_JOBS ?= 2
FUZZ_BOUND ?= 60
fuzz: $(STAMP)
	$(PY) tests/fuzz/runner.py --inputs $(FUZZ_INPUTS) --seed $(FUZZ_SEED) --jobs $(FUZZ_JOBS) --bound $(FUZZ_BOUND)

clean:
	rm -rf $(VENV) dist build bench/out
