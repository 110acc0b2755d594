#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""make docs, make docs-check: the READMEs' generated figures, made again from the build.

usage: tools/docs.py HOST_SIM [--check] [--stm32f4 BUILD] [--compare] [--only NAME,...]

A generated block of a Markdown page lies between `<!-- figures: NAME -->` and
`<!-- /figures -->`; each NAME has a generator below that runs the simulator or a tool
that measures the build, and returns the block's text and the pictures it draws
(sim-report, pose-report and the bench's fill several blocks, one a section of their
report; the bench's and compare's are in slamtools/docgen_bench.py and docgen_compare.py). Without --check the blocks and pictures are
rewritten in place. With --check they are made in a temporary folder and compared with
the committed ones: text exactly, except the line of wall time and speed, which follows
the machine; pictures byte for byte (tools/plot_run.py renders with matplotlib's Agg
backend and no version in the file, so the same build on the same Debian draws the same
bytes), except the web viewer's screenshot: another machine's Chromium can draw the page
in other bytes, so it carries the digest of what it shows (the run's telemetry and the
page's files) and is compared, and drawn again, by that digest alone. The simulator is
deterministic and callgrind, QEMU -icount and unicorn count instructions exactly: the same
build gives the same numbers. Wall-clock speeds, which do not repeat, are never in a
block.

Generators:
  make-sim   README.md: what `make sim` prints; host_sim/figures/default_room.png, its
             figure.png (the README's first picture)
  headline   README.md: the table of "How good the maps are", the paper's row included,
             and the runs' wall coverage and touches: every shipped room x seeds 1-10,
             ten minutes, at the default (typical) sonar (180 runs, under a minute)
  corpus     host_sim/README.md: the corpus tables, what `make corpus` prints
             (tools/corpus_report.py, 344 runs, about a minute), and
             host_sim/figures/corpus.png (tools/roomgen.py figure)
  screenshot tools/web/screenshot.png (README.md's and tools/web/README.md's picture of
             the web viewer), as the page test draws it with Chromium; --check runs the
             simulator alone, for the digest
  sim-report host_sim/README.md: the tables of "What the simulator shows" that
             tools/sim_report.py prints (make report), one block a section
             (sim-report-cell-size, ...; about half a minute), and their picture,
             host_sim/figures/report.png
  pose-report host_sim/README.md: tools/pose_report.py's tables without its ten-hour
             runs (pose-report-on-off, -work, -by-room), and
             host_sim/figures/pose_correction.png from its one-hour runs of seed 1
  calibrate  tools/README.md: what `make calibrate` prints (tools/calibrate_sim.py, a few
             seconds; the calibration it writes is left in the temporary folder)
  bench-core firmware/README.md: the tick on the host and the core's RAM
             (tools/bench.py --core-only; callgrind, about 30 s)
  bench-sim  host_sim/README.md: the default run's instructions per control period, by
             part (tools/bench.py --sim-only, the wall-clock speed left out; about 20 s)
  bench-world hal/host/README.md: bench_world's instructions per tick (its three
             callgrind commands, a few seconds)
  bench-stm32f4 hal/stm32f4/README.md: the table of `make bench` on the Cortex-M4 and the
             HAL calls of the tick (tools/stm32f4.py bench BUILD --json: QEMU and unicorn,
             about 2 min); only with --stm32f4 BUILD (make docs and make docs-check give
             build/stm32f4), else its blocks are left as they are
  compare    tools/README.md and host_sim/README.md: the firmware's mapper beside OctoMap
             (tools/compare.py, what `make compare` runs: OctoMap from make compare's
             build/compare); only with --compare: make docs runs it, make docs-check
             only as `make docs-check DOCS_CHECK_ARGS=--compare` (CI leaves it out: it
             needs OctoMap, and on two cores it takes the whole check from under three
             minutes to over four; run it after a change to the mapper or the sonar)
--only NAME,... runs those generators alone (the others' blocks are left as they are).
The generators run two at a time, the bench's beside the simulator's.
Exit status: 0 up to date (or rewritten); 1 --check found a difference, or a run failed;
2 bad options.
"""
import difflib
import filecmp
import glob
import json
import os
import re
import shutil
import subprocess
import statistics
import sys
import tempfile
import textwrap
from concurrent.futures import ThreadPoolExecutor

from slamtools import docgen_bench, docgen_compare, pngtext
from slamtools.commands import take_value
from slamtools.errors import FAILED, ToolError, main as tool_main

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLOCK = re.compile(r"(<!-- figures: ([a-z0-9-]+) -->\n)(.*?)(<!-- /figures -->)", re.S)
WALL_TIME = re.compile(r"in [0-9.]+ s of wall time: [0-9]+x real time")


def make_sim(host_sim, work):
    """host_sim as make sim runs it (the default room, robot and options): its summary as
    README.md shows it, and its figure."""
    out = os.path.join(work, "sim")
    p = subprocess.run([host_sim, "--out", out], cwd=SRC, stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise ToolError("host_sim --out %s exited %d:\n%s" % (out, p.returncode, p.stderr),
                        FAILED)
    text = p.stdout.replace(out, "out/sim").replace(SRC + "/", "").lstrip("\n")
    block = "```\n%s```\n" % text
    return {"README.md": block}, {"host_sim/figures/default_room.png":
                                  os.path.join(out, "figure.png")}


# The rows of the README's table: what each runs beyond the default robot.
HEADLINE_ROWS = (
    ("the paper's map (`--paper --set localize=0`: hit counts, TH 3, K 1, insert; odometry "
     "alone)", ["--paper", "--set", "localize=0"]),
    ("free-space evidence, odometry alone (`--set localize=0`)", ["--set", "localize=0"]),
    ("free-space evidence and the pose correction (the default)", []),
)
HEADLINE_SEEDS = 10


def headline_run(host_sim, out, args):
    """One ten-minute run; its metrics.json read, its folder removed."""
    p = subprocess.run([host_sim, "--out", out, "--no-plot", "--quiet", "--duration", "600"]
                       + args, cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True)
    if p.returncode != 0:
        raise ToolError("host_sim %s exited %d:\n%s" % (" ".join(args), p.returncode, p.stderr),
                        FAILED)
    with open(os.path.join(out, "metrics.json"), encoding="utf-8") as f:
        m = json.load(f)
    shutil.rmtree(out, ignore_errors=True)
    return m


def headline(host_sim, work):
    """The README's table: mean final F1 from the robot's own pose and from the true poses,
    the median final heading error, over every shipped room x seeds 1..10; then the
    default robot's wall coverage and the runs that touched."""
    rooms = sorted(glob.glob(os.path.join(SRC, "host_sim", "rooms", "*.room")))
    jobs = [(r, room, seed) for r in range(len(HEADLINE_ROWS)) for room in rooms
            for seed in range(1, HEADLINE_SEEDS + 1)]

    def one(job):
        r, room, seed = job
        name = "headline-%d-%s-%d" % (r, os.path.basename(room)[:-5], seed)
        return r, headline_run(host_sim, os.path.join(work, name),
                               ["--room", os.path.relpath(room, SRC), "--seed", str(seed)]
                               + HEADLINE_ROWS[r][1])
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        done = list(pool.map(one, jobs))
    lines = ["| method | F1 from the robot's own pose | F1 at the true poses | "
             "heading error, median |", "|---|---|---|---|"]
    for r, (label, _) in enumerate(HEADLINE_ROWS):
        ms = [m for i, m in done if i == r]
        own = statistics.mean(m["maps"]["odometry"]["insert"]["f1"] for m in ms)
        true = statistics.mean(m["maps"]["perfect_odometry"]["insert"]["f1"] for m in ms)
        head = statistics.median(m["odometry"]["final_heading_deg"] for m in ms)
        bold = "**%s**" if r == len(HEADLINE_ROWS) - 1 else "%s"
        lines.append("| %s | %s | %s | %s |" % (label, bold % ("%.3f" % own),
                                                bold % ("%.3f" % true),
                                                bold % ("%.1f°" % head)))
    ms = [m for i, m in done if i == len(HEADLINE_ROWS) - 1]
    cover = statistics.mean(m["exploration"]["wall_coverage"] for m in ms)
    touched = sum(1 for m in ms if m["exploration"]["first_touch"] is not None)
    lines += [""] + textwrap.wrap(
        "With the default robot the sonar looked at %.0f %% of the walls from within 1 m "
        "(wall coverage %.2f), and %d of the %d runs touched an obstacle."
        % (100 * cover, cover, touched, len(ms)), width=90)
    return {"README.md": "\n".join(lines) + "\n"}, {}


def corpus(host_sim, work):
    """host_sim/README.md's corpus tables: tools/corpus_report.py's, one heading level down."""
    p = subprocess.run([os.path.join(SRC, "tools", "corpus_report.py"), "--host-sim", host_sim,
                        "--out", os.path.join(work, "corpus")], cwd=SRC,
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise ToolError("tools/corpus_report.py exited %d:\n%s" % (p.returncode, p.stderr), FAILED)
    text = re.sub(r"^### ", "#### ", p.stdout.strip(), flags=re.M)
    png = os.path.join(work, "corpus.png")
    p = subprocess.run([os.path.join(SRC, "tools", "roomgen.py"), "figure", "--out", png],
                       cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise ToolError("tools/roomgen.py figure exited %d:\n%s" % (p.returncode, p.stderr),
                        FAILED)
    return {"host_sim/README.md": "\n" + text + "\n\n"}, {"host_sim/figures/corpus.png": png}


# tools/sim_report.py's sections (how each heading begins) and the block each fills.
SIM_REPORT_BLOCKS = (
    ("Post-processing, the paper's method", "sim-report-post-paper"),
    ("Post-processing, the evidence map", "sim-report-post-evidence"),
    ("Acceleration and odometry", "sim-report-acceleration"),
    ("Perfect odometry", "sim-report-perfect-odometry"),
    ("Cell size", "sim-report-cell-size"),
    ("Exploration", "sim-report-exploration"),
    ("Wall coverage per room", "sim-report-wall-coverage"),
    ("Visiting the free cells", "sim-report-free-cells"),
    ("Building maps", "sim-report-building-maps"),
    ("Faults", "sim-report-faults"),
    ("Sonar realism levels", "sim-report-sonar-levels"),
)


def report_blocks(script, args, mapping):
    """Runs a report of tools/ and cuts its Markdown into blocks of host_sim/README.md, one
    a section: `make report` and the runs its heading describes, then its tables."""
    p = subprocess.run([os.path.join(SRC, "tools", script)] + args, cwd=SRC,
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise ToolError("tools/%s exited %d:\n%s" % (script, p.returncode, p.stderr), FAILED)
    sections = re.split(r"^### ", p.stdout, flags=re.M)[1:]
    blocks = {}
    for begins, name in mapping:
        found = [s for s in sections if s.startswith(begins)]
        if len(found) != 1:
            raise ToolError("tools/%s printed %d sections that begin %r"
                            % (script, len(found), begins), FAILED)
        heading, body = found[0].split("\n", 1)
        body = re.sub(r"^\(figure: .*\)$", "", body, flags=re.M)  # where it drew, not what
        runs = re.search(r"\(([^()]*(?:`[^`]*`[^()]*)*)\)$", heading.strip())
        said = "`make report` (%s):" % runs.group(1) if runs else "`make report`:"
        blocks[("host_sim/README.md", name)] = "%s\n\n%s\n\n" % (said, body.strip())
    return blocks


def sim_report(host_sim, work):
    """host_sim/README.md's tables of tools/sim_report.py, a block a section, and their
    picture."""
    png = os.path.join(work, "report.png")
    return report_blocks("sim_report.py", ["--host-sim", host_sim, "--out",
                                           os.path.join(work, "sim_report"), "--figure", png],
                         SIM_REPORT_BLOCKS), {"host_sim/figures/report.png": png}


# tools/pose_report.py's sections and their blocks; its long runs are not among them (ten
# hours, twelve seeds: tools/pose_report.py alone, host_sim/experiments.md).
POSE_REPORT_BLOCKS = (
    ("Pose correction on and off", "pose-report-on-off"),
    ("The correction's work", "pose-report-work"),
    ("What the correction changes", "pose-report-by-room"),
)


def pose_report(host_sim, work):
    """host_sim/README.md's tables of tools/pose_report.py without its ten-hour runs, and
    the picture of the one-hour runs of seed 1 (both READMEs show it)."""
    png = os.path.join(work, "pose_correction.png")
    blocks = report_blocks("pose_report.py", [
        "--host-sim", host_sim, "--out", os.path.join(work, "pose_report"),
        "--long-durations", "3600", "--long-seeds", "1", "--figure", png], POSE_REPORT_BLOCKS)
    return blocks, {"host_sim/figures/pose_correction.png": png}


def calibrate(host_sim, work):
    """tools/README.md: what `make calibrate` prints, its runs' lines left out; the
    calibration it writes goes to the temporary folder, not to host_sim/calibration."""
    p = subprocess.run([os.path.join(SRC, "tools", "calibrate_sim.py"), host_sim, "--write",
                        os.path.join(work, "calibration.conf"), "--out",
                        os.path.join(work, "calibrate")], cwd=SRC, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        raise ToolError("tools/calibrate_sim.py exited %d:\n%s" % (p.returncode, p.stdout[-2000:]),
                        FAILED)
    lines = [ln for ln in p.stdout.splitlines()
             if re.match(r"[123]/3 |  E_max,syst = |  seed ", ln)]
    return {"tools/README.md": "```\n%s\n```\n" % "\n".join(lines)}, {}


class Drawn:
    """A picture a browser draws: its bytes follow the machine's Chromium, so it is compared
    by the digest of what it shows (a tEXt chunk "source") and drawn only when that differs."""

    def __init__(self, source, draw):
        self.source, self.draw = source, draw

    def current(self, path):
        return os.path.exists(path) and pngtext.read_text(path).get("source") == self.source


def page_test(host_sim, *args):
    p = subprocess.run(["/usr/bin/python3", os.path.join(SRC, "tests", "web", "test_web_page.py"),
                        host_sim, SRC] + list(args), cwd=SRC, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        raise ToolError("tests/web/test_web_page.py exited %d (77: no Chromium):\n%s"
                        % (p.returncode, p.stdout[-2000:]), FAILED)
    return p.stdout


def screenshot(host_sim, work):
    """The README's picture of the web viewer: the page test's screenshot
    (tools/web/README.md), made with the same Chromium the page test drives."""
    png = os.path.join(work, "screenshot.png")
    source = page_test(host_sim, "--screenshot-source").split()[-1]

    def draw():
        page_test(host_sim, "--screenshot", png)
        return png
    return {}, {"tools/web/screenshot.png": Drawn(source, draw)}


def only_texts(gen):
    """A generator of blocks alone, no pictures."""
    return lambda host_sim, work: (gen(host_sim, work), {})


# Two chains run side by side: the simulator's runs (each a pool over every core) and the
# measurements under callgrind, QEMU and unicorn (one process each).
GENERATORS = {"make-sim": make_sim, "headline": headline, "corpus": corpus,
              "sim-report": sim_report, "pose-report": pose_report, "calibrate": calibrate,
              "screenshot": screenshot}
BENCH_GENERATORS = {"bench-core": only_texts(docgen_bench.bench_core),
                    "bench-sim": only_texts(docgen_bench.bench_sim),
                    "bench-world": only_texts(docgen_bench.bench_world)}


def blocks_of(page):
    with open(os.path.join(SRC, page), encoding="utf-8") as f:
        return f.read()


USAGE = ("usage: tools/docs.py HOST_SIM [--check] [--stm32f4 BUILD] [--compare] "
         "[--only NAME,...] (--help)")


def chains(host_sim, stm32f4, compare):
    """The generators to run, in two chains: {name: generator} each."""
    sims = dict(GENERATORS)
    bench = dict(BENCH_GENERATORS)
    if stm32f4:
        bench["bench-stm32f4"] = lambda h, w: (docgen_bench.bench_stm32f4(stm32f4, w), {})
    if compare:
        # OctoMap's runs are the simulator's kind: a pool of their own over every core.
        sims["compare"] = lambda h, w: (docgen_compare.compare(h, w), {})
    return sims, bench


def run_chain(gens, host_sim, work):
    texts, pictures = {}, {}
    for name, gen in gens.items():
        t, pics = gen(host_sim, work)
        # A generator names its page, or its page and block when it fills several.
        for key, block in t.items():
            texts[key if isinstance(key, tuple) else (key, name)] = block
        pictures.update(pics)
    return texts, pictures


def main(argv):
    if argv and argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    args = list(argv)
    stm32f4 = take_value(args, "--stm32f4", "a build folder of the stm32f4 preset")
    only = take_value(args, "--only", "generators' names")
    check = "--check" in args
    compare = "--compare" in args
    args = [a for a in args if a not in ("--check", "--compare")]
    if len(args) != 1 or args[0].startswith("-"):
        raise ToolError(USAGE)
    host_sim = os.path.abspath(args[0])
    if not os.access(host_sim, os.X_OK):
        raise ToolError("%s is not a program (build host_sim first)" % host_sim)
    if stm32f4 is not None:
        stm32f4 = os.path.abspath(stm32f4)
        if not os.path.isdir(stm32f4):
            raise ToolError("%s is not a build folder (cmake --preset stm32f4)" % stm32f4)
    sims, bench = chains(host_sim, stm32f4, compare or (only is not None and
                                                       "compare" in only.split(",")))
    if only is not None:
        names = only.split(",")
        unknown = [n for n in names if n not in sims and n not in bench]
        if unknown:
            raise ToolError("no generator %s (--help lists them; bench-stm32f4 needs "
                            "--stm32f4 BUILD)" % ", ".join(unknown))
        sims = {n: g for n, g in sims.items() if n in names}
        bench = {n: g for n, g in bench.items() if n in names}
    ran = list(sims) + list(bench)
    work = tempfile.mkdtemp(prefix="slam-docs-")
    stale = []
    try:
        with ThreadPoolExecutor(max_workers=2) as pool:
            done = [pool.submit(run_chain, gens, host_sim, work) for gens in (sims, bench)]
            results = [d.result() for d in done]
        texts, pictures = {}, {}
        for t, pics in results:
            texts.update(t)
            pictures.update(pics)
        pages = sorted({page for page, _ in texts})
        for page in pages:
            old = blocks_of(page)
            found = {m.group(2) for m in BLOCK.finditer(old)}
            for (p, name) in texts:
                if p == page and name not in found:
                    raise ToolError("%s has no <!-- figures: %s --> block" % (page, name), FAILED)

            def fill(m, page=page):
                return m.group(1) + texts.get((page, m.group(2)), m.group(3)) + m.group(4)
            new = BLOCK.sub(fill, old)
            if WALL_TIME.sub("", new) != WALL_TIME.sub("", old):
                stale.append(page)
                if check:
                    sys.stdout.writelines(difflib.unified_diff(
                        old.splitlines(True), new.splitlines(True), page + " (committed)",
                        page + " (made now)"))
                else:
                    with open(os.path.join(SRC, page), "w", encoding="utf-8") as f:
                        f.write(new)
        for dest, made in sorted(pictures.items()):
            path = os.path.join(SRC, dest)
            if isinstance(made, Drawn):
                if made.current(path):
                    continue
            elif os.path.exists(path) and filecmp.cmp(path, made, shallow=False):
                continue
            stale.append(dest)
            if not check:
                shutil.copyfile(made.draw() if isinstance(made, Drawn) else made, path)
    except OSError as e:
        raise ToolError(str(e), FAILED) from None
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if check:
        if stale:
            raise ToolError("out of date: %s (make docs makes them again)" % ", ".join(stale),
                            FAILED)
        print("docs: the generated figures are up to date (%s)" % ", ".join(ran))
    else:
        print("docs: %s" % ("rewrote " + ", ".join(stale) if stale else "nothing to change"))
    left = [n for n, why in (("bench-stm32f4", stm32f4 is None and only is None),
                             ("compare", not compare and only is None)) if why]
    if left:
        print("docs: not made again: %s (--help says how)" % ", ".join(left))
    return 0


if __name__ == "__main__":
    tool_main(main, sys.argv[1:])
