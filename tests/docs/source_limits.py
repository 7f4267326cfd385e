#!/usr/bin/env python3
"""ctest docs.source_limits: no C/C++ source file over 600 lines, no function over 150 lines.

Fails (exit 1, one line per finding) when a git-tracked C/C++ source (*.cpp *.hpp *.h *.cc *.c)
  * outside tests/ has more than 600 lines ("FILE: N lines > 600"); the tests are exempt from
    the file limit (several test files hold one suite each and are longer);
  * has a function whose body spans more than 150 lines, from the line of its `{` to the line
    of its `}` ("FILE:LINE: function NAME: N lines > 150"), tests included.
Exempt from both: the literate deal.II tutorial examples/dealii_fracture/dealii_fracture.cc (a
commented walk-through read top to bottom) and the frozen ABI 1.0 copy under
tests/fe_material/abi_v1/ (kept byte for byte as released).

Function detection: comments, string literals (raw strings too), character literals and
preprocessor lines are blanked (line numbers kept), then the braces are matched. Outside any
function body, a `{` opens a function body when the text before it (since the previous `;`,
or the previous `{` or `}` of a block: brace initialisers do not count as boundaries) ends in
`)` optionally followed by const/noexcept/override/final/mutable/`-> type`, or in a
constructor's member initialiser list, or in a lambda introducer at namespace scope, and is not
a control statement (if/for/while/switch/catch). Everything inside a function body (lambdas,
local classes, blocks) belongs to that function: only the outermost body is measured.

    python3 tests/docs/source_limits.py [--root DIR]
    python3 tests/docs/source_limits.py --self-test   # the detector on synthetic files
Python 3 standard library only.
"""

import argparse
import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__)))), "scripts"))
from tracked_files import tracked_files  # noqa: E402  scripts/tracked_files.py

FILE_LIMIT = 600  # lines per source file
FUNCTION_LIMIT = 150  # lines per function body, `{` line to `}` line inclusive
SUFFIXES = (".cpp", ".hpp", ".h", ".cc", ".c")
EXEMPT = ("examples/dealii_fracture/dealii_fracture.cc",)  # the literate tutorial
EXEMPT_DIRS = ("tests/fe_material/abi_v1/",)  # the frozen ABI 1.0 copy
FILE_LIMIT_EXEMPT_DIRS = ("tests/",)

RAW_STRING = re.compile(r'(?:u8|[uUL])?R"([^()\\\s]{0,16})\(')
QUALIFIERS = r"(?:\s*(?:const|volatile|noexcept|override|final|mutable|&&|&))*"
TRAILING_RETURN = r"(?:\s*->\s*[\w:<>,\s*&]+)?"
FUNCTION_END = re.compile(r"\)" + QUALIFIERS + TRAILING_RETURN + r"\s*$")
LAMBDA_END = re.compile(r"\]\s*(?:mutable)?\s*$")
CTOR_INIT = re.compile(r"\)\s*(?:noexcept)?\s*:(?!:)")
CONTROL = re.compile(r"^(?:else\s+)?(?:if|for|while|switch|catch)\b|^(?:else|do|try)$")
SCOPE = re.compile(r'\b(?:class|struct|union|enum|namespace)\b|\bextern\s*"\s*"$|^$')


def blank(text):
    """`text` with comments, literals and preprocessor lines replaced by spaces (newlines kept;
    a string keeps its quotes, so `extern "C"` reads `extern " "`)."""
    out = []
    i, n = 0, len(text)

    def fill(a, b):
        out.append("".join("\n" if c == "\n" else " " for c in text[a:b]))

    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":  # preprocessor directive, with its continuation lines
            j = i
            while j < n and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            fill(i, min(j, n))
            i = min(j, n)
            continue
        if c == "\n":
            line_start = True
            out.append(c)
            i += 1
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            fill(i, j)
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            fill(i, j)
            i = j
        elif (m := RAW_STRING.match(text, i)) and (i == 0 or not (text[i - 1].isalnum() or
                                                                  text[i - 1] == "_")):
            end = ")" + m.group(1) + '"'
            j = text.find(end, m.end())
            j = n if j < 0 else j + len(end)
            out.append('"')
            fill(i + 1, j - 1)
            out.append('"')
            i = j
        elif c == '"' or (c == "'" and not digit_separator(text, i)):
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            closed = j < n and text[j] == c  # else unterminated: the newline stays
            out.append(c)
            fill(i + 1, min(j, n))
            if closed:
                out.append(c)
            i = j + 1 if closed else min(j, n)
        else:
            out.append(c)
            i += 1
    return "".join(out)


