#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Tests the STM32F4 drivers' own code against models of their registers.

usage: tests/stm32f4/drivers_model_test.py DRIVER_IMAGE_ELF [--board NAME]

NAME is the board table the image was built for (hal/stm32f4/board_NAME.h; default
generic_f405): its pins, timers, storage sectors and clock tree are what is expected.

QEMU emulates neither the flash interface nor the IWDG, nor encoder mode, captures or
GPIO, so the test image's functions (every driver linked) run in python3-unicorn here.
Flash and IWDG are models written from RM0090 (RM0383 for the F411, the same interface): the flash key sequence and LOCK, sector
erase (SER, SNB, STRT), programming only with PG set and at the PSIZE width, bits that
only go from 1 to 0, BSY for a while after every operation, rc_w1 error flags; the IWDG
key register, PR/RLR writable only after 0x5555, reloads. Timers, SysTick and GPIO are
plain memory the test sets (a counter, a capture) and reads back (a compare value, a
BSRR word), RCC's ready flags answer or not as a test wants. Checked: the clock tree and
its fallbacks, map storage, the watchdog, the tick's overrun detection, the sonar
state machine with its capture interrupt, servo clamping, motor PWM and direction pins,
encoder counters and the safe state a fault leaves the motors in.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
from slamtools.errors import ToolError  # noqa: E402
try:
    from slamtools.cortex_m.elf32 import Elf  # noqa: E402
    from slamtools.stm32f4.tick_unicorn import Machine, unicorn  # noqa: E402
except ToolError as e:  # python3-unicorn is missing
    sys.exit("drivers_model_test: %s" % e)

FLASH_BASE = 0x08000000
SECTOR_BYTES = 128 * 1024

# What each board table puts where, and the clock tree it asks for.
BOARDS = {
    "generic_f405": dict(
        storage=0x080C0000, sectors=(10, 11),
        time_cnt=0x40000024, echo_sr=0x40000C10, echo_ccr2=0x40000C38, echo_irq="TIM5_IRQHandler",
        trig_cr1=0x40014000, motor_ccr=(0x4000043C, 0x40000440), enc_cnt=(0x40010024, 0x40010424),
        dir_bsrr=0x40020818, dir_pins=(0, 1, 2, 3), stby_pin=4, port="PC",
        clocks=(168000000, 42000000, 84000000, 84000000, 168000000), crystal_mhz=8,
        pll=(4, 168, 7), hsi_m=8, wait_states=5, apb=(4, 2), vos=1,
        servos=1, sonars=1, bumps=()),
    "blackpill_f411": dict(
        storage=0x08040000, sectors=(6, 7),
        time_cnt=0x40000C24, echo_sr=0x40000010, echo_ccr2=0x40000038, echo_irq="TIM2_IRQHandler",
        trig_cr1=0x40010000, motor_ccr=(0x40014034, 0x40014038), enc_cnt=(0x40000424, 0x40000824),
        dir_bsrr=0x40020418, dir_pins=(12, 13, 14, 15), stby_pin=10, port="PB",
        clocks=(96000000, 48000000, 96000000, 96000000, 96000000), crystal_mhz=25,
        pll=(25, 192, 4), hsi_m=16, wait_states=3, apb=(2, 1), vos=3,
        servos=1, sonars=1, bumps=()),
}
# tests/stm32f4/board_test_f405_side.h: the F405 with sonar 1 (trigger TIM4 CH4, echo on
# TIM12's CH2 pin, 16-bit, the width captured on CH1) and bump switches on PC8, PC9.
BOARDS["test_f405_side"] = dict(
    BOARDS["generic_f405"], sonars=2,
    sonar1=dict(trig_cr1=0x40000800, echo_sr=0x40001810, echo_egr=0x40001814,
                echo_ccr_width=0x40001834, width_flag=1 << 1, echo_irq="TIM8_BRK_TIM12_IRQHandler"),
    bumps=((0x40020810, 8), (0x40020810, 9)))
BOARD = BOARDS["generic_f405"]
PPRE = {1: 0, 2: 4, 4: 5, 8: 6, 16: 7}
KEY1, KEY2 = 0x45670123, 0xCDEF89AB
HAL_OK, HAL_EINVAL, HAL_EIO, HAL_ENOSYS = 0, -1 & 0xFFFFFFFF, -2 & 0xFFFFFFFF, -4 & 0xFFFFFFFF
SCRATCH = 0x2001E000            # test buffers in RAM, below the call stack
LSI_MIN, LSI_MAX = 17000, 47000 # RM0090: the LSI may run anywhere in this range

