# SPDX-License-Identifier: MIT
# Thin wrapper over the CMake presets. `make help` lists the targets.

JOBS ?= $(shell nproc 2>/dev/null || echo 2)
TEST_PRESETS := host host-asan host-m32

SIM_OUT ?= out/sim
SIM_ARGS ?=

.PHONY: help sim test bench report deps deps-sim clean $(addprefix build-,$(TEST_PRESETS)) $(addprefix test-,$(TEST_PRESETS))

help:
	@echo "make sim     install what is missing, build, run the default room; picture in $(SIM_OUT)/"
	@echo "             (more: make sim SIM_ARGS='--room host_sim/rooms/obstacles.room --seed 2')"
	@echo "make test    install what is missing, build and run every test (host, sanitizers, 32-bit)"
	@echo "make bench   instructions per robot_tick() (callgrind) and the core's static RAM"
	@echo "make report  the simulator's figures over several seeds (tools/sim_report.py)"
	@echo "make clean   remove build/ and out/"

deps:
	@tools/install-deps.sh test sim

deps-sim:
	@tools/install-deps.sh sim

sim: deps-sim
	cmake --preset host
	cmake --build --preset host -j $(JOBS) --target host_sim
	build/host/host_sim/host_sim --out $(SIM_OUT) $(SIM_ARGS)

report: build-host
	tools/sim_report.py

$(addprefix build-,$(TEST_PRESETS)): build-%: deps
	cmake --preset $*
	cmake --build --preset $* -j $(JOBS)

$(addprefix test-,$(TEST_PRESETS)): test-%: build-%
	ctest --preset $*

test: $(addprefix test-,$(TEST_PRESETS))
	@echo "All tests passed in: $(TEST_PRESETS)."

bench: build-host
	tools/bench.py build/host

clean:
	rm -rf build out
