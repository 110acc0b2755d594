# SPDX-License-Identifier: MIT
"""Runs Cortex-M images in one of QEMU's machines: the self-test, a boot, a run by hand.

usage:
  tools/cortex_m.py qemu --machine NAME selftest ELF HOST_REPLAY [--out DIR] [--tick-budget N]
      Run the self-test image (hal/cortex_m/selftest), run the host build of the same
      replay (replay_host), and compare the two reports byte for byte; OM and TM are also
      decoded, checked against their CRC-32 and compared cell by cell. Prints robot_tick()
      instructions (mean and worst, from the chip's counter under -icount) and fails when
      the worst exceeds the budget.
  tools/cortex_m.py qemu --machine NAME boot ELF [--status N]
      Boot the robot image, wait for its text banner and then N telemetry STATUS frames on
      the first serial port (decoded by slamtools/link.py), check that the ticks advance
      without overruns and that the HELLO frame describes the grid, then stop it.
  tools/cortex_m.py qemu --machine NAME run ELF [--seconds S]
      Run an image for a person: the first serial port and semihosting to this terminal.

NAME is a machine of qemu-system-arm (-M help lists them) that has the image's chip: a
chip's own tools say which (tools/stm32f4.py qemu: netduinoplus2, an STM32F405).
QEMU runs with -icount shift=0,sleep=off: deterministic, and a timer at the core clock
counts one per executed instruction. Every run is bounded by timeout(1) and a time limit
of its own.

A failure (QEMU missing, an image that faults or disagrees with the host) is a ToolError
with exit status 1, a wrong command line one with 2.
"""
import os
import re
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import zlib

from .. import link
from ..errors import FAILED, ToolError

# After -M NAME: no display, no monitor, one executed instruction a nanosecond.
MACHINE_OPTIONS = ["-display", "none", "-monitor", "none", "-icount", "shift=0,sleep=off"]
# What a wrong command line prints; main() puts the chip runner's own there.
usage = __doc__
SELFTEST_EXIT = {0: "passed", 1: "the replay found mismatches", 2: "the configuration was refused",
                 3: "the image faulted", 124: "timed out"}


def qemu_command(machine):
    """qemu-system-arm with the machine and the options every run uses."""
    q = shutil.which("qemu-system-arm")
    if q is None:
        raise ToolError("qemu-system-arm was not found (Debian: tools/install-deps.sh firmware)",
                        FAILED)
    return [q, "-M", machine] + MACHINE_OPTIONS


def check_elf(path):
    if not os.path.isfile(path):
        raise ToolError("%s does not exist: build it first (make firmware)" % path)
    with open(path, "rb") as f:
        if f.read(4) != b"\x7fELF":
            raise ToolError("%s is not an ELF file" % path)


