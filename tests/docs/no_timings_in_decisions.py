#!/usr/bin/env python3
"""ctest docs.no_timings_in_decisions: no timing or machine load in a decision record.

A decision record (docs/decisions/*.md) says what was chosen, why and what it changes; the
measurements behind it (run times, speeds, the machine's load) live in the results or bench
section of the matching guide (bench/README.md, gimp_coupler/bench/README.md, docs/<part>.md
"Measurements behind the decision records", docs/dealii_demo.md) and the record links there
(decision D361). Fails (exit 1, one line per finding "FILE:LINE: KIND 'TEXT'") when a record
line holds
  * a number with a unit of time spent: ns, µs, us, ms, s, min (e.g. "267 ns", "~9 s",
    "2–4 s", "6 min", "0.5 s per step"). Simulated times (fs, ps) are physics, not timings;
    "s.e." (standard error) and a mesh size h are not units of time;
  * a machine load: "load 13", "load average of 5.5", "load 5–11";
  * a speed ratio: a number with × next to "wall time" or "speed" ("0.11× the wall time").
Deliberate exceptions are whole records, listed in ALLOWED below by their anchor, each with its
reason.

    python3 tests/docs/no_timings_in_decisions.py [--root DIR]
    python3 tests/docs/no_timings_in_decisions.py --self-test   # the patterns on planted lines
Python 3 standard library only.
"""

import argparse
import glob
import os
import re
import sys

NUM = r"~?≈?\s?\d+(?:[.,]\d+)?(?:\s?[–-]\s?\d+(?:[.,]\d+)?)?"
PATTERNS = [
    ("a timing", re.compile(r"(?<![\w.])" + NUM + r"\s?(?:ns|µs|us|ms|s|min)\b(?!\.e\b|\.e\.)")),
    ("a machine load", re.compile(r"\bload(?: average)?(?: of)?\s?[≈~]?\s?\d", re.I)),
    ("a speed ratio", re.compile(NUM + r"\s?×[^;]{0,45}\b(?:wall time|speed)\b"
                                 r"|\b(?:wall time|speed)\b[^;]{0,45}\d\s?×")),
]

# (file path from the root, anchor of the record, reason): every line of that record, from its
# `<a id="..."></a>` line to the next record's, is exempt. Keep this list short; each entry says why
# the numbers of the record are part of the decision rather than a measurement of one run.
ALLOWED = [
    ("docs/decisions/core.md", "d344",
     "the progress line's own format: example lines and display thresholds, not a measurement"),
    ("docs/decisions/core.md", "d345",
     "the ETA's own format and thresholds: example lines, not a measurement"),
]
ANCHOR = re.compile(r'^<a id="([\w-]+)"></a>\s*$')


def findings(name, text, allowed=None):
    """Findings of one file; a line is read together with the next one (a phrase broken by a
    line wrap is still found) and a match is reported at the line it starts on. Lines of a
    record listed in `allowed` (default ALLOWED) are skipped."""
    exempt = {a for f, a, _ in (ALLOWED if allowed is None else allowed) if f == name}
    out = []
    lines = text.split("\n")
    record = None  # anchor of the record the line belongs to
    for n, line in enumerate(lines, 1):
        if m := ANCHOR.match(line):
            record = m.group(1)
        if record in exempt:
            continue
        joined = line + " " + (lines[n] if n < len(lines) else "")
        for kind, pat in PATTERNS:
            for m in pat.finditer(joined):
                if m.start() >= len(line):
                    continue
                out.append(f"{name}:{n}: {kind} '{m.group(0).strip()}'")
    return out


def check(root):
    bad = []
    files = sorted(glob.glob(os.path.join(root, "docs", "decisions", "*.md")))
    if not files:
        return [f"{root}/docs/decisions: no decision records found"]
    for path in files:
        with open(path, encoding="utf-8") as f:
            bad += findings("docs/decisions/" + os.path.basename(path), f.read())
    return bad


def self_test():
    must = ["a point 267 ns against 61 ns", "the test takes ~9 s", "in 2–4 s of wall",
            "at ≈ 6 min on an idle machine", "under a load average of 13", "(2 cores, load 5–11)",
            "costs 0.5 s per step", "0.11× the wall time of the default",
            "the batch is 0.84–1.19× the single-point speed", "12.5 ms per call", "3 µs",
            "the campaign took 0.11× the\nwall time of the default", "62 s on\nan idle core",
            "it takes 1.19× (1.17–1.25) the local executor's wall time"]
    must_not = ["within 4 s.e. of a sample sd", "holds of 2500 steps (50 ps)", "r_out = 4h",
                "0.5 h / c_L ≈ 175 fs", "wall time in s", "`wall_s` 12.5", "the load ramp",
                "5000× below k_BT", "a few seconds"]
    errors = []
    for line in must:
        if not findings("t.md", line):
            errors.append(f"not caught: {line}")
    for line in must_not:
        got = findings("t.md", line)
        if got:
            errors.append(f"caught wrongly: {line}: {got}")
    # the exemption covers the listed record only: the same line is caught before any record,
    # in another record and in another file
    line = "printed `ETA 4.1 s` when it ends"
    allowed = [("t.md", "d9", "test")]
    inside = '<a id="d9"></a>\n### D9. x\n' + line
    if findings("t.md", inside, allowed):
        errors.append(f"caught inside an allowed record: {line}")
    for where, text in [("before any record", line + '\n<a id="d9"></a>'),
                        ("in another record", inside.replace('"d9"', '"d90"')),
                        ("in another file", None)]:
        got = findings("u.md" if text is None else "t.md", inside if text is None else text,
                       allowed)
        if not got:
            errors.append(f"not caught {where}: {line}")
    for e in errors:
        print(e)
    print(f"self-test: {len(must)} planted timings, {len(must_not)} non-timings, "
          f"{len(errors)} errors")
    return 1 if errors else 0


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))))
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args(argv)
    if a.self_test:
        return self_test()
    bad = check(a.root)
    for b in bad:
        print(b)
    if bad:
        print(f"{len(bad)} timings or loads in decision records: move them to the guide's "
              "results section and link it (D361)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