SR_EOP, SR_WRPERR, SR_PGAERR, SR_PGPERR, SR_PGSERR, SR_BSY = 1, 1 << 4, 1 << 5, 1 << 6, 1 << 7, 1 << 16
CR_PG, CR_SER, CR_STRT, CR_LOCK = 1, 2, 1 << 16, 1 << 31


RCC_CR, RCC_PLLCFGR, RCC_CFGR = 0x800, 0x804, 0x808   # offsets in the page at 0x40023000
HSEON, HSERDY, PLLON, PLLRDY = 1 << 16, 1 << 17, 1 << 24, 1 << 25


class FlashModel:
    """The flash interface page (0x40023000, which also holds RCC) and the storage sectors."""

    def __init__(self, watchdog):
        self.wd = watchdog
        self.hse_starts = False                # RCC: does the crystal come up?
        self.pll_locks = False                 # does the PLL lock?
        self.page = bytearray(0x1000)          # RCC and anything else on the page: plain memory
        self.mem = bytearray(b"\x5a" * (2 * SECTOR_BYTES))  # not erased at power-up
        self.cr = CR_LOCK
        self.sr = 0
        self.key_step = 0
        self.dead = False                      # a wrong key: locked until reset
        self.busy_reads = 0
        self.erased = []                       # sector numbers, in order
        self.erase_timeouts = []               # watchdog timeout (s, fastest LSI) at each erase
        self.words = self.bytes = 0            # programming operations by width
        self.fail_next_erase = 0               # an error flag the next erase ends with
        self.fail_program = 0                  # an error flag every program ends with

    # -- registers ----------------------------------------------------------------------
    def read(self, off, size):
        if off == 0xC0C:                       # FLASH_SR
            v = self.sr | (SR_BSY if self.busy_reads else 0)
            self.busy_reads = max(0, self.busy_reads - 1)
            return v
        if off == 0xC10:                       # FLASH_CR
            return self.cr
        v = int.from_bytes(self.page[off:off + size], "little")
        if off == RCC_CR:                      # ready flags follow their enables
            v |= 2                             # HSIRDY
            v |= HSERDY if self.hse_starts and v & HSEON else 0
            v |= PLLRDY if self.pll_locks and v & PLLON else 0
        if off == RCC_CFGR:                    # SWS follows SW
            v = (v & ~0xC) | ((v & 3) << 2)
        return v

    def write(self, off, size, value):
        if off == 0xC04:                       # FLASH_KEYR
            if self.dead or not self.cr & CR_LOCK:
                return
            if self.key_step == 0 and value == KEY1:
                self.key_step = 1
            elif self.key_step == 1 and value == KEY2:
                self.cr &= ~CR_LOCK
                self.key_step = 0
            else:
                self.dead = True
            return
        if off == 0xC0C:                       # FLASH_SR: error flags and EOP are rc_w1
            self.sr &= ~(value & 0xF3)
            return
        if off == 0xC10:                       # FLASH_CR
            if self.cr & CR_LOCK:
                return                         # ignored while locked
            if self.busy_reads:
                raise AssertionError("FLASH_CR written while BSY")
            self.cr = value
            if value & CR_STRT:
                self.cr &= ~CR_STRT
                if not value & CR_SER or value & CR_PG:
                    self.sr |= SR_PGSERR
                    return
                snb = (value >> 3) & 0xF
                self.erased.append(snb)
                self.erase_timeouts.append(self.wd.timeout_s(LSI_MAX))
                if snb not in BOARD["sectors"]:
                    raise AssertionError("the driver erased sector %d, which holds code" % snb)
                self.busy_reads = 3
                if self.fail_next_erase:
                    self.sr |= self.fail_next_erase
                    self.fail_next_erase = 0
                    return
                start = (snb - BOARD["sectors"][0]) * SECTOR_BYTES
                self.mem[start:start + SECTOR_BYTES] = b"\xff" * SECTOR_BYTES
            return
        self.page[off:off + size] = value.to_bytes(size, "little")

    # -- the storage sectors -------------------------------------------------------------
    def mem_read(self, off, size):
        return int.from_bytes(self.mem[off:off + size], "little")

    def mem_write(self, off, size, value):
        psize = {0: 1, 1: 2, 2: 4, 3: 8}[(self.cr >> 8) & 3]
        if self.cr & CR_LOCK or not self.cr & CR_PG:
            self.sr |= SR_PGSERR
            return
        if size != psize:
            self.sr |= SR_PGPERR
            return
        if off % size:
            self.sr |= SR_PGAERR
            return
        self.busy_reads = 2
        if self.fail_program:
            self.sr |= self.fail_program
            return
        if size == 4:
            self.words += 1
        else:
            self.bytes += 1
        for i in range(size):
            self.mem[off + i] &= (value >> (8 * i)) & 0xFF   # flash bits only go 1 -> 0


