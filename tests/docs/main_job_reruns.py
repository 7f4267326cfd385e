#!/usr/bin/env python3
"""The README's main job (scripts/main.sh) can run again in the same output folder: every
command of it that keeps a run folder and refuses to start over an existing one without
--resume (`pnc characterize`, `pnc thermo ti`) is given --resume, which starts a fresh run in an
empty folder and continues or reuses the run in a kept one. A second `bash scripts/main.sh`
otherwise stops with exit 1 ("already holds a run") at its first MD step.

--self-test plants a script with one such command without --resume (must be reported), one
with it and one continued over two lines with it (must not), and passes only on that.
"""
import argparse
import pathlib
import re
import sys

RUN_FOLDER_COMMANDS = re.compile(r'"\$pnc"\s+(characterize|thermo\s+ti)\b')


def logical_lines(text):
    """Lines joined at trailing backslashes, with the line number where each starts."""
    out, buf, start = [], "", 0
    for n, line in enumerate(text.splitlines(), 1):
        if not buf:
            start = n
        if line.rstrip().endswith("\\"):
            buf += line.rstrip()[:-1] + " "
            continue
        out.append((start, buf + line))
        buf = ""
    if buf:
        out.append((start, buf))
    return out


def problems(text):
    found, bad = 0, []
    for n, line in logical_lines(text):
        code = line.split("#", 1)[0] if not line.lstrip().startswith("#") else ""
        if RUN_FOLDER_COMMANDS.search(code):
            found += 1
            if "--resume" not in code:
                bad.append(f"line {n}: {code.strip()}")
    return found, bad


def self_test():
    planted = "\n".join([
        '"$pnc" characterize demo_glass --out md_glass --json > a.json || rc=$?',
        '"$pnc" characterize demo --out md_demo --resume --json > b.json',
        '"$pnc" thermo ti spec.json --out ti \\',
        '  --resume --json > c.json',
        '# "$pnc" characterize commented --out x',
    ])
    found, bad = problems(planted)
    ok = found == 3 and len(bad) == 1 and bad[0].startswith("line 1:")
    print(f"main_job_reruns self-test: {found} commands, reported {bad}: {'ok' if ok else 'FAILED'}")
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", default=".")
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        return self_test()
    path = pathlib.Path(a.root) / "scripts" / "main.sh"
    found, bad = problems(path.read_text())
    if found == 0:
        print(f"main_job_reruns: {path}: no `pnc characterize` or `pnc thermo ti` found; "
              "this check no longer matches the script")
        return 1
    for b in bad:
        print(f"{path}: {b}: a run-folder command without --resume (a second main job stops "
              "with 'already holds a run')")
    print(f"main_job_reruns: {found} run-folder command(s), {len(bad)} without --resume")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
