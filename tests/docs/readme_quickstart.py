#!/usr/bin/env python3
"""ctest docs.readme_quickstart: run the README's quick-starts (a) and (c) as printed.

The commands are read from the README itself, so the test cannot drift from it: the fenced
block after the marker line <!-- quickstart:a --> and the one after <!-- quickstart:c -->,
one command per line, run in that order in one fresh temporary directory ((c) uses the card
that (a) wrote). A line is split like a shell word list (no shell is started): pipes,
redirections, variables and command lists are refused, so a quick-start stays a list of plain
commands. Mapped: the program `pnc` to the built pnc, `python3` to the configured Python,
arguments starting with `examples/` or `scripts/` to the source tree and `build/` to the
build tree. Checked: every command exits 0 within the time left of 60 s, every `--out` file
exists afterwards, and each line of the block after <!-- quickstart:a-csv-header --> is a
line of the CSV that quick-start (a) hands to `pnc fit` (the README shows the real header).
With --cc and --plugin, the C block after <!-- quickstart:c-abi --> is compiled as the body of
main() (its #include lines above it) with -Wall -Wextra -Werror against the plugin's header,
linked with the plugin and run next to the card of (a): it must exit 0.

    python3 tests/docs/readme_quickstart.py --root SRC --build BUILD --pnc PNC --python PY
"""

import argparse
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

BUDGET_S = 60.0
MARKER = re.compile(r"^<!--\s*quickstart:([\w-]+)\s*-->\s*$")
FENCE = re.compile(r"^\s*(```|~~~)")
SHELL_TOKENS = {"|", "||", "&", "&&", ";", ">", ">>", "<", "2>", "2>&1"}


class Failure(Exception):
    pass


def blocks(readme_text):
    """{marker name: lines of the first fenced block after the marker}."""
    out, lines, i = {}, readme_text.split("\n"), 0
    while i < len(lines):
        m = MARKER.match(lines[i])
        i += 1
        if not m:
            continue
        while i < len(lines) and not lines[i].strip():
            i += 1
        if i >= len(lines) or not FENCE.match(lines[i]):
            raise Failure(f"README.md: marker quickstart:{m.group(1)} is not followed by a "
                          "fenced block")
        i += 1
        body = []
        while i < len(lines) and not FENCE.match(lines[i]):
            body.append(lines[i])
            i += 1
        if m.group(1) in out:
            raise Failure(f"README.md: marker quickstart:{m.group(1)} appears twice")
        out[m.group(1)] = body
        i += 1
    return out


def commands(name, body):
    cmds = []
    for ln in body:
        if not ln.strip() or ln.lstrip().startswith("#"):
            continue
        words = shlex.split(ln, comments=True)
        bad = [w for w in words if w in SHELL_TOKENS or "$" in w or "`" in w]
        if bad or ln.rstrip().endswith("\\"):
            raise Failure(f"README.md quick-start ({name}): '{ln.strip()}': {bad or 'a '}"
                          "continuation: quick-start commands must be plain commands, one per "
                          "line (no pipes, redirections, variables or continuations)")
        if words:
            cmds.append((ln.strip(), words))
    if not cmds:
        raise Failure(f"README.md quick-start ({name}): no commands in its block")
    return cmds


def mapped(words, a):
    prog = {"pnc": a.pnc, "python3": a.python}.get(words[0])
    if prog is None:
        raise Failure(f"README.md: '{words[0]}': a quick-start command must be pnc or python3")
    out = [prog]
    for w in words[1:]:
        if w.startswith(("examples/", "scripts/")):
            w = os.path.join(a.root, w)
        elif w.startswith("build/"):
            w = os.path.join(a.build, w[len("build/"):])
        out.append(w)
    return out


def option(words, name):
    for k, w in enumerate(words[:-1]):
        if w == name:
            return words[k + 1]
    return None


def run_block(name, cmds, a, cwd, start):
    for text, words in cmds:
        argv = mapped(words, a)
        left = BUDGET_S - (time.monotonic() - start)
        if left <= 0:
            raise Failure(f"quick-start ({name}): the {BUDGET_S:.0f} s budget is spent before "
                          f"'{text}'")
        t0 = time.monotonic()
        try:
            r = subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=left)
        except subprocess.TimeoutExpired:
            raise Failure(f"quick-start ({name}): '{text}' did not finish within the "
                          f"{BUDGET_S:.0f} s budget")
        print(f"[{name}] {text}: exit {r.returncode}, {time.monotonic() - t0:.1f} s")
        if r.returncode != 0:
            tail = "\n".join((r.stdout + r.stderr).strip().split("\n")[-15:])
            raise Failure(f"quick-start ({name}): '{text}' exited {r.returncode}:\n{tail}")
        out = option(words, "--out")
        if out and not os.path.exists(os.path.join(cwd, out)):
            raise Failure(f"quick-start ({name}): '{text}' exited 0 but wrote no {out}")


