#!/bin/sh
# SPDX-License-Identifier: MIT
# Programs the robot image into the STM32F4 through an ST-LINK: OpenOCD when it is
# installed (interface/stlink.cfg, target/stm32f4x.cfg), st-flash otherwise.
#
#   tools/stm32f4/flash.sh [IMAGE.elf]      (make flash)
#
# Only the sectors the image occupies are erased: the maps saved in the storage sectors
# (10 and 11 of an F405, 6 and 7 of an F411) survive. OpenOCD's stm32f4x target and
# st-flash serve every STM32F4, the F411 "Black Pill" included.
set -eu

ELF=${1:-build/stm32f4/hal/stm32f4/sonarslam_stm32f4.elf}
BIN=${ELF%.elf}.bin
if [ ! -f "$ELF" ] || [ ! -f "$BIN" ]; then
    echo "flash: $ELF (and .bin) not found: build it first with 'make firmware'" >&2
    exit 1
fi

if command -v openocd >/dev/null 2>&1; then
    echo "flash: programming $ELF with OpenOCD"
    if ! openocd -f interface/stlink.cfg -f target/stm32f4x.cfg \
                 -c "program $ELF verify reset exit"; then
        echo "flash: OpenOCD could not program the board. Is an ST-LINK plugged in (lsusb shows" >&2
        echo "       0483:3748 or 0483:374b), the board powered, and SWDIO, SWCLK and GND wired?" >&2
        exit 1
    fi
elif command -v st-flash >/dev/null 2>&1; then
    if ! st-info --probe 2>/dev/null | grep -q "Found [1-9]"; then
        echo "flash: st-flash found no ST-LINK probe: plug one in and power the board" >&2
        exit 1
    fi
    echo "flash: programming $BIN at 0x08000000 with st-flash"
    st-flash --reset write "$BIN" 0x08000000
else
    echo "flash: neither OpenOCD nor st-flash is installed. Install one of them:" >&2
    echo "         tools/install-deps.sh flash           (OpenOCD and gdb-multiarch)" >&2
    echo "         sudo apt-get install stlink-tools     (st-flash)" >&2
    exit 1
fi
echo "flash: done; the robot prints its banner on its telemetry UART (115200 8N1; the pins"
echo "       are in hal/stm32f4/README.md)"
