#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""host_sim against the second round of hostile input (issue 30): nothing lost, nothing
hung, every message clean.

Each part names the item it proves; the data-loss items (N3, N4) compare the earlier files
byte for byte after the second run.
"""
import os
import signal
import subprocess
import time

from simtest import Sim, check, check_path

sim = Sim()


def clean(text):
    """No byte a terminal acts on: only printable characters, newlines and tabs."""
    return all(c in "\n\t" or (c.isprintable() and not 0x80 <= ord(c) < 0xA0) for c in text)


def write(name, data):
    path = sim.out(name)
    with open(path, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)
    return path


# ---- N5: messages show control bytes escaped --------------------------------------------
ESC_TITLE = "\033]0;PWNED\007"
for name, args, says in [
    ("esc.room", ["--room", write("esc.room", "wall %s 0 5 0\n" % ESC_TITLE)],
     "esc.room:1: '\\x1b]0;PWNED\\x07' is not a number"),
    ("esc.conf", ["--config", write("esc.conf", "cell_um = %s\n" % ESC_TITLE)],
     "esc.conf:1: cell_um = '\\x1b]0;PWNED\\x07'"),
    ("esc key", ["--config", write("esckey.conf", "\033[2J = 1\n")], "unknown key '\\x1b[2J'"),
    ("esc.yaml", ["--room", write("esc.yaml", "image: x.pgm\nmode: \033[5m\n")],
     "esc.yaml:2: unknown mode '\\x1b[5m'"),
    ("esc commands", ["--commands", write("esc.txt", "1 mode \033[31m\n")],
     "esc.txt:1: mode: '\\x1b[31m' is not one of"),
    ("--set", ["--set", "cruise_mm_s=\033[31m"], "cruise_mm_s = '\\x1b[31m'"),
]:
    p = sim.run(*args, "--out", sim.out("never"), expect=2)
    check(says in p.stderr and clean(p.stderr),
          "N5 %s: the message shows the control bytes escaped: %s" % (name, p.stderr.strip()))

# ---- N10: --calibration holds the odometry's factors, and at least one ------------------
for name, text, says in [
    ("cell.conf", "cal_left = 0.99\ncell_um = 100000\n",
     "cell.conf:2: cell_um is not a calibration key"),
    ("empty.conf", "", "empty.conf holds no calibration"),
    ("comments.conf", "# measured later\n\n", "comments.conf holds no calibration"),
]:
    p = sim.run("--calibration", write(name, text), "--out", sim.out("never"), expect=2)
    check(says in p.stderr and ("--calibration none" in p.stderr or "--config" in p.stderr),
          "N10 --calibration %s: refused: %s" % (name, p.stderr.strip()))
    check(not os.path.exists(sim.out("never")), "N10 --calibration %s: nothing written" % name)
out = sim.out("cal")
sim.run("--calibration", write("cal.conf", "cal_left = 0.99\ncal_base = 1.01\n"), "--duration", "1",
        "--out", out)
with open(os.path.join(out, "config.txt")) as f:
    cfg = f.read()
check("cal_left = 0.99000000" in cfg and "cal_base = 1.00999999" in cfg,
      "N10: a calibration file of cal_* keys is taken")

# ---- N4: a replay never writes over a simulation's outputs ------------------------------


def snapshot(folder):
    """Every file of a folder and its bytes."""
    out = {}
    for root, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                out[os.path.relpath(path, folder)] = f.read()
    return out


# A simulation into out/sim (the default, run from a scratch folder), a second run's log.
scratch = sim.out("cwd")
os.makedirs(scratch)
cmd = [sim.bin, "--no-plot", "--quiet", "--duration", "20"]
subprocess.run(cmd, cwd=scratch, check=True)
run2 = sim.out("run2")
sim.run("--duration", "20", "--seed", "2", "--out", run2)
default_out = os.path.join(scratch, "out", "sim")
before = snapshot(default_out)
p = subprocess.run([sim.bin, "--quiet", "--replay", os.path.join(run2, "readings.csv")], cwd=scratch,
                   capture_output=True, text=True)
check(p.returncode == 0 and snapshot(default_out) == before,
      "N4: --replay without --out leaves out/sim byte for byte as the simulation wrote it")
check(os.path.exists(os.path.join(run2, "replay", "om.pgm")),
      "N4: ... and writes the replay beside its log, run2/replay/om.pgm")
before2 = snapshot(run2)
p = sim.run("--replay", os.path.join(run2, "readings.csv"), "--out", run2, expect=2)
check("holds a simulation's outputs" in p.stderr and snapshot(run2) == before2,
      "N4: --out naming a simulation's folder: exit 2, every file byte for byte as it was")
p = sim.run("--replay", os.path.join(run2, "readings.csv"), "--out", default_out, expect=2)
check(snapshot(default_out) == before, "N4: --out out/sim given: refused, nothing replaced")

# ---- N3: --storage never wipes the slots already in its folder --------------------------
store = sim.out("storage")
sim.run("--duration", "130", "--seed", "2", "--out", sim.out("st1"), "--storage", store)
before = snapshot(store)
check(sorted(before) == ["slot0.bin", "slot1.bin"], "N3: a first run writes both slots")
p = sim.run("--duration", "30", "--out", sim.out("st2"), "--storage", store, expect=2)
check("holds map slots already" in p.stderr and "slot0.bin" in p.stderr and "slot1.bin" in p.stderr
      and "Move them away" in p.stderr, "N3: a second run into it: exit 2, naming both slots and "
      "how to go on")
check(snapshot(store) == before and not os.path.exists(sim.out("st2")),
      "N3: ... the slots byte for byte as the first run left them, nothing written")
robot = sim.out("robot_storage")  # a copy of a Linux robot's storage: one slot, and its maps
os.makedirs(robot)
with open(os.path.join(robot, "slot1.bin"), "wb") as f:
    f.write(before["slot1.bin"])
with open(os.path.join(robot, "om.pgm"), "wb") as f:
    f.write(b"P5\n1 1\n255\n\0")
before = snapshot(robot)
p = sim.run("--duration", "30", "--out", sim.out("st3"), "--storage", robot, expect=2)
check("slot1.bin" in p.stderr and snapshot(robot) == before,
      "N3: a robot's storage folder with one slot: refused, byte for byte as it was")

# ---- N6, N7: a run that is cut off leaves no temporary file and no folder of its own -----


def hidden(folder):
    return sorted(n for n in os.listdir(folder) if n.startswith(".")) if os.path.isdir(folder) else []


# N6: the reader of --telemetry goes away (host_sim --telemetry /dev/stdout | head -c 1000).
out = sim.out("n6")
p = subprocess.Popen([sim.bin, "--no-plot", "--quiet", "--duration", "3600", "--out", out,
                      "--telemetry", "/dev/stdout"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
first = p.stdout.read(1000)
p.stdout.close()
err = p.stderr.read().decode(errors="replace")
rc = p.wait(timeout=600)
check(len(first) == 1000 and rc == 1 and "writing /dev/stdout failed" in err,
      "N6: the telemetry pipe's reader gone: exit 1 with a message (%d, %s)" % (rc, err.strip()))
check(not os.path.exists(out), "N6: ... no temporary file left, and the folder it made removed")

# N7: SIGINT or SIGTERM in the middle of a run, into a new folder and into an earlier run's.
earlier = sim.out("n7")
sim.run("--duration", "5", "--out", earlier)
before = snapshot(earlier)
for sig, folder in ((signal.SIGINT, sim.out("n7new")), (signal.SIGTERM, earlier)):
    p = subprocess.Popen([sim.bin, "--no-plot", "--quiet", "--duration", "100000", "--out", folder],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    # (the logs are opened one after the other: wait for them all, not for the first)
    while len(hidden(folder)) < 3 and time.monotonic() < deadline:
        time.sleep(0.05)
    check(len(hidden(folder)) >= 3, "N7: a run writes its logs under temporary names (%s)"
          % ", ".join(hidden(folder)))
    p.send_signal(sig)
    _, err = p.communicate(timeout=600)
    check(p.returncode == 128 + sig and b"stopped by signal %d" % sig in err,
          "N7: stopped by signal %d: exit %d, says so" % (sig, p.returncode))
    if folder == earlier:
        check(hidden(folder) == [] and snapshot(folder) == before,
              "N7: ... no temporary file left; the earlier run's files byte for byte as they were")
    else:
        check(not os.path.exists(folder), "N7: ... the folder it made is gone with its temporary files")

# A run killed at once (SIGKILL) cannot clean up: the next run into that folder removes
# what dead runs left, and never a live run's files.
dead = subprocess.Popen(["true"])
dead.wait()
stale = os.path.join(earlier, ".om.pgm.tmp%d" % dead.pid)
live = os.path.join(earlier, ".om.pgm.tmp%d" % os.getpid())
other = os.path.join(earlier, ".notes.tmp%d" % dead.pid)
for path in (stale, live, other):
    with open(path, "w") as f:
        f.write("x")
sim.run("--duration", "2", "--out", earlier)
check(not os.path.exists(stale) and os.path.exists(live) and os.path.exists(other),
      "N7: a later run removes a dead run's temporary file, not a live run's nor another name")

# ---- FIFOs: nothing waits for ever ------------------------------------------------------
fifo = sim.out("fifo")
os.mkfifo(fifo)
for args, says in [
    (["--room", fifo], "fifo: is not a regular file (a FIFO"),
    (["--config", fifo], "fifo: is not a regular file"),
    (["--calibration", fifo], "fifo: is not a regular file"),
    (["--commands", fifo], "fifo: is not a regular file"),
    (["--replay", fifo, "--config", os.path.join(earlier, "config.txt")], "fifo: is not a regular file"),
]:
    p = subprocess.run([sim.bin, "--no-plot", "--quiet", "--out", sim.out("never")] + args,
                       capture_output=True, text=True, timeout=120)
    check(p.returncode == 2 and says in p.stderr and not os.path.exists(sim.out("never")),
          "an input FIFO without a writer (%s): refused at once, exit 2" % args[0])
p = subprocess.run([sim.bin, "--no-plot", "--quiet", "--duration", "1", "--out", sim.out("nf"),
                    "--telemetry", fifo], capture_output=True, text=True, timeout=120)
check(p.returncode == 1 and "a FIFO that no program is reading" in p.stderr
      and not os.path.exists(sim.out("nf")),
      "--telemetry FIFO without a reader: exit 1 at once, says so, nothing left")
reader = subprocess.Popen(["cat", fifo], stdout=subprocess.PIPE)
time.sleep(0.2)  # let cat open it: host_sim does not wait for a reader
p = subprocess.run([sim.bin, "--no-plot", "--quiet", "--duration", "5", "--out", sim.out("wf"),
                    "--telemetry", fifo], capture_output=True, text=True, timeout=120)
data = reader.communicate(timeout=60)[0]
check(p.returncode == 0 and len(data) > 1000, "--telemetry FIFO with its reader running: written "
      "(%d bytes)" % len(data))

# ---- a gap the start check's eight rays miss ---------------------------------------------
# A 0.6 m gap in the far wall at 67.5 deg from the start, between the rays at 45 and 90 deg:
# accepted before, and in hour-long runs the robot left through it (to x = 17 m).
walls = "wall 0 0 6 0\nwall 6 0 6 5\nwall 6 5 4.34 5\nwall 3.74 5 0 5\nwall 0 5 0 0\n"
p = sim.run("--room", write("gap.room", walls + "start 3 2.5 0\n"), "--out", sim.out("never"),
            expect=2)
check("gap.room:6: start pose (3, 2.5): the room is not closed" in p.stderr
      and not os.path.exists(sim.out("never")), "a 0.6 m gap between the start check's rays: "
      "exit 2, named: %s" % p.stderr.strip())
p = sim.run("--room", write("narrowgap.room", walls.replace("3.74", "4.2") + "start 3 2.5 0\n"),
            "--duration", "1", "--out", sim.out("narrow"))
check(p.returncode == 0, "a 0.14 m gap, narrower than the robot (0.18 m): the room is closed to it")
for name in sorted(os.listdir(os.path.join(sim.src, "host_sim", "rooms"))):
    if name.endswith(".room"):
        sim.run("--room", sim.room(name), "--duration", "1", "--out", sim.out("shipped"))
check(True, "every shipped room is closed")

# ---- configurations that drove the robot into a wall within 30 s: refused ---------------
for kv, words in [
    ("accel_mm_s2=10", "100..50000"),
    ("mount_x_um=-1000000", "-100000..200000"),
    ("mount_y_um=1000000", "-100000..100000"),
    ("mount_y_um=-1000000", "-100000..100000"),
    ("mount_yaw_mdeg=180000", "-20000..20000"),
    ("mount_yaw_mdeg=-180000", "-20000..20000"),
    ("sweep_first_mdeg=180000", "0..90000"),
    ("sweep_last_mdeg=0", "90000..180000"),
]:
    p = sim.run("--set", kv, "--out", sim.out("never"), expect=2)
    key = kv.split("=")[0]
    check(("--set %s" % kv) in p.stderr and ("%s = " % key) in p.stderr and words in p.stderr,
          "--set %s: refused, its valid range given: %s" % (kv, p.stderr.strip()))
# The edges of what is taken still keep off the walls (the default room, 60 s, 2 seeds),
# judged with the optimistic sonar as test_sim_explore.py's goals are: at the typical level
# the firmware does not keep off every wall yet (issue 28).
for kv in ("accel_mm_s2=100", "mount_x_um=-100000", "mount_x_um=200000", "mount_y_um=100000",
           "mount_y_um=-100000", "mount_yaw_mdeg=20000", "mount_yaw_mdeg=-20000",
           "sweep_first_mdeg=90000", "sweep_last_mdeg=90000"):
    for seed in (1, 2):
        out = sim.out("edge")
        sim.run("--set", kv, "--seed", seed, "--duration", "60", "--sonar", "optimistic",
                "--out", out)
        touch = sim.metrics(out)["exploration"]["first_touch"]
        check_path(touch is None, "--set %s, seed %d: 60 s without touching anything" % (kv, seed))

# ---- messages that blamed the wrong thing --------------------------------------------------
p = sim.run("--set", "range_min_um=1000000", "--out", sim.out("never"), expect=2)
check("--set range_min_um=1000000: confidence_radius_um = 1000000 is out of its valid range" in p.stderr
      and "(range_min_um = 1000000)" in p.stderr,
      "--set range_min_um=1000000: the message blames that option and shows both values")
p = sim.run("--config", write("rmin.conf", "# sonar\nrange_min_um = 1000000\n"), "--out",
            sim.out("never"), expect=2)
check("rmin.conf:2: confidence_radius_um" in p.stderr,
      "... and in a file, the line that set range_min_um")
p = sim.run("--set", "start_heading_mdeg=360000", "--duration", "1", "--out", sim.out("heading"))
check(p.returncode == 0, "--set start_heading_mdeg=360000: a whole turn from the room's 0 is its heading")
p = sim.run("--set", "start_heading_mdeg=90000", "--out", sim.out("never"), expect=2)
check("start_heading_mdeg = 90000 disagrees with the run's start pose (0.000 deg)" in p.stderr,
      "--set start_heading_mdeg=90000: refused, the room's heading named")

sim.done()