def check_header(header_lines, cmds_a, cwd):
    data = None
    for _, words in cmds_a:
        if words[0] == "pnc" and len(words) > 1 and words[1] == "fit":
            data = option(words, "--data")
    if data is None or not data.endswith(".csv"):
        raise Failure("README.md quick-start (a): no `pnc fit --data FILE.csv` whose header "
                      "the README's header block could be checked against")
    with open(os.path.join(cwd, data), encoding="utf-8") as f:
        lines = [ln.rstrip("\n") for ln in f]
    for ln in header_lines:
        if ln.strip() and ln.strip() not in (x.strip() for x in lines):
            raise Failure(f"README.md quick-start (a): the header line '{ln.strip()}' is not "
                          f"a line of {data} as pnc writes it")


def run_c_snippet(lines, a, cwd, start):
    includes = [ln for ln in lines if ln.startswith("#include")]
    body = [ln for ln in lines if not ln.startswith("#include")]
    src = os.path.join(cwd, "quickstart_c_abi.c")
    with open(src, "x", encoding="utf-8") as f:
        f.write("\n".join(includes + ["int main(void) {"] + body + ["  return 0;", "}", ""]))
    exe = os.path.join(cwd, "quickstart_c_abi")
    inc = os.path.join(a.root, "fe_material", "include")
    steps = [("compile", [a.cc, "-std=c11", "-Wall", "-Wextra", "-Werror", "-I", inc, src,
                          a.plugin, "-Wl,-rpath," + os.path.dirname(a.plugin), "-o", exe]),
             ("run", [exe])]
    for what, argv in steps:
        left = BUDGET_S - (time.monotonic() - start)
        try:
            r = subprocess.run(argv, cwd=cwd, capture_output=True, text=True, timeout=max(left, 1))
        except subprocess.TimeoutExpired:
            raise Failure(f"quick-start (c), C ABI snippet: {what} did not finish in time")
        print(f"[c-abi] {what}: exit {r.returncode}")
        if r.returncode != 0:
            raise Failure(f"quick-start (c), the C ABI snippet of README.md: {what} failed "
                          f"(exit {r.returncode}):\n{(r.stdout + r.stderr).strip()[-2000:]}")


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", required=True, help="source tree (holds README.md)")
    ap.add_argument("--build", required=True, help="build tree")
    ap.add_argument("--pnc", required=True, help="the built pnc executable")
    ap.add_argument("--python", default=sys.executable, help="python3 for the ctypes example")
    ap.add_argument("--cc", help="C compiler for the C ABI snippet (skipped without it)")
    ap.add_argument("--plugin", help="the built libpnc_material.so for the C ABI snippet")
    ap.add_argument("--keep", action="store_true", help="keep the temporary directory")
    a = ap.parse_args(argv)
    for k in ("root", "build", "pnc", "plugin"):
        if getattr(a, k):
            setattr(a, k, os.path.abspath(getattr(a, k)))
    start = time.monotonic()
    cwd = tempfile.mkdtemp(prefix="pnc_readme_quickstart_")
    try:
        with open(os.path.join(a.root, "README.md"), encoding="utf-8") as f:
            found = blocks(f.read())
        for need in ("a-csv-header", "a", "c"):
            if need not in found:
                raise Failure(f"README.md: no <!-- quickstart:{need} --> marker before a "
                              "fenced block")
        cmds_a = commands("a", found["a"])
        cmds_c = commands("c", found["c"])
        run_block("a", cmds_a, a, cwd, start)
        check_header(found["a-csv-header"], cmds_a, cwd)
        run_block("c", cmds_c, a, cwd, start)
        if a.cc and a.plugin:
            if "c-abi" not in found:
                raise Failure("README.md: no <!-- quickstart:c-abi --> marker before the C block")
            run_c_snippet(found["c-abi"], a, cwd, start)
    except Failure as e:
        print(f"readme_quickstart: {e}", file=sys.stderr)
        if a.keep:
            print(f"readme_quickstart: kept {cwd}", file=sys.stderr)
        return 1
    finally:
        if not a.keep:
            shutil.rmtree(cwd, ignore_errors=True)
    print(f"readme_quickstart: quick-starts (a) and (c) ran as printed in "
          f"{time.monotonic() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
