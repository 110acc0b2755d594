# SPDX-License-Identifier: MIT
"""tools/docs.py's generators of the measured figures: `make bench` and bench_world.

Each runs what its README names, reads the figures as numbers (tools/bench.py and
tools/stm32f4.py bench write them with --json) and returns {(page, block): text}.
Instruction counts and sizes repeat exactly on the same build; the wall-clock speed
these tools also print is left out of every block.
"""
import json
import os
import re
import subprocess
import textwrap

from .errors import FAILED, ToolError

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def grouped(value, decimals=0):
    """A figure as the READMEs write it: thousands apart by a space (1 132.2, 57 944)."""
    text = "%.*f" % (decimals, value)
    whole, _, frac = text.partition(".")
    sign = "-" if whole.startswith("-") else ""
    whole = whole.lstrip("-")
    if len(whole) >= 4:
        parts = []
        while len(whole) > 3:
            parts.insert(0, whole[-3:])
            whole = whole[:-3]
        whole = " ".join([whole] + parts)
    return sign + whole + ("." + frac if frac else "")


def run_json(cmd, json_path, what, ok_codes=(0,)):
    """Runs cmd, which writes json_path; its figures, or a ToolError with its output."""
    try:
        p = subprocess.run(cmd, cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True)
    except OSError as e:
        raise ToolError("cannot run %s: %s" % (cmd[0], e.strerror), FAILED) from None
    if p.returncode not in ok_codes or not os.path.exists(json_path):
        raise ToolError("%s exited %d:\n%s%s" % (what, p.returncode, p.stdout[-2000:],
                                                  p.stderr[-2000:]), FAILED)
    with open(json_path, encoding="utf-8") as f:
        return json.load(f)


def host_build(host_sim):
    """The build folder of host_sim (BUILD/host_sim/host_sim)."""
    return os.path.dirname(os.path.dirname(host_sim))


def bench_core(host_sim, work):
    """firmware/README.md's tick on the host and the core's RAM (tools/bench.py
    --core-only: bench_tick under callgrind, `size` of the objects)."""
    out = os.path.join(work, "bench_core.json")
    f = run_json([os.path.join(SRC, "tools", "bench.py"), host_build(host_sim), "--core-only",
                  "--json", out], out, "tools/bench.py --core-only")["core"]
    text = ("On the host (x86-64, `-O2`), over a scripted ten-minute drive with the full sweep "
            "(`tools/bench/bench_tick.c`; HAL calls excluded), `robot_tick()` costs %s "
            "instructions on average over %s ticks and %s at worst: the tick alone, since the "
            "scripted drive calls no `robot_idle()` and its readings wait in the queue."
            % (grouped(f["mean"]), grouped(f["ticks"]), grouped(f["worst"])))
    if "grid_a" in f:
        text += (" The core's static RAM at A×B = %d×%d is %s B (OM + TM %s B, state %s B)."
                 % (f["grid_a"], f["grid_b"], grouped(f["robot_t"]), grouped(f["om_tm"]),
                    grouped(f["robot_t"] - f["om_tm"])))
    return {("firmware/README.md", "bench-core"): wrap(text) + "\n"}


def bench_sim(host_sim, work):
    """host_sim/README.md's instructions per control period of the default run, by part
    (tools/bench.py --sim-only: host_sim under callgrind)."""
    out = os.path.join(work, "bench_sim.json")
    f = run_json([os.path.join(SRC, "tools", "bench.py"), host_build(host_sim), "--sim-only",
                  "--json", out], out, "tools/bench.py --sim-only", ok_codes=(0, 1))["sim"]
    labels = {
        "firmware: robot_tick() without its HAL calls":
            "firmware: `robot_tick()` without its HAL calls",
        "firmware: robot_idle(), the background loop":
            "firmware: `robot_idle()`, the background loop (mapping, pose correction, telemetry)",
        "simulated world: sim_step() and the tick's HAL calls":
            "simulated world: `sim_step()` and the tick's HAL calls",
        "host_sim measuring and logging every period":
            "host_sim's measuring and logs, every period (`observe_tick()`)",
        "end of the run: scores, maps, metrics.json":
            "end of the run: scores, maps, `metrics.json`",
    }
    lines = ["| part | instructions per control period |", "|---|---|"]
    for name, per in f["parts"]:
        lines.append("| %s | %s |" % (labels.get(name, name), grouped(per)))
    lines.append("| **whole run** (budget %s; the bench fails over it) | **%s** (%.1f M "
                 "instructions) |" % (grouped(f["budget"]), grouped(f["per_period"]),
                                      f["total"] / 1e6))
    lines += ["", wrap("The end of the run is %.1f %% of it (budget %.0f %%)."
                       % (100.0 * f["end_share"], 100.0 * f["end_budget"]))]
    return {("host_sim/README.md", "bench-sim"): "\n".join(lines) + "\n"}


