#!/usr/bin/env python3
"""ctest docs.no_dangling_refs: the repository cites nothing a reader cannot follow.

Fails (exit 1, one line per finding: file, line, what, the rule) when a tracked text file
  * refers to an issue tracker (the word issue followed by a number or a hash-number, a bare
    hash-number, or a phrase pointing at what an issue asks) instead of saying what is meant;
  * names a file outside the repository (a path into a parent folder or into the machine's
    work area, a PDF, the source dissertation)
    or a path into the repository's folders (rve/src/x.cpp, tests/install/x.sh, ...) that does
    not exist (from the root, from the citing file's folder, or as <lib>/<header>);
or when a Markdown file (README.md, docs/**/*.md and every other tracked *.md) has a relative
link whose target file does not exist, or whose #anchor is neither a heading nor an
<a id="..."> of the target. Python 3 standard library only.

    python3 tests/docs/no_dangling_refs.py [--root DIR]
"""

import argparse
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__)))), "scripts"))
from tracked_files import tracked_files  # noqa: E402  scripts/tracked_files.py

SELF = "tests/docs/no_dangling_refs.py"

ISSUE_PATTERNS = [
    (re.compile(r"\bissues?\s*#?\s*\d+", re.I), "an issue number"),
    (re.compile(r"(?<![\w&/#'\"])#\d+\b(?![\w.])"), "a bare #number (an issue or pull request)"),
    (re.compile(r"\b(?:the|this|that|an|from the)\s+issue(?:'s)?\s+(?:asks|says|requires|wants)\b", re.I),
     "an issue's wording"),
    (re.compile(r"\bfrom the issue\b|\bthe issue's\b|\bdone-when\b", re.I), "an issue's wording"),
]
MISSING_FILE_PATTERNS = [
    (re.compile(r"\.\./shared/|(?<![\w.])shared/design/"), "a file outside the repository (../shared)"),
    (re.compile(r"(?<![\w])/work/(?!\w*\")"), "an absolute path of the development machine"),
    (re.compile(r"\b[\w-]+\.pdf\b", re.I), "a PDF the repository does not contain"),
    (re.compile(r"\b(?:dissertation|thesis)\.(?:md|txt|tex)\b", re.I),
     "a dissertation file the repository does not contain"),
    (re.compile(r"\bARCHITECTURE\.md\b"), "a design file the repository does not contain"),
]
# A path into the repository's own folders, e.g. rve/src/deform.cpp or tests/install/check.sh.
TOPS = ("core", "damage", "fe_material", "campaign", "rve", "thermo", "gimp_coupler", "app", "examples",
        "tests", "bench", "fuzz", "docs", "scripts", "cmake")
REPO_PATH = re.compile(r"(?<![\w./$-])((?:" + "|".join(TOPS) + r")/[\w./-]*\w\.(?:hpp|h|cpp|cc|c|py|sh|"
                       r"md|json|toml|prm|cmake|txt|f90|in|map))\b")
LINK = re.compile(r"(?<!\!)\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)|!\[[^\]]*\]\(([^)\s]+)\)")
ANCHOR = re.compile(r'<a\s+(?:id|name)="([^"]+)"')
HEADING = re.compile(r"^#{1,6}\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s*(```|~~~)")


def text_of(path):
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:
        return None
    if b"\0" in data[:8192]:
        return None
    return data.decode("utf-8", "replace")


def slug(heading):
    """GitHub's anchor of a heading: markup and punctuation dropped, lower case, '-' for ' '."""
    h = re.sub(r"`|\*\*|\*|_(?=\W)|(?<=\W)_", "", heading)
    h = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", h)
    h = re.sub(r"<[^>]+>", "", h)
    h = re.sub(r"[^\w\- ]", "", h.strip().lower())
    return h.replace(" ", "-")


def anchors_of(text):
    found, fenced, counts = set(ANCHOR.findall(text)), False, {}
    for ln in text.split("\n"):
        if FENCE.match(ln):
            fenced = not fenced
            continue
        m = None if fenced else HEADING.match(ln)
        if m:
            s = slug(m.group(1))
            n = counts.get(s, 0)
            counts[s] = n + 1
            found.add(s if n == 0 else f"{s}-{n}")
    return found


def check_refs(rel, text, problems):
    for k, ln in enumerate(text.split("\n"), 1):
        for pat, what in ISSUE_PATTERNS:
            m = pat.search(ln)
            if m:
                problems.append(f"{rel}:{k}: '{m.group(0)}': {what}: say what is meant and cite "
                                "docs/theory.md or a decision record (Dnn) instead")
        for pat, what in MISSING_FILE_PATTERNS:
            m = pat.search(ln)
            if m:
                problems.append(f"{rel}:{k}: '{m.group(0)}': {what}: cite a file of the "
                                "repository or say what is meant")


def path_exists(root, rel, p):
    """A cited path exists: from the root, from the citing file's folder, or as the short form
    <lib>/<header> of <lib>/include/pnc/<lib>/<header> or <lib>/src/<file>."""
    if os.path.exists(os.path.join(root, p)):
        return True
    if os.path.exists(os.path.join(root, os.path.dirname(rel), p)):
        return True
    lib, _, rest = p.partition("/")
    return any(os.path.exists(os.path.join(root, lib, sub, rest))
               for sub in (os.path.join("include", "pnc", lib), "src"))


def check_paths(root, rel, text, problems):
    for k, ln in enumerate(text.split("\n"), 1):
        for m in REPO_PATH.finditer(ln):
            if not path_exists(root, rel, m.group(1)):
                problems.append(f"{rel}:{k}: '{m.group(1)}': no such file in the repository "
                                "(renamed or removed?): cite the file that exists")


def check_links(root, rel, text, problems, cache):
    fenced = False
    base = os.path.dirname(rel)
    for k, ln in enumerate(text.split("\n"), 1):
        if FENCE.match(ln):
            fenced = not fenced
            continue
        if fenced:
            continue
        for m in LINK.finditer(ln):
            target = m.group(1) or m.group(2)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):
                continue  # http:, https:, mailto: ...
            path, _, frag = target.partition("#")
            dest = os.path.normpath(os.path.join(base, path)) if path else rel
            if dest.startswith(".."):
                problems.append(f"{rel}:{k}: link '{target}': points outside the repository")
                continue
            full = os.path.join(root, dest)
            if not os.path.exists(full):
                problems.append(f"{rel}:{k}: link '{target}': {dest} does not exist")
                continue
            if frag and dest.endswith(".md"):
                if dest not in cache:
                    cache[dest] = anchors_of(text_of(full) or "")
                if frag not in cache[dest] and frag.lower() not in cache[dest]:
                    problems.append(f"{rel}:{k}: link '{target}': {dest} has no heading or "
                                    f"<a id> '{frag}'")


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))), help="repository root")
    args = ap.parse_args(argv)
    root = os.path.abspath(args.root)
    problems, cache, n = [], {}, 0
    for rel in tracked_files(root):
        if rel == SELF or rel.startswith("fuzz/corpus/") or rel.startswith("fuzz/hdf5-defects/"):
            continue
        text = text_of(os.path.join(root, rel))
        if text is None:
            continue
        n += 1
        check_refs(rel, text, problems)
        check_paths(root, rel, text, problems)
        if rel.endswith(".md"):
            check_links(root, rel, text, problems, cache)
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print(f"no_dangling_refs: {len(problems)} dangling reference(s) in {n} files",
              file=sys.stderr)
        return 1
    print(f"no_dangling_refs: {n} tracked text files, no issue numbers, no missing files, "
          "every relative Markdown link resolves")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
