# rgbd_lane_detector: set-up, build, test and demo from a clean Debian 12 checkout.
#   make demo   - install deps, build, run the detector graph on generated synthetic data
#   make test   - install deps, build, run every gtest/rostest, catkin_lint, roslaunch-check
# Other targets: build, bench, eval, test-arm64, test-sanitize, test-load, fuzz, soak, format, clean.

SHELL := /bin/bash
.ONESHELL:
.SHELLFLAGS := -eo pipefail -c

ROOT      := $(CURDIR)
BUILD     := $(ROOT)/build
WS        := $(BUILD)/ws
PKG       := rgbd_lane_detector
JOBS      ?= $(shell nproc)
# catkin, rostest and pluginlib need Debian's python3 (not a pyenv/venv one first on PATH)
export PATH := /usr/bin:/bin:$(PATH)
export PYTHONNOUSERSITE := 1
export ROS_HOME ?= $(BUILD)/ros_home
CMAKE_ARGS := -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON
SETUP := source $(WS)/devel/setup.bash

.PHONY: all deps build test demo bench eval test-arm64 test-sanitize test-load fuzz soak format clean

all: build

deps:
	@$(ROOT)/scripts/install_deps.sh

build: deps
	@$(ROOT)/scripts/build.sh $(WS)

test: build
	@$(ROOT)/scripts/run_tests.sh $(WS)

demo: build
	@$(SETUP) && $(ROOT)/scripts/demo.sh

bench: build
	@$(SETUP) && $(ROOT)/scripts/bench.sh

eval: build
	@$(SETUP) && $(ROOT)/scripts/evaluate.sh

test-sanitize: deps
	@$(ROOT)/scripts/test_sanitize.sh

# The core, its gtests and benchmarks cross-compiled for aarch64 (Debian arm64 libraries in a
# sysroot under build/arm64), the gtests under qemu-aarch64, detections compared with this machine's
test-arm64: deps
	@$(ROOT)/scripts/install_deps.sh arm64
	@$(ROOT)/scripts/test_arm64.sh

# make test (LOAD_TEST_RUNS, default 5) and make test-sanitize (LOAD_SANITIZE_RUNS, default 3)
# with every CPU kept busy by stress-ng; pass counts in build/test_load/summary.md
test-load: deps
	@$(ROOT)/scripts/install_deps.sh load
	@$(ROOT)/scripts/test_load.sh

# libFuzzer targets (clang-14) for FUZZ_SECONDS (default 60) each, see docs/RELIABILITY.md
fuzz: deps
	@$(ROOT)/scripts/install_deps.sh fuzz
	@$(ROOT)/scripts/fuzz.sh

soak: build
	@$(SETUP) && $(ROOT)/scripts/soak.sh

format:
	@clang-format -i $$(git ls-files '*.cpp' '*.h')

clean:
	rm -rf $(BUILD)