# bench_world's parts as hal/host/README.md's commands count them: (row, toggles).
WORLD_HAL = ["hal_encoder_count", "hal_sonar_poll", "hal_sonar_trigger", "hal_servo_set_pulse",
             "hal_motor_set"]
WORLD_PARTS = (
    ("world (`sim_step` + the HAL calls into it, pings included)", ["sim_step"] + WORLD_HAL),
    ("firmware run (`robot_tick` and the HAL calls toggled by name)",
     ["robot_tick"] + WORLD_HAL + ["hal_watchdog_kick"]),
    ("whole `hal_host_step()` (with the benchmark's own drive)", ["hal_host_step"]),
)
WORLD_TICKS = 60000


def bench_world(host_sim, work):
    """hal/host/README.md's instructions per tick of bench_world: the commands of its
    Performance section, each a callgrind run of 60 000 ticks in the default room."""
    bench = os.path.join(host_build(host_sim), "hal", "host", "bench_world")
    if not os.access(bench, os.X_OK):
        raise ToolError("%s is missing: build the host preset first" % bench, FAILED)
    room = os.path.join("host_sim", "rooms", "default.room")
    rows = []
    for k, (label, toggles) in enumerate(WORLD_PARTS):
        out = os.path.join(work, "world%d.callgrind" % k)
        cmd = ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out] + \
            ["--toggle-collect=" + t for t in toggles] + [bench, room, str(WORLD_TICKS)]
        try:
            p = subprocess.run(cmd, cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
        except OSError as e:
            raise ToolError("cannot run valgrind: %s" % e.strerror, FAILED) from None
        m = re.search(r"Collected : (\d+)", p.stderr)
        if p.returncode != 0 or m is None:
            raise ToolError("bench_world under callgrind exited %d:\n%s"
                            % (p.returncode, p.stderr[-2000:]), FAILED)
        rows.append("| %s | %s |" % (label, grouped(int(m.group(1)) / WORLD_TICKS)))
    lines = ["| part | instructions per tick (the default errors: the typical sonar) |",
             "|---|---|"] + rows
    return {("hal/host/README.md", "bench-world"): "\n".join(lines) + "\n"}


def build_compiler(build):
    """The C compiler a CMake build folder was configured with (the ARM toolchain file
    finds it as ARM_NONE_EABI_GCC)."""
    try:
        with open(os.path.join(build, "CMakeCache.txt"), encoding="utf-8") as f:
            for line in f:
                if line.startswith(("CMAKE_C_COMPILER:", "ARM_NONE_EABI_GCC:")):
                    return line.split("=", 1)[1].strip()
    except OSError:
        pass
    return "arm-none-eabi-gcc"


def gcc_version(compiler):
    try:
        v = subprocess.run([compiler, "-dumpversion"], stdout=subprocess.PIPE, text=True,
                           check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        raise ToolError("%s -dumpversion failed" % compiler, FAILED) from None
    return ".".join(v.split(".")[:2])


def bench_stm32f4(build, work):
    """hal/stm32f4/README.md's table of `make bench` on the Cortex-M4, the HAL calls of the
    tick beside it (tools/stm32f4.py bench BUILD --json: QEMU, unicorn, the image's sizes
    and stack)."""
    out = os.path.join(work, "bench_stm32f4.json")
    f = run_json([os.path.join(SRC, "tools", "stm32f4.py"), "bench", build, "--json", out], out,
                 "tools/stm32f4.py bench", ok_codes=(0, 1))
    t, s, bg = f["tick"], f["sizes"], f["background"]
    kib = f["flash_budget"] // 1024
    rows = [
        ("instructions per `robot_tick()`, QEMU TIM2 under `-icount`",
         "mean %s, worst %s" % (grouped(t["qemu_mean"], 1), grouped(t["qemu_worst"])),
         "≤ %s" % grouped(f["tick_budget"])),
        ("the same in unicorn with a code hook",
         "mean %s, worst %s (%s)" % (grouped(t["unicorn_mean"], 1), grouped(t["unicorn_worst"]),
                                     "identical in all %s ticks" % grouped(t["compared"])
                                     if t["identical"] == t["compared"] else
                                     "%s of %s ticks identical" % (grouped(t["identical"]),
                                                                   grouped(t["compared"]))), ""),
        ("firmware only, the replay HAL's calls excluded",
         "mean %s, worst %s" % (grouped(t["firmware_mean"], 1), grouped(t["firmware_worst"])), ""),
        ("worst tick with the robot image's own HAL on the tick path (at most %s), bound"
         % grouped(f["hal_per_tick"]), grouped(f["bound"]), "≤ %s" % grouped(f["tick_budget"])),
        ("a reading mapped in the background loop, free-space ray included",
         "mean %s, worst %s" % (grouped(bg["reading_mean"]), grouped(bg["reading_worst"])), ""),
        ("worst `robot_idle()` call (the pose correction's match, the way to a frontier, "
         "telemetry)", grouped(bg["idle_worst"]), "≤ %s" % grouped(bg["idle_budget"])),
        ("flash (`.text` + `.data`)", "%s B" % grouped(s["text"] + s["data"]),
         "≤ %d KiB" % kib),
        ("RAM (`.data` + `.bss`, with the %s B stack reserve)" % grouped(s["stack_reserve"]),
         "%s B" % grouped(s["data"] + s["bss"]),
         "≤ 2·A·B + 8 KiB = %s B" % grouped(f["ram_budget"])),
        ("stack of the tick path (`-fcallgraph-info`, exception frame included)",
         "%s B" % grouped(f["stack"]["SysTick_Handler"]), "≤ %s B" % grouped(f["stack_budget"])),
        ("stack with every handler nested (main, USART1, tick, echo, fault)",
         "%s B" % grouped(f["stack"]["all nested"]),
         "≤ %s B reserved" % grouped(s["stack_reserve"])),
    ]
    ticks = t["ticks"]
    head = ("`make bench` runs `tools/stm32f4.py bench build/stm32f4` (arm-none-eabi-gcc %s "
            "`-O2`; the self-test's scenario `%s`, %s s, %s ticks, `make trace`):"
            % (gcc_version(build_compiler(build)), t["scenario"],
               grouped(ticks / 100.0), grouped(ticks)))
    lines = [wrap(head), "", "| figure | value | budget |", "|---|---|---|"]
    lines += [("| %s | %s | %s |" % r).replace("|  |", "| |") for r in rows]
    spare = f["tick_budget"] - f["bound"]
    us = f["bound"] / 168.0
    lines += ["", wrap(
        "The bound of the worst tick has %s instructions to spare. These are instructions, "
        "not cycles: at about one instruction a cycle the bound takes some %.0f µs at 168 MHz, "
        "%.2f %% of the 10 ms period, and a 16 MHz part would spend %.1f %% of it."
        % (grouped(spare), us, us / 100.0, f["bound"] / 16.0 / 100.0))]
    hal = ["| HAL call (the robot image, in unicorn) | instructions |", "|---|---|"]
    hal += ["| %s | %s |" % (code_name(k), grouped(v)) for k, v in f["hal"].items()]
    hal += ["| every HAL call a tick can make, and the SysTick entry | %s |"
            % grouped(f["hal_per_tick"])]
    return {("hal/stm32f4/README.md", "bench-stm32f4"): "\n".join(lines) + "\n",
            ("hal/stm32f4/README.md", "bench-stm32f4-hal"): "\n".join(hal) + "\n"}


def code_name(label):
    """hal_sonar_poll (idle) as `hal_sonar_poll` (idle): a function's name as code."""
    first, _, rest = label.partition(" ")
    return ("`%s` %s" % (first, rest) if "_" in first else label).strip()


def wrap(text, width=90):
    """A paragraph broken as the READMEs break theirs."""
    return "\n".join(textwrap.wrap(text, width=width, break_on_hyphens=False,
                                   break_long_words=False))