class WatchdogModel:
    def __init__(self):
        self.page = bytearray(0x1000)
        self.unlocked = False
        self.pr = 0
        self.rlr = 0xFFF
        self.running = False
        self.reloads = 0

    def timeout_s(self, lsi_hz):
        return self.rlr * (4 << self.pr) / lsi_hz

    def read(self, off, size):
        return 0 if off == 0xC else int.from_bytes(self.page[off:off + size], "little")

    def write(self, off, size, value):
        if off == 0:
            if value == 0x5555:
                self.unlocked = True
            elif value == 0xAAAA:
                self.reloads += 1
                self.unlocked = False
            elif value == 0xCCCC:
                self.running = True
        elif off == 4 and self.unlocked:
            self.pr = value & 7
        elif off == 8 and self.unlocked:
            self.rlr = value & 0xFFF
        else:
            self.page[off:off + size] = value.to_bytes(size, "little")


class Rig:
    def __init__(self, elf_path):
        self.wd = WatchdogModel()
        self.flash = FlashModel(self.wd)
        mmio = [(0x40023000, 0x1000, self.flash.read, self.flash.write),
                (0x40003000, 0x1000, self.wd.read, self.wd.write),
                (BOARD["storage"], 2 * SECTOR_BYTES, self.flash.mem_read, self.flash.mem_write)]
        self.m = Machine(Elf(elf_path), mmio)

    def call(self, name, *args):
        return self.m.call(name, *args)

    def buffer(self, data, at=SCRATCH):
        self.m.uc.mem_write(at, bytes(data))
        return at

    def ram(self, at, n):
        return bytes(self.m.uc.mem_read(at, n))


failures = []


def check(cond, what):
    print("  %s %s" % ("ok  " if cond else "FAIL", what))
    if not cond:
        failures.append(what)


