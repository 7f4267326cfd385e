#!/usr/bin/python3
"""Reads a pnc VTU (or PVD) with VTK's own XML readers and checks it (D236).

    /usr/bin/python3 read_vtu.py FILE.vtu   # the sample of vtu_sample_writer.cpp
    /usr/bin/python3 read_vtu.py FILE.pvd   # its series: timesteps strictly increasing

For a .vtu: the arrays, their numbers of components and values against the closed forms of
vtu_sample_writer.cpp, the field data (time_s, load_N, the "units" string array). For a
.pvd: the timesteps are 0, 1, 2 and every frame, read by VTK, has the load_N field scalar
(1, 2, 1.5: the load goes back while the pseudo-time goes on). Exit code 0 when all holds.
Needs python3-vtk9 (Debian: /usr/bin/python3).
"""
import os
import sys
import xml.etree.ElementTree as ET

import vtk

FAILS = []


def check(cond, what):
    if not cond:
        FAILS.append(what)


def close(a, b, tol=1e-12):
    return abs(a - b) <= tol * max(1.0, abs(a), abs(b))


def field_scalar(data, name):
    arr = data.GetFieldData().GetAbstractArray(name)
    check(arr is not None, "field data %s missing" % name)
    return arr.GetTuple1(0) if arr is not None else float("nan")


def check_frame(g, load):
    check(g.GetNumberOfPoints() == 5, "5 points, got %d" % g.GetNumberOfPoints())
    check(g.GetNumberOfCells() == 5, "5 vertex cells")
    check(all(g.GetCellType(i) == vtk.VTK_VERTEX for i in range(g.GetNumberOfCells())),
          "cells are VTK_VERTEX")
    pd = g.GetPointData()
    expect = {"displacement_m": 3, "stress_Pa": 6, "deformation_gradient_1": 9,
              "damage_1": 1, "material_index": 1}
    for name, nc in expect.items():
        a = pd.GetArray(name)
        check(a is not None, "point array %s missing" % name)
        if a is not None:
            check(a.GetNumberOfComponents() == nc,
                  "%s has %d components, expected %d" % (name, a.GetNumberOfComponents(), nc))
    if FAILS:
        return
    for i in range(5):
        x = g.GetPoint(i)
        for got, want in zip(x, (0.5 * i, -1.0 * i, 0.25 * i)):
            check(close(got, want), "point %d: %s" % (i, x))
        u = pd.GetArray("displacement_m").GetTuple3(i)
        for got, want in zip(u, (1e-3 * i, 2e-3 * i, -1e-3 * i)):
            check(close(got, want), "displacement_m %d: %s" % (i, u))
        # VTK's symmetric order XX YY ZZ XY YZ XZ
        s = pd.GetArray("stress_Pa").GetTuple(i)
        want = (1e6 * (i + 1), 2e6, -3e6, 4e5 * i, 5e5, -6e5 * i)
        check(all(close(a, b) for a, b in zip(s, want)), "stress_Pa %d: %s != %s" % (i, s, want))
        F = pd.GetArray("deformation_gradient_1").GetTuple(i)
        want = [r + 3 * c + 0.1 * i for r in range(3) for c in range(3)]
        check(all(close(a, b) for a, b in zip(F, want)), "deformation_gradient_1 %d: %s" % (i, F))
        check(close(pd.GetArray("damage_1").GetTuple1(i), 0.2 * i), "damage_1 %d" % i)
        m = pd.GetArray("material_index")
        check(m.GetDataType() == vtk.VTK_INT, "material_index is Int32")
        check(m.GetTuple1(i) == i % 2, "material_index %d" % i)
    check(close(field_scalar(g, "time_s"), 0.125), "time_s")
    check(close(field_scalar(g, "load_N"), load), "load_N")
    units = g.GetFieldData().GetAbstractArray("units")
    check(units is not None, "field data 'units' missing")
    if units is not None:
        got = {units.GetValue(k) for k in range(units.GetNumberOfValues())}
        for u in ("stress_Pa=Pa", "displacement_m=m", "time_s=s", "load_N=N", "Points=m",
                  "damage_1=1", "material_index=index", "deformation_gradient_1=1"):
            check(u in got, "units lacks %s (has %s)" % (u, sorted(got)))


def read_vtu(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    check(r.GetErrorCode() == 0, "VTK reader error %d" % r.GetErrorCode())
    return r.GetOutput()


def read_pvd(path):
    """VTK 9 has no PVD reader of its own (ParaView's vtkPVDReader reads the same XML): the
    collection is parsed here and every frame read with VTK's VTU reader."""
    root = ET.parse(path).getroot()
    check(root.get("type") == "Collection", "VTKFile type Collection")
    sets = root.findall("./Collection/DataSet")
    steps = [float(d.get("timestep")) for d in sets]
    check(steps == [0.0, 1.0, 2.0], "timesteps %s, expected [0, 1, 2]" % steps)
    check(all(b > a for a, b in zip(steps, steps[1:])), "timesteps increase strictly")
    for d, load in zip(sets, (1.0, 2.0, 1.5)):
        check(d.get("part") == "0", "part 0")
        check_frame(read_vtu(os.path.join(os.path.dirname(path), d.get("file"))), load)


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    path = sys.argv[1]
    if path.endswith(".pvd"):
        read_pvd(path)
    else:
        check_frame(read_vtu(path), -7.5)
    for f in FAILS:
        print("FAIL:", f)
    print("%s: %s" % (path, "ok" if not FAILS else "%d failures" % len(FAILS)))
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
