# SPDX-License-Identifier: MIT
"""The STM32F4 image measured, not timed: tick instructions, sizes, stack, against budgets.

usage: tools/stm32f4.py bench [BUILD_DIR] [--static-only] [--image NAME] [--json FILE]
       (BUILD_DIR defaults to build/stm32f4, made by `make firmware`; NAME is the robot
       image, sonarslam_stm32f4 by default, sonarslam_<board> for another board table;
       FILE receives every figure printed, for tools/docs.py's tables)

1. Instructions per robot_tick() over the self-test scenario, two ways: TIM2 under QEMU
   -icount (the self-test image's own measurement) and the image's functions run in
   python3-unicorn with a code hook (tools/stm32f4.py tick). The two must agree tick by tick.
2. The real HAL calls of the tick, from the robot image in unicorn, and a bound on the tick
   with them: the worst firmware-only tick plus every HAL call a tick can make.
3. .text/.data/.bss of the robot image (arm-none-eabi-size); RAM counts the stack reserve.
4. The worst-case stack depth of the tick path and of all handlers nested
   (tools/cortex_m.py stack-depth, from -fcallgraph-info/-fstack-usage).

Budgets: worst tick <= 1500 instructions; RAM <= 2*A*B + 8 KiB (A x B the image's grid,
its symbols _grid_a and _grid_b); flash <= 64 KiB; tick stack <= 512 bytes; and a grid of
at least 240 x 240 cells. Exit status 1 when one is exceeded or a measurement fails, 2 for
a wrong command line or an image that is not there. --static-only skips 1 and 2 (no QEMU,
no unicorn): what the ctest stm32f4_budgets checks, for every board's image.
"""
import json
import os
import subprocess
import tempfile

from ..cortex_m import stack_depth
from ..cortex_m.elf32 import Elf
from ..commands import take_value
from ..errors import FAILED, ToolError


TICK_BUDGET = 1500
IDLE_BUDGET = 960_000  # one robot_idle() call between two 60 ms readings on a 16 MHz part
READING_PLAN = 400  # instructions a reading was to cost the mapper when it mapped in the tick
FLASH_BUDGET = 64 * 1024  # half of a 128 KiB part: the rest for map storage and a bootloader
STACK_BUDGET = 512
GRID_MIN = (240, 240)  # the least map an STM32F4 board holds: 12 m x 12 m at 50 mm


def sizes(elf):
    size = os.environ.get("SIZE", "arm-none-eabi-size")
    try:
        out = subprocess.run([size, elf], stdout=subprocess.PIPE, text=True, check=True).stdout
        text, data, bss = (int(x) for x in out.splitlines()[1].split()[:3])
    except (OSError, subprocess.CalledProcessError, IndexError, ValueError) as e:
        raise ToolError("%s %s gave no sizes: %s" % (size, elf, e), FAILED) from None
    return text, data, bss


def stack(elf):
    """The image's interrupt nesting, its tick through main.c's tick(): ({root: ...}, text)."""
    result, lines = stack_depth.measure(elf, indirect={"SysTick_Handler": ["tick"]})
    return result, "\n".join(lines)


def qemu_costs(selftest_elf):
    from . import qemu
    with tempfile.TemporaryDirectory(prefix="slam-bench-") as tmp:
        status, text = qemu.run_selftest_image(selftest_elf, tmp)
    if status != 0:
        raise ToolError("the self-test image exited with %d" % status, FAILED)
    _, _, info, costs, summary = qemu.parse_report(text, "MCU")
    return costs, summary, info


