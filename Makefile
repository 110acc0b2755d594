# SPDX-License-Identifier: MIT
# Thin wrapper over the CMake presets. `make help` lists the targets.

JOBS ?= $(shell nproc 2>/dev/null || echo 2)
TEST_PRESETS := host host-asan host-m32

.PHONY: help test bench deps linux clean $(addprefix build-,$(TEST_PRESETS)) $(addprefix test-,$(TEST_PRESETS))

help:
	@echo "make test    install what is missing, build and run every test (host, sanitizers, 32-bit)"
	@echo "make bench   instructions per robot_tick() (callgrind) and the core's static RAM"
	@echo "make linux   build sonarslam-linux for a Linux robot (build/linux/hal/linux/)"
	@echo "make clean   remove build/"

deps:
	@tools/install-deps.sh test linux

$(addprefix build-,$(TEST_PRESETS)): build-%: deps
	cmake --preset $*
	cmake --build --preset $* -j $(JOBS)

$(addprefix test-,$(TEST_PRESETS)): test-%: build-%
	ctest --preset $*

test: $(addprefix test-,$(TEST_PRESETS))
	@echo "All tests passed in: $(TEST_PRESETS)."

linux:
	@tools/install-deps.sh linux
	cmake --preset linux
	cmake --build --preset linux -j $(JOBS)

bench: build-host
	tools/bench.py build/host

clean:
	rm -rf build