def parse_report(text, who):
    """The lines up to `end`, the maps as bytes, and the cost lines after `end`."""
    lines = text.split("\n")
    if not lines or lines[0] != "sonarslam-selftest 1":
        raise ToolError("%s: no self-test report (first line %r)"
                        % (who, lines[0] if lines else ""), FAILED)
    try:
        end = lines.index("end")
    except ValueError:
        raise ToolError("%s: the report has no 'end' line (cut short?)" % who, FAILED)
    head = "\n".join(lines[:end + 1]) + "\n"
    maps = {}
    for name in ("om", "tm"):
        hdr = [l for l in lines[:end] if l.startswith(name + " crc32 ")]
        if len(hdr) != 1:
            raise ToolError("%s: no '%s crc32' line" % (who, name), FAILED)
        m = re.match(r"^\w+ crc32 ([0-9a-f]{8}) bytes (\d+)$", hdr[0])
        if m is None:
            raise ToolError("%s: malformed line %r" % (who, hdr[0]), FAILED)
        data = bytes.fromhex("".join(l[len(name) + 1:] for l in lines[:end]
                                     if l.startswith(name + " ") and " crc32 " not in l))
        if len(data) != int(m.group(2)):
            raise ToolError("%s: %s has %d cells, the header says %s"
                            % (who, name, len(data), m.group(2)), FAILED)
        if zlib.crc32(data) != int(m.group(1), 16):
            raise ToolError("%s: %s fails its CRC-32: the transfer was corrupted" % (who, name),
                            FAILED)
        maps[name] = data
    info = {}
    for l in lines[:end]:
        if l.startswith("replay "):
            info["replay"] = l
        if l.startswith("scenario "):
            info["scenario"] = l.split()[1]
        if l.startswith("grid "):
            info["grid"] = tuple(int(x) for x in l.split()[1:3])
    costs = []
    summary = {}
    for l in lines[end + 1:]:
        f = l.split()
        if len(f) >= 2 and f[0] == "cost" and f[1] == "nop":
            summary["nop"] = int(f[2])
        elif len(f) >= 3 and f[0] == "cost" and f[1] == "idle":
            summary["idle_worst"] = int(f[3])
            summary["idle_after"] = int(f[5]) if len(f) >= 6 else None
        elif len(f) >= 3 and f[0] == "cost" and f[1] == "reading":
            summary.update(reading_worst=int(f[3]), reading_mean=int(f[5]))
        elif len(f) >= 2 and f[0] == "cost" and f[1] == "ticks":
            summary.update(ticks=int(f[2]), sum=int(f[4]), worst=int(f[6]), at=int(f[8]))
        elif len(f) >= 2 and f[0] == "cost":
            costs += [int(x, 16) for x in f[1:]]
        elif len(f) == 2 and f[0] in ("overruns",):
            summary[f[0]] = int(f[1])
        elif len(f) == 2 and f[0] == "clock":
            summary["clock"] = f[1]
    return head, maps, info, costs, summary


def start(cmd, **kw):
    """Start timeout(1) + QEMU in a process group of their own, so both can be ended:
    killing only timeout would leave QEMU running."""
    return subprocess.Popen(cmd, start_new_session=True, **kw)


def stop(proc):
    """End the process group start() made: TERM, then KILL if it lingers."""
    for sig, wait in ((signal.SIGTERM, 5), (signal.SIGKILL, 5)):
        if proc.poll() is not None:
            break
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            break
        try:
            proc.wait(timeout=wait)
        except subprocess.TimeoutExpired:
            pass
    try:
        os.killpg(proc.pid, signal.SIGKILL)  # QEMU, should timeout(1) have gone first
    except (ProcessLookupError, PermissionError):
        pass


