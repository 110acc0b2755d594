# SPDX-License-Identifier: MIT
"""tools/docs.py's generator of the comparison with OctoMap and HIMM (`make compare`).

Runs tools/compare.py as make compare does (every shipped room x seeds 1-10, 600 s, every
OctoMap setting; then the generated rooms 1-100, each with its seed, the chosen setting)
into folders of its own, takes their tables from compare.md for tools/README.md, and from
compare.json the summary of host_sim/README.md and the sentences both pages draw from the
tables. F1 scores and callgrind's instruction counts
repeat exactly on the same build and the same OctoMap.
"""
import json
import os
import subprocess

from .docgen_bench import grouped, wrap
from .errors import FAILED, ToolError

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OCTOMAP = os.path.join(SRC, "build", "compare", "octomap_replay")

# The settings the sentences name, as tools/compare.py labels them.
AXIS = "axis only (1 ray, as the firmware), 1 m, 0.6 / 0.45"
CENTRAL = "fan 7.5° (the cone's central half), 1 m, 0.6 / 0.45"
FAN = "fan 15°"
LEVEL = 0.005   # F1 nearer than this to the firmware's is "level with" it


def mean(xs):
    xs = list(xs)
    return sum(xs) / len(xs)


def tables(md):
    """compare.md's Markdown tables, in order: each a list of lines."""
    found, cur = [], []
    for line in md.splitlines():
        if line.startswith("|"):
            cur.append(line)
        elif cur:
            found.append(cur)
            cur = []
    if cur:
        found.append(cur)
    return found


GENERATED = 100  # make compare's COMPARE_GENERATED


