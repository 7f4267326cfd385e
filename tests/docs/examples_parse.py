#!/usr/bin/env python3
"""Every file under examples/ is at least parsed by a test (ctest docs.examples_parse).

    examples_parse.py --root SRC --pnc BUILD/app/pnc

Each file is matched by the first rule below that fits its path; a file that no rule fits is
an error (a new example file needs a rule here, or a test of its own that the rule names):

  * GIMP inputs (examples/gimp/*.json, *.toml): `pnc gimp run FILE --max-steps 1` (the whole
    input read and checked by pnc's parser, the model set up, one explicit step);
  * point-driver paths (examples/drive/*.toml): `pnc material drive` over the whole path with
    the dissertation's card (`pnc card tables --model pnc`);
  * ESCM inputs (examples/escm/*.json; running them needs LAMMPS) and RVE recipes
    (examples/rve/*/recipe.toml): parsed here (JSON, TOML) and read by the tests that name
    them (tests/gimp_coupler/, tests/rve/), which must exist;
  * deal.II parameter files (examples/dealii_fracture/*.prm): read by the program's
    ParameterHandler in ctest dealii_fracture.parameter_files, which reads every .prm of that
    folder (checked here: the test iterates over the folder);
  * shell scripts: `bash -n`; Python scripts: compiled (py_compile);
  * LAMMPS data files: read by tests/rve/test_user_system.cpp (which must name them);
  * C/C++ sources and CMakeLists.txt: compiled by the build; Markdown: links checked by
    docs.no_dangling_refs; PNG figures: must be referenced by a Markdown page of the
    repository.

Python 3 standard library only; every program is run without a shell, temporary files in a
directory created for this run.
"""

import argparse
import json
import os
import py_compile
import subprocess
import sys
import tempfile
import tomllib


def read(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return f.read()


def named_by(root, folder, name, exts=(".cpp", ".cc", ".h", ".hpp", ".txt")):
    """Files under root/folder whose text names `name`."""
    hits = []
    for d, _, files in os.walk(os.path.join(root, folder)):
        for f in files:
            if f.endswith(exts) and name in read(os.path.join(d, f)):
                hits.append(os.path.relpath(os.path.join(d, f), root))
    return hits


def run(cmd, cwd, timeout=120):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout,
                       check=False)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr.strip()[-400:]}")


class Checker:
    def __init__(self, root, pnc, work):
        self.root, self.pnc, self.work = root, pnc, work
        self.card = None

    def dissertation_card(self):
        if self.card is None:
            self.card = os.path.join(self.work, "card.h5")
            run([self.pnc, "card", "tables", "--model", "pnc", "--out", self.card], self.work)
        return self.card

    def check(self, rel):
        """What was done with examples file `rel` (a sentence); raises on failure."""
        path = os.path.join(self.root, rel)
        parts = rel.split("/")
        name, ext = parts[-1], os.path.splitext(parts[-1])[1]
        if parts[1] == "gimp" and ext in (".json", ".toml"):
            # Run from a copy in a folder of its own; a card the input names relative to its
            # folder and that the folder lacks is made as examples/gimp/README.md says
            # (`pnc card tables --model pp` for a pp_* card, else the nanocomposite's).
            here = tempfile.mkdtemp(prefix="gimp_", dir=self.work)
            text = read(path)
            made = []
            doc = tomllib.loads(text) if ext == ".toml" else json.loads(text)
            for m in doc.get("materials", []):
                card = m.get("card") if isinstance(m, dict) else None
                if card and not os.path.isabs(card) and not os.path.exists(
                        os.path.join(os.path.dirname(path), card)):
                    model = "pp" if os.path.basename(card).startswith("pp") else "pnc"
                    run([self.pnc, "card", "tables", "--model", model, "--out",
                         os.path.join(here, card)], here)
                    made.append(f"{card} ({model})")
            with open(os.path.join(here, name), "w", encoding="utf-8") as f:
                f.write(text)
            run([self.pnc, "gimp", "run", name, "--out", "out", "--max-steps", "1",
                 "--no-plot", "--quiet"], here, timeout=300)
            return "pnc gimp run --max-steps 1" + (", card " + ", ".join(made) if made else "")
        if parts[1] == "drive" and ext == ".toml":
            run([self.pnc, "material", "drive", self.dissertation_card(), "--path", path,
                 "--out", os.path.join(self.work, name + ".csv"), "--no-plot"], self.work)
            return "pnc material drive (whole path)"
        if parts[1] == "escm" and ext == ".json":
            json.loads(read(path))
            users = named_by(self.root, "tests/gimp_coupler", name)
            if not users:
                raise RuntimeError("no test in tests/gimp_coupler/ reads it")
            return "JSON; run by " + ", ".join(users)
        if parts[1] == "rve" and name == "recipe.toml":
            with open(path, "rb") as f:
                tomllib.load(f)
            users = [u for u in named_by(self.root, "tests/rve", parts[-2])
                     if "recipe.toml" in read(os.path.join(self.root, u))]
            if not users:
                raise RuntimeError(f"no test in tests/rve/ reads {parts[-2]}/recipe.toml")
            return "TOML; read by " + ", ".join(users)
        if ext == ".prm" and parts[1] == "dealii_fracture":
            test = os.path.join(self.root, "tests/dealii_fracture/test_files_and_solvers.cc")
            if "directory_iterator" not in read(test):
                raise RuntimeError("dealii_fracture.parameter_files no longer reads the folder")
            return "ParameterHandler (ctest dealii_fracture.parameter_files)"
        if ext == ".sh":
            run(["bash", "-n", path], self.work)
            return "bash -n"
        if ext == ".py":
            py_compile.compile(path, cfile=os.path.join(self.work, name + "c"), doraise=True)
            return "py_compile"
        if ext == ".data":
            if not named_by(self.root, "tests/rve", name):
                raise RuntimeError("no test in tests/rve/ reads it")
            return "LAMMPS data, read by tests/rve"
        if ext in (".cc", ".cpp", ".h", ".hpp") or name == "CMakeLists.txt":
            return "compiled by the build"
        if ext == ".md":
            return "Markdown (docs.no_dangling_refs)"
        if ext == ".png":
            for d, _, files in os.walk(self.root):
                if "/build" in d or "/.git" in d:
                    continue
                if any(f.endswith(".md") and name in read(os.path.join(d, f)) for f in files):
                    return "figure of a Markdown page"
            raise RuntimeError("no Markdown page shows it")
        raise RuntimeError("no rule for this file: add one to tests/docs/examples_parse.py")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", required=True)
    ap.add_argument("--pnc", required=True)
    a = ap.parse_args()
    root = os.path.abspath(a.root)
    files = []
    for d, dirs, names in os.walk(os.path.join(root, "examples")):
        dirs[:] = sorted(x for x in dirs if not x.startswith("."))
        files += sorted(os.path.relpath(os.path.join(d, n), root) for n in names)
    failures = 0
    with tempfile.TemporaryDirectory(prefix="examples_parse_") as work:
        checker = Checker(root, os.path.abspath(a.pnc), work)
        for rel in files:
            try:
                print(f"ok   {rel}: {checker.check(rel)}")
            except Exception as e:  # noqa: BLE001 - every failure is reported, then counted
                failures += 1
                print(f"FAIL {rel}: {e}")
    print(f"{len(files)} files, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
