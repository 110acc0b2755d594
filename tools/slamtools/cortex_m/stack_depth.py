# SPDX-License-Identifier: MIT
"""Worst-case stack depth of an image's call paths, from GCC's own per-function numbers.

usage: tools/cortex_m.py stack-depth ELF [--root NAME] [--indirect CALLER=TARGET[,TARGET]]...
                                        [--budget ROOT=BYTES]... [--json FILE]

The image is built with -fcallgraph-info=su: next to every object GCC writes a .ci file
holding each function's frame size (what -fstack-usage reports) and its calls. This script
finds the objects linked into ELF from its map file (ELF with .map instead of .elf), reads
their call graphs, and sums the deepest path from each root. Functions without a .ci file
(newlib, libgcc) are read from the disassembly: their pushes and SP subtractions, and
their calls. Calls through a pointer are resolved with --indirect. Recursion or a frame of
unbounded size is an error. An exception entry stacks 32 bytes (8 words, no FPU context)
plus up to 4 of alignment; roots that are handlers get those added.

Without --root it reports the robot image's interrupt nesting: Reset_Handler (main),
the UART, SysTick (the tick), the echo capture (whichever timer the board table uses) and
a fault, each preempting the one before.

Exit status 1 when a root is over its budget or the image cannot be bounded (recursion, a
frame of unbounded size); 2 for a wrong command line, a missing map file or call graph.
"""
import json
import os
import re
import subprocess

from .. import link
from ..errors import FAILED, ToolError
from .elf32 import Elf

