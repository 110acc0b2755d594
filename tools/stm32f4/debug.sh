#!/bin/sh
# SPDX-License-Identifier: MIT
# Debugs an image on the board: OpenOCD on the ST-LINK in the background, gdb-multiarch
# attached to it with the image's symbols; OpenOCD stops when gdb does.
#
#   tools/stm32f4/debug.sh [IMAGE.elf]      (make debug)
#
# Semihosting is switched on, so the self-test image (sonarslam_selftest.elf) also runs on
# a real board and prints its report in OpenOCD's output. `load` in gdb programs the image.
set -eu

ELF=${1:-build/stm32f4/hal/stm32f4/sonarslam_stm32f4.elf}
if [ ! -f "$ELF" ]; then
    echo "debug: $ELF not found: build it first with 'make firmware'" >&2
    exit 1
fi
for tool in openocd gdb-multiarch; do
    if ! command -v $tool >/dev/null 2>&1; then
        echo "debug: $tool is not installed: tools/install-deps.sh flash" >&2
        exit 1
    fi
done

LOG=$(mktemp "${TMPDIR:-/tmp}/sonarslam-openocd.XXXXXX")
openocd -f interface/stlink.cfg -f target/stm32f4x.cfg >"$LOG" 2>&1 &
OPENOCD=$!
trap 'kill $OPENOCD 2>/dev/null || true; rm -f "$LOG"' EXIT INT TERM

# Wait for OpenOCD to find the probe and open its gdb port, or to give up.
tries=0
until grep -q "Listening on port 3333" "$LOG"; do
    if ! kill -0 $OPENOCD 2>/dev/null || [ $tries -ge 50 ]; then
        echo "debug: OpenOCD did not start. Its output:" >&2
        cat "$LOG" >&2
        echo "debug: is an ST-LINK plugged in and the board powered?" >&2
        exit 1
    fi
    tries=$((tries + 1))
    sleep 0.2
done

gdb-multiarch -q "$ELF" \
    -ex "target extended-remote localhost:3333" \
    -ex "monitor arm semihosting enable" \
    -ex "monitor reset halt"
