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
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from vtk_read import Checks, check_arrays, pvd_frames, read_vtu, run_pnc  # noqa: E402

check = Checks()
ATOMS = {"zone_index": 1, "displacement_m": 3, "velocity_m_per_s": 3,
         "displacement_gradient_1": 9, "gradient_supported_1": 1}
PARTICLES = {"zone_index": 1, "displacement_m": 3, "velocity_m_per_s": 3,
             "deformation_gradient_solver_1": 9, "displacement_gradient_1": 9,
             "gradient_supported_1": 1}


def series(out, name, arrays):
    """[(timestep, time_s, grid)] of out/name, each frame checked against `arrays`."""
    frames = []
    for ts, path in pvd_frames(out, name):
        g = read_vtu(path, check)
        fd = g.GetFieldData()
        check(fd.GetArray("frame_index") is not None and fd.GetArray("time_s") is not None,
              "%s: field data frame_index and time_s" % path)
        if check.fails:
            return frames
        check(fd.GetArray("frame_index").GetTuple1(0) == ts,
              "%s: frame_index != timestep %g" % (path, ts))
        check_arrays(g, arrays, path, check)
        frames.append((ts, fd.GetArray("time_s").GetTuple1(0), g))
    return frames


def check_run(out, r):
    reported = json.loads(r.stdout)["frames"]
    atoms = series(out, "atoms.pvd", ATOMS)
    particles = series(out, "particles.pvd", PARTICLES)
    check(len(atoms) == len(reported) >= 2 and len(particles) == len(reported),
          "frames: %d reported, %d atoms, %d particles" % (len(reported), len(atoms),
                                                          len(particles)))
    if not check.fails:
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
    return check.report("escm frame series")


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    exe, src = sys.argv[1], sys.argv[2]
    return run_pnc(exe, ["gimp", "couple", os.path.join(src, "examples/escm/case1_lj_tension.json"),
                         "--short", "--quiet", "--no-plot", "--json"], "pnc_escm_vtk_", check_run)


if __name__ == "__main__":
    sys.exit(main())