EXC_FRAME = 32 + 4  # hardware-stacked r0-r3, r12, lr, pc, xpsr, plus alignment padding
NODE = re.compile(r'^node: \{ title: "([^"]+)" label: "([^"]*)"(.*)\}$')
EDGE = re.compile(r'^edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
FRAME = re.compile(r"\\n(\d+) bytes \(([a-z,]+)\)$")


def linked_objects(elf):
    """The .ci files of the objects the map file says were linked."""
    mapfile = elf[:-4] + ".map" if elf.endswith(".elf") else elf + ".map"
    if not os.path.exists(mapfile):
        raise ToolError("%s is missing: the map file tells which objects were linked" % mapfile)
    base = os.path.dirname(os.path.abspath(elf))
    text = open(mapfile).read()
    cis = set()
    for m in re.finditer(r"(\S+?\.a)\(([^)\s]+\.c\.obj)\)", text):
        lib, member = m.group(1), m.group(2)
        libdir = os.path.normpath(os.path.join(base, os.path.dirname(lib)))
        name = re.sub(r"^lib|\.a$", "", os.path.basename(lib))
        found = None
        for root, _, files in os.walk(os.path.join(libdir, "CMakeFiles", name + ".dir")):
            if member[:-4] + ".ci" in files:
                found = os.path.join(root, member[:-4] + ".ci")
        if found is None:
            raise ToolError("no call graph for %s in %s: build with -fcallgraph-info=su"
                            % (member, lib))
        cis.add(found)
    for m in re.finditer(r"(?<![(\w])((?:[\w.+-]+/)*CMakeFiles/[\w.+-]+\.dir/\S+?\.c)\.obj\b", text):
        path = os.path.normpath(os.path.join(base, m.group(1) + ".ci"))
        if not os.path.exists(path):
            raise ToolError("no call graph %s: build with -fcallgraph-info=su" % path)
        cis.add(path)
    return cis


def read_graphs(cis):
    frames = {}   # title -> (bytes, qualifier, file)
    calls = {}    # title -> set of target titles (as written)
    local = {}    # (file, plain name) -> title, for static functions
    for ci in sorted(cis):
        for line in open(ci):
            line = line.strip()
            m = NODE.match(line)
            if m:
                title, label = m.group(1), m.group(2)
                f = FRAME.search(label)
                if f:
                    if title in frames:
                        raise ToolError("%s is defined twice (%s and %s)"
                                        % (title, frames[title][2], ci), FAILED)
                    frames[title] = (int(f.group(1)), f.group(2), ci)
                    plain = title.rsplit(":", 1)[-1]
                    local[(ci, plain)] = title
                continue
            m = EDGE.match(line)
            if m:
                calls.setdefault(m.group(1), set()).add((ci, m.group(2)))
    return frames, calls, local


def disassembly(elf):
    """Frame size and callees of every function, from objdump: for library code."""
    objdump = os.environ.get("OBJDUMP", "arm-none-eabi-objdump")
    try:
        out = subprocess.run([objdump, "-d", "--no-show-raw-insn", elf], stdout=subprocess.PIPE,
                             text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise ToolError("%s -d %s failed: %s" % (objdump, elf, e), FAILED) from None
    funcs = {}
    cur = None
    for line in out.splitlines():
        m = re.match(r"^[0-9a-f]+ <([^>]+)>:$", line)
        if m:
            cur = funcs.setdefault(m.group(1), [0, set()])
            continue
        if cur is None:
            continue
        m = re.search(r"\t(push(?:\.w)?|stmdb(?:\.w)?\s+sp!,)\s*\{([^}]*)\}", line)
        if m:
            regs = 0
            for part in m.group(2).split(","):
                part = part.strip()
                r = re.match(r"r(\d+)-r(\d+)$", part)
                regs += int(r.group(2)) - int(r.group(1)) + 1 if r else 1
            cur[0] += 4 * regs
        m = re.search(r"\tsub(?:\.w|w)?\s+sp,\s*(?:sp,\s*)?#(\d+)", line)
        if m:
            cur[0] += int(m.group(1))
        m = re.search(r"\[sp, #-(\d+)\]!", line)  # a store with pre-decrement of SP
        if m:
            cur[0] += int(m.group(1))
        m = re.search(r"\t(?:bl|blx|b\.w|b)\s+[0-9a-f]+ <([^>+]+)>$", line)
        if m:
            cur[1].add(m.group(1))
    return funcs


class Graph:
    def __init__(self, elf, indirect):
        self.frames, self.calls, self.local = read_graphs(linked_objects(elf))
        self.asm = disassembly(elf)
        image = Elf(elf)
        self.in_image = set(image.symbols)
        self.image_locals = image.local_functions
        self.indirect = indirect
        self.memo = {}

    def resolve(self, ci, name):
        """The title of a callee as written in file ci."""
        if (ci, name) in self.local:
            name = self.local[(ci, name)]
        plain = self.plain(name)
        # GCC titles a weak definition like a static one; when a strong definition
        # elsewhere replaced it at link time (no local function of that name is left in
        # the image), the call goes there.
        if name != plain and plain in self.frames and plain not in self.image_locals:
            return plain
        return name

    def plain(self, title):
        return title.rsplit(":", 1)[-1]

    def find(self, name):
        hits = [t for t in self.frames if self.plain(t) == name]
        if len(hits) > 1:
            raise ToolError("%s is ambiguous: %s" % (name, ", ".join(hits)))
        if hits:
            return hits[0]
        if name in self.asm:
            return name
        raise ToolError("no function %s in the image" % name)

    def callees(self, title):
        if title in self.frames:
            out = []
            for ci, target in sorted(self.calls.get(title, ())):
                if target == "__indirect_call":
                    plain = self.plain(title)
                    if plain not in self.indirect:
                        raise ToolError("%s calls through a pointer: say where with --indirect "
                                        "%s=TARGET" % (plain, plain))
                    out += [self.find(t) for t in self.indirect[plain]]
                elif self.plain(target) in self.in_image:
                    out.append(self.resolve(ci, self.plain(target)))
                # else: a helper GCC considered but did not call in the end; a call to a
                # symbol the image lacks could not have linked.
            return out
        return sorted(self.asm.get(title, (0, set()))[1] - {title})

    def frame(self, title):
        if title in self.frames:
            size, qual, _ = self.frames[title]
            if qual == "dynamic":
                raise ToolError("%s has a frame of unbounded size (alloca or a VLA)" % title,
                                FAILED)
            return size
        if title in self.asm:
            return self.asm[title][0]
        raise ToolError("no stack information for %s (not in any call graph or the disassembly)"
                        % title, FAILED)

    def deepest(self, title, path=()):
        """(bytes, [(function, frame)...]) of the deepest path from title."""
        if title in path:
            raise ToolError("recursion: %s" % " -> ".join(self.plain(t) for t in path + (title,)),
                            FAILED)
        if title in self.memo:
            return self.memo[title]
        own = self.frame(title)
        best = (0, [])
        for callee in self.callees(title):
            d = self.deepest(callee, path + (title,))
            if d[0] > best[0]:
                best = d
        result = (own + best[0], [(self.plain(title), own)] + best[1])
        self.memo[title] = result
        return result


def measure(elf, roots=(), indirect=None):
    """({root: {bytes, frames, exception_entry, path}}, the lines that print it) for each
    root; without roots, the robot image's interrupt nesting and its total, "all nested"."""
    g = Graph(elf, indirect or {})
    nesting = not roots
    if nesting:
        # Every interrupt handler the image defines (those that are not the weak default),
        # in priority order as the board tables give it: the UART (lowest), the tick, the
        # echo capture; then a fault, whose naked handler branches to cm_fault_report.
        syms = Elf(elf).symbols
        default = syms["cm_default_handler"][0] if "cm_default_handler" in syms else None
        irqs = sorted(n for n, v in syms.items()
                      if n.endswith("_IRQHandler") and v[0] != default)
        uart = [n for n in irqs if "USART" in n or "UART" in n]
        roots = (["Reset_Handler"] + uart + ["SysTick_Handler"] +
                 [n for n in irqs if n not in uart] + ["cm_fault_report"])
    result = {}
    lines = []
    total = 0
    for root in roots:
        title = g.find(root)
        depth, path = g.deepest(title)
        exc = 0 if root == "Reset_Handler" else EXC_FRAME
        result[root] = {"bytes": depth + exc, "frames": depth, "exception_entry": exc,
                        "path": path}
        total += depth + exc
        lines.append("%-20s %4d bytes = %s%s" % (
            root, depth + exc, " + ".join("%s %d" % (f, n) for f, n in path),
            " + exception entry %d" % exc if exc else ""))
    if nesting:
        lines.append("%-20s %4d bytes (each handler preempting the one above)"
                     % ("all nested", total))
        result["all nested"] = {"bytes": total}
    return result, lines


def main(argv):
    args = argv[1:]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args else 2
    elf = args.pop(0)
    roots = []
    indirect = {}
    budgets = {}
    out_json = None
    while args:
        opt = args.pop(0)
        if opt not in ("--root", "--indirect", "--budget", "--json"):
            raise ToolError("unknown option %s" % opt)
        if not args:
            raise ToolError("%s needs a value" % opt)
        val = args.pop(0)
        if opt == "--root":
            roots.append(val)
        elif opt == "--indirect":
            caller, _, targets = val.partition("=")
            indirect[caller] = [t for t in targets.split(",") if t]
        elif opt == "--budget":
            root, _, n = val.partition("=")
            budgets[root] = link.parse_int(n, 0, None, "--budget " + root)
        else:
            out_json = val
    result, lines = measure(elf, roots, indirect)
    for line in lines:
        print(line)
    over = ["%s needs %d bytes, over its budget of %d" % (r, result[r]["bytes"], n)
            for r, n in sorted(budgets.items()) if r in result and result[r]["bytes"] > n]
    if out_json:
        with open(out_json, "w") as f:
            json.dump(result, f)
    if over:
        raise ToolError("; ".join(over), FAILED)
    return 0
