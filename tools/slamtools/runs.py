# SPDX-License-Identifier: MIT
"""host_sim over many runs, and the figures over them: what sim_report.py, pose_report.py
and corpus_report.py share.

A run is cached in its folder (args.json beside its metrics.json) and loses its bulky
files once read; run_all() runs a dict of them in parallel, the longest first. The
statistics are the reports' own: mean, median, standard error, percentiles.
"""
import json
import math
import os
import statistics
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

from .errors import FAILED, ToolError

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROOMS = os.path.join(SRC, "host_sim", "rooms")
# Building maps of other projects (each with its licence in its folder), and the part of
# each the robot explores: the crops host_building_maps loads.
BUILDINGS = (
    ("edu_room", "edu_room/edu_room_cropped.yaml", None),
    ("intel_lab", "intel_lab/intel.yaml", (5.0, 5.0, 12.0, 10.0)),
    ("willow_garage", "willow_garage/willow-2010-02-18-0.10.yaml", (20.0, 20.0, 12.0, 12.0)),
    ("utexas_gdc_3ne", "utexas_gdc_3ne/3ne.yaml", (-20.0, -10.0, 12.0, 10.0)),
)
BUILDING_S = 1800


# What a run writes that grows with its length: deleted once its metrics.json is read,
# unless the run is kept (--keep, or a figure draws it), so that a report's hundreds of
# runs leave megabytes, not gigabytes (the ten-hour runs' logs alone are 70 MB each).
BULKY_FILES = ("readings.csv", "trajectory.csv", "scoring_estimate.csv")
BULKY_EXT = (".pgm", ".yaml")


def bulky(out):
    return [n for n in os.listdir(out) if n in BULKY_FILES or n.endswith(BULKY_EXT)]


def run(bin_, out, args, keep=False):
    """One host_sim run (cached: an existing metrics.json of the same args and the same
    host_sim binary is reused; a rebuilt binary runs again, and so does a run to keep whose
    files were deleted). Unless keep, its bulky files are deleted once it is read."""
    stamp = os.path.join(out, "args.json")
    key = {"args": [str(a) for a in args], "host_sim_mtime_ns": os.stat(bin_).st_mtime_ns}
    cached = False
    if os.path.exists(stamp) and os.path.exists(os.path.join(out, "metrics.json")):
        with open(stamp) as f:
            cached = json.load(f) == key and \
                (not keep or os.path.exists(os.path.join(out, "trajectory.csv")))
    if not cached:
        cmd = [bin_, "--quiet", "--no-plot", "--out", out] + [str(a) for a in args]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            raise ToolError("%s failed:\n%s" % (" ".join(cmd), p.stderr), FAILED)
        with open(stamp, "w") as f:
            json.dump(key, f)
    with open(os.path.join(out, "metrics.json")) as f:
        m = json.load(f)
    if not keep:
        for name in bulky(out):
            os.remove(os.path.join(out, name))
    return m


def cores():
    """The processors this process may run on: every one, unless an affinity mask (taskset,
    a container) leaves it fewer."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 2


def duration(args):
    """The simulated seconds a run's arguments ask for (host_sim's default: 600)."""
    a = [str(x) for x in args]
    if "--duration" in a[:-1]:
        try:
            return float(a[a.index("--duration") + 1])
        except ValueError:
            pass
    return 600.0


def run_all(bin_, base, jobs, workers, what="sim_report", keep=lambda name: False):
    """jobs: {name: args}; returns {name: metrics}, running `workers` at a time, the longest
    runs first (a ten-hour run started last would finish alone on one core), and says on
    stderr how long it took. keep(name): whether that run keeps its bulky files."""
    names = sorted(jobs)
    order = sorted(names, key=lambda n: -duration(jobs[n]))
    fresh = []
    t0 = time.monotonic()

    def one(n):
        stamp = os.path.join(base, n, "args.json")  # run() rewrites it when it runs
        before = os.stat(stamp).st_mtime_ns if os.path.exists(stamp) else None
        m = run(bin_, os.path.join(base, n), jobs[n], keep(n))
        if before is None or os.stat(stamp).st_mtime_ns != before:
            fresh.append(n)
        return m

    with ThreadPoolExecutor(max_workers=workers) as ex:
        done = dict(zip(order, ex.map(one, order)))
    print("%s: %d runs of host_sim (%d reused) in %.0f s, %d at a time"
          % (what, len(names), len(names) - len(fresh), time.monotonic() - t0, workers),
          file=sys.stderr)
    return {n: done[n] for n in names}


def mean(xs):
    xs = list(xs)
    return sum(xs) / len(xs) if xs else float("nan")


def median(xs):
    xs = sorted(xs)
    n = len(xs)
    if n == 0:
        return float("nan")
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])


def std_error(xs):
    """The standard error of the mean of xs (the sample's σ over √n); NaN under two."""
    xs = list(xs)
    return statistics.stdev(xs) / math.sqrt(len(xs)) if len(xs) > 1 else math.nan


def percentile(xs, q):
    """The q-th percentile (0..100), linear between the nearest ranks."""
    xs = sorted(xs)
    if not xs:
        return math.nan
    pos = (len(xs) - 1) * q / 100.0
    lo = int(pos)
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def add_host_arg(ap, example):
    """--host-arg, as sim_report, pose_report and corpus_report take it: one more host_sim argument for
    every run."""
    ap.add_argument("--host-arg", action="append", default=[], metavar="ARG",
                    help="one more host_sim argument for every run (repeatable), for example "
                    + example)
