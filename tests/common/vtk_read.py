"""Shared pieces of the tests that read pnc's VTU/PVD output with VTK's own XML readers (D236).

Imported by tests/gimp_coupler/read_gimp_vtu.py and read_escm_vtu.py (run with /usr/bin/python3,
which has Debian's python3-vtk9). `Checks` collects failed conditions; `run_pnc` runs one pnc
command in a fresh temporary folder and gives its output folder to a callback; `report` prints
the failures and returns the exit code. `tensor_problems` checks a 3 x 3 tensor array (the
deal.II demo's stress and strain, D328).
"""
import os
import shutil
import subprocess
import tempfile
import xml.etree.ElementTree as ET

import vtk


class Checks:
    def __init__(self):
        self.fails = []

    def __call__(self, cond, what):
        if not cond:
            self.fails.append(what)

    def report(self, title):
        for f in self.fails[:20]:
            print("FAIL:", f)
        print("%s: %s" % (title, "ok" if not self.fails else "%d failures" % len(self.fails)))
        return 1 if self.fails else 0


def read_vtu(path, check):
    """The unstructured grid of `path`, read by VTK; a reader error is a failed check."""
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    check(r.GetErrorCode() == 0, "%s: VTK reader error %d" % (path, r.GetErrorCode()))
    return r.GetOutput()


def pvd_frames(out, name):
    """[(timestep, path)] of the DataSet entries of out/name, in file order."""
    sets = ET.parse(os.path.join(out, name)).getroot().findall("./Collection/DataSet")
    return [(float(d.get("timestep")), os.path.join(out, d.get("file"))) for d in sets]


def check_arrays(g, arrays, path, check):
    """Every point array of `arrays` (name -> number of components) is present with that many."""
    for name, nc in arrays.items():
        a = g.GetPointData().GetArray(name)
        check(a is not None and a.GetNumberOfComponents() == nc,
              "%s: %s with %d components" % (path, name, nc))


# VTK's 9 tensor components, row-major: the index of ij (i, j = 0, 1, 2)
TENSOR_IJ = ["11", "12", "13", "21", "22", "23", "31", "32", "33"]


def tensor_problems(a, label):
    """What is wrong with the tensor array `a` (None when absent): it must have 9 components
    (VTK's 3 x 3, row-major, TENSOR_IJ) and be symmetric, ij == ji exactly, in every tuple."""
    if a is None:
        return ["%s: missing" % label]
    if a.GetNumberOfComponents() != 9:
        return ["%s: %d components, not 9" % (label, a.GetNumberOfComponents())]
    for t in range(a.GetNumberOfTuples()):
        v = a.GetTuple9(t)
        for i, j in ((0, 1), (0, 2), (1, 2)):
            if v[3 * i + j] != v[3 * j + i]:
                return ["%s tuple %d: %s = %r != %s = %r" % (label, t, TENSOR_IJ[3 * i + j],
                        v[3 * i + j], TENSOR_IJ[3 * j + i], v[3 * j + i])]
    return []


def units(g):
    """The set of "name=unit" strings of the field data "units"."""
    u = g.GetFieldData().GetAbstractArray("units")
    return {u.GetValue(k) for k in range(u.GetNumberOfValues())} if u is not None else set()


def run_pnc(exe, args, prefix, body):
    """Runs `exe args --out TMP/out` in a fresh temporary folder, then body(out, completed);
    returns body's value, or 1 (after printing pnc's stderr) when pnc failed."""
    tmp = tempfile.mkdtemp(prefix=prefix)
    try:
        out = os.path.join(tmp, "out")
        r = subprocess.run([exe, *args, "--out", out], capture_output=True, text=True)
        if r.returncode != 0:
            print(r.stderr)
            print("pnc %s failed with exit code %d" % (" ".join(args[:2]), r.returncode))
            return 1
        return body(out, r)
    finally:
        shutil.rmtree(tmp)
