#!/usr/bin/env python3
"""Generate docs/decisions.md, the index of the decision records, from docs/decisions/*.md.

Every Markdown file in docs/decisions/ is read (the part files and any pending-<name>.md
that holds new records). A record is a heading "### Dnn. Title" (two to four '#'; "Dnn:"
or "Dnn" followed by the title are accepted too), optionally preceded by an anchor line
<a id="dnn"></a>, and runs to the next record or the end of the file. Each record must say
**What.** and **Why.** (bold labels, or "What:"/"Why:" at the start of a line).

The index has one row per record: ID, title, part (a link to the file and the record's
anchor), code sites (tracked files outside docs/ and outside Markdown that cite the ID,
"Dnn" or a range "Dnn-Dmm") and tests (the test names of the record's **Tests.** line, else
the tests in tests/ that cite the ID). For D1, D2 and D3, which are also the names of the
three damage variables, a line counts only when it says "decision" or cites the ID in
parentheses.

    python3 scripts/decisions_index.py            # rewrite docs/decisions.md
    python3 scripts/decisions_index.py --check    # exit 1 if it is stale, an ID is
                                                  # duplicated or a record lacks What/Why
Python 3 standard library only.
"""

import argparse
import difflib
import os
import re
import sys

from tracked_files import tracked_files  # scripts/, next to this file

INDEX = os.path.join("docs", "decisions.md")
FOLDER = os.path.join("docs", "decisions")
SELF = "scripts/decisions_index.py"

HEADING = re.compile(r"^#{2,4}\s+(D\d+[a-z]?)(?:\.|:|\s)\s*(.*?)\s*$")
ANCHOR = re.compile(r'^<a\s+(?:id|name)="([^"]+)"\s*>\s*</a>\s*$')
WHAT = re.compile(r"\*\*What\b|^What\s*[:.]", re.M)
WHY = re.compile(r"\*\*Why\b|^Why\s*[:.]", re.M)
TESTS = re.compile(r"\*\*Tests?\b[^*]*\*\*|^Tests?\s*:", re.M)
NEXT_LABEL = re.compile(r"\*\*[A-Z][A-Za-z ()'-]*[.:]\*\*")
# A test name: GoogleTest Suite.Name (optionally with a ctest prefix such as gimp., a * or …),
# or a ctest of the families dealii_fracture., install., docs., material_cli.
TEST_NAME = re.compile(r"`((?:[a-z_]+\.)?[A-Z]\w*\.(?:\w+\*?|\*|\.\.\.|…\w*)|"
                       r"(?:dealii_fracture|install|docs|material_cli)\.\w+)`")
# A citation: Dnn or Dnn-Dmm / Dnn–Dmm, not inside a longer identifier or number.
CITE = re.compile(r"(?<![A-Za-z0-9_*])D(\d+)([a-z]?)(?:\s*[-–]\s*D(\d+)([a-z]?))?(?![A-Za-z0-9_])")
TEST_MACRO = re.compile(r"^\s*TEST(?:_F|_P)?\(\s*(\w+)\s*,\s*(\w+)")
MODE_NAMES = {(1, ""), (2, ""), (3, "")}


class IndexError_(Exception):
    pass


def key(rid):
    m = re.match(r"D(\d+)([a-z]?)$", rid)
    return (int(m.group(1)), m.group(2))


def slug(text):
    """GitHub's heading anchor: lower case, punctuation dropped, spaces to hyphens."""
    s = re.sub(r"[^\w\- ]", "", text.strip().lower())
    return s.replace(" ", "-")