def digit_separator(text, i):
    """True when the ' at i separates digits of a number (C++14: 1'000'000, 0x7fff'ffff)."""
    if i == 0 or i + 1 >= len(text) or not text[i - 1].isalnum() or not text[i + 1].isalnum():
        return False
    j = i - 1
    while j >= 0 and (text[j].isalnum() or text[j] in "_'."):
        j -= 1
    return text[j + 1].isdigit()


def function_name(header):
    """The name before the parameter list that ends `header` (best effort, for the message)."""
    h = header
    k = h.rfind(")")
    if CTOR_INIT.search(h):
        k = CTOR_INIT.search(h).start()
    depth = 0
    while k >= 0:
        if h[k] == ")":
            depth += 1
        elif h[k] == "(":
            depth -= 1
            if depth == 0:
                break
        k -= 1
    m = re.search(r"([\w:~]+(?:\s*(?:<[^<>]*>)?)?|operator\s*\S+?|\])\s*$", h[:max(k, 0)])
    name = m.group(1).strip() if m else "?"
    return "lambda" if name == "]" else name


def is_function(header):
    h = " ".join(header.split())
    if CONTROL.match(h):
        return False
    if FUNCTION_END.search(h) or LAMBDA_END.search(h):
        return True
    return bool(CTOR_INIT.search(h)) and h.endswith((")", "}"))


def long_functions(text, limit=FUNCTION_LIMIT):
    """(line of `{`, name, lines) of every outermost function body longer than `limit`."""
    s = blank(text)
    found = []
    stack = []  # per open brace: "function", "block" (namespace, class, ...) or "init"
    header_start = 0
    func_open = None  # (line, name) of the open function body
    line = 1
    for i, c in enumerate(s):
        if c == "\n":
            line += 1
        elif c == ";":
            if func_open is None:
                header_start = i + 1
        elif c == "{":
            if func_open is not None:
                stack.append("inner")
                continue
            header = s[header_start:i].strip()
            if is_function(header):
                stack.append("function")
                func_open = (line, function_name(" ".join(header.split())))
            elif SCOPE.search(" ".join(header.split())):
                stack.append("block")
                header_start = i + 1
            else:
                stack.append("init")  # a brace initialiser: the header goes on
        elif c == "}":
            if not stack:
                continue  # unbalanced (e.g. braces split over #if branches): ignore
            kind = stack.pop()
            if kind == "function":
                n = line - func_open[0] + 1
                if n > limit:
                    found.append((func_open[0], func_open[1], n))
                func_open = None
                header_start = i + 1
            elif kind == "block":
                header_start = i + 1
    return found


def tracked_sources(root):
    return [f for f in tracked_files(root) if f.endswith(SUFFIXES)]


def check(root, files):
    """One line per finding; `files` relative to `root`."""
    problems = []
    for f in files:
        rel = f.replace(os.sep, "/")
        if rel in EXEMPT or rel.startswith(EXEMPT_DIRS):
            continue
        try:
            with open(os.path.join(root, f), encoding="utf-8", errors="replace") as fh:
                text = fh.read()
        except OSError as e:
            problems.append(f"{rel}: cannot be read ({e.strerror})")
            continue
        n = len(text.splitlines())
        if n > FILE_LIMIT and not rel.startswith(FILE_LIMIT_EXEMPT_DIRS):
            problems.append(f"{rel}: {n} lines > {FILE_LIMIT} (split the file by topic)")
        for ln, name, length in long_functions(text):
            problems.append(f"{rel}:{ln}: function {name}: {length} lines > {FUNCTION_LIMIT} "
                            f"(split it into named steps)")
    return problems


