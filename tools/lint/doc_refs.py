#!/usr/bin/env python3
"""Checks that what the README and docs/*.md name exists: every repository path, every
`make` target and every option of the project's own programs.

    tools/lint/doc_refs.py [REPO_ROOT]

Prints one line per dangling name (file:line: what) and exits 1 if there is any.

- Paths: a name under one of the tree's top folders (in prose, a code span or a link
  target; a link target relative to its document too). Globs (`fdir/event_log.*`) must match
  something; a module named without its extension (`fdir/tile_health`) must match a file of
  that stem. Outputs (`build/`, `out/`) are made by the build and runs, not checked.
- Make targets: `make X` in a code span or block; X a target of the Makefile or mk/*.mk.
- Options: `--opt` in a code span or block that runs one of the programs of tools/ (or in a
  span of options alone): the option must be written in that program's sources (for a span
  of options alone, in the sources of the programs its line names; a span on a line that
  names none is another tool's).
"""
import glob
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))
TOP = sorted(d for d in os.listdir(ROOT) if os.path.isdir(os.path.join(ROOT, d)) and not d.startswith(".")
             and d not in ("build", "out"))
TOP += [".ci"]
PATH_RE = re.compile(r"(?<![\w./-])((?:%s)/[\w./*+-]*[\w*])" % "|".join(re.escape(t) for t in TOP))
LINK_RE = re.compile(r"\]\(([^)\s#]+)(?:#[^)]*)?\)")
SPAN_RE = re.compile(r"`([^`]+)`")
MAKE_RE = re.compile(r"(?<![\w-])make\s+((?:[A-Z_]+=\S+\s+)*)([a-z][\w-]*)(?![\w=/.-])")
OPT_RE = re.compile(r"(?<![\w-])(--[a-z][\w-]*)")


def programs():
    out = {}
    for d in sorted(os.listdir(os.path.join(ROOT, "tools"))):
        if d in ("common", "lint", "build", "study", "slurm"):
            continue
        src = os.path.join(ROOT, "tools", d)
        if os.path.isdir(src) and glob.glob(os.path.join(src, "*.cpp")):
            out[d] = src
    return out


def read_sources(dirs):
    text = []
    for d in dirs:
        for f in glob.glob(os.path.join(d, "**", "*.[ch]pp"), recursive=True):
            with open(f, encoding="utf-8", errors="replace") as h:
                text.append(h.read())
    return "\n".join(text)


def make_targets():
    names = set()
    files = [os.path.join(ROOT, "Makefile")] + glob.glob(os.path.join(ROOT, "mk", "*.mk"))
    for f in files:
        with open(f, encoding="utf-8") as h:
            for line in h:
                m = re.match(r"^([a-z][\w-]*(?:\s+[a-z][\w-]*)*)\s*:(?!=)", line)
                if m:
                    names.update(m.group(1).split())
    return names


def path_exists(p, base):
    p = p.rstrip(".")
    for root in (ROOT, base):
        full = os.path.normpath(os.path.join(root, p))
        if any(ch in p for ch in "*?["):
            if glob.glob(full):
                return True
        elif os.path.exists(full) or glob.glob(full + ".*") or glob.glob(full + "_*"):
            return True
    return False


def main():
    progs = programs()
    prog_src = {p: read_sources([d, os.path.join(ROOT, "tools", "common")]) for p, d in progs.items()}
    all_src = "\n".join(prog_src.values())
    targets = make_targets()
    docs = [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "docs", "*.md")))
    bad = []
    for doc in docs:
        rel = os.path.relpath(doc, ROOT)
        base = os.path.dirname(doc)
        in_block = False
        with open(doc, encoding="utf-8") as h:
            lines = h.read().splitlines()
        for n, line in enumerate(lines, 1):
            if line.lstrip().startswith("```"):
                in_block = not in_block
                continue
            code = [line] if in_block else SPAN_RE.findall(line)
            for m in PATH_RE.finditer(line):
                p = m.group(1)
                if p.startswith(("build/", "out/")) or "<" in p:
                    continue
                if not path_exists(p, base):
                    bad.append(f"{rel}:{n}: no such path: {p}")
            for m in LINK_RE.finditer(line):
                p = m.group(1)
                if "://" in p or p.startswith("mailto:"):
                    continue
                if not path_exists(p, base):
                    bad.append(f"{rel}:{n}: link to no such file: {p}")
            for span in code:
                for m in MAKE_RE.finditer(span):
                    if m.group(2) not in targets:
                        bad.append(f"{rel}:{n}: no make target: {m.group(2)}")
                words = span.split()
                if not words:
                    continue
                first = os.path.basename(words[0])
                opts = OPT_RE.findall(span)
                named = [p for p in progs if re.search(r"\b%s\b" % re.escape(p), line)]
                if first in progs:
                    src = prog_src[first]
                elif words[0].startswith("--") and named:
                    src = "\n".join(prog_src[p] for p in named)
                else:
                    continue
                for o in opts:
                    if f'"{o}"' not in src and f"{o}=" not in src and f"{o} " not in src and f'{o}"' not in src:
                        who = first if first in progs else " or ".join(named)
                        bad.append(f"{rel}:{n}: {who} has no option {o}")
    for b in bad:
        print(b)
    print(f"doc_refs: {len(docs)} documents, {len(bad)} dangling names")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
