#!/usr/bin/python3
"""`pnc gimp run` frames read back with VTK's own XML reader (D236).

    /usr/bin/python3 read_gimp_vtu.py PNC_EXE SOURCE_DIR

Runs examples/gimp/bar_impact_3d.json (a polymer bar, E = 1.5 GPa, rho = 1200 kg/m^3, moving
at 10 m/s into a fixed wall) into a fresh temporary folder and checks particles.pvd and every
frame: the timesteps increase strictly and equal each frame's field data time_s; the arrays
have their names with units and their numbers of components (stress_Pa and strain_1: 6, the
symmetric tensors); reference positions (points - displacement_m) lie in the bar; the first
frame has velocity (-10, 0, 0) m/s and zero stress; the last frame's most compressive
stress_Pa XX lies within a factor 3 of the bar-wave stress rho c v (c = sqrt(E / rho)).
Exit code 0 when all holds. Needs python3-vtk9 (Debian: /usr/bin/python3).
"""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import vtk

FAILS = []
COMPONENTS = {"displacement_m": 3, "velocity_m_per_s": 3, "stress_Pa": 6, "strain_1": 6,
              "density_kg_per_m3": 1, "volume_m3": 1, "mass_kg": 1,
              "strain_energy_density_J_per_m3": 1, "material_index": 1}


def check(cond, what):
    if not cond:
        FAILS.append(what)


def read_frame(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    check(r.GetErrorCode() == 0, "%s: VTK reader error %d" % (path, r.GetErrorCode()))
    return r.GetOutput()


def check_frame(path, g, timestep, first):
    pd = g.GetPointData()
    for name, nc in COMPONENTS.items():
        a = pd.GetArray(name)
        check(a is not None and a.GetNumberOfComponents() == nc,
              "%s: %s with %d components" % (path, name, nc))
    if FAILS:
        return None
    t = g.GetFieldData().GetArray("time_s").GetTuple1(0)
    check(abs(t - timestep) <= 1e-9 * max(abs(t), 1e-300), "%s: time_s %g != timestep %g" %
          (path, t, timestep))
    units = g.GetFieldData().GetAbstractArray("units")
    got = {units.GetValue(k) for k in range(units.GetNumberOfValues())}
    check("stress_Pa=Pa" in got and "Points=m" in got, "%s: units %s" % (path, sorted(got)))
    u, s, v = pd.GetArray("displacement_m"), pd.GetArray("stress_Pa"), pd.GetArray("velocity_m_per_s")
    tol = 1e-9
    for i in range(g.GetNumberOfPoints()):
        x = g.GetPoint(i)
        X = [x[k] - u.GetComponent(i, k) for k in range(3)]
        check(-tol <= X[0] <= 0.05 + tol and all(-tol <= X[k] <= 0.008 + tol for k in (1, 2)),
              "%s: reference position %s outside the bar" % (path, X))
        if first:
            check(v.GetTuple3(i) == (-10.0, 0.0, 0.0), "%s: initial velocity" % path)
            check(all(c == 0.0 for c in s.GetTuple(i)), "%s: initial stress" % path)
    return min(s.GetComponent(i, 0) for i in range(g.GetNumberOfPoints()))


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    exe, src = sys.argv[1], sys.argv[2]
    tmp = tempfile.mkdtemp(prefix="pnc_gimp_vtk_")
    try:
        out = os.path.join(tmp, "out")
        r = subprocess.run([exe, "gimp", "run", os.path.join(src, "examples/gimp/bar_impact_3d.json"),
                            "--out", out, "--quiet", "--no-plot"], capture_output=True, text=True)
        if r.returncode != 0:
            print(r.stderr)
            print("pnc gimp run failed with exit code %d" % r.returncode)
            return 1
        sets = ET.parse(os.path.join(out, "particles.pvd")).getroot().findall("./Collection/DataSet")
        steps = [float(d.get("timestep")) for d in sets]
        check(len(steps) >= 3, "at least 3 frames, got %d" % len(steps))
        check(all(b > a for a, b in zip(steps, steps[1:])), "timesteps increase: %s" % steps)
        sxx = None
        for k, (d, ts) in enumerate(zip(sets, steps)):
            path = os.path.join(out, d.get("file"))
            sxx = check_frame(path, read_frame(path), ts, k == 0)
            if FAILS:
                break
        if not FAILS:
            rho, E, v = 1200.0, 1.5e9, 10.0
            wave = rho * math.sqrt(E / rho) * v
            check(-3 * wave <= sxx <= -wave / 3,
                  "last frame's min stress_Pa XX %g not within a factor 3 of -rho c v = %g" %
                  (sxx, -wave))
    finally:
        shutil.rmtree(tmp)
    for f in FAILS[:20]:
        print("FAIL:", f)
    print("gimp frames: %s" % ("ok" if not FAILS else "%d failures" % len(FAILS)))
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
