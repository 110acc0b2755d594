#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/plot_run.py draws what a user has: a run, a replay, the maps a robot saved (its
storage slots, a flash dump), says where the picture went, picks the newest record whose
CRCs check out, and answers a missing or empty folder with a message, not a traceback."""
import os
import shutil
import subprocess

from simtest import Sim, check

sim = Sim()
tool = os.path.join(sim.src, "tools", "plot_run.py")


def plot(*args):
    return subprocess.run(["/usr/bin/python3", tool] + [str(a) for a in args],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n"


run = sim.out("run")
store = sim.out("store")
sim.run("--duration", 130, "--seed", 2, "--out", run, "--storage", store)
rep = sim.out("replay")
sim.run("--replay", os.path.join(run, "readings.csv"), "--out", rep)
dump = sim.out("flash.bin")
with open(dump, "wb") as f:  # both slots read back from the flash, one after the other
    for slot in ("slot0.bin", "slot1.bin"):
        with open(os.path.join(store, slot), "rb") as s:
            f.write(s.read())
linux = sim.out("linux")      # a Linux robot's storage_dir: slots and the maps of its exit
shutil.copytree(store, linux)
for name in ("om.pgm", "om.yaml", "tm.pgm"):
    shutil.copy(os.path.join(run, name), linux)

for target, png, extra in ((run, os.path.join(run, "figure.png"), ""),
                           (rep, os.path.join(rep, "figure.png"), ""),
                           (store, os.path.join(store, "figure.png"), "number 2 (slot1.bin"),
                           (linux, os.path.join(linux, "figure.png"), "number 2"),
                           (dump, sim.out("flash.png"), "number 2 (flash.bin at byte %d)" % os.path.getsize(os.path.join(store, "slot0.bin")))):
    p = plot(target)
    check(p.returncode == 0 and "wrote " + png in p.stdout and extra in p.stdout and is_png(png),
          "%s: drawn, and it says where: %s" % (os.path.basename(target), p.stdout.strip().replace("\n", "; ")))

# The newest record rotten: the one before it is drawn.
with open(dump, "rb") as f:
    data = bytearray(f.read())
slot_bytes = os.path.getsize(os.path.join(store, "slot0.bin"))
header_bytes = 56  # mapstore_header_t
data[slot_bytes + header_bytes + 100] ^= 0xFF  # a cell of record 2's OM
with open(dump, "wb") as f:
    f.write(data)
p = plot(dump, "--out", sim.out("older.png"))
check(p.returncode == 0 and "number 1 (flash.bin at byte 0)" in p.stdout,
      "a record whose data CRC fails is passed over: %s" % p.stdout.strip().splitlines()[0])

os.makedirs(sim.out("empty"))
with open(sim.out("notes.txt"), "w") as f:
    f.write("not a map\n")
for target, what in ((sim.out("missing"), "no such file or folder"), (sim.out("empty"), "nothing to draw"),
                     (sim.out("notes.txt"), "no map record")):
    p = plot(target)
    check(p.returncode == 2 and what in p.stderr and "Traceback" not in p.stderr,
          "%s: exit 2, '%s'" % (os.path.basename(target), p.stderr.strip()))
p = plot(run, "--out", sim.out("no/such/dir/x.png"))
check(p.returncode == 1 and "cannot write" in p.stderr and "Traceback" not in p.stderr,
      "an unwritable picture: exit 1, '%s'" % p.stderr.strip())
sim.done()
