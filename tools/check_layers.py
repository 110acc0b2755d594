#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Fails when the files of a module folder of the firmware call each other in a cycle.

usage: tools/check_layers.py SRC_DIR OBJECTS [--nm NM]

A module of several files gets a folder under firmware/src/ whose files form layers: each
calls only the ones below it. SRC_DIR is firmware/src; OBJECTS the core library's object
files, separated by ';' (CMake's $<TARGET_OBJECTS:slam_core>) or given as a folder to
search. Every folder of SRC_DIR that holds .c files is a module, checked with the files of
the folders within it: a file calls another when its object leaves undefined a symbol the
other's object defines (nm: functions and data alike; a static inline function of a
header is no call). A file calling itself is fine.

Prints each folder's layers, the bottom first; or each cycle found, with the symbols that
close it. Exit 1 on a cycle, 2 on bad input (a folder's source without its object: build
first).
"""
import os
import subprocess
import sys

from slamtools.commands import take_value
from slamtools.errors import ToolError, main as tool_main


def module_folders(src):
    """{folder of src: [its .c files and those of the folders within it, relative to it]}."""
    out = {}
    for folder in sorted(os.listdir(src)):
        top = os.path.join(src, folder)
        if not os.path.isdir(top):
            continue
        cs = []
        for root, _, files in os.walk(top):
            rel = os.path.relpath(root, top)
            cs += [os.path.normpath(os.path.join(rel, f)).replace(os.sep, "/")
                   for f in files if f.endswith(".c")]
        if cs:
            out[folder] = sorted(cs)
    return out


def count(n, what):
    return "%d %s%s" % (n, what, "" if n == 1 else "s")


def object_of(rel_c, objects):
    """The object built from firmware/src/<rel_c>: its path ends in src/<rel_c>.o(bj)."""
    tails = ["src/" + rel_c + ".o", "src/" + rel_c + ".obj"]
    found = [o for o in objects if any(o.replace(os.sep, "/").endswith("/" + t) for t in tails)]
    if len(found) != 1:
        raise ToolError("%s: %s object for it among the objects given (build the core first)"
                    % (rel_c, "no" if not found else "more than one"))
    return found[0]


def symbols(nm, obj):
    """(defined global symbols, undefined symbols) of an object."""
    try:
        run = subprocess.run([nm, "-P", obj], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    except OSError as e:
        raise ToolError("cannot run %s: %s (--nm)" % (nm, e.strerror)) from None
    if run.returncode != 0:
        raise ToolError("%s %s: %s" % (nm, obj, run.stderr.strip()))
    defined, undefined = set(), set()
    for line in run.stdout.splitlines():
        f = line.split()
        if len(f) < 2:
            continue
        name, kind = f[0], f[1]
        if kind == "U":
            undefined.add(name)
        elif kind.isupper():
            defined.add(name)
    return defined, undefined


def calls(files, syms):
    """{file: {callee: [symbols]}} within one folder, calls to itself left out."""
    owner = {}
    for f in files:
        for s in syms[f][0]:
            owner.setdefault(s, []).append(f)
    out = {f: {} for f in files}
    for f in files:
        for s in sorted(syms[f][1]):
            for g in owner.get(s, []):
                if g != f:
                    out[f].setdefault(g, []).append(s)
    return out


def cycles(graph):
    """Every cycle a depth-first walk meets, each as a list of files, the first repeated."""
    found = []
    state = {f: 0 for f in graph}  # 0 not seen, 1 on the path, 2 done
    path = []

    def walk(f):
        state[f] = 1
        path.append(f)
        for g in sorted(graph[f]):
            if state[g] == 1:
                found.append(path[path.index(g):] + [g])
            elif state[g] == 0:
                walk(g)
        path.pop()
        state[f] = 2

    for f in sorted(graph):
        if state[f] == 0:
            walk(f)
    return found


def layers(graph):
    """Each file's layer: 0 calls nothing of the folder, else one above its highest callee."""
    level = {}

    def of(f):
        if f not in level:
            level[f] = 1 + max((of(g) for g in graph[f]), default=-1)
        return level[f]

    for f in graph:
        of(f)
    return level


def main(argv):
    args = argv[1:]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args else 2
    nm = take_value(args, "--nm", "a program", os.environ.get("NM", "nm"))
    if len(args) != 2:
        raise ToolError("give SRC_DIR and OBJECTS (see --help)")
    src, objs = args
    if not os.path.isdir(src):
        raise ToolError("%s is no folder" % src)
    if os.path.isdir(objs):
        objects = [os.path.join(r, f) for r, _, fs in os.walk(objs) for f in fs
                   if f.endswith((".o", ".obj"))]
    else:
        objects = [o for o in objs.split(";") if o]
    folders = module_folders(src)
    if not folders:
        raise ToolError("%s holds no module folder" % src)
    bad = 0
    for folder, files in folders.items():
        syms = {f: symbols(nm, object_of(folder + "/" + f, objects)) for f in files}
        graph = calls(files, syms)
        loops = cycles(graph)
        if loops:
            bad += 1
            for loop in loops:
                steps = ["%s calls %s (%s)" % (a, b, ", ".join(graph[a][b][:3]))
                         for a, b in zip(loop, loop[1:])]
                print("check_layers: %s: a cycle: %s; %s" % (folder, " -> ".join(loop),
                                                              "; ".join(steps)))
            continue
        level = layers(graph)
        rows = ["%d: %s" % (n, " ".join(sorted(f for f in files if level[f] == n)))
                for n in range(max(level.values()) + 1)]
        print("check_layers: %s: %s in %s, each calling only below it (%s)"
              % (folder, count(len(files), "file"), count(len(rows), "layer"), "; ".join(rows)))
    return 1 if bad else 0


if __name__ == "__main__":
    tool_main(main, sys.argv)