def run_compare(host_sim, out, args, n_tables):
    """tools/compare.py into `out`: its Markdown tables and its compare.json."""
    p = subprocess.run([os.path.join(SRC, "tools", "compare.py"), "--host-sim", host_sim,
                        "--octomap", OCTOMAP, "--out", out, "--jobs", str(os.cpu_count() or 1)]
                       + args, cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        raise ToolError("tools/compare.py exited %d:\n%s" % (p.returncode, p.stderr[-3000:]),
                        FAILED)
    with open(os.path.join(out, "compare.md"), encoding="utf-8") as f:
        found = tables(f.read())
    with open(os.path.join(out, "compare.json"), encoding="utf-8") as f:
        data = json.load(f)
    if len(found) != n_tables:
        raise ToolError("tools/compare.py printed %d tables, not %d" % (len(found), n_tables),
                        FAILED)
    return found, data


def compare(host_sim, work):
    """Both pages' blocks from the runs of tools/compare.py make compare makes."""
    if not os.access(OCTOMAP, os.X_OK):
        raise ToolError("%s is missing: make compare builds it (OctoMap from Debian)" % OCTOMAP,
                        FAILED)
    found, data = run_compare(host_sim, os.path.join(work, "compare"), [], 2)
    gen_found, gen = run_compare(host_sim, os.path.join(work, "compare-generated"),
                                 ["--generated", str(GENERATED), "--no-variants"], 1)
    runs = data["runs"]
    irs = data["variant_instructions_per_reading"]
    rooms = sorted({r["room"] for r in runs})
    seeds = sorted({r["seed"] for r in runs})
    duration = data.get("duration")
    n = len(runs)

    def f1(key):
        return mean(r[key]["f1"] for r in runs)

    def wins(fw, om):
        return sum(r[fw]["f1"] >= r[om]["f1"] for r in runs)

    def prf(key, bold=False):
        m = {k: mean(r[key][k] for r in runs) for k in ("precision", "recall", "f1")}
        f = "**%.3f**" if bold else "%.3f"
        return ("%.3f / %.3f / " + f) % (m["precision"], m["recall"], m["f1"])

    counted = [r for r in runs if "firmware_ir" in r]
    reads = sum(r["readings"] for r in counted)
    fw_ir = sum(r["firmware_ir"] for r in counted) / reads
    om_ir = sum(r["octomap_ir"] for r in counted) / reads
    variant_f1 = {label: mean(r["variants"][label]["f1"] for r in runs)
                  for label in runs[0]["variants"]}
    fans = [v for v in variant_f1 if v.startswith(FAN)]
    fw_true, om_true = f1("firmware"), f1("octomap")
    fw_est, om_est = f1("firmware_est"), f1("octomap_est")
    what = "%d rooms × seeds %d–%d, %s s" % (len(rooms), seeds[0], seeds[-1],
                                            grouped(duration) if duration else "600")

    # tools/README.md: both tables as compare.py prints them, and what they say.
    lost = []
    for room in rooms:
        rs = [r for r in runs if r["room"] == room]
        a, b = (mean(r["firmware_est"]["f1"] for r in rs), mean(r["octomap_est"]["f1"] for r in rs))
        if a < b:
            lost.append("`%s`'s (%.3f against %.3f)" % (room, a, b))
    if not lost:
        by_room = "and in every room's mean"
    else:
        by_room = ("and in every room's mean but " + ", ".join(lost) if len(lost) < len(rooms) / 2
                   else "lower in %d of %d rooms' means" % (len(lost), len(rooms)))
    fans_beaten = all(fw_true > variant_f1[v] for v in fans)
    cheapest = min((v for v in fans if v in irs), key=lambda v: irs[v])
    # "fan 15°, 1 m, 0.6 / 0.45, lazy evaluation (...)": the part after the chosen setting
    named = cheapest.split(", ", 3)[3] if cheapest.count(", ") >= 3 else cheapest
    cheap_ratio = irs["firmware"] / irs[cheapest]
    bullets = [
        "With OctoMap inserting the sonar as a fan across the 15° cone (the chosen setting%s), "
        "the firmware's F1 from the true poses is at least OctoMap's in %d of %d runs (%.3f "
        "against %.3f) at 1/%.0f of the instructions; against %s, OctoMap's cheapest 15° fan, "
        "1/%.0f on the one run counted (%s), %s 1/100."
        % (", and every 15° fan tried" if fans_beaten else "", wins("firmware", "octomap"), n,
           fw_true, om_true, om_ir / fw_ir, named, 1 / cheap_ratio, irs["run"],
           "short of" if 1 / cheap_ratio < 100 else "within"),
        "From the estimated poses the firmware's mean F1 is %s (%.3f against %.3f), at least "
        "OctoMap's in %d of %d runs, %s."
        % ("higher" if fw_est > om_est else "lower", fw_est, om_est,
           wins("firmware_est", "octomap_est"), n, by_room),
    ]
    axis = variant_f1.get(AXIS)
    if axis is not None and AXIS in irs:
        said = ("level with the firmware's %.3f" if abs(axis - fw_true) < LEVEL
                else "against the firmware's %.3f") % fw_true
        text = ("OctoMap reduced to the beam's axis (one ray a reading, the way the firmware "
                "maps it) scores F1 %.3f, %s, at %.0f times its instructions"
                % (axis, said, irs[AXIS] / irs["firmware"]))
        if CENTRAL in variant_f1 and CENTRAL in irs:
            text += "; its central 7.5° gets %.3f at %.0f times" % (
                variant_f1[CENTRAL], irs[CENTRAL] / irs["firmware"])
        text += "."
        axis_p = mean(r["variants"][AXIS]["precision"] for r in runs)
        if all(axis_p > mean(r["variants"][v]["precision"] for r in runs) for v in fans):
            text += (" It is the fan's spread that costs OctoMap precision (%.3f on the axis, "
                     "%.3f with the chosen fan)."
                     % (axis_p, mean(r["octomap"]["precision"] for r in runs)))
        bullets.append(text)
    gen_runs = gen["runs"]

    def gen_f1(key):
        return mean(r[key]["f1"] for r in gen_runs)

    def gen_wins(fw, other):
        return sum(r[fw]["f1"] >= r[other]["f1"] for r in gen_runs)

    bullets.append(
        "In the generated rooms, from the estimated poses, the firmware's mean F1 is %.3f "
        "against OctoMap's %.3f and HIMM's %.3f (at least theirs in %d and %d of %d runs); "
        "from the true poses %.3f against %.3f and %.3f."
        % (gen_f1("firmware_est"), gen_f1("octomap_est"), gen_f1("himm_est"),
           gen_wins("firmware_est", "octomap_est"), gen_wins("firmware_est", "himm_est"),
           len(gen_runs), gen_f1("firmware"), gen_f1("octomap"), gen_f1("himm")))
    tools_md = ["`make compare` (%s):" % what, ""] + found[0] + [
        "", wrap("The generated rooms (`tools/roomgen.py` rooms 1–%d, each with its own seed, "
                 "%s s, the chosen OctoMap setting):"
                 % (len(gen_runs), grouped(gen.get("duration") or 600))),
        ""] + gen_found[0] + [
        "", "The OctoMap settings tried, from the true poses (instructions on one run):", ""] + \
        found[1] + ["", wrap("What this says against the goals \"F1 ≥ OctoMap's at ≤ 1/100 "
                         "of its instructions per reading\" and, from the estimated poses in "
                         "rooms nobody tuned for, \"at least OctoMap's and HIMM's\":"), ""]
    for b in bullets:
        tools_md.append("- " + wrap(b, 88).replace("\n", "\n  "))

    # host_sim/README.md: the means over every run.
    host_md = [
        "Means over the %d runs of %s s:" % (n, grouped(duration) if duration else "600"), "",
        "| poses | firmware P / R / F1 | OctoMap P / R / F1 | HIMM P / R / F1 | firmware's F1 ≥ "
        "OctoMap's, HIMM's | instructions a reading, firmware / OctoMap |",
        "|---|---|---|---|---|---|",
        "| true | %s | %s | %s | in %d, %d of %d runs | %s / %s (%.0f×) |"
        % (prf("firmware", True), prf("octomap"), prf("himm"), wins("firmware", "octomap"),
           wins("firmware", "himm"), n, grouped(fw_ir), grouped(om_ir), om_ir / fw_ir),
        "| estimated (the firmware's) | %s | %s | %s | in %d, %d of %d runs | |"
        % (prf("firmware_est", True), prf("octomap_est"), prf("himm_est"),
           wins("firmware_est", "octomap_est"), wins("firmware_est", "himm_est"), n)]
    if axis is not None and AXIS in irs:
        host_md += ["", wrap(
            "OctoMap reduced to the beam's axis, as the firmware maps it, scores F1 %.3f from "
            "the true poses, %s the firmware, at %.0f times its instructions."
            % (axis, "level with" if abs(axis - fw_true) < LEVEL else "against %.3f for" % fw_true,
               irs[AXIS] / irs["firmware"]))]
    return {("tools/README.md", "compare"): "\n".join(tools_md) + "\n",
            ("host_sim/README.md", "compare-summary"): "\n".join(host_md) + "\n"}
