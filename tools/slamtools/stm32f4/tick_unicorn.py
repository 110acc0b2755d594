# SPDX-License-Identifier: MIT
"""Counts the instructions of robot_tick() by running the ELF's own functions in unicorn.

usage: tools/stm32f4.py tick SELFTEST_ELF [ROBOT_ELF] [--json FILE]

The self-test image is loaded into python3-unicorn over the STM32F405's memory map and
played as its main loop does (slamtools/cortex_m/unicorn_run.py): a code hook counts every
instruction executed between robot_tick()'s entry and its return, and separately those
inside hal_* functions (the replay HAL), and a memory hook records the deepest stack write.
This is the second, independent measurement of the figure QEMU's TIM2 gives under -icount.

With the robot image, the real HAL functions the tick calls are measured too: each call's
instructions with the peripherals as plain memory, and the SysTick handler's own overhead.
Without python3-unicorn importing this module is a ToolError (exit status 1).
"""
import json

from ..cortex_m import unicorn_run
from ..cortex_m.elf32 import Elf
from ..cortex_m.unicorn_run import RETURN, Counter, summarize, unicorn  # noqa: F401  (the API)
from ..commands import take_value
from ..errors import FAILED, ToolError


class Machine(unicorn_run.Machine):
    """The STM32F405's memory map in unicorn (the F411's lies within it)."""

    PLAIN = [(0x08000000, 0x100000),   # flash
             (0x20000000, 0x20000),    # SRAM1 + SRAM2
             (0x40000000, 0x80000),    # APB and AHB1 peripherals, as plain memory
             (0xE0000000, 0x100000)]   # the core's private peripherals
    STACK_TOP = 0x2001F000  # a call stack of our own near the end of RAM, away from the image's


def measure_selftest(path):
    """Per tick: (instructions, firmware-only instructions, stack bytes, whether the tick
    completed a reading) of robot_tick(), in the self-test image at path."""
    return unicorn_run.measure_selftest(Machine(Elf(path)))


def measure_hal(path):
    """Instructions of each real HAL call the tick makes, from the robot image."""
    m = Machine(Elf(path))
    m.call("hal_init")  # clocks fall back to HSI here too: the ready bits stay zero
    out = {}

    def cost(label, func, *args):
        c = Counter(m, func, excluded_prefix="\0")
        m.call(func, *args)
        n, _, depth, _ = c.take()
        c.close()
        out[label] = {"instructions": n, "stack": depth}

    cost("hal_time_us", "hal_time_us")
    cost("hal_encoder_count", "hal_encoder_count", 0)
    cost("hal_motor_set", "hal_motor_set", 1, -500)  # int16_t arrives sign-extended
    # The tick's servo and sonar are instance 0 (HAL_SERVO_SWEEP, HAL_SONAR_SWEPT).
    cost("hal_servo_set_pulse", "hal_servo_set_pulse", 0, 1500)
    cost("hal_sonar_poll (idle)", "hal_sonar_poll", 0, 0x2001F800)
    cost("hal_sonar_trigger", "hal_sonar_trigger", 0)
    cost("hal_sonar_poll (busy)", "hal_sonar_poll", 0, 0x2001F800)
    # The echo's falling edge: CC2IF set in the echo timer, then its interrupt posts the width.
    tim5 = 0x40000C00
    m.write32(tim5 + 0x10, 1 << 2)
    m.write32(tim5 + 0x38, 5831)
    cost("echo capture ISR", "TIM5_IRQHandler")
    cost("hal_sonar_poll (echo)", "hal_sonar_poll", 0, 0x2001F800)
    # SysTick_Handler around a callback that returns at once (a lone `bx lr`).
    m.uc.mem_write(RETURN + 0x100, b"\x70\x47")
    if m.call("hal_tick_start", RETURN + 0x101, 0) != 0:
        raise ToolError("hal_tick_start failed in the robot image", FAILED)
    cost("SysTick_Handler (without the callback)", "SysTick_Handler")
    out["SysTick_Handler (without the callback)"]["instructions"] -= 1
    # main.c's tick(ctx) around robot_tick(): its own instructions, with a started robot.
    cfg = 0x2001F800
    m.call("slam_config_default", cfg)
    if m.call("robot_init", m.elf.addr("robot"), cfg) != 0:
        raise ToolError("robot_init failed in the robot image", FAILED)
    c = Counter(m, "tick", excluded_prefix="\0")
    m.call("tick", m.elf.addr("robot"))
    out["tick wrapper (main.c)"] = {"instructions": c.own, "stack": 0}
    c.close()
    return out


def main(argv):
    args = argv[1:]
    out_json = take_value(args, "--json", "a file")
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args else 2
    if len(args) > 2 or any(a.startswith("-") for a in args):
        raise ToolError("give SELFTEST_ELF and at most ROBOT_ELF (--help)")
    per_tick = measure_selftest(args[0])
    s = summarize(per_tick)
    result = {"selftest": s, "per_tick": [t[0] for t in per_tick]}
    print("unicorn: robot_tick() over %d ticks: mean %.1f, worst %d instructions (tick %d); "
          "firmware only (replay HAL excluded): mean %.1f, worst %d; stack %d bytes"
          % (s["ticks"], s["mean"], s["worst"], s["worst_tick"], s["firmware_mean"],
             s["firmware_worst"], s["stack"]))
    print("unicorn: ticks that complete a sonar reading: worst %d; the others: worst %d"
          % (s["worst_with_reading"], s["worst_without_reading"]))
    if len(args) > 1:
        hal = measure_hal(args[1])
        result["hal"] = hal
        for k, v in hal.items():
            print("unicorn: %-40s %3d instructions, %2d bytes of stack"
                  % (k, v["instructions"], v["stack"]))
    if out_json:
        with open(out_json, "w") as f:
            json.dump(result, f)
    return 0
