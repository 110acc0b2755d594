# SPDX-License-Identifier: MIT
# Thin wrapper over the CMake presets. `make help` lists the targets.

# make's "Entering directory" lines say nothing a reader of make test needs.
MAKEFLAGS += --no-print-directory

JOBS ?= $(shell nproc 2>/dev/null || echo 2)
TEST_PRESETS := host host-asan host-m32 host-tsan host-clang stm32f4
# The STM32F4 board: a table hal/stm32f4/board_<BOARD>.h. The preset's own board
# (generic_f405, the one QEMU runs) is sonarslam_stm32f4; every other is sonarslam_<BOARD>.
BOARD ?= generic_f405
BOARDS := $(patsubst hal/stm32f4/board_%.h,%,$(wildcard hal/stm32f4/board_*.h))
FIRMWARE_IMAGE := $(if $(filter generic_f405,$(BOARD)),sonarslam_stm32f4,sonarslam_$(BOARD))
FIRMWARE_ELF := build/stm32f4/hal/stm32f4/$(FIRMWARE_IMAGE).elf

FUZZ_RUNS ?= 50000
FUZZ_SEED ?= 1000

SIM_OUT ?= out/sim
SIM_ARGS ?=
CORPUS_ARGS ?=
COMPARE_ARGS ?=
COMPARE_GENERATED ?= 100
FUZZ_SECONDS ?= 60
DOCS_CHECK_ARGS ?=
FUZZ_EXAMPLES ?= 100000

.PHONY: help sim calibrate test docs docs-check bench fuzz fuzz-core report corpus compare trace deps deps-sim deps-firmware \
        deps-fuzz firmware flash debug linux clean \
        $(addprefix build-,$(TEST_PRESETS)) $(addprefix test-,$(TEST_PRESETS))

help:
	@echo "make sim       install what is missing, build, run the default room; picture in $(SIM_OUT)/"
	@echo "               (more: make sim SIM_ARGS='--room host_sim/rooms/obstacles.room --seed 2')"
	@echo "make calibrate UMBmark on the simulated robot: the calibration make sim uses"
	@echo "               (host_sim/calibration/default_robot.conf), E_max,syst before and after on 5 seeds"
	@echo "make test      install what is missing, build and run every test (host, sanitizers,"
	@echo "               32-bit, ThreadSanitizer on the Linux backend, clang, the STM32F4 images in QEMU):"
	@echo "               a line a build, logs in build/PRESET/test.log, ~10 min on 2 idle cores"
	@echo "make fuzz-core the core fuzz under ASan + UBSan: $(FUZZ_RUNS) random configurations (minutes)"
	@echo "make bench     instructions per robot_tick() (callgrind, and QEMU + unicorn on the"
	@echo "               Cortex-M4), sizes, stack depth, the simulator's instructions per"
	@echo "               control period, against the budgets"
	@echo "make docs      the READMEs' generated figures and pictures, from this build: the"
	@echo "               simulator's, the bench's (host and STM32F4) and make compare's"
	@echo "               (make docs-check: which are out of date, changing nothing; all but"
	@echo "               make compare's, unless DOCS_CHECK_ARGS=--compare)"
	@echo "make report    the simulator's figures over several seeds (tools/sim_report.py),"
	@echo "               the pose correction on and off in every room (tools/pose_report.py)"
	@echo "               and the corpus (tools/corpus_report.py), with the time it took"
	@echo "make corpus    the corpus report: shipped rooms x 20 seeds, 100 generated rooms"
	@echo "               (10 and 30 min), 12 flats (1 h), the building maps; tools/corpus_report.py"
	@echo "               (more: make corpus CORPUS_ARGS='--quick')"
	@echo "make compare   the firmware's mapper beside OctoMap and HIMM on the same logs: P/R/F1"
	@echo "               and instructions per reading, shipped rooms and generated rooms"
	@echo "               (installs OctoMap; tools/compare.py)"
	@echo "make trace     record the HAL trace the STM32F4 self-test replays, again"
	@echo "make fuzz      the parsers' libFuzzer targets (clang), FUZZ_SECONDS each (default 60),"
	@echo "               then the Python link's properties, FUZZ_EXAMPLES cases each (default 100000)"
	@echo "make firmware  the STM32F4 image: $(FIRMWARE_ELF:.elf=.{elf,bin,hex,map})"
	@echo "               (another board: make firmware BOARD=blackpill_f411; boards: $(BOARDS))"
	@echo "make flash     program it through an ST-LINK (OpenOCD or st-flash); BOARD= as above"
	@echo "make debug     OpenOCD and gdb-multiarch on the board"
	@echo "make linux     sonarslam-linux for a Linux robot (build/linux/hal/linux/)"
	@echo "make clean     remove build/ and out/"

deps:
	@tools/install-deps.sh test sim firmware linux

deps-sim:
	@tools/install-deps.sh sim

deps-firmware:
	@tools/install-deps.sh firmware

deps-fuzz:
	@tools/install-deps.sh fuzz

sim: deps-sim
	cmake --preset host
	cmake --build --preset host -j $(JOBS) --target host_sim
	build/host/host_sim/host_sim --out $(SIM_OUT) $(SIM_ARGS)

# UMBmark as a robot builder follows it, in the simulator: the uncalibrated robot's runs,
# tools/umbmark.py, verification on five fresh seeds (each uncalibrated and calibrated);
# writes the calibration host_sim uses by default.
calibrate: deps-sim
	cmake --preset host
	cmake --build --preset host -j $(JOBS) --target host_sim
	tools/calibrate_sim.py build/host/host_sim/host_sim --out out/calibrate