def run_selftest_image(elf, out_dir, machine, seconds=120):
    """Run the self-test image on the machine; returns (exit status, report text)."""
    report = os.path.join(out_dir, "arm.txt")
    if os.path.exists(report):
        os.remove(report)
    cmd = ["timeout", "-k", "5", str(seconds)] + qemu_command(machine) + [
        "-serial", "null",
        "-chardev", "file,id=semihost,path=" + report,
        "-semihosting-config", "enable=on,target=native,chardev=semihost",
        "-kernel", elf]
    proc = start(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _, err = proc.communicate(timeout=seconds + 30)
    except subprocess.TimeoutExpired:
        stop(proc)
        raise ToolError("QEMU did not end within %d s" % (seconds + 30), FAILED)
    finally:
        stop(proc)
    text = open(report).read() if os.path.exists(report) else ""
    if err.strip():
        print(err.strip(), file=sys.stderr)
    return proc.returncode, text


def first_difference(a, b, grid):
    for i, (x, y) in enumerate(zip(a, b)):
        if x != y:
            return "cell (a=%d, b=%d): MCU %d, host %d" % (i % grid[0], i // grid[0], x, y)
    return "lengths %d and %d" % (len(a), len(b))


def cmd_selftest(machine, args):
    if len(args) < 2:
        raise ToolError(usage.strip())
    elf, host = args[0], args[1]
    out_dir = None
    budget = None
    rest = args[2:]
    while rest:
        if rest[0] == "--out" and len(rest) > 1:
            out_dir = rest[1]
        elif rest[0] == "--tick-budget" and len(rest) > 1:
            budget = link.parse_int(rest[1], 0, None, "--tick-budget")
        else:
            raise ToolError("unknown option %r" % rest[0])
        rest = rest[2:]
    check_elf(elf)
    if not os.access(host, os.X_OK):
        raise ToolError("%s is not an executable: build the host replay first" % host)
    tmp = None
    if out_dir is None:
        tmp = tempfile.TemporaryDirectory(prefix="slam-selftest-")
        out_dir = tmp.name
    os.makedirs(out_dir, exist_ok=True)

    t0 = time.monotonic()
    status, arm_text = run_selftest_image(elf, out_dir, machine)
    seconds = time.monotonic() - t0
    if status != 0:
        tail = "\n".join(arm_text.strip().split("\n")[-5:])
        raise ToolError("the self-test image exited with %d (%s):\n%s"
                        % (status, SELFTEST_EXIT.get(status, "unknown"), tail), FAILED)
    host_run = subprocess.run([host], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              timeout=120)
    with open(os.path.join(out_dir, "host.txt"), "w") as f:
        f.write(host_run.stdout)
    if host_run.returncode != 0:
        raise ToolError("replay_host exited with %d:\n%s"
                        % (host_run.returncode, host_run.stderr.strip()), FAILED)

    arm_head, arm_maps, info, costs, summary = parse_report(arm_text, "MCU")
    host_head, host_maps, _, _, _ = parse_report(host_run.stdout, "host")
    mismatches = int(re.search(r"mismatches (\d+)", info.get("replay", "mismatches -1")).group(1))
    for name in ("om", "tm"):
        if arm_maps[name] != host_maps[name]:
            raise ToolError("%s differs between the MCU and the host: first at %s"
                            % (name.upper(), first_difference(arm_maps[name], host_maps[name],
                                                              info["grid"])), FAILED)
    if arm_head != host_head:
        for n, (a, b) in enumerate(zip(arm_head.split("\n"), host_head.split("\n")), 1):
            if a != b:
                raise ToolError("the reports differ at line %d:\n  MCU:  %s\n  host: %s"
                                % (n, a[:120], b[:120]), FAILED)
        raise ToolError("the reports differ in length", FAILED)
    if mismatches != 0:
        raise ToolError("the replay found %d mismatched outputs: %s"
                        % (mismatches, info["replay"]), FAILED)
    if summary.get("overruns", 0) != 0:
        raise ToolError("the self-test counted %d tick overruns" % summary["overruns"], FAILED)

    occupied = sum(1 for c in arm_maps["om"] if c)
    visited = sum(1 for c in arm_maps["tm"] if c)
    print("selftest: OM and TM byte-identical on the MCU and the host "
          "(%d + %d bytes, %d occupied and %d visited cells); %s; %.1f s in QEMU"
          % (len(arm_maps["om"]), len(arm_maps["tm"]), occupied, visited,
             info["replay"], seconds))
    if "worst" in summary:
        n = summary["ticks"]
        print("selftest: robot_tick() on %s (its counter under -icount): mean %.1f, worst %d "
              "instructions (tick %d of %d); clock %s in QEMU"
              % (machine, summary["sum"] / n, summary["worst"], summary["at"], n,
                 summary.get("clock", "?")))
        if budget is not None and summary["worst"] > budget:
            raise ToolError("the worst tick, %d instructions, exceeds the budget of %d"
                            % (summary["worst"], budget), FAILED)
    if tmp is not None:
        tmp.cleanup()
    return 0


def cmd_boot(machine, args):
    if not args:
        raise ToolError(usage.strip())
    elf = args[0]
    want = 3
    if len(args) == 3 and args[1] == "--status":
        want = link.parse_int(args[2], 1, None, "--status")
    elif len(args) != 1:
        raise ToolError("unknown option %r" % args[1])
    check_elf(elf)
    limit = 60
    cmd = ["timeout", "-k", "5", str(limit)] + qemu_command(machine) + [
        "-serial", "stdio", "-kernel", elf]
    proc = start(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    text = b""          # what came before the first frame: the banner
    decoder = None
    hello = None
    statuses = []
    deadline = time.monotonic() + limit
    try:
        while len(statuses) < want and time.monotonic() < deadline:
            ready, _, _ = select.select([proc.stdout], [], [], 1.0)
            if not ready:
                if proc.poll() is not None:
                    break
                continue
            chunk = os.read(proc.stdout.fileno(), 4096)
            if not chunk:
                break
            if decoder is None:
                text += chunk
                start_of_frames = text.find(link.SYNC)
                if start_of_frames < 0:
                    continue
                chunk = text[start_of_frames:]
                text = text[:start_of_frames]
                for line in text.decode("ascii", "replace").splitlines():
                    print("  | " + line)
                if b"FAULT" in text:
                    raise ToolError("the image faulted", FAILED)
                decoder = link.Decoder()
            for ftype, payload in decoder.feed(chunk):
                fr = link.decode(ftype, payload)
                if fr["type"] == "hello" and hello is None:
                    hello = fr
                    print("  | telemetry HELLO: grid %dx%d, %d mm cells" % (
                        fr["a"], fr["b"], fr["cell_um"] // 1000))
                elif fr["type"] == "status":
                    statuses.append(fr)
                    print("  | telemetry STATUS: ticks %d, pings %d, echoes %d, overruns %d" % (
                        fr["ticks"], fr["pings"], fr["echoes"], fr["overruns"]))
    finally:
        stop(proc)
    banner = [l for l in text.decode("ascii", "replace").splitlines() if l.startswith("sonarslam ")]
    if not banner:
        raise ToolError("no banner from the robot image within %d s" % limit, FAILED)
    if hello is None or hello["a"] <= 0 or hello["b"] <= 0:
        raise ToolError("no telemetry HELLO frame describing the grid", FAILED)
    if len(statuses) < want:
        raise ToolError("%d telemetry STATUS frames within %d s, wanted %d"
                        % (len(statuses), limit, want), FAILED)
    ticks = [s["ticks"] for s in statuses]
    if any(b <= a for a, b in zip(ticks, ticks[1:])):
        raise ToolError("the ticks do not advance: %s" % ticks, FAILED)
    if statuses[-1]["overruns"] != 0:
        raise ToolError("the tick overran %d times" % statuses[-1]["overruns"], FAILED)
    if decoder.bad:
        raise ToolError("%d telemetry frames failed their CRC" % decoder.bad, FAILED)
    print("boot: banner, HELLO and %d STATUS frames; ticks %s, no overruns" % (len(statuses), ticks))
    return 0


def cmd_run(machine, args):
    if not args:
        raise ToolError(usage.strip())
    elf = args[0]
    seconds = 10
    if len(args) == 3 and args[1] == "--seconds":
        seconds = link.parse_int(args[2], 1, None, "--seconds")
    elif len(args) != 1:
        raise ToolError("unknown option %r" % args[1])
    check_elf(elf)
    cmd = ["timeout", "-k", "5", str(seconds)] + qemu_command(machine) + [
        "-serial", "stdio", "-semihosting-config", "enable=on,target=native", "-kernel", elf]
    return subprocess.call(cmd, stdin=subprocess.DEVNULL)


def main(argv, machine=None, doc=__doc__):
    """The command line; a chip's own runner passes its machine and its usage text."""
    global usage
    usage = doc
    args = argv[1:]
    if machine is None and args and args[0] == "--machine":
        if len(args) < 2:
            raise ToolError("--machine needs a name (qemu-system-arm -M help lists them)")
        machine, args = args[1], args[2:]
    if not args or args[0] in ("-h", "--help"):
        print(usage.strip())
        return 0 if args else 2
    if machine is None:
        raise ToolError("which machine? --machine NAME first (qemu-system-arm -M help lists them)")
    commands = {"selftest": cmd_selftest, "boot": cmd_boot, "run": cmd_run}
    if args[0] not in commands:
        raise ToolError("unknown command %r (selftest, boot, run)" % args[0])
    return commands[args[0]](machine, args[1:])
