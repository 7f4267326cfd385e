#!/usr/bin/python3
"""`pnc gimp couple` frame series read back with VTK's own XML reader (D236).

    /usr/bin/python3 read_escm_vtu.py PNC_EXE SOURCE_DIR

Runs examples/escm/case1_lj_tension.json --short (an LJ slab of 16 + 20 + 64 columns of 12
atoms between continuum strips, pulled in tension) into a fresh temporary folder and reads
atoms.pvd and particles.pvd: each lists every frame the run reports; the timesteps are the
frame indices 1, 2, ... (strictly increasing) and equal each frame's field data frame_index;
time_s (the continuum time) is the same in the atoms and particles frame of one index and,
frames being equally spaced in steps of a fixed dt, proportional to the index; every frame
has its arrays with units in the names and the right numbers of components (gradients as
9-component tensors); the atoms frame has 1200 points, in metres (the slab is nanometres
wide, so every coordinate is below 1e-6 m). Exit code 0 when all holds. Needs python3-vtk9.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import vtk

FAILS = []
ATOMS = {"zone_index": 1, "displacement_m": 3, "velocity_m_per_s": 3,
         "displacement_gradient_1": 9, "gradient_supported_1": 1}
PARTICLES = {"zone_index": 1, "displacement_m": 3, "velocity_m_per_s": 3,
             "deformation_gradient_solver_1": 9, "displacement_gradient_1": 9,
             "gradient_supported_1": 1}


def check(cond, what):
    if not cond:
        FAILS.append(what)


def read(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    check(r.GetErrorCode() == 0, "%s: VTK reader error %d" % (path, r.GetErrorCode()))
    return r.GetOutput()


def series(out, name, arrays):
    """[(timestep, time_s, grid)] of out/name, each frame checked against `arrays`."""
    frames = []
    for d in ET.parse(os.path.join(out, name)).getroot().findall("./Collection/DataSet"):
        path = os.path.join(out, d.get("file"))
        g = read(path)
        ts = float(d.get("timestep"))
        fd = g.GetFieldData()
        check(fd.GetArray("frame_index") is not None and fd.GetArray("time_s") is not None,
              "%s: field data frame_index and time_s" % path)
        if FAILS:
            return frames
        check(fd.GetArray("frame_index").GetTuple1(0) == ts,
              "%s: frame_index != timestep %g" % (path, ts))
        for a, nc in arrays.items():
            arr = g.GetPointData().GetArray(a)
            check(arr is not None and arr.GetNumberOfComponents() == nc,
                  "%s: %s with %d components" % (path, a, nc))
        frames.append((ts, fd.GetArray("time_s").GetTuple1(0), g))
    return frames


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    exe, src = sys.argv[1], sys.argv[2]
    tmp = tempfile.mkdtemp(prefix="pnc_escm_vtk_")
    try:
        out = os.path.join(tmp, "out")
        r = subprocess.run([exe, "gimp", "couple", os.path.join(src, "examples/escm/case1_lj_tension.json"),
                            "--out", out, "--short", "--quiet", "--no-plot", "--json"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            print(r.stderr)
            print("pnc gimp couple failed with exit code %d" % r.returncode)
            return 1
        reported = json.loads(r.stdout)["frames"]
        atoms = series(out, "atoms.pvd", ATOMS)
        particles = series(out, "particles.pvd", PARTICLES)
        check(len(atoms) == len(reported) >= 2 and len(particles) == len(reported),
              "frames: %d reported, %d atoms, %d particles" % (len(reported), len(atoms),
                                                              len(particles)))
        if not FAILS:
            steps = [a[0] for a in atoms]
            check(steps == [float(k) for k in range(1, len(steps) + 1)],
                  "timesteps are the frame indices: %s" % steps)
            for (ka, ta, ga), (kp, tp, _) in zip(atoms, particles):
                check(ka == kp and ta == tp, "frame %g: atoms time %g, particles time %g" % (ka, ta, tp))
                check(ta > 0 and abs(ta / ka - atoms[0][1]) <= 1e-9 * atoms[0][1],
                      "frame %g: time_s %g not %g x the first frame's" % (ka, ta, ka))
                check(ga.GetNumberOfPoints() == 1200, "frame %g: %d atoms" % (ka, ga.GetNumberOfPoints()))
                b = ga.GetBounds()
                check(max(abs(x) for x in b) < 1e-6, "frame %g: atom bounds %s not in m" % (ka, b))
    finally:
        shutil.rmtree(tmp)
    for f in FAILS[:20]:
        print("FAIL:", f)
    print("escm frame series: %s" % ("ok" if not FAILS else "%d failures" % len(FAILS)))
    return 1 if FAILS else 0


if __name__ == "__main__":
    sys.exit(main())
