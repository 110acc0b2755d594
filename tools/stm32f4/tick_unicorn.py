#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Counts the instructions of robot_tick() by running the ELF's own functions in unicorn.

usage: tools/stm32f4/tick_unicorn.py SELFTEST_ELF [ROBOT_ELF] [--json FILE]

The self-test image is loaded into python3-unicorn (Debian's; the QEMU CPU core without
the machine) and its functions are called directly: selftest_begin(), then selftest_step()
and robot_idle() for every tick of the compiled-in scenario, as the image's main loop
does. A code hook counts every instruction executed
between robot_tick()'s entry and its return, and separately those inside hal_* functions
(the replay HAL), and a memory hook records the deepest stack write. This is the second,
independent measurement of the figure QEMU's TIM2 gives under -icount.

With the robot image, the real HAL functions the tick calls are measured too: each call's
instructions with the peripherals as plain memory, and the SysTick handler's own overhead.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from elf32 import Elf  # noqa: E402

try:
    import unicorn
    import unicorn.arm_const as A
except ImportError:
    sys.exit("tick_unicorn: python3-unicorn is missing (Debian: tools/install-deps.sh firmware; "
             "run this script with /usr/bin/python3)")

RETURN = 0x30000000  # a page with nothing but the address the called function returns to
STACK_TOP = 0x2001F000  # a call stack of our own near the end of RAM, away from the image's


class Machine:
    """An STM32F405 memory map in unicorn with one image loaded, and a way to call into it."""

    PLAIN = [(0x08000000, 0x100000),   # flash
             (0x20000000, 0x20000),    # SRAM1 + SRAM2
             (0x40000000, 0x80000),    # APB and AHB1 peripherals, as plain memory
             (0xE0000000, 0x100000),   # the core's private peripherals
             (RETURN, 0x1000)]

    def __init__(self, elf, mmio=()):
        """mmio: (base, size, read(offset, size), write(offset, size, value)) models of
        4 KiB-aligned pages; everything else is plain memory."""
        self.elf = elf
        uc = unicorn.Uc(unicorn.UC_ARCH_ARM, unicorn.UC_MODE_THUMB | unicorn.UC_MODE_MCLASS)
        uc.ctl_set_cpu_model(A.UC_CPU_ARM_CORTEX_M4)
        for base, size in self.PLAIN:
            cuts = sorted((b, b + n) for b, n, _, _ in mmio if base <= b < base + size)
            at = base
            for b, e in cuts + [(base + size, base + size)]:
                if b > at:
                    uc.mem_map(at, b - at)
                at = max(at, e)
        for base, size, read, write in mmio:
            uc.mmio_map(base, size, lambda _uc, off, sz, _u, r=read: r(off, sz), None,
                        lambda _uc, off, sz, val, _u, w=write: w(off, sz, val), None)
        for vaddr, paddr, data, memsz in elf.segments:
            uc.mem_write(vaddr, data)                    # .data lands initialised, .bss zero
            if paddr != vaddr:
                uc.mem_write(paddr, data)
        self.uc = uc

    def call(self, name_or_addr, *args):
        addr = self.elf.addr(name_or_addr) if isinstance(name_or_addr, str) else name_or_addr
        regs = [A.UC_ARM_REG_R0, A.UC_ARM_REG_R1, A.UC_ARM_REG_R2, A.UC_ARM_REG_R3]
        for r, v in zip(regs, args):
            self.uc.reg_write(r, v & 0xFFFFFFFF)
        self.uc.reg_write(A.UC_ARM_REG_SP, STACK_TOP)
        self.uc.reg_write(A.UC_ARM_REG_LR, RETURN | 1)
        self.uc.emu_start(addr | 1, RETURN, timeout=0, count=200_000_000)
        return self.uc.reg_read(A.UC_ARM_REG_R0)

    def read32(self, addr):
        return int.from_bytes(self.uc.mem_read(addr, 4), "little")

    def write32(self, addr, value):
        self.uc.mem_write(addr, (value & 0xFFFFFFFF).to_bytes(4, "little"))


