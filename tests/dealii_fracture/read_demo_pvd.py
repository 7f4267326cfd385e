#!/usr/bin/python3
"""The deal.II demo's solution.pvd read back with VTK's own XML reader (D236).

    /usr/bin/python3 read_demo_pvd.py DIR   # DIR/solution.pvd of a demo run

Checks: the PVD timesteps increase strictly and are the step indices; every frame, read by
VTK, has the field data step_index (= its timestep), displacement_mm and force_N_per_mm and
the point array "displacement" with 2 or 3 components. Prints the loads, so a snap-back
(the load going back while the timestep goes on) is visible. Exit code 0 when all holds.
Needs python3-vtk9 (Debian: /usr/bin/python3).
"""
import os
import sys
import xml.etree.ElementTree as ET

import vtk


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    d = sys.argv[1]
    fails = []
    sets = ET.parse(os.path.join(d, "solution.pvd")).getroot().findall("./Collection/DataSet")
    steps = [float(s.get("timestep")) for s in sets]
    if len(steps) < 2:
        fails.append("at least 2 frames, got %d" % len(steps))
    if not all(b > a for a, b in zip(steps, steps[1:])):
        fails.append("timesteps increase strictly: %s" % steps)
    if any(t != int(t) or t < 0 for t in steps):
        fails.append("timesteps are step indices: %s" % steps)
    loads = []
    for s, t in zip(sets, steps):
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(os.path.join(d, s.get("file")))
        r.Update()
        g = r.GetOutput()
        fd = g.GetFieldData()
        for name in ("step_index", "displacement_mm", "force_N_per_mm"):
            if fd.GetArray(name) is None:
                fails.append("%s: field data %s missing" % (s.get("file"), name))
        if fails:
            break
        if fd.GetArray("step_index").GetTuple1(0) != t:
            fails.append("%s: step_index != timestep %g" % (s.get("file"), t))
        u = g.GetPointData().GetArray("displacement")
        if u is None or u.GetNumberOfComponents() not in (2, 3):
            fails.append("%s: point array displacement" % s.get("file"))
        loads.append(fd.GetArray("displacement_mm").GetTuple1(0))
    print("timesteps", steps)
    print("displacement_mm", loads)
    for f in fails:
        print("FAIL:", f)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