def main(argv):
    args = argv[1:]
    static_only = "--static-only" in args
    args = [a for a in args if a != "--static-only"]
    image = take_value(args, "--image", "the name of a robot image", "sonarslam_stm32f4")
    out_json = take_value(args, "--json", "a file")
    if args and args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if len(args) > 1 or (args and args[0].startswith("-")):
        raise ToolError("unknown argument %r (--help)" % args[-1])
    build = args[0] if args else "build/stm32f4"
    img_dir = os.path.join(build, "hal", "stm32f4")
    robot_elf = os.path.join(img_dir, image + ".elf")
    selftest_elf = os.path.join(img_dir, "sonarslam_selftest.elf")
    for p in (robot_elf,) if static_only else (robot_elf, selftest_elf):
        if not os.path.exists(p):
            raise ToolError("%s is missing: build the stm32f4 preset first (make firmware)" % p)

    verdicts = []
    # What is printed, as numbers: tools/docs.py formats the README's tables from it.
    figures = {"image": image, "budgets": {}}

    def budget(name, value, limit, unit):
        ok = value <= limit
        verdicts.append(ok)
        figures["budgets"][name] = {"value": value, "limit": limit, "unit": unit, "ok": ok}
        print("  %-44s %7d %-12s budget %6d  %s" % (name, value, unit, limit,
                                                     "ok" if ok else "OVER BUDGET"))

    robot = Elf(robot_elf)
    if "robot" not in robot.symbols:
        raise ToolError("%s has no object robot: not a robot image" % robot_elf)
    grid = robot.symbols["robot"][1]
    text, data, bss = sizes(robot_elf)
    stack_reserve = robot.symbols["_stack_size"][0] if "_stack_size" in robot.symbols else 0
    # OM + TM: 2*A*B cells, A and B the image's own (its board's, as absolute symbols).
    if "_grid_a" not in robot.symbols or "_grid_b" not in robot.symbols:
        raise ToolError("%s has no _grid_a/_grid_b: link it with cortex_m_image(... GRID A B)"
                        % robot_elf, FAILED)
    grid_a, grid_b = robot.symbols["_grid_a"][0], robot.symbols["_grid_b"][0]
    ram_budget = 2 * grid_a * grid_b + 8 * 1024
    figures.update(grid={"a": grid_a, "b": grid_b},
                   sizes={"text": text, "data": data, "bss": bss, "stack_reserve": stack_reserve,
                          "robot_t": grid},
                   ram_budget=ram_budget, flash_budget=FLASH_BUDGET, stack_budget=STACK_BUDGET,
                   tick_budget=TICK_BUDGET)

    print("sonarslam STM32F4 image (%s), grid %d x %d cells" % (robot_elf, grid_a, grid_b))
    print("  sizes (arm-none-eabi-size): .text %d  .data %d  .bss %d (of which stack %d, robot_t %d)"
          % (text, data, bss, stack_reserve, grid))
    st, st_text = stack(robot_elf)
    for line in st_text.strip().splitlines():
        print("  stack: " + line)
    figures["stack"] = {k: v["bytes"] for k, v in st.items()}

    if not static_only:
        from . import tick_unicorn
        costs, summary, info = qemu_costs(selftest_elf)
        n = summary["ticks"]
        print("  robot_tick() over the self-test scenario %s (%d ticks):" % (info["scenario"], n))
        print("    QEMU, TIM2 under -icount:         mean %.1f, worst %d instructions (tick %d)"
              % (summary["sum"] / n, summary["worst"], summary["at"]))
        per_tick = tick_unicorn.measure_selftest(selftest_elf)
        u = tick_unicorn.summarize(per_tick)
        print("    unicorn, code hook:               mean %.1f, worst %d instructions (tick %d)"
              % (u["mean"], u["worst"], u["worst_tick"]))
        # The image keeps each tick's cost only as far as the RAM its map leaves allows
        # (selftest_main.c); its sum and worst cover every tick.
        kept = min(n, len(per_tick))
        same = sum(1 for (t, _, _, _), q in zip(per_tick, costs) if t == q)
        print("    cross-check: %d of the %d ticks the image kept identical in both; sum and "
              "worst of all %d ticks %s" % (same, len(costs), n, "identical"
                                            if (sum(t[0] for t in per_tick), u["worst"])
                                            == (summary["sum"], summary["worst"])
                                            else "DIFFERENT"))
        if (same != len(costs) or len(costs) > kept or len(per_tick) != n
                or sum(t[0] for t in per_tick) != summary["sum"] or u["worst"] != summary["worst"]):
            verdicts.append(False)
            print("    CROSS-CHECK FAILED")
        print("    firmware only (replay HAL excluded): mean %.1f, worst %d; dynamic stack %d bytes"
              % (u["firmware_mean"], u["firmware_worst"], u["stack"]))
        print("    ticks that complete a sonar reading: worst %d; the others: worst %d"
              % (u["worst_with_reading"], u["worst_without_reading"]))
        hal = tick_unicorn.measure_hal(robot_elf)
        print("  the robot image's HAL on the tick path (unicorn):")
        for k, v in hal.items():
            print("    %-40s %3d instructions" % (k, v["instructions"]))
        per_tick_hal = (hal["SysTick_Handler (without the callback)"]["instructions"]
                        + hal["tick wrapper (main.c)"]["instructions"]
                        + hal["hal_time_us"]["instructions"]
                        + 2 * hal["hal_encoder_count"]["instructions"]
                        + max(hal[k]["instructions"] for k in hal if k.startswith("hal_sonar_poll"))
                        + hal["hal_sonar_trigger"]["instructions"]
                        + hal["hal_servo_set_pulse"]["instructions"]
                        + 2 * hal["hal_motor_set"]["instructions"])
        bound = u["firmware_worst"] + per_tick_hal
        print("    every HAL call a tick can make, and the SysTick entry: %d instructions"
              % per_tick_hal)
        figures["tick"] = {
            "ticks": n, "scenario": info["scenario"], "qemu_mean": summary["sum"] / n, "qemu_worst": summary["worst"],
            "qemu_worst_tick": summary["at"], "unicorn_mean": u["mean"],
            "unicorn_worst": u["worst"], "identical": same, "compared": len(costs),
            "firmware_mean": u["firmware_mean"], "firmware_worst": u["firmware_worst"],
            "dynamic_stack": u["stack"], "worst_with_reading": u["worst_with_reading"],
            "worst_without_reading": u["worst_without_reading"]}
        figures["hal"] = {k: v["instructions"] for k, v in hal.items()}
        figures["hal_per_tick"] = per_tick_hal
        figures["bound"] = bound
        figures["background"] = {"reading_mean": summary["reading_mean"],
                                 "reading_worst": summary["reading_worst"],
                                 "idle_worst": summary["idle_worst"],
                                 "idle_worst_after": summary["idle_after"], "idle_budget": IDLE_BUDGET,
                                 "reading_plan": READING_PLAN}
        print("  the background loop (QEMU, TIM2 under -icount):")
        print("    one reading mapped, free-space rays included: mean %d, worst %d instructions"
              % (summary["reading_mean"], summary["reading_worst"]))
        print("    worst robot_idle() call (a match of the held-back hits, a way to a frontier, "
              "saves, telemetry): %d instructions, after tick %d"
              % (summary["idle_worst"], summary["idle_after"]))
        print("  budgets:")
        budget("worst robot_tick(), measured (QEMU = unicorn)", summary["worst"], TICK_BUDGET,
               "instructions")
        budget("worst tick with the robot image's HAL, bound", bound, TICK_BUDGET, "instructions")
        budget("worst robot_idle() call", summary["idle_worst"], IDLE_BUDGET, "instructions")
        # Not a budget of the tick: the background loop maps the readings (localize.h). The
        # figure the free-space evidence was first planned at, for the README to compare.
        print("  %-46s %6d instructions (planned at %d, in the tick)"
              % ("worst reading mapped, background loop", summary["reading_worst"], READING_PLAN))
    else:
        print("  budgets:")
    # Not over a budget but under a floor: the map the board promises (DESIGN.md).
    ok = grid_a >= GRID_MIN[0] and grid_b >= GRID_MIN[1]
    verdicts.append(ok)
    print("  %-44s %7s %-12s least %6s  %s" % ("grid A x B (12 m x 12 m at 50 mm)",
                                               "%dx%d" % (grid_a, grid_b), "cells",
                                               "%dx%d" % GRID_MIN, "ok" if ok else "TOO SMALL"))
    budget("RAM: .data + .bss incl. stack (2*A*B + 8 KiB)", data + bss, ram_budget, "bytes")
    budget("flash: .text + .data", text + data, FLASH_BUDGET, "bytes")
    budget("tick stack (SysTick_Handler, static)", st["SysTick_Handler"]["bytes"], STACK_BUDGET,
           "bytes")
    budget("all handlers nested, within the reserve", st["all nested"]["bytes"], stack_reserve,
           "bytes")
    if out_json:
        figures["ok"] = all(verdicts)
        try:
            with open(out_json, "w") as f:
                json.dump(figures, f, indent=1)
        except OSError as e:
            raise ToolError("cannot write %s: %s" % (out_json, e.strerror), FAILED) from None
    return 0 if all(verdicts) else FAILED
