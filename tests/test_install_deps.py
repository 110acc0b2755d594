#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""tools/install-deps.sh against a stand-in apt: it says what it installs and its size before
installing, waits (saying so) while another program holds apt's lock, gives up after its
time with a message naming the holder, and installs nothing when everything is there.

usage: test_install_deps.py SRC_DIR

The stand-ins (dpkg, dpkg-query, apt-get, apt-cache, id) are shell scripts first on PATH;
nothing of the real system is read or changed.
"""
import os
import shutil
import subprocess
import sys
import tempfile

SRC = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(SRC, "tools", "install-deps.sh")
failures = []


def check(ok, what):
    print("%s: %s" % ("ok" if ok else "FAIL", what))
    if not ok:
        failures.append(what)


STUBS = {
    # Root, so no sudo; amd64 with i386 enabled.
    "id": 'echo 0',
    "dpkg": 'case "$1" in --print-architecture) echo amd64 ;; --print-foreign-architectures) echo i386 ;; esac',
    # A package is installed when its name is a line of $STATE/installed.
    "dpkg-query": 'for p; do :; done; p=${p%%:*}; grep -qx "$p" "$STATE/installed" 2>/dev/null && printf "install ok installed" || exit 1',
    # The lock is held while $STATE/locked holds a number: each call takes one off.
    "apt-get": r'''
if [ "$1" = "-s" ]; then
    for p in "$@"; do case "$p" in -*|install) ;; *) echo "Inst $p (1.0 Debian:12/stable [amd64])"; echo "Inst lib$p (1.0 Debian:12/stable [amd64])" ;; esac; done
    exit 0
fi
n=$(cat "$STATE/locked" 2>/dev/null || echo 0)
if [ "$n" -gt 0 ]; then
    echo $((n - 1)) > "$STATE/locked"
    echo "E: Could not get lock /var/lib/dpkg/lock-frontend. It is held by process $$ (unattended-upgr)" >&2
    echo "E: Unable to acquire the dpkg frontend lock (/var/lib/dpkg/lock-frontend), is another process using it?" >&2
    exit 100
fi
echo "apt-get $*" >> "$STATE/calls"
if [ "$1" = "install" ]; then
    for p in "$@"; do case "$p" in -*|install) ;; *) echo "${p%%:*}" >> "$STATE/installed" ;; esac; done
fi
exit 0''',
    # Each package: 2 MB to download, 5 MiB installed.
    "apt-cache": r'''shift 2; for p in "$@"; do printf 'Package: %s\nSize: 2000000\nInstalled-Size: 5120\n\n' "$p"; done''',
}


def run(state, *groups, env=None):
    e = dict(os.environ)
    e.update({"PATH": os.path.join(state, "bin") + ":" + e["PATH"], "STATE": state,
              "INSTALL_DEPS_LOCK_POLL": "0"})
    e.update(env or {})
    return subprocess.run(["/bin/sh", SCRIPT] + list(groups), env=e, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, timeout=120)


def fresh():
    state = tempfile.mkdtemp(prefix="slam-deps-")
    os.mkdir(os.path.join(state, "bin"))
    for name, body in STUBS.items():
        path = os.path.join(state, "bin", name)
        with open(path, "w") as f:
            f.write("#!/bin/sh\n" + body + "\n")
        os.chmod(path, 0o755)
    return state


def calls(state):
    try:
        with open(os.path.join(state, "calls")) as f:
            return f.read().splitlines()
    except FileNotFoundError:
        return []


# A fresh machine: the web group's two packages, announced with their size.
state = fresh()
p = run(state, "web")
check(p.returncode == 0 and "installing python3 python3-websockets" in p.stdout
      and "4 packages with what they need: about 8 MB to download, 21 MB on disk" in p.stdout,
      "what it installs and its size, before installing:\n%s" % p.stdout)
check([c.split()[1] for c in calls(state)] == ["update", "install"],
      "then apt-get update and install: %s" % calls(state))
p = run(state, "web")
check(p.returncode == 0 and "all needed Debian packages are installed" in p.stdout
      and len(calls(state)) == 2, "a second run installs nothing and says so")
shutil.rmtree(state)

# apt busy for three tries: the script says so once and waits.
state = fresh()
with open(os.path.join(state, "locked"), "w") as f:
    f.write("3\n")
p = run(state, "web")
check(p.returncode == 0 and p.stderr.count("apt is busy") == 1 and "unattended" in p.stderr
      and "Could not get lock" not in p.stderr and len(calls(state)) == 2,
      "a held lock is waited for, with one message:\n%s" % p.stderr)
shutil.rmtree(state)

# apt busy for longer than the script waits: a clear error, exit 1, nothing installed.
state = fresh()
with open(os.path.join(state, "locked"), "w") as f:
    f.write("1000\n")
p = run(state, "web", env={"INSTALL_DEPS_LOCK_WAIT": "0"})
check(p.returncode == 1 and "apt is still busy after 0 s" in p.stderr
      and "INSTALL_DEPS_LOCK_WAIT" in p.stderr and "still missing" in p.stderr,
      "a lock held too long: exit 1, naming the holder and how to wait longer:\n%s" % p.stderr)
shutil.rmtree(state)

p = subprocess.run(["/bin/sh", SCRIPT, "nonsense"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                   text=True)
check(p.returncode == 2 and "unknown group 'nonsense'" in p.stderr, "an unknown group: exit 2")

print("%d failed" % len(failures) if failures else "all passed")
sys.exit(1 if failures else 0)