def parse_file(root, name):
    """The records of one file: dicts with id, title, anchor, body, file."""
    path = os.path.join(root, FOLDER, name)
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    records, cur, prev_anchor = [], None, None
    for ln in lines:
        a = ANCHOR.match(ln)
        h = HEADING.match(ln)
        if h:
            heading_text = ln.lstrip("#").strip()
            cur = {"id": h.group(1), "title": h.group(2).strip(), "file": name, "body": [],
                   "anchor": prev_anchor or slug(heading_text)}
            if prev_anchor and prev_anchor.lower() != h.group(1).lower():
                raise IndexError_(f"{FOLDER}/{name}: anchor '{prev_anchor}' precedes "
                                  f"{h.group(1)}: the anchor must be the ID in lower case")
            records.append(cur)
            prev_anchor = None
            continue
        if a:
            prev_anchor = a.group(1)
            continue
        if ln.strip():
            prev_anchor = None
        if ln.startswith("#") and not ln.startswith("####"):
            cur = None  # a section heading ends the record
            continue
        if cur is not None:
            cur["body"].append(ln)
    for r in records:
        r["body"] = "\n".join(r["body"]).strip()
    return records


def read_records(root):
    folder = os.path.join(root, FOLDER)
    names = sorted(n for n in os.listdir(folder) if n.endswith(".md"))
    records, problems, seen = [], [], {}
    for n in names:
        for r in parse_file(root, n):
            if r["id"] in seen:
                problems.append(f"{r['id']} is duplicated: {FOLDER}/{seen[r['id']]} and "
                                f"{FOLDER}/{n} (IDs are unique; take the next free one)")
            else:
                seen[r["id"]] = n
            if not WHAT.search(r["body"]):
                problems.append(f"{FOLDER}/{n}: {r['id']} has no **What.** (every record says "
                                "what was chosen and why)")
            if not WHY.search(r["body"]):
                problems.append(f"{FOLDER}/{n}: {r['id']} has no **Why.** (every record says "
                                "what was chosen and why)")
            records.append(r)
    return records, problems


def citing_files(root):
    """Files to search for citations: the tree's files (tracked_files.py) but the docs."""
    keep = []
    for f in tracked_files(root):
        if f.startswith(("docs/", "tests/docs/")) or f.endswith(".md") or f == SELF:
            continue
        keep.append(f)
    return keep


def read_text(path):
    try:
        with open(path, "rb") as f:
            data = f.read(2_000_000)
    except OSError:
        return None
    if b"\0" in data[:8192]:
        return None
    return data.decode("utf-8", "replace")


def cited_ids(line, ids_sorted):
    """The record IDs a line cites (ranges expanded over the existing IDs)."""
    found = set()
    low = line.lower()
    for m in CITE.finditer(line):
        a = (int(m.group(1)), m.group(2))
        if m.group(3) is not None:
            b = (int(m.group(3)), m.group(4))
            found.update(i for i in ids_sorted if a <= key(i) <= b)
            continue
        if a in MODE_NAMES:
            around = line[max(0, m.start() - 1):m.end() + 1]
            if "decision" not in low and not (around.startswith("(") and around.endswith(")")):
                continue
        rid = f"D{a[0]}{a[1]}"
        found.add(rid)
    return found


def code_sites(root, ids):
    ids_sorted = sorted(ids, key=key)
    known = set(ids)
    sites = {i: set() for i in ids}
    tests = {i: [] for i in ids}
    for f in citing_files(root):
        text = read_text(os.path.join(root, f))
        if text is None:
            continue
        lines = text.split("\n")
        macros = [(k, m.group(1) + "." + m.group(2))
                  for k, ln in enumerate(lines) for m in [TEST_MACRO.match(ln)] if m]
        for k, ln in enumerate(lines):
            if "D" not in ln:
                continue
            for rid in cited_ids(ln, ids_sorted):
                if rid not in known:
                    continue
                sites[rid].add(f)
                if f.startswith("tests/") and macros:
                    after = [n for j, n in macros if k <= j <= k + 3]
                    before = [n for j, n in macros if j <= k]
                    name = after[0] if after else (before[-1] if before else None)
                    if name and name not in tests[rid]:
                        tests[rid].append(name)
    return sites, tests


