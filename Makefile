# blind_navigation: every target does its own set-up on a fresh Debian 12
# machine (Debian's ROS 1 packages via apt, or /opt/ros/noetic when present),
# builds the catkin workspace in .ws/ and runs.
SHELL := /bin/bash
# Debian's ROS Python libraries live in /usr/bin/python3: put /usr/bin first so
# `#!/usr/bin/env python3` nodes never pick another interpreter.
export PATH := /usr/bin:/bin:$(PATH)
export BN_WS ?= $(CURDIR)/.ws

.PHONY: all deps build test demo bench soak clean

all: build

deps:
	@bash scripts/install_deps.sh

build: deps
	@bash scripts/build.sh

test: build
	@bash scripts/run_tests.sh

demo: build
	@bash scripts/demo.sh

bench: build
	@bash scripts/bench.sh

# one hour of the default launch recording at rtf 1 (scripts/soak.py; not part of test)
soak: build
	@source scripts/ros_env.sh && /usr/bin/python3 scripts/soak.py --out results/soak.md $(SOAK_ARGS)

clean:
	rm -rf $(BN_WS) results