class Counter:
    """Counts instructions of one function call from its entry to its return."""

    def __init__(self, m, func, excluded_prefix="hal_"):
        self.m = m
        self.entry = m.elf.addr(func)
        self.own_range = (self.entry, self.entry + m.elf.symbols[func][1])
        self.own = 0
        self.excluded = [(s, e) for _, s, e in m.elf.functions(excluded_prefix)]
        self.inside = False
        self.ret = None
        self.total = 0
        self.excl = 0
        self.it_pending = []  # addresses of the IT block's instructions not seen yet
        self.min_sp = None
        # A tick that completes a sonar reading posts it to the telemetry: such ticks carry
        # the map update and are told apart from the others.
        self.reading_at = m.elf.addr("telem_post_reading") if "telem_post_reading" in m.elf.symbols else None
        self.reading = False
        self.h_code = m.uc.hook_add(unicorn.UC_HOOK_CODE, self._code)
        # Only writes to the call stack (which starts at STACK_TOP) tell its depth.
        self.h_mem = m.uc.hook_add(unicorn.UC_HOOK_MEM_WRITE, self._mem,
                                   begin=STACK_TOP - 0x4000, end=STACK_TOP - 1)
        # Code translated before the hook existed would run without calling it.
        m.uc.ctl_flush_tb()

    def _code(self, uc, addr, size, _):
        if not self.inside:
            if addr == self.entry:
                self.inside = True
                self.ret = uc.reg_read(A.UC_ARM_REG_LR) & ~1
                self.entry_sp = uc.reg_read(A.UC_ARM_REG_SP)
            else:
                return
        elif addr == self.ret:
            self.inside = False
            self.it_pending = []
            return
        # An instruction of an IT block whose condition fails executes as a no-op: the core
        # spends its slot and QEMU's icount counts it, but unicorn calls no hook for it.
        # Count the block's instructions the hook skipped over.
        while self.it_pending and self.it_pending[0] != addr:
            self._count(self.it_pending.pop(0))
        if self.it_pending:
            self.it_pending.pop(0)
        self._count(addr)
        if addr == self.reading_at:
            self.reading = True
        hw = int.from_bytes(uc.mem_read(addr, 2), "little")
        if hw & 0xFF00 == 0xBF00 and hw & 0xF != 0:  # IT{x{y{z}}} cond
            n = 4 - ((hw & 0xF) & -(hw & 0xF)).bit_length() + 1
            a = addr + 2
            for _ in range(n):
                self.it_pending.append(a)
                first = int.from_bytes(uc.mem_read(a, 2), "little")
                a += 4 if (first >> 11) in (0x1D, 0x1E, 0x1F) else 2

    def _count(self, addr):
        self.total += 1
        if self.own_range[0] <= addr < self.own_range[1]:
            self.own += 1
        for s, e in self.excluded:
            if s <= addr < e:
                self.excl += 1
                break

    def _mem(self, uc, access, addr, size, value, _):
        if self.inside and (self.min_sp is None or addr < self.min_sp):
            self.min_sp = addr

    def take(self):
        """(instructions, instructions outside the excluded functions, stack bytes used,
        whether the tick completed a sonar reading)."""
        depth = self.entry_sp - self.min_sp if self.min_sp is not None else 0
        out = (self.total, self.total - self.excl, depth, self.reading)
        self.total = self.excl = 0
        self.min_sp = None
        self.reading = False
        return out

    def close(self):
        self.m.uc.hook_del(self.h_code)
        self.m.uc.hook_del(self.h_mem)
        self.m.uc.ctl_flush_tb()


def measure_selftest(path):
    """Per tick: (instructions, firmware-only instructions, stack bytes) of robot_tick()."""
    m = Machine(Elf(path))
    st = m.elf.addr("selftest_begin")
    # selftest_begin(st, robot, costs, max): use the image's own statics.
    st_obj = m.elf.addr("st")
    robot = m.elf.addr("robot")
    if m.call(st, st_obj, robot, 0, 0) != 0:
        raise RuntimeError("selftest_begin refused the scenario")
    scenario = m.elf.addr("replay_scenario")
    ticks = m.read32(scenario + 4)
    c = Counter(m, "robot_tick")
    per_tick = []
    for _ in range(ticks):
        m.call("selftest_step", st_obj)
        per_tick.append(c.take())
        # The background loop between ticks, as in the image and in replay_host: it drains
        # the telemetry ring, which changes what the next tick's posts cost.
        m.call("robot_idle", robot)
    c.close()
    return per_tick


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
    cost("hal_servo_set_pulse", "hal_servo_set_pulse", 1500)
    cost("hal_sonar_poll (idle)", "hal_sonar_poll", 0x2001F800)
    cost("hal_sonar_trigger", "hal_sonar_trigger")
    cost("hal_sonar_poll (busy)", "hal_sonar_poll", 0x2001F800)
    # The echo's falling edge: CC2IF set in the echo timer, then its interrupt posts the width.
    tim5 = 0x40000C00
    m.write32(tim5 + 0x10, 1 << 2)
    m.write32(tim5 + 0x38, 5831)
    cost("echo capture ISR", "TIM5_IRQHandler")
    cost("hal_sonar_poll (echo)", "hal_sonar_poll", 0x2001F800)
    # SysTick_Handler around a callback that returns at once (a lone `bx lr`).
    m.uc.mem_write(RETURN + 0x100, b"\x70\x47")
    if m.call("hal_tick_start", RETURN + 0x101, 0) != 0:
        raise RuntimeError("hal_tick_start failed")
    cost("SysTick_Handler (without the callback)", "SysTick_Handler")
    out["SysTick_Handler (without the callback)"]["instructions"] -= 1
    # main.c's tick(ctx) around robot_tick(): its own instructions, with a started robot.
    cfg = 0x2001F800
    m.call("slam_config_default", cfg)
    if m.call("robot_init", m.elf.addr("robot"), cfg) != 0:
        raise RuntimeError("robot_init failed in the robot image")
    c = Counter(m, "tick", excluded_prefix="\0")
    m.call("tick", m.elf.addr("robot"))
    out["tick wrapper (main.c)"] = {"instructions": c.own, "stack": 0}
    c.close()
    return out


def summarize(per_tick):
    n = len(per_tick)
    tot = [t[0] for t in per_tick]
    fw = [t[1] for t in per_tick]
    quiet = [t[0] for t in per_tick if not t[3]]
    return {
        "ticks": n,
        "mean": sum(tot) / n, "worst": max(tot), "worst_tick": tot.index(max(tot)),
        "firmware_mean": sum(fw) / n, "firmware_worst": max(fw),
        "stack": max(t[2] for t in per_tick),
        "worst_without_reading": max(quiet) if quiet else 0,
        "worst_with_reading": max((t[0] for t in per_tick if t[3]), default=0),
    }


def main(argv):
    args = argv[1:]
    out_json = None
    if "--json" in args:
        i = args.index("--json")
        out_json = args[i + 1]
        del args[i:i + 2]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args else 2
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


if __name__ == "__main__":
    sys.exit(main(sys.argv))