def body(n_lines, indent="  "):
    """A function body of exactly n_lines lines, `{` and `}` included."""
    inner = [indent + f"x += {k}; // }} {{ in a comment" for k in range(n_lines - 2)]
    return "{\n" + "\n".join(inner) + "\n}\n"


def self_test():
    """The detector on synthetic sources whose answer is known by construction."""
    cases = {
        # 151-line function reported, 150-line one not; braces in strings, chars, comments
        "a.cpp": ("#include <string>\n#define OPEN {\n"
                  "int too_long(int x) " + body(151) +
                  "int just_fits(int x) " + body(150) +
                  'const char* s = "{{{"; char c = \'{\'; /* { */ int n = 1\'000;\n'
                  'auto r = R"x({ ")" })x";\n'),
        # a long namespace and class hold short functions; a ctor initialiser list with a
        # brace-initialised member; a const member function with a trailing return type
        "b.hpp": ("namespace ns {\nstruct S {\n  S(int a) : a_(a), v_{1, 2} " + body(151, "    ") +
                  "  auto f() const -> int " + body(150, "    ") +
                  "  int a_;\n  int v_[2];\n};\n" + "int g(int x) " + body(10) * 20 + "}\n"),
        # lambdas and control blocks inside one function are part of it: one finding
        "c.cc": ("void outer() {\n  auto l = [&](int y) " + body(100, "    ") +
                 "  for (int i = 0; i < 2; ++i) " + body(60, "    ") + "}\n" +
                 'extern "C" {\nint c_entry(void) ' + body(151) + "}\n"),
        # file limit: 601 lines outside tests/ fail, 600 lines pass, 700 lines in tests/ pass
        "long.cpp": "int a;\n" * 601,
        "fits.cpp": "int a;\n" * 600,
        os.path.join("tests", "t.cpp"): "int a;\n" * 700,
    }
    want = sorted([
        "a.cpp:3: function too_long: 151 lines > 150",
        "b.hpp:3: function S: 151 lines > 150",
        "c.cc:1: function outer: 162 lines > 150",
        "c.cc:164: function c_entry: 151 lines > 150",
        "long.cpp: 601 lines > 600",
    ])
    with tempfile.TemporaryDirectory() as d:
        for name, text in cases.items():
            os.makedirs(os.path.dirname(os.path.join(d, name)), exist_ok=True)
            with open(os.path.join(d, name), "w", encoding="utf-8") as fh:
                fh.write(text)
        got = sorted(p.split(" (")[0] for p in check(d, sorted(cases)))
    if got != want:
        print("source_limits --self-test: FAILED\n  want: " + "\n        ".join(want) +
              "\n  got:  " + "\n        ".join(got), file=sys.stderr)
        return 1
    print(f"source_limits --self-test: the {len(want)} planted findings and no other")
    return 0


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))), help="repository root (default: this file's)")
    ap.add_argument("--self-test", action="store_true",
                    help="check the detector on synthetic files instead of the repository")
    a = ap.parse_args(argv)
    if a.self_test:
        return self_test()
    files = tracked_sources(a.root)
    problems = check(a.root, files)
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print(f"source_limits: {len(problems)} finding(s) in {len(files)} C/C++ sources "
              f"(limits: {FILE_LIMIT} lines per file outside tests/, {FUNCTION_LIMIT} lines "
              f"per function)", file=sys.stderr)
        return 1
    print(f"source_limits: {len(files)} C/C++ sources, none over {FILE_LIMIT} lines (outside "
          f"tests/), no function over {FUNCTION_LIMIT} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