# The READMEs' generated figures (<!-- figures: NAME --> blocks and the pictures beside
# them), made again from this build; docs-check says which differ, and changes nothing.
# make compare's figures take minutes more: docs-check leaves them out unless
# DOCS_CHECK_ARGS=--compare (tools/docs.py --help).
OCTOMAP_BUILD = tools/install-deps.sh compare && cmake -S tools/octomap -B build/compare \
	&& cmake --build build/compare -j $(JOBS)

docs: build-host build-stm32f4
	@$(OCTOMAP_BUILD)
	tools/docs.py build/host/host_sim/host_sim --stm32f4 build/stm32f4 --compare

docs-check: build-host build-stm32f4
	@$(if $(findstring --compare,$(DOCS_CHECK_ARGS)),$(OCTOMAP_BUILD))
	tools/docs.py build/host/host_sim/host_sim --stm32f4 build/stm32f4 --check $(DOCS_CHECK_ARGS)

# Every report the READMEs quote, one after the other, and how long they took together
# (about 15 min on a two-core machine is the budget).
report: build-host
	@start=$$(date +%s); set -e; \
	tools/sim_report.py; \
	tools/pose_report.py; \
	tools/corpus_report.py --jobs $(JOBS); \
	s=$$(( $$(date +%s) - start )); \
	echo "make report: the simulator's report, the pose report and the corpus in $$((s / 60)) min $$((s % 60)) s (budget: 15 min on 2 cores)"

# Every goal judged on distributions: the shipped rooms, generated rooms and flats
# (tools/roomgen.py) and the building maps, every core at once; runs in out/corpus.
corpus: deps-sim
	cmake --preset host
	cmake --build --preset host -j $(JOBS) --target host_sim
	tools/corpus_report.py --jobs $(JOBS) $(CORPUS_ARGS)

# OctoMap is needed here only: a project of its own (tools/octomap), never in make test.
compare:
	@tools/install-deps.sh sim compare
	cmake --preset host
	cmake --build --preset host -j $(JOBS) --target host_sim
	cmake -S tools/octomap -B build/compare
	cmake --build build/compare -j $(JOBS)
	tools/compare.py $(COMPARE_ARGS)
	tools/compare.py --generated $(COMPARE_GENERATED) --no-variants --out out/compare-generated

# The HAL trace the STM32F4 self-test replays: 260 s of the clutter room, long enough for
# the pose correction to apply matches, the frontier to be sought, openings measured and
# ways to frontiers out of sight asked for, so that the worst tick and background call
# are measured over those too (escapes and stalls were measured once:
# hal/stm32f4/experiments.md). Recorded by the simulator with the MCU's grid
# (240 x 240, the start in cell 80, 80): the frontier's scan goes over the whole grid, so
# a larger one parts the two ways at the first seek. No map saves: the replay HAL has no
# map storage, and a save, which takes background calls, would move the background work
# of the recording against the replay's. Record it again whenever the firmware's
# behaviour changes (the test replay_host_matches_trace says when).
trace: build-host
	build/host/host_sim/host_sim --room host_sim/rooms/clutter.room --duration 260 --seed 2 \
	    --set grid_a=240 --set grid_b=240 --set start_cell_a=80 --set start_cell_b=80 \
	    --set save_period_s=0 --trace tests/data/clutter_260s.trace \
	    --out out/trace --no-plot --quiet

# The fuzz targets of tests/fuzz, built with clang's libFuzzer and run one after another;
# what they find stays in build/fuzz/corpus, a crash in build/fuzz/artifacts.
fuzz: deps-fuzz
	cmake --preset fuzz
	cmake --build --preset fuzz -j $(JOBS)
	tools/fuzz.py --seconds $(FUZZ_SECONDS) --examples $(FUZZ_EXAMPLES)

$(addprefix build-,$(TEST_PRESETS)): build-%: deps
	cmake --preset $*
	cmake --build --preset $* -j $(JOBS)

# A line a build (its tests' count, time and skips with their reasons), progress every
# 30 s, the whole output in build/PRESET/test.log, a failure's output in full
# (tools/test_builds.py). host-m32's tests run only where the kernel runs 32-bit programs.
$(addprefix test-,$(TEST_PRESETS)): test-%: deps
	@tools/test_builds.py --jobs $(JOBS) $*

test: deps
	@tools/test_builds.py --jobs $(JOBS) $(TEST_PRESETS)

linux:
	@tools/install-deps.sh linux
	cmake --preset linux
	cmake --build --preset linux -j $(JOBS)

# The core fuzz of make test (500 configurations, seconds), longer: FUZZ_RUNS configurations
# from FUZZ_SEED on. A failure names its seed; `test_core_fuzz 1 SEED` runs that one again.
fuzz-core: build-host-asan
	build/host-asan/tests/test_core_fuzz $(FUZZ_RUNS) $(FUZZ_SEED)

# Both benches run whatever the first finds; either over a budget fails the target.
bench: build-host build-stm32f4
	@rc=0; tools/bench.py build/host || rc=1; \
	tools/stm32f4.py bench build/stm32f4 || rc=1; exit $$rc

firmware: deps-firmware
	@case " $(BOARDS) " in *" $(BOARD) "*) ;; *) echo "make: unknown BOARD '$(BOARD)'; boards: $(BOARDS)" >&2; exit 2 ;; esac
	cmake --preset stm32f4
	cmake --build --preset stm32f4 -j $(JOBS) --target $(FIRMWARE_IMAGE)
	tools/stm32f4.py bench build/stm32f4 --static-only --image $(FIRMWARE_IMAGE)
	@echo "firmware: $(FIRMWARE_ELF) (and .bin, .hex, .map)"

flash: firmware
	tools/stm32f4/flash.sh $(FIRMWARE_ELF)

debug: firmware
	tools/stm32f4/debug.sh $(FIRMWARE_ELF)

clean:
	rm -rf build out
