#!/usr/bin/python3
"""The deal.II demo's solution.pvd read back with VTK's own XML reader (D236).

    /usr/bin/python3 read_demo_pvd.py DIR   # DIR/solution.pvd of a demo run

Checks: the PVD timesteps increase strictly and are the step indices; every frame, read by
VTK, has the field data step_index (= its timestep), displacement_m and force_N_per_m (SI,
D318), the point array "displacement_m" with 2 or 3 components, the array D1_1 and the
tensors stress_Pa and strain_1 (cell averages, written by deal.II as point data of each cell):
9 components, symmetric (ij == ji exactly), no scalar component arrays beside them (D328); in
2-D (plane strain) strain 13, 23, 33 exactly 0 and stress 33 not 0 everywhere (the
out-of-plane stress is written, not padded); "Points=m", and every point, cell and field array
named with its unit: its name is in the String field data "units" ("name=unit") and ends with
"_" and the unit ("/" spelled "_per_", "1" for dimensionless). Prints the loads, so a
snap-back (the load going back while the timestep goes on) is visible. Exit code 0 when all
holds.
Needs python3-vtk9 (Debian: /usr/bin/python3).
"""
import os
import sys
import xml.etree.ElementTree as ET

import vtk

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from vtk_read import tensor_problems  # noqa: E402


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
        for name in ("step_index", "displacement_m", "force_N_per_m"):
            if fd.GetArray(name) is None:
                fails.append("%s: field data %s missing" % (s.get("file"), name))
        if fails:
            break
        if fd.GetArray("step_index").GetTuple1(0) != t:
            fails.append("%s: step_index != timestep %g" % (s.get("file"), t))
        u = g.GetPointData().GetArray("displacement_m")
        if u is None or u.GetNumberOfComponents() not in (2, 3):
            fails.append("%s: point array displacement_m" % s.get("file"))
        # deal.II's DataOut writes the cell-averaged values as point data of each cell's patch
        pd = g.GetPointData()
        if pd.GetArray("D1_1") is None:
            fails.append("%s: array D1_1 missing" % s.get("file"))
        for name in ("stress_Pa", "strain_1"):
            fails += tensor_problems(pd.GetArray(name), "%s: %s" % (s.get("file"), name))
        for k in range(pd.GetNumberOfArrays()):
            if pd.GetArrayName(k).startswith(("stress_Pa_", "strain_1_")):
                fails.append("%s: scalar component array %s" % (s.get("file"), pd.GetArrayName(k)))
        if fails:
            break
        b = g.GetBounds()
        if b[5] == b[4]:  # 2-D plane strain: eps_13 = eps_23 = eps_33 = 0, sigma_33 != 0
            e, sg = pd.GetArray("strain_1"), pd.GetArray("stress_Pa")
            n = e.GetNumberOfTuples()
            if any(e.GetComponent(i, c) != 0.0 for i in range(n) for c in (2, 5, 8)):
                fails.append("%s: 2-D strain_1 13, 23 or 33 not 0" % s.get("file"))
            loaded = fd.GetArray("displacement_m").GetTuple1(0) != 0.0
            if loaded and all(sg.GetComponent(i, 8) == 0.0 for i in range(n)):
                fails.append("%s: 2-D stress_Pa 33 is 0 everywhere" % s.get("file"))
        ua = fd.GetAbstractArray("units")
        units = dict(ua.GetValue(k).split("=", 1) for k in range(ua.GetNumberOfValues())) \
            if ua is not None else {}
        if units.get("Points") != "m":
            fails.append("%s: units has no Points=m: %s" % (s.get("file"), units))
        for data in (g.GetPointData(), g.GetCellData(), fd):
            for k in range(data.GetNumberOfArrays()):
                name = data.GetArrayName(k)
                if name in ("units", "step_index"):
                    continue
                if name not in units:
                    fails.append("%s: array %s not in units" % (s.get("file"), name))
                elif not name.endswith("_" + units[name].replace("/", "_per_")):
                    fails.append("%s: %s has unit %s, its name does not end with it"
                                 % (s.get("file"), name, units[name]))
        loads.append(fd.GetArray("displacement_m").GetTuple1(0))
    print("timesteps", steps)
    print("displacement_m", loads)
    for f in fails:
        print("FAIL:", f)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