def main(argv):
    global BOARD
    args = argv[1:]
    board = "generic_f405"
    if "--board" in args:
        i = args.index("--board")
        board = args[i + 1] if i + 1 < len(args) else ""
        del args[i:i + 2]
    if len(args) != 1 or board not in BOARDS:
        print(__doc__.strip())
        print("boards: %s" % ", ".join(BOARDS))
        return 2
    BOARD = BOARDS[board]
    print("drivers_model_test: %s, board %s" % (args[0], board))
    r = Rig(args[0])
    f = r.flash
    check(r.call("hal_storage_size") == SECTOR_BYTES, "a slot is 128 KiB")
    check(r.call("hal_storage_write", 0, 0, r.buffer(b"x"), 1) == HAL_EINVAL,
          "writing a slot that was not begun is refused")
    check(r.call("hal_storage_begin", 2) == HAL_EINVAL, "slot 2 does not exist")

    r.call("stm32_watchdog_start", 250)
    normal = r.wd.timeout_s(32000)
    check(0.2 <= normal <= 0.3, "the watchdog runs at 250 ms nominal (%.3f s)" % normal)

    check(r.call("hal_storage_begin", 0) == HAL_OK, "begin(0) erases and verifies slot 0")
    s0, s1 = BOARD["sectors"]
    check(f.erased == [s0], "only sector %d was erased (%s)" % (s0, f.erased))
    check(f.erase_timeouts and f.erase_timeouts[0] > 2.0,
          "the watchdog allows more than the 2 s erase even with the fastest LSI (%.2f s)"
          % f.erase_timeouts[0])
    check(abs(r.wd.timeout_s(32000) - normal) < 1e-9, "the normal watchdog timeout is back")
    check(f.cr & CR_LOCK, "the flash is locked again")
    check(not f.dead, "the key sequence was right")

    data = bytes((i * 7 + 3) & 0xFF for i in range(1000))
    check(r.call("hal_storage_write", 0, 3, r.buffer(data), len(data)) == HAL_OK,
          "1000 bytes at the unaligned offset 3 are written")
    check(bytes(f.mem[3:1003]) == data, "the flash holds them")
    check(f.mem[0:3] == b"\xff\xff\xff" and f.mem[1003] == 0xFF, "and nothing around them")
    check(f.words == 249 and f.bytes == 4,
          "aligned words at x32, the head and tail bytes at x8 (%d words, %d bytes)"
          % (f.words, f.bytes))
    check(f.sr & (SR_PGSERR | SR_PGPERR | SR_PGAERR) == 0, "no programming error flag")
    out = SCRATCH + 0x800
    check(r.call("hal_storage_read", 0, 3, out, len(data)) == HAL_OK and r.ram(out, len(data)) == data,
          "hal_storage_read() reads them back")
    check(r.call("hal_storage_read", 0, SECTOR_BYTES - 4, out, 8) == HAL_EINVAL,
          "a read past the slot is refused")
    check(r.call("hal_storage_write", 0, SECTOR_BYTES - 4, r.buffer(b"12345678"), 8) == HAL_EINVAL,
          "a write past the slot is refused")
    check(r.call("hal_storage_write", 0, 0xFFFFFFF0, r.buffer(b"1234"), 0x20) == HAL_EINVAL,
          "an offset that wraps around is refused")
    check(r.call("hal_storage_write", 0, 2000, r.buffer(b"\x00\x00\x00\x00"), 4) == HAL_OK
          and r.call("hal_storage_write", 0, 2000, r.buffer(b"\xff\xff\xff\xff"), 4) == HAL_EIO,
          "rewriting programmed bytes fails the read-back check")
    check(r.call("hal_storage_commit", 0) == HAL_OK, "commit(0)")
    check(r.call("hal_storage_write", 0, 4000, r.buffer(b"z"), 1) == HAL_EINVAL,
          "a committed slot takes no more writes")
    check(r.call("hal_storage_commit", 0) == HAL_EINVAL, "a slot is committed once")

    f.fail_next_erase = SR_WRPERR
    check(r.call("hal_storage_begin", 1) == HAL_EIO, "an erase that ends in WRPERR fails with EIO")
    check(r.call("hal_storage_write", 1, 0, r.buffer(b"q"), 1) == HAL_EINVAL,
          "and leaves the slot closed")
    check(r.call("hal_storage_begin", 1) == HAL_OK and f.erased[-1] == s1,
          "a second begin(1) clears the stale flag and erases sector %d" % s1)
    f.fail_program = SR_PGPERR
    check(r.call("hal_storage_write", 1, 0, r.buffer(b"abcd"), 4) == HAL_EIO,
          "a programming error fails with EIO")
    f.fail_program = 0
    check(r.call("hal_storage_write", 1, 8, r.buffer(b"abcd"), 4) == HAL_OK,
          "the next write after a programming error works")
    check(set(f.erased) <= {s0, s1}, "no sector below %d was ever erased" % s0)

    r.wd.reloads = 0
    r.call("hal_watchdog_kick")
    check(r.wd.reloads == 1, "hal_watchdog_kick() reloads the watchdog")

    test_tick(r)
    test_sonar(r)
    test_instances(r)
    test_wheels(r)
    test_clock(r)

    if failures:
        print("drivers_model_test: %d checks failed" % len(failures), file=sys.stderr)
        return 1
    print("drivers_model_test: the STM32F4 drivers behave as RM0090 describes")
    return 0


SYST_LOAD, SYST_VAL, ICSR = 0xE000E014, 0xE000E018, 0xE000ED04
PENDSTSET = 1 << 26
STUB = 0x30000100      # a tick callback: stores its argument at STUB_OUT
STUB_OUT = 0x2001E800


def signed(v):
    return v - (1 << 32) if v & 0x80000000 else v


