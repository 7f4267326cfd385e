#!/usr/bin/env python3
"""Regenerate, or check, the regions of the user guides that pnc prints.

A generated region of a Markdown file in docs/ starts with a line

    <!-- begin generated: pnc recipe parameters --format markdown -->

and ends with the line

    <!-- end generated -->

Everything between the two lines is the output of the pnc command named on the first one
(run without a shell, its words taken from the marker line; only `pnc recipe parameters ...`,
`pnc gimp parameters ...`, `pnc gimp couple-parameters ...`, `pnc thermo ti-parameters ...`,
`pnc thermo persistence-parameters ...` and `pnc thermo work-parameters ...` are run). The
recipe key tables of docs/rve.md and the input key tables of docs/gimp.md, docs/escm.md and
docs/thermo.md are such regions: the keys are declared once (in
rve/src/recipe_parameters.cpp, gimp_coupler/src/input_parameters.cpp,
gimp_coupler/src/escm/couple_parameters.cpp, thermo/src/ti_parameters.cpp,
thermo/src/persistence_parameters.cpp, thermo/src/work_parameters.cpp), and the tables
follow.

    python3 scripts/generated_docs.py --pnc build/app/pnc            # rewrite the regions
    python3 scripts/generated_docs.py --pnc build/app/pnc --check    # exit 1 if one is stale

The ctest docs.recipe_parameters runs the check (decisions D232, D292, D295, D301, D321, D322). Python 3 standard library only.
"""

import argparse
import difflib
import os
import re
import subprocess
import sys

BEGIN = re.compile(r"^<!-- begin generated: pnc ((?:[a-z0-9_-]+ ?)+) -->$")
END = "<!-- end generated -->"
ALLOWED = [["recipe", "parameters"], ["gimp", "parameters"], ["gimp", "couple-parameters"],
           ["thermo", "ti-parameters"], ["thermo", "persistence-parameters"],
           ["thermo", "work-parameters"]]


def render(pnc, words):
    if not any(words[: len(a)] == a for a in ALLOWED):
        raise SystemExit("generated_docs: not an allowed command: pnc " + " ".join(words))
    out = subprocess.run([pnc] + words, check=True, capture_output=True, text=True).stdout
    return out if out.endswith("\n") else out + "\n"


def process(path, pnc):
    """The file's text with every generated region rendered anew."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines(keepends=True)
    out, i = [], 0
    while i < len(lines):
        m = BEGIN.match(lines[i].rstrip("\n"))
        out.append(lines[i])
        i += 1
        if not m:
            continue
        j = i
        while j < len(lines) and lines[j].rstrip("\n") != END:
            j += 1
        if j == len(lines):
            raise SystemExit(f"generated_docs: {path}: '{lines[i - 1].strip()}' has no '{END}'")
        out.append(render(pnc, m.group(1).split()))
        out.append(lines[j])
        i = j + 1
    return "".join(lines), "".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=".", help="repository root (default: .)")
    ap.add_argument("--pnc", required=True, help="the pnc executable")
    ap.add_argument("--check", action="store_true", help="exit 1 if a region is stale")
    a = ap.parse_args()
    docs = os.path.join(a.root, "docs")
    stale = 0
    for name in sorted(os.listdir(docs)):
        if not name.endswith(".md"):
            continue
        path = os.path.join(docs, name)
        old, new = process(path, a.pnc)
        if old == new:
            continue
        if a.check:
            stale += 1
            sys.stdout.writelines(difflib.unified_diff(
                old.splitlines(keepends=True), new.splitlines(keepends=True),
                fromfile=path + " (committed)", tofile=path + " (pnc prints)", n=1))
        else:
            with open(path, "w", encoding="utf-8") as f:
                f.write(new)
            print("generated_docs: rewrote", path)
    if stale:
        print(f"generated_docs: {stale} file(s) differ from what pnc prints; run "
              "python3 scripts/generated_docs.py --pnc build/app/pnc", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
