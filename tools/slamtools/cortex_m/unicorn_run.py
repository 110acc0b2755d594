# SPDX-License-Identifier: MIT
"""Runs a Cortex-M image's own functions in unicorn and counts their instructions.

A library for a chip's tools (slamtools/stm32f4/tick_unicorn.py, bench_arm.py, the driver
tests): Machine loads an image into python3-unicorn (Debian's; the QEMU CPU core without
the machine) over the chip's memory map, which a subclass gives, and calls its functions
directly. Counter counts every instruction executed between a function's entry and its
return, and separately those inside hal_* functions, and records the deepest stack write.

measure_selftest() plays the self-test image (hal/cortex_m/selftest) the way its main loop
does: selftest_begin(), then selftest_step() and robot_idle() for every tick of the
compiled-in scenario, counting robot_tick(). It is the second, independent measurement of
the figure the chip's counter gives in QEMU under -icount.

Importing it without python3-unicorn is a ToolError (exit status 1) that says how to get it:
a tool imports it only once it needs it.
"""
from ..errors import FAILED, ToolError

try:
    import unicorn
    import unicorn.arm_const as A
except ImportError:
    raise ToolError("python3-unicorn is missing (Debian: tools/install-deps.sh firmware; "
                    "run this tool with /usr/bin/python3)", FAILED) from None

RETURN = 0x30000000  # a page with nothing but the address the called function returns to


class Machine:
    """A chip's memory map in unicorn with one image loaded, and a way to call into it.

    A chip's subclass sets PLAIN, the (base, size) regions mapped as plain memory (flash,
    RAM, peripherals, the core's private peripherals at 0xE0000000), and STACK_TOP, the top
    of a call stack of the tools' own in RAM, away from the image's. RETURN is added.
    CPU is unicorn's model of the core (A.UC_CPU_ARM_CORTEX_M3, _M7...): the M4 unless the
    subclass says otherwise."""

    PLAIN = ()
    STACK_TOP = None
    CPU = A.UC_CPU_ARM_CORTEX_M4

    def __init__(self, elf, mmio=()):
        """mmio: (base, size, read(offset, size), write(offset, size, value)) models of
        4 KiB-aligned pages; everything else is plain memory."""
        if not self.PLAIN or self.STACK_TOP is None:
            raise TypeError("Machine needs a chip's subclass that sets PLAIN and STACK_TOP")
        self.elf = elf
        uc = unicorn.Uc(unicorn.UC_ARCH_ARM, unicorn.UC_MODE_THUMB | unicorn.UC_MODE_MCLASS)
        uc.ctl_set_cpu_model(self.CPU)
        for base, size in list(self.PLAIN) + [(RETURN, 0x1000)]:
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
        self.uc.reg_write(A.UC_ARM_REG_SP, self.STACK_TOP)
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
        # Only writes to the call stack (which starts at STACK_TOP) tell its depth; the
        # image's own data, up to _ebss (a board's map may reach close to STACK_TOP), not.
        low = max(m.STACK_TOP - 0x4000, m.elf.symbols.get("_ebss", (0,))[0])
        self.h_mem = m.uc.hook_add(unicorn.UC_HOOK_MEM_WRITE, self._mem,
                                   begin=low, end=m.STACK_TOP - 1)
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


def measure_selftest(m):
    """Per tick of the self-test image loaded in m: (instructions, firmware-only
    instructions, stack bytes, whether the tick completed a reading) of robot_tick()."""
    st = m.elf.addr("selftest_begin")
    # selftest_begin(st, robot, costs, max): use the image's own statics.
    st_obj = m.elf.addr("st")
    robot = m.elf.addr("robot")
    if m.call(st, st_obj, robot, 0, 0) != 0:
        raise ToolError("selftest_begin refused the scenario", FAILED)
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
