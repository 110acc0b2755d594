#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Every file, make target and host_sim option the READMEs (and the other Markdown pages
beside them) name exists.

usage: test_readme_refs.py HOST_SIM SRC_DIR

Reads every Markdown file of the source tree and checks, in links, inline code and code blocks:
- a relative link's target is a file or folder of the repository, and its anchor
  (`FILE.md#anchor`, or `#anchor` within the page) names a heading of that page, by
  GitHub's rule for a heading's anchor (or an explicit `<a id>`/`<a name>`);
- a path that starts with one of the repository's folders (firmware/, hal/, tools/ ...)
  is there; a bare source file name (board_generic_f405.h, hal_template.c) is somewhere;
- `make TARGET` names a target of the Makefile;
- a host_sim command line uses only options `host_sim --help` lists.
Paths under build/ and out/ are what a build or a run writes, and placeholders (DIR, FILE,
<board>, {a,b}, *) stand for a choice of the reader's: those are not checked.
"""
import os
import re
import subprocess
import sys

SOURCE_EXT = (".c", ".h", ".py", ".sh", ".ld", ".cmake", ".cpp", ".room", ".conf", ".json",
              ".md", ".trace", ".txt", ".yaml")
SKIP_DIRS = {".git", "build", "out", "__pycache__"}


def pages(src):
    for root, dirs, files in os.walk(src):
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith("build"))
        for f in sorted(files):
            if f.endswith(".md"):
                yield os.path.join(root, f)


def make_targets(src):
    targets = set()
    with open(os.path.join(src, "Makefile")) as f:
        for line in f:
            m = re.match(r"^([A-Za-z0-9_.-]+)\s*:(?!=)", line)
            if m:
                targets.add(m.group(1))
    return targets


def all_basenames(src):
    names = set()
    for root, dirs, files in os.walk(src):
        dirs[:] = [d for d in dirs if d not in SKIP_DIRS and not d.startswith("build")]
        names.update(files)
        names.update(dirs)
    return names


def slug(text):
    """GitHub's anchor of a heading: its text as rendered (no code marks, link targets or
    emphasis), lower case, every character but letters, digits, '_', '-' and spaces left
    out, spaces made hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)
    text = re.sub(r"<[^>]+>", "", text)
    text = text.replace("`", "").lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    """Every anchor a Markdown page offers: its headings' (a repeated one gets -1, -2 ...,
    as on GitHub) and explicit HTML ones."""
    found = set()
    count = {}
    fenced = False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            if fenced:
                continue
            found.update(re.findall(r"<a\s+(?:id|name)=\"([^\"]+)\"", line))
            m = re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                s = slug(m.group(1))
                n = count.get(s, 0)
                count[s] = n + 1
                found.add(s if n == 0 else "%s-%d" % (s, n))
    return found


def placeholder(tok):
    if re.search(r"[<>{}*$?\[\]]|\.\.\.|…", tok):
        return True
    return any(re.fullmatch(r"[A-Z][A-Z0-9_]*(\.[a-z0-9.]+)?", part) for part in tok.split("/"))


def clean(tok):
    tok = tok.strip("`'\"(),;.")
    tok = re.sub(r"#.*$", "", tok)          # an anchor
    tok = re.sub(r":\d+.*$", "", tok)       # file:line
    return tok.rstrip(":")


class Checker:
    def __init__(self, host_sim, src):
        self.src = src
        self.top = {d for d in os.listdir(src)
                    if os.path.isdir(os.path.join(src, d)) and d not in SKIP_DIRS
                    and not d.startswith("build")}
        self.targets = make_targets(src)
        self.names = all_basenames(src)
        helptext = subprocess.run([host_sim, "--help"], stdout=subprocess.PIPE, text=True).stdout
        self.options = set(re.findall(r"--[a-z][a-z-]*", helptext))
        self.errors = []
        self.checked = 0
        self.anchor_cache = {}

    def anchor(self, where, page, anchor, target):
        """A link's #anchor must be one the page it points to offers."""
        if not page.endswith(".md") or not os.path.isfile(page):
            return
        page = os.path.realpath(page)
        if page not in self.anchor_cache:
            self.anchor_cache[page] = anchors(page)
        self.checked += 1
        if anchor not in self.anchor_cache[page]:
            self.fail(where, "links to %s: %s has no heading with the anchor #%s"
                      % (target, os.path.relpath(page, self.src), anchor))

    def fail(self, where, msg):
        self.errors.append("%s: %s" % (where, msg))

    def path(self, where, tok, readme_dir):
        tok = clean(tok)
        if not tok or placeholder(tok) or tok.startswith(("http:", "https:", "/", "~")):
            return
        first = tok.split("/")[0]
        if "/" in tok and first in self.top:
            self.checked += 1
            if not (os.path.exists(os.path.join(self.src, tok)) or
                    os.path.exists(os.path.join(readme_dir, tok))):
                self.fail(where, "names %s, which is not in the repository" % tok)
        elif "/" not in tok and tok.endswith(SOURCE_EXT[:8]) and re.fullmatch(r"[\w.+-]+", tok):
            self.checked += 1
            if tok not in self.names:
                self.fail(where, "names the file %s, which is nowhere in the repository" % tok)

    def command(self, where, text, readme_dir):
        words = text.split()
        for i, w in enumerate(words):
            self.path(where, w, readme_dir)
            if w == "make" and i + 1 < len(words):
                t = words[i + 1]
                if re.fullmatch(r"[a-z][a-z0-9-]*", t):
                    self.checked += 1
                    if t not in self.targets:
                        self.fail(where, "`make %s`: the Makefile has no such target" % t)
        if words and words[0].endswith("host_sim") and "/" in words[0] or \
                (words and words[0] == "host_sim"):
            for w in words[1:]:
                m = re.match(r"(--[a-z][a-z-]*)", w.strip("`'\""))
                if m:
                    self.checked += 1
                    if m.group(1) not in self.options:
                        self.fail(where, "host_sim has no option %s" % m.group(1))

    def readme(self, path):
        rel = os.path.relpath(path, self.src)
        d = os.path.dirname(path)
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        fenced = False
        for n, line in enumerate(lines, 1):
            where = "%s:%d" % (rel, n)
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            if fenced:
                code = line.split(" #")[0]
                self.command(where, code.replace("\\", " "), d)
                continue
            for target in re.findall(r"\]\(([^)\s]+)\)", line):
                if target.startswith(("http:", "https:", "mailto:")):
                    continue
                t, _, anchor = target.partition("#")
                if t:
                    self.checked += 1
                    if not os.path.exists(os.path.join(d, t)):
                        self.fail(where, "links to %s, which is not there" % target)
                        continue
                if anchor:
                    self.anchor(where, os.path.join(d, t) if t else path, anchor, target)
            for span in re.findall(r"`([^`]+)`", line):
                self.command(where, span, d)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    host_sim, src = sys.argv[1], sys.argv[2]
    c = Checker(host_sim, src)
    files = list(pages(src))
    for f in files:
        c.readme(f)
    if len(files) < 6 or c.checked < 100:
        c.fail("Markdown pages", "only %d pages and %d references found: the checker reads "
               "nothing" % (len(files), c.checked))
    for e in c.errors:
        print("FAIL", e)
    print("%d Markdown pages, %d references checked, %d wrong" % (len(files), c.checked, len(c.errors)))
    sys.exit(1 if c.errors else 0)


if __name__ == "__main__":
    main()
