#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Tests the map storage and watchdog drivers of the robot image against register models.

usage: tests/stm32f4/storage_model_test.py ROBOT_ELF

QEMU emulates neither the flash interface nor the IWDG, so the image's own functions run
in python3-unicorn here, with models of both written from RM0090: the flash key sequence
and LOCK, sector erase (SER, SNB, STRT), programming only with PG set and at the PSIZE
width, bits that only go from 1 to 0, BSY for a while after every operation, rc_w1 error
flags; the IWDG key register, PR/RLR writable only after 0x5555, reloads. The tests call
hal_storage_*() and check the model's flash, the register traffic, the return codes, and
the watchdog timeout in force during an erase.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools", "stm32f4"))
from elf32 import Elf  # noqa: E402
from tick_unicorn import Machine  # noqa: E402

FLASH_BASE = 0x08000000
STORAGE = 0x080C0000            # sectors 10 and 11
SECTOR_BYTES = 128 * 1024
KEY1, KEY2 = 0x45670123, 0xCDEF89AB
HAL_OK, HAL_EINVAL, HAL_EIO = 0, -1 & 0xFFFFFFFF, -2 & 0xFFFFFFFF
SCRATCH = 0x2001E000            # test buffers in RAM, below the call stack
LSI_MIN, LSI_MAX = 17000, 47000 # RM0090: the LSI may run anywhere in this range

SR_EOP, SR_WRPERR, SR_PGAERR, SR_PGPERR, SR_PGSERR, SR_BSY = 1, 1 << 4, 1 << 5, 1 << 6, 1 << 7, 1 << 16
CR_PG, CR_SER, CR_STRT, CR_LOCK = 1, 2, 1 << 16, 1 << 31


class FlashModel:
    """The flash interface page (0x40023000, which also holds RCC) and the storage sectors."""

    def __init__(self, watchdog):
        self.wd = watchdog
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
        return int.from_bytes(self.page[off:off + size], "little")

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
                if snb not in (10, 11):
                    raise AssertionError("the driver erased sector %d, which holds code" % snb)
                self.busy_reads = 3
                if self.fail_next_erase:
                    self.sr |= self.fail_next_erase
                    self.fail_next_erase = 0
                    return
                start = (snb - 10) * SECTOR_BYTES
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
                (STORAGE, 2 * SECTOR_BYTES, self.flash.mem_read, self.flash.mem_write)]
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
    if len(argv) != 2:
        print(__doc__.strip())
        return 2
    r = Rig(argv[1])
    f = r.flash
    check(r.call("hal_storage_size") == SECTOR_BYTES, "a slot is 128 KiB")
    check(r.call("hal_storage_write", 0, 0, r.buffer(b"x"), 1) == HAL_EINVAL,
          "writing a slot that was not begun is refused")
    check(r.call("hal_storage_begin", 2) == HAL_EINVAL, "slot 2 does not exist")

    r.call("stm32_watchdog_start", 250)
    normal = r.wd.timeout_s(32000)
    check(0.2 <= normal <= 0.3, "the watchdog runs at 250 ms nominal (%.3f s)" % normal)

    check(r.call("hal_storage_begin", 0) == HAL_OK, "begin(0) erases and verifies slot 0")
    check(f.erased == [10], "only sector 10 was erased (%s)" % f.erased)
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
    check(r.call("hal_storage_begin", 1) == HAL_OK and f.erased[-1] == 11,
          "a second begin(1) clears the stale flag and erases sector 11")
    f.fail_program = SR_PGPERR
    check(r.call("hal_storage_write", 1, 0, r.buffer(b"abcd"), 4) == HAL_EIO,
          "a programming error fails with EIO")
    f.fail_program = 0
    check(r.call("hal_storage_write", 1, 8, r.buffer(b"abcd"), 4) == HAL_OK,
          "the next write after a programming error works")
    check(set(f.erased) <= {10, 11}, "no sector below 10 was ever erased")

    r.wd.reloads = 0
    r.call("hal_watchdog_kick")
    check(r.wd.reloads == 1, "hal_watchdog_kick() reloads the watchdog")

    if failures:
        print("storage_model_test: %d checks failed" % len(failures), file=sys.stderr)
        return 1
    print("storage_model_test: flash storage and watchdog drivers behave as RM0090 describes")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