def test_tick(r):
    m = r.m
    # ldr r1, [pc, #4]; str r0, [r1]; bx lr; nop; .word STUB_OUT
    m.uc.mem_write(STUB, bytes.fromhex("0149" "0860" "7047" "00bf") + STUB_OUT.to_bytes(4, "little"))
    check(signed(r.call("hal_tick_start", 0, 0)) == -1, "hal_tick_start(NULL) is refused")
    r.call("stm32_clock_init")  # HSI: the model's ready bits never come
    check(r.call("hal_tick_start", STUB | 1, 0x1234) == HAL_OK, "the tick starts")
    check(signed(r.call("hal_tick_start", STUB | 1, 0)) == -3, "and cannot start twice")
    load = m.read32(SYST_LOAD)
    check(load == 16000000 // 100 - 1, "SysTick reloads every 10 ms at 16 MHz (LOAD %d)" % load)
    check(r.wd.running, "the watchdog runs from the first tick on")

    def tick(val, pending):
        m.write32(SYST_VAL, val)
        m.write32(ICSR, PENDSTSET if pending else 0)
        m.write32(STUB_OUT, 0)
        r.call("SysTick_Handler")
        return m.read32(STUB_OUT)

    check(tick(load, False) == 0x1234, "SysTick_Handler calls the callback with its context")
    check(r.call("hal_tick_overruns") == 0, "a tick one count into its period is on time")
    tick(0, False)
    check(r.call("hal_tick_overruns") == 0,
          "a tick that sees the counter at 0 (the reload not yet done) is on time")
    tick(load - load // 10 + 1, False)
    check(r.call("hal_tick_overruns") == 0, "a tick a tenth of the period late is on time")
    tick(load // 2, False)
    check(r.call("hal_tick_overruns") == 1, "a tick half a period late is an overrun")
    tick(load, True)
    check(r.call("hal_tick_overruns") == 2, "a tick still running at the next period is an overrun")
    tick(load // 2, True)
    check(r.call("hal_tick_overruns") == 3, "a tick both late and overrunning counts once")


TIM10_CCR1 = 0x40014434
ECHO_OUT = 0x2001E900
IDLE, BUSY, ECHO, TIMEOUT = 0, 1, 2, 3


def test_sonar(r):
    m = r.m
    r.call("hal_init")
    now = [1000]

    def advance(us):
        now[0] += us
        m.write32(BOARD["time_cnt"], now[0])

    def echo(width):
        m.write32(BOARD["echo_ccr2"], width)
        m.write32(BOARD["echo_sr"], 1 << 2)        # CC2IF: the falling edge was captured
        r.call(BOARD["echo_irq"])

    def poll():
        m.write32(ECHO_OUT, 0xDEAD)
        return r.call("hal_sonar_poll", 0, ECHO_OUT), m.read32(ECHO_OUT)

    advance(0)
    check(poll()[0] == IDLE, "no ping, the sonar is idle")
    m.write32(BOARD["trig_cr1"], 0)
    check(r.call("hal_sonar_trigger", 0) == HAL_OK, "a ping goes out")
    check(m.read32(BOARD["trig_cr1"]) & 0x9 == 0x9, "by starting the one-pulse trigger timer (OPM, CEN)")
    check(signed(r.call("hal_sonar_trigger", 0)) == -3, "a second ping while the first is out is busy")
    advance(3000)
    check(poll()[0] == BUSY, "no echo yet: busy")
    echo(5831)
    check(poll() == (ECHO, 5831), "the captured width comes back with the echo")
    check(poll()[0] == IDLE, "once")
    r.call("hal_sonar_trigger", 0)
    advance(59999)
    check(poll()[0] == BUSY, "59.999 ms without an echo: still busy")
    advance(1)
    check(poll()[0] == TIMEOUT, "60 ms without an echo: timeout")
    r.call("hal_sonar_trigger", 0)
    echo(38000)
    check(poll()[0] == TIMEOUT, "a 38 ms echo is the sensor's 'nothing in range': timeout")
    r.call("hal_sonar_trigger", 0)
    advance(70000)
    check(r.call("hal_sonar_trigger", 0) == HAL_OK, "a ping nobody polled is over after 60 ms")
    echo(1200)
    check(r.call("hal_sonar_trigger", 0) == HAL_OK, "and one whose echo came back is over at once")
    check(poll()[0] == BUSY, "the new ping does not take the old echo")
    echo(1500)
    check(poll() == (ECHO, 1500), "but its own")
    m.write32(BOARD["echo_sr"], 1 << 9)            # a stray CC1 flag, no capture on CH2
    r.call(BOARD["echo_irq"])
    check(poll()[0] == IDLE, "an interrupt without a CH2 capture posts nothing")

    for pulse, want in ((100, 400), (1500, 1500), (3000, 2600)):
        check(r.call("hal_servo_set_pulse", 0, pulse) == HAL_OK and m.read32(TIM10_CCR1) == want,
              "servo %d us is set as %d us" % (pulse, want))


def test_instances(r):
    """The instance tables: counts, an index the board does not have, the rows past 0."""
    m = r.m
    servos, sonars, bumps = BOARD["servos"], BOARD["sonars"], BOARD["bumps"]
    check((r.call("hal_servo_count"), r.call("hal_sonar_count"), r.call("hal_bump_count"))
          == (servos, sonars, len(bumps)),
          "the board has %d servo(s), %d sonar(s), %d bump switch(es)" % (servos, sonars, len(bumps)))
    before = m.read32(TIM10_CCR1)
    for n in (servos, 255):
        check(r.call("hal_servo_set_pulse", n, 1000) == HAL_EINVAL and m.read32(TIM10_CCR1) == before,
              "servo %d does not exist: HAL_EINVAL, no pulse changes" % n)
    m.write32(BOARD["trig_cr1"], 0)
    for n in (sonars, 255):
        m.write32(ECHO_OUT, 0xDEAD)
        check(r.call("hal_sonar_trigger", n) == HAL_EINVAL and m.read32(BOARD["trig_cr1"]) == 0,
              "sonar %d does not exist: its trigger is HAL_EINVAL and starts no timer" % n)
        check(r.call("hal_sonar_poll", n, ECHO_OUT) == HAL_EINVAL and m.read32(ECHO_OUT) == 0xDEAD,
              "and its poll HAL_EINVAL, the width untouched")
    out = SCRATCH + 0x40
    if not bumps:
        check(r.call("hal_bump_read", 0, out) == HAL_ENOSYS, "no bump switches: HAL_ENOSYS")
    else:
        for i, (idr, pin) in enumerate(bumps):
            for level, pressed in ((0, 1), (1 << pin, 0)):
                m.write32(idr, level)
                m.uc.mem_write(out, b"\x5a")
                check(r.call("hal_bump_read", i, out) == HAL_OK and r.ram(out, 1)[0] == pressed,
                      "bump switch %d reads %s with its pin %s" % (i, "pressed" if pressed else
                                                                  "released", "low" if pressed else "high"))
        check(r.call("hal_bump_read", len(bumps), out) == HAL_EINVAL, "a switch past the last: HAL_EINVAL")
        check(r.call("hal_bump_read", 0, 0) == HAL_EINVAL, "no place for the answer: HAL_EINVAL")
    if "sonar1" in BOARD:
        test_sonar1(r, BOARD["sonar1"])


def test_sonar1(r, s1):
    """Sonar 1 of the test board: its own timers and ping, a 16-bit echo timer, the pin on CH2."""
    m = r.m
    t = [m.read32(BOARD["time_cnt"])]

    def advance(us):
        t[0] += us
        m.write32(BOARD["time_cnt"], t[0])

    def poll(n):
        m.write32(ECHO_OUT, 0xDEAD)
        return r.call("hal_sonar_poll", n, ECHO_OUT), m.read32(ECHO_OUT)

    def echo(width, overflowed=False):
        m.write32(s1["echo_ccr_width"], width)
        m.write32(s1["echo_sr"], s1["width_flag"] | (1 if overflowed else 0))
        r.call(s1["echo_irq"])

    tim = s1["echo_sr"] - 0x10
    regs = [m.read32(tim + off) for off in (0x00, 0x08, 0x0C, 0x18, 0x20, 0x2C)]
    check(regs == [0x5, 0x64, 0x2, 0x3132, 0x13, 0xFFFF],
          "sonar 1's echo timer: PWM input from its CH2 pin (TI2FP2 resets), the falling edge "
          "captured on CH1 with its interrupt, 16 bits, only overflows update (%s)"
          % " ".join("%x" % v for v in regs))
    advance(100000)
    check(poll(1)[0] == IDLE, "sonar 1: idle before its first ping")
    m.write32(s1["trig_cr1"], 0)
    m.write32(s1["echo_sr"], 0xFFFFFFFF)
    m.write32(BOARD["trig_cr1"], 0)
    check(r.call("hal_sonar_trigger", 1) == HAL_OK and m.read32(s1["trig_cr1"]) & 0x9 == 0x9
          and m.read32(BOARD["trig_cr1"]) == 0,
          "sonar 1's trigger starts its own one-pulse timer, not sonar 0's")
    check(m.read32(s1["echo_egr"]) & 1 and not m.read32(s1["echo_sr"]) & 1,
          "and restarts its 16-bit echo timer with the overflow flag cleared")
    check(r.call("hal_sonar_trigger", 0) == HAL_OK, "sonar 0 pings while sonar 1's ping is out")
    check(signed(r.call("hal_sonar_trigger", 1)) == -3, "sonar 1 is busy with its own")
    advance(2000)
    echo(2345)
    check(poll(1) == (ECHO, 2345), "the width captured on CH1 comes back to sonar 1")
    check(poll(0)[0] == BUSY, "and sonar 0 still waits for its own")
    check(r.call("hal_sonar_trigger", 1) == HAL_OK, "sonar 1 pings again")
    echo(1234, overflowed=True)
    check(poll(1)[0] == TIMEOUT, "an echo that overflowed the 16-bit timer is a timeout, not 1.2 ms")


def test_wheels(r):
    m = r.m
    period = 16000000 // 20000   # TIM3 at 16 MHz (HSI), 20 kHz

    def motor(wheel, duty):
        r.call("hal_motor_set", wheel, duty)  # AAPCS: sign-extended
        return m.read32(BOARD["motor_ccr"][wheel]), m.read32(BOARD["dir_bsrr"])

    l1, l2, r1, r2 = BOARD["dir_pins"]
    pin = lambda n: "%s%d" % (BOARD["port"], n)
    check(motor(0, 500) == (period // 2, (1 << l1) | (1 << (l2 + 16))),
          "left half forward: %s high, %s low" % (pin(l1), pin(l2)))
    check(motor(0, -1000) == (period, (1 << l2) | (1 << (l1 + 16))),
          "left full reverse: %s high, %s low" % (pin(l2), pin(l1)))
    check(motor(0, 0) == (0, (1 << (l1 + 16)) | (1 << (l2 + 16))), "left stop: both low, no PWM")
    check(motor(1, 250) == (period // 4, (1 << r2) | (1 << (r1 + 16))),
          "right quarter forward, wired inverted: %s high, %s low" % (pin(r2), pin(r1)))
    check(motor(1, 30000)[0] == period, "a duty beyond full scale is clamped")
    check(motor(1, -30000)[0] == period, "in both directions")
    m.write32(BOARD["enc_cnt"][0], 0x1234)
    m.write32(BOARD["enc_cnt"][1], 0xFFFF)
    check(r.call("hal_encoder_count", 0) == 0x1234 and r.call("hal_encoder_count", 1) == 0xFFFF,
          "the encoders read their timers' 16-bit counters")
    test_wheels_never_reverse_at_the_old_duty(r, motor)
    motor(0, 700)
    r.call("cm_safe_outputs")
    check(m.read32(BOARD["motor_ccr"][0]) == 0 and m.read32(BOARD["motor_ccr"][1]) == 0,
          "the safe state stops both PWMs")
    check(m.read32(BOARD["dir_bsrr"]) == 1 << (BOARD["stby_pin"] + 16),
          "and puts the driver in standby (%s low)" % pin(BOARD["stby_pin"]))



def test_wheels_never_reverse_at_the_old_duty(r, motor):
    """TIM3 as RM0090 has it with OCxPE: a CCR write goes to the preload register, which
    the timer takes at the end of the PWM period or at once on an update (EGR.UG). The pins
    change with the BSRR write. A reversal must never let the bridge drive the new direction
    while the duty commanded for the old one is still in force."""
    uc = r.m.uc
    base = BOARD["motor_ccr"][0] & ~0x3FF        # the motors' timer
    ccr = {BOARD["motor_ccr"][0] - base: 0, BOARD["motor_ccr"][1] - base: 1}  # left, right
    bsrr = BOARD["dir_bsrr"]
    pin_of = BOARD["dir_pins"]
    pins = {"now": 0}
    pre, pre_dir, act, act_dir = [0, 0], [0, 0], [0, 0], [0, 0]
    bad = []

    def drive(p, wheel):                         # +1, -1 or 0 (coast): IN1 minus IN2
        in1, in2 = pin_of[0:2] if wheel == 0 else pin_of[2:4]
        return (p >> in1 & 1) - (p >> in2 & 1)

    def tim(_uc, _access, addr, _size, value, _data):
        off = addr - base
        if off in ccr:
            w = ccr[off]
            pre[w], pre_dir[w] = value, drive(pins["now"], w)
        elif off == 0x14 and value & 1:
            update()

    def gpio(_uc, _access, _addr, _size, value, _data):
        p = (pins["now"] | (value & 0xFFFF)) & ~(value >> 16)
        for w in (0, 1):
            d = drive(p, w)
            if d != 0 and act[w] != 0 and act_dir[w] != 0 and d != act_dir[w]:
                bad.append("wheel %d drives %+d at the duty %d commanded for %+d"
                           % (w, d, act[w], act_dir[w]))
        pins["now"] = p

    def update():                                # the end of a PWM period, or UG
        act[:], act_dir[:] = pre, pre_dir

    hooks = [uc.hook_add(unicorn.UC_HOOK_MEM_WRITE, tim, begin=base, end=base + 0x3FF),
             uc.hook_add(unicorn.UC_HOOK_MEM_WRITE, gpio, begin=bsrr, end=bsrr + 3)]
    uc.ctl_flush_tb()
    for w in (0, 1):
        motor(w, 0)
    update()
    for w in (0, 1):
        for a, b in ((700, -700), (-1000, 1000), (300, -1), (1, -1000)):
            motor(w, a)
            update()
            motor(w, b)
            update()
    motor(0, 900)
    motor(1, -900)
    update()
    motor(0, -900)                               # both reverse within one period
    motor(1, 900)
    update()
    for h in hooks:
        uc.hook_del(h)
    check(not bad, "a reversal zeroes the duty in force before the pins turn (%s)"
          % ("; ".join(bad[:3]) or "no reverse drive at an old duty"))
    check(drive(pins["now"], 0) == -1 and act[0] == pre[0] == 16000000 // 20000 * 900 // 1000,
          "and the new duty follows")


FLASH_ACR = 0x40023C00
PWR_CR = 0x40007000


def test_clock(r):
    m, f = r.m, r.flash
    base = 0x40023000
    clocks = m.elf.addr("stm32_clocks")

    def run(hse, pll):
        f.hse_starts, f.pll_locks = hse, pll
        m.write32(base + RCC_CR, 0x83)               # reset values
        m.write32(base + RCC_PLLCFGR, 0x24003010)
        m.write32(base + RCC_CFGR, 0)
        m.write32(FLASH_ACR, 0)
        m.write32(PWR_CR, 0x8000 if BOARD["vos"] == 3 else 0x4000)  # reset values
        r.call("stm32_clock_init")
        return [m.read32(clocks + 4 * i) for i in range(6)], m.read32(base + RCC_PLLCFGR)

    want = BOARD["clocks"]
    mhz = tuple(v // 1000000 for v in want)
    (src, sys_hz, p1, p2, t1, t2), pll = run(True, True)
    check((src, sys_hz, p1, p2, t1, t2) == (0,) + want,
          "crystal and PLL: %d MHz, APB1 %d MHz, APB2 %d MHz, timers %d and %d MHz" % mhz)
    pm, pn, pq = BOARD["pll"]
    check(pll == 0x20000000 | (1 << 22) | pm | (pn << 6) | (pq << 24),
          "PLL from the %d MHz crystal: M %d, N %d, P 2, Q %d, reserved bits kept (0x%08x)"
          % (BOARD["crystal_mhz"], pm, pn, pq, pll))
    vos = (m.read32(PWR_CR) >> 14) & 3
    check(vos == BOARD["vos"], "the regulator's scale for this speed (PWR_CR VOS %d)" % vos)
    ws = BOARD["wait_states"]
    check(m.read32(FLASH_ACR) & 7 == ws, "%d flash wait states before the switch" % ws)
    a1, a2 = BOARD["apb"]
    check(m.read32(base + RCC_CFGR) & 0xFCF3 == (PPRE[a1] << 10) | (PPRE[a2] << 13) | 2,
          "AHB /1, APB1 /%d, APB2 /%d, PLL selected" % (a1, a2))
    (src, sys_hz, *_), pll = run(False, True)
    check((src, sys_hz) == (1, want[0]) and pll & 0x3F == BOARD["hsi_m"] and not pll & (1 << 22),
          "no crystal: %d MHz from HSI through the PLL (M %d)" % (mhz[0], BOARD["hsi_m"]))
    (src, sys_hz, p1, p2, t1, t2), _ = run(False, False)
    check((src, sys_hz, p1, t2) == (2, 16000000, 16000000, 16000000)
          and m.read32(base + RCC_CFGR) & 3 == 0 and not m.read32(base + RCC_CR) & PLLON,
          "no PLL either: HSI at 16 MHz, PLL off, every clock 16 MHz")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
