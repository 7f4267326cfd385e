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
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from vtk_read import Checks, check_arrays, pvd_frames, read_vtu, run_pnc, units  # noqa: E402

check = Checks()
COMPONENTS = {"displacement_m": 3, "velocity_m_per_s": 3, "stress_Pa": 6, "strain_1": 6,
              "density_kg_per_m3": 1, "volume_m3": 1, "mass_kg": 1,
              "strain_energy_density_J_per_m3": 1, "material_index": 1}


def check_frame(path, g, timestep, first):
    check_arrays(g, COMPONENTS, path, check)
    if check.fails:
        return None
    t = g.GetFieldData().GetArray("time_s").GetTuple1(0)
    check(abs(t - timestep) <= 1e-9 * max(abs(t), 1e-300), "%s: time_s %g != timestep %g" %
          (path, t, timestep))
    got = units(g)
    check("stress_Pa=Pa" in got and "Points=m" in got, "%s: units %s" % (path, sorted(got)))
    pd = g.GetPointData()
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


def check_run(out, _):
    frames = pvd_frames(out, "particles.pvd")
    steps = [ts for ts, _ in frames]
    check(len(steps) >= 3, "at least 3 frames, got %d" % len(steps))
    check(all(b > a for a, b in zip(steps, steps[1:])), "timesteps increase: %s" % steps)
    sxx = None
    for k, (ts, path) in enumerate(frames):
        sxx = check_frame(path, read_vtu(path, check), ts, k == 0)
        if check.fails:
            break
    if not check.fails:
        rho, E, v = 1200.0, 1.5e9, 10.0
        wave = rho * math.sqrt(E / rho) * v
        check(-3 * wave <= sxx <= -wave / 3,
              "last frame's min stress_Pa XX %g not within a factor 3 of -rho c v = %g" %
              (sxx, -wave))
    return check.report("gimp frames")


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    exe, src = sys.argv[1], sys.argv[2]
    return run_pnc(exe, ["gimp", "run", os.path.join(src, "examples/gimp/bar_impact_3d.json"),
                         "--quiet", "--no-plot"], "pnc_gimp_vtk_", check_run)


if __name__ == "__main__":
    sys.exit(main())
