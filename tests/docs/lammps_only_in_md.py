#!/usr/bin/env python3
"""ctest docs.lammps_only_in_md: pnc code outside md/ reaches LAMMPS only through md/ (D346, D347).

Fails (exit 1, one line per finding "FILE:LINE: NAME") when a file under one of the guarded
directories (every library folder but md/; C/C++ sources and CMake files)
  * includes a LAMMPS header (`#include <lammps/...>` or "lammps/..."), or
  * names an identifier the LAMMPS C library interface declares: every `lammps_*` function,
    `LMP_*` / `LAMMPS_*` constant and `FixExternalFnPtr` of the header given by --header
    (lammps/library.h of the LAMMPS pnc builds against), as a whole word, or
  * links LAMMPS::lammps in a CMake file.
Names that merely contain "lammps_" (Config::lammps_log, the JSON key outside_lammps_share,
pnc::md::lammps_path) are pnc's own and are not C API names, so they pass.
Exit 2 when the header is missing or declares none of lammps_open, lammps_command (the list of
names could not be read: a failure, never a pass).

    python3 tests/docs/lammps_only_in_md.py --root DIR --header /usr/include/lammps/library.h
    python3 tests/docs/lammps_only_in_md.py --self-test   # the check on a synthetic tree
Python 3 standard library only.
"""

import argparse
import os
import re
import sys
import tempfile

GUARDED = ("app", "campaign", "core", "damage", "fe_material", "gimp_coupler", "rve", "thermo")
SUFFIXES = (".cpp", ".hpp", ".h", ".cc", ".c", ".txt", ".cmake")
INCLUDE = re.compile(r'#\s*include\s*[<"]lammps/')
STRING = re.compile(r'"(?:\\.|[^"\\])*"')


def api_names(header_text):
    """The identifiers the LAMMPS C library header declares."""
    names = set(re.findall(r"\b(lammps_\w+)\s*\(", header_text))
    names |= set(re.findall(r"\b((?:LMP|LAMMPS)_[A-Z0-9_]+)\b", header_text))
    names |= set(re.findall(r"\b(FixExternalFnPtr)\b", header_text))
    names.discard("LAMMPS_LIB_H")  # the include guard
    return names


def findings(root, dirs, names):
    word = re.compile(r"\b(" + "|".join(sorted(map(re.escape, names), key=len, reverse=True)) +
                      r")\b") if names else None
    out = []
    for d in dirs:
        for base, subdirs, files in os.walk(os.path.join(root, d)):
            subdirs.sort()
            for f in sorted(files):
                if not (f.endswith(SUFFIXES) or f == "CMakeLists.txt"):
                    continue
                path = os.path.join(base, f)
                rel = os.path.relpath(path, root)
                with open(path, encoding="utf-8", errors="replace") as fh:
                    for n, line in enumerate(fh, 1):
                        if INCLUDE.search(line):
                            out.append(f"{rel}:{n}: includes a LAMMPS header")
                        if "LAMMPS::lammps" in line:
                            out.append(f"{rel}:{n}: links LAMMPS::lammps")
                        if word:  # a name inside a string literal is data (an HDF5 key), not a call
                            for m in word.finditer(STRING.sub('""', line)):
                                out.append(f"{rel}:{n}: {m.group(1)} (LAMMPS C API)")
    return out


def read_names(header):
    if not os.path.isfile(header):
        print(f"lammps_only_in_md: header '{header}' not found (--header: lammps/library.h)")
        sys.exit(2)
    with open(header, encoding="utf-8", errors="replace") as fh:
        names = api_names(fh.read())
    if not {"lammps_open", "lammps_command"} <= names:
        print(f"lammps_only_in_md: '{header}' declares no lammps_open/lammps_command: not the "
              "LAMMPS C library header")
        sys.exit(2)
    return names


def self_test():
    """Two guarded directories lib_a, lib_b with planted uses and pnc's own names, and lib_md
    (not guarded) with a real use."""
    header = """#ifndef LAMMPS_LIB_H
enum _LMP_STYLE_CONST { LMP_STYLE_GLOBAL = 0 };
void *lammps_open(int argc, char **argv, void *comm, void **ptr);
void lammps_command(void *handle, const char *cmd);
int lammps_extract_setting(void *handle, const char *keyword);
typedef void (*FixExternalFnPtr)(void *, int, int, int *, double **, double **);
#endif
"""
    planted = {
        "lib_a/src/a.cpp": "#include <lammps/library.h>\nint x;\n",
        "lib_a/src/b.cpp": "void f(void* h) {\n  lammps_command(h, \"run 1\");\n}\n",
        "lib_a/src/c.hpp": "int k = LMP_STYLE_GLOBAL;\nFixExternalFnPtr p;\n",
        "lib_b/CMakeLists.txt": "target_link_libraries(x PRIVATE LAMMPS::lammps)\n",
    }
    clean = {
        "lib_a/src/ok.cpp": "c.lammps_log = \"x\";\nj[\"outside_lammps_share\"] = 1;\n"
                                   "auto p = pnc::md::lammps_path(d, \"data\");\n"
                                   "#include \"pnc/md/lammps_path.hpp\"\n"
                                   "void lammps_command_count();\n"
                                   "f.write_string(\"/lammps_version\", v);\n",
        "lib_md/src/fine.cpp": "#include <lammps/library.h>\nvoid g(void* h) { lammps_command(h, \"\"); }\n",
    }
    want = [
        "lib_a/src/a.cpp:1: includes a LAMMPS header",
        "lib_a/src/b.cpp:2: lammps_command (LAMMPS C API)",
        "lib_a/src/c.hpp:1: LMP_STYLE_GLOBAL (LAMMPS C API)",
        "lib_a/src/c.hpp:2: FixExternalFnPtr (LAMMPS C API)",
        "lib_b/CMakeLists.txt:1: links LAMMPS::lammps",
    ]
    with tempfile.TemporaryDirectory() as d:
        for rel, text in {**planted, **clean}.items():
            os.makedirs(os.path.dirname(os.path.join(d, rel)), exist_ok=True)
            with open(os.path.join(d, rel), "w", encoding="utf-8") as fh:
                fh.write(text)
        with open(os.path.join(d, "library.h"), "w", encoding="utf-8") as fh:
            fh.write(header)
        got = findings(d, ("lib_a", "lib_b"), read_names(os.path.join(d, "library.h")))
    if sorted(got) != sorted(want):
        print("self-test failed:\n got:  " + "\n       ".join(sorted(got)) + "\n want: " +
              "\n       ".join(sorted(want)))
        return 1
    print(f"self-test: the {len(want)} planted uses found, the pnc names and md/ passed")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=os.path.join(os.path.dirname(__file__), "..", ".."))
    ap.add_argument("--header", help="lammps/library.h of the LAMMPS pnc builds against")
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        return self_test()
    if not a.header:
        ap.error("--header is required")
    got = findings(os.path.abspath(a.root), GUARDED, read_names(a.header))
    for g in got:
        print(g)
    if got:
        print(f"{len(got)} direct LAMMPS use(s) outside md/: go through pnc::md (D346)")
        return 1
    print("no direct LAMMPS use in " + ", ".join(d + "/" for d in GUARDED))
    return 0


if __name__ == "__main__":
    sys.exit(main())