def tests_cell(record, found):
    m = TESTS.search(record["body"])
    if m:
        rest = record["body"][m.end():]
        n = NEXT_LABEL.search(rest)
        para = rest[:n.start()] if n else rest
        names = []
        for t in TEST_NAME.findall(para):
            if t not in names:
                names.append(t)
        if names:
            return ", ".join(f"`{t}`" for t in names)
        text = " ".join(para.split())
        if text:
            return text if len(text) <= 160 else text[:157].rstrip() + "…"
    if found:
        return ", ".join(f"`{t}`" for t in found)
    return "—"


def cell(s):
    return s.replace("|", "\\|")


def render(root):
    records, problems = read_records(root)
    if problems:
        raise IndexError_("\n".join(problems))
    ids = [r["id"] for r in records]
    sites, found = code_sites(root, ids)
    parts = sorted({r["file"] for r in records})
    out = [
        "# Decision records: the index",
        "",
        "<!-- Generated by scripts/decisions_index.py from docs/decisions/*.md: do not edit by hand. -->",
        "",
        "Every place where the method leaves a question open, or where a printed equation or constant",
        "is wrong, is settled once in a decision record: what was chosen, why, what it changes and",
        "which tests hold it. [`theory.md`](theory.md) states the equations as decided. The records",
        "live in one file per part; this page is generated from them by",
        "`python3 scripts/decisions_index.py` (ctest `docs.decisions_index` fails when it is stale,",
        "when an ID is used twice or when a record lacks What or Why). Code comments cite a record",
        "as \"Dnn\" or \"docs/decisions.md Dnn\": find the ID below.",
        "",
        "New records go into `docs/decisions/pending-<name>.md` (any file in that folder is indexed)",
        "with the next free ID, a heading `### Dnn. Title` preceded by `<a id=\"dnn\"></a>`, and the",
        "labels **What.**, **Why.**, **Changes.**, **Tests.**; then run the script.",
        "",
        "Parts: " + ", ".join(f"[{p[:-3]}](decisions/{p})" for p in parts) + ".",
        "",
        "Code sites are the tracked files outside `docs/` that cite the ID (ranges such as",
        "\"D1-D12\" included); tests are the names on the record's **Tests.** line, else the tests in",
        "`tests/` that cite it.",
        "",
        "| ID | title | part | code sites | tests |",
        "|---|---|---|---|---|",
    ]
    for r in sorted(records, key=lambda r: key(r["id"])):
        rid = r["id"]
        part = f"[{r['file'][:-3]}](decisions/{r['file']}#{r['anchor']})"
        where = ", ".join(f"`{f}`" for f in sorted(sites[rid])) or "—"
        out.append(f"| {rid} | {cell(r['title'])} | {part} | {cell(where)} | "
                   f"{cell(tests_cell(r, found[rid]))} |")
    return "\n".join(out) + "\n"


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                    help="repository root (default: the parent of scripts/)")
    ap.add_argument("--check", action="store_true",
                    help="do not write; exit 1 when docs/decisions.md differs from the generated index")
    args = ap.parse_args(argv)
    root = os.path.abspath(args.root)
    try:
        text = render(root)
    except IndexError_ as e:
        print(f"decisions_index: {e}", file=sys.stderr)
        return 1
    target = os.path.join(root, INDEX)
    if args.check:
        try:
            with open(target, encoding="utf-8") as f:
                old = f.read()
        except OSError as e:
            print(f"decisions_index: {INDEX}: cannot read ({e.strerror})", file=sys.stderr)
            return 1
        if old != text:
            diff = list(difflib.unified_diff(old.split("\n"), text.split("\n"), INDEX,
                                             "generated", lineterm="", n=0))
            print(f"decisions_index: {INDEX} is stale: run python3 scripts/decisions_index.py "
                  "and commit the result. First differences:", file=sys.stderr)
            print("\n".join(diff[:40]), file=sys.stderr)
            return 1
        n = text.count("\n| D")
        print(f"decisions_index: {INDEX} is up to date ({n} records)")
        return 0
    tmp = target + ".tmp"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
    with os.fdopen(fd, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, target)
    print(f"decisions_index: wrote {INDEX}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
