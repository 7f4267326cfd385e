#!/usr/bin/env python3
"""Helper of bench/peer/cbgeo_compare.sh (standard library only; h5dump for CB-Geo's HDF5).

  peer_tool.py cbgeo-input PNC_JSON DIR ELEMENT   CB-Geo mpm's input for the same problem
                                          (ELEMENT linear: ED2Q4; gimp: ED2Q16G)
  peer_tool.py pnc-result OUT_DIR         tip displacement and base stress of a pnc run
  peer_tool.py cbgeo-result RUN_DIR       the same from CB-Geo's last particles*.h5
  peer_tool.py check PNC_JSON PNC.json CBGEO.json   compare both with the static solution
  peer_tool.py summary TIMES_TXT PARTICLES STEPS    median and range of the timings

The problem (bench/peer/column_gravity.json): a 2-D column on a fixed base under its own
weight, Poisson's ratio 0, so that the static solution is one-dimensional:
  u_y(y) = -rho g (H y - y^2 / 2) / E   (m),   sigma_yy(y) = -rho g (H - y)   (Pa).
Measured: the mean u_y of the top row of particles and the mean sigma_yy of the bottom row.
"""
import glob
import json
import math
import os
import re
import statistics
import subprocess
import sys


def load_problem(path):
    with open(path) as f:
        p = json.load(f)
    if p["dimension"] != 2 or len(p["bodies"]) != 1 or p["bodies"][0]["shape"] != "box":
        sys.exit(f"peer_tool: {path}: expected one 2-D box body")
    m = p["materials"][0]
    if m["type"] != "linear_elastic":
        sys.exit(f"peer_tool: {path}: materials[0].type = {m['type']}, expected linear_elastic")
    h = p["grid"]["cell_size"]
    ppc = p.get("particles_per_cell", 2)
    lo, hi = p["bodies"][0]["min"], p["bodies"][0]["max"]
    return {
        "h": h, "ppc": ppc, "lo": lo, "hi": hi, "rho": m["density"], "E": m["E"],
        "nu": m["nu"], "g": -p["loads"]["gravity"][1], "dt": p["time"]["dt"],
        "steps": p["time"]["max_steps"], "damping": p.get("damping", 0.0),
        "H": hi[1] - lo[1],
    }


def particle_positions(pr):
    """The sub-grid points of pnc's box body: spacing h/ppc, centred in the sub-cells."""
    s = pr["h"] / pr["ppc"]
    nx = round((pr["hi"][0] - pr["lo"][0]) / s)
    ny = round((pr["hi"][1] - pr["lo"][1]) / s)
    return [(pr["lo"][0] + (i + 0.5) * s, pr["lo"][1] + (j + 0.5) * s)
            for j in range(ny) for i in range(nx)]


def cbgeo_input(pnc_json, out, element="linear"):
    pr = load_problem(pnc_json)
    h = pr["h"]
    os.makedirs(out, exist_ok=True)
    if element == "linear":
        # Linear quadrilaterals (ED2Q4) over the body plus two rows of cells above it; the
        # base nodes at y = lo[1] are held in y (the fixed base of pnc's "base" boundary).
        x0, y0 = pr["lo"]
        nx = round((pr["hi"][0] - pr["lo"][0]) / h)
        ny = round((pr["hi"][1] - pr["lo"][1]) / h) + 2
        cells = [(i, j) for j in range(ny) for i in range(nx)]
    elif element == "gimp":
        # CB-Geo's GIMP element (ED2Q16G): pnc's grid as is; a cell lists its 4 corners and the
        # 12 nodes around them, so only cells with a full ring of nodes are made.
        with open(pnc_json) as f:
            grid = json.load(f)["grid"]
        x0, y0 = grid.get("origin", [0.0, 0.0])
        nx, ny = grid["cells"]
        cells = [(i, j) for j in range(1, ny - 1) for i in range(1, nx - 1)]
    else:
        sys.exit(f"peer_tool: element {element}: expected linear or gimp")
    node = lambda i, j: j * (nx + 1) + i
    ring = [(0, 0), (1, 0), (1, 1), (0, 1), (-1, -1), (0, -1), (1, -1), (2, -1), (2, 0), (2, 1),
            (2, 2), (1, 2), (0, 2), (-1, 2), (-1, 1), (-1, 0)]  # ED2Q16G's local node order
    corners = ring[:4] if element == "linear" else ring
    with open(os.path.join(out, "mesh.txt"), "x") as f:
        f.write(f"{(nx + 1) * (ny + 1)}\t{len(cells)}\n")
        for j in range(ny + 1):
            for i in range(nx + 1):
                f.write(f"{x0 + i * h:.12g}\t{y0 + j * h:.12g}\n")
        for i, j in cells:
            f.write("\t".join(str(node(i + a, j + b)) for a, b in corners) + "\n")
    with open(os.path.join(out, "velocity-constraints.txt"), "x") as f:
        for j in range(ny + 1):  # every node at or below the base, held in y
            if y0 + j * h <= pr["lo"][1] + 1e-9 * h:
                for i in range(nx + 1):
                    f.write(f"{node(i, j)}\t1\t0\n")
    pts = particle_positions(pr)
    with open(os.path.join(out, "particles.txt"), "x") as f:
        f.write(f"{len(pts)}\n")
        for x, y in pts:
            f.write(f"{x:.12g}\t{y:.12g}\n")
    # Cundall's local damping (force-proportional) is CB-Geo's only damping; its factor 0.8
    # (about 25 % of critical) brings the column to rest within the same number of steps.
    cfg = {
        "title": "pnc peer comparison: elastic column under gravity (SI units)",
        "mesh": {
            "mesh": "mesh.txt", "io_type": "Ascii2D", "isoparametric": False,
            "check_duplicates": True, "node_type": "N2D",
            "cell_type": "ED2Q4" if element == "linear" else "ED2Q16G",
            "boundary_conditions": {"velocity_constraints": [{"file": "velocity-constraints.txt"}]},
        },
        "particles": [{"generator": {
            "type": "file", "io_type": "Ascii2D", "location": "particles.txt",
            "material_id": 0, "pset_id": 0, "particle_type": "P2D", "check_duplicates": True}}],
        "materials": [{"id": 0, "type": "LinearElastic2D", "density": pr["rho"],
                       "youngs_modulus": pr["E"], "poisson_ratio": pr["nu"]}],
        "external_loading_conditions": {"gravity": [0.0, -pr["g"]]},
        "analysis": {
            "type": "MPMExplicit2D", "mpm_scheme": "usf", "locate_particles": True,
            "velocity_update": False, "dt": pr["dt"], "nsteps": pr["steps"],
            "damping": {"type": "Cundall", "damping_factor": 0.8},
        },
        "post_processing": {"path": "results/", "output_steps": pr["steps"] - 1, "vtk": []},
    }
    with open(os.path.join(out, "mpm.json"), "x") as f:
        json.dump(cfg, f, indent=2)
    print(f"{len(pts)} particles, {len(cells)} {element} cells, {pr['steps']} steps of {pr['dt']} s")


def rows(points, key, top):
    """Particles of the top (or bottom) row: within a quarter sub-spacing of the extreme y."""
    ys = [p[key] for p in points]
    y0 = max(ys) if top else min(ys)
    tol = 0.25 * (max(ys) - min(ys)) / max(1, len(set(round(y, 9) for y in ys)))
    return [p for p in points if abs(p[key] - y0) <= tol]


def measure(points):
    top = rows(points, "y", True)
    bot = rows(points, "y", False)
    return {
        "particles": len(points),
        "y_top_m": statistics.mean(p["y"] for p in top),
        "uy_top_m": statistics.mean(p["uy"] for p in top),
        "y_bottom_m": statistics.mean(p["y"] for p in bot),
        "syy_bottom_Pa": statistics.mean(p["syy"] for p in bot),
        "vrms_m_per_s": math.sqrt(statistics.mean(p["v"] ** 2 for p in points)),
    }


def vtu_array(text, name):
    m = re.search(r'<DataArray[^>]*Name="%s"[^>]*NumberOfComponents="(\d+)"[^>]*format="ascii">'
                  r'([^<]*)</DataArray>' % re.escape(name), text)
    if not m:
        sys.exit(f"peer_tool: VTU array {name} missing (output.vtu must be \"ascii\")")
    n = int(m.group(1))
    v = [float(x) for x in m.group(2).split()]
    return [v[i:i + n] for i in range(0, len(v), n)]


def pnc_result(out):
    frames = sorted(glob.glob(os.path.join(out, "frames", "particles_*.vtu")))
    if not frames:
        sys.exit(f"peer_tool: no frames in {out}/frames")
    text = open(frames[-1]).read()
    x, u, v, s = (vtu_array(text, n)
                  for n in ("Points", "displacement_m", "velocity_m_per_s", "stress_Pa"))
    # Points are the current positions: y0 = y - u_y.
    pts = [{"y": xi[1] - ui[1], "uy": ui[1], "v": math.hypot(vi[0], vi[1]), "syy": si[1]}
           for xi, ui, vi, si in zip(x, u, v, s)]
    print(json.dumps(measure(pts)))


def cbgeo_result(run):
    files = sorted(glob.glob(os.path.join(run, "results", "**", "particles*.h5"), recursive=True))
    if not files:
        sys.exit(f"peer_tool: no results/**/particles*.h5 in {run}")
    last = max(files, key=lambda f: int(re.findall(r"(\d+)\.h5$", f)[0]))
    dump = subprocess.run(["h5dump", "-d", "/table", "-y", "-w", "0", last], check=True,
                          capture_output=True, text=True).stdout
    head, data = dump.split("DATASPACE", 1)
    names = re.findall(r'H5T_\w+\s+"(\w+)";', head)
    data = data[data.index("DATA {") + len("DATA {"):]
    data = data.split("ATTRIBUTE", 1)[0]  # the table's attributes follow its data
    recs = re.findall(r"\{([^{}]*)\}", data)
    pts = []
    for r in recs:
        vals = [v.strip() for v in r.split(",")]
        d = dict(zip(names, vals))
        y = float(d["coord_y"]) - float(d["displacement_y"])
        v = math.hypot(float(d["velocity_x"]), float(d["velocity_y"]))
        pts.append({"y": y, "uy": float(d["displacement_y"]), "v": v, "syy": float(d["stress_yy"])})
    if not pts:
        sys.exit(f"peer_tool: {last}: no particle records")
    res = measure(pts)
    res["file"] = last
    print(json.dumps(res))


def check(pnc_json, a_json, b_json):
    pr = load_problem(pnc_json)
    a, b = json.load(open(a_json)), json.load(open(b_json))
    rg, H, E = pr["rho"] * pr["g"], pr["H"], pr["E"]
    ok = True
    print(f"{'quantity':32s} {'pnc':>13s} {'CB-Geo':>13s} {'static':>13s}  pnc/CB-Geo")
    for key, label, exact in (
        ("uy_top_m", "u_y, top row (m)",
         lambda r: -rg * (H * r["y_top_m"] - r["y_top_m"] ** 2 / 2) / E),
        ("syy_bottom_Pa", "sigma_yy, bottom row (Pa)", lambda r: -rg * (H - r["y_bottom_m"])),
    ):
        ratio = a[key] / b[key]
        print(f"{label:32s} {a[key]:13.6g} {b[key]:13.6g} {exact(a):13.6g}  {ratio:.4f}")
        for name, r in (("pnc", a), ("CB-Geo", b)):
            if abs(r[key] / exact(r) - 1) > 0.01:
                print(f"  {name}: {key} = {r[key]:.6g} differs from the static solution "
                      f"{exact(r):.6g} by more than 1 %")
                ok = False
        if abs(ratio - 1) > 0.01:
            print(f"  pnc and CB-Geo differ by more than 1 % in {key}")
            ok = False
    # Scale: the peak speed of the undamped response, u_static(H) * omega_1 (first mode).
    vpeak = rg * H * H / (2 * E) * math.pi / (2 * H) * math.sqrt(E / pr["rho"])
    print(f"rms particle speed at the end (m/s): pnc {a['vrms_m_per_s']:.3g}, "
          f"CB-Geo {b['vrms_m_per_s']:.3g} (undamped peak about {vpeak:.3g})")
    print("agreement within 1 %: " + ("yes" if ok else "NO"))
    return 0 if ok else 1


def summary(times_txt, particles, steps):
    """times.txt rows: rep code wall_s cpu_s load1 (code = pnc | cbgeo-<element>)."""
    runs = {}
    for line in open(times_txt):
        if line.startswith("#") or not line.strip():
            continue
        rep, code, wall, cpu, load = line.split()
        runs[(int(rep), code)] = (float(wall), float(cpu), float(load))
    codes = ["pnc"] + sorted({k[1] for k in runs if k[1] != "pnc"})
    reps = sorted({k[0] for k in runs if all((k[0], c) in runs for c in codes)})
    ps = float(particles) * float(steps)

    def stat(xs, f):
        return f"{f(statistics.median(xs))} ({f(min(xs))}–{f(max(xs))})"

    ns = lambda x: f"{x * 1e9:.0f} ns"
    f2 = lambda x: f"{x:.2f}"
    labels = {"pnc": "pnc gimp run (uGIMP)", "cbgeo-gimp": "CB-Geo mpm (USF, GIMP ED2Q16G)",
              "cbgeo-linear": "CB-Geo mpm (USF, linear ED2Q4)"}
    print(f"{len(reps)} interleaved rounds, {int(float(particles))} particles x {steps} steps; "
          "median (min–max); whole process (input, set-up, two output files included)")
    print("| code | wall / particle-step | CPU / particle-step | wall / pnc | CPU / pnc |")
    print("|---|---:|---:|---:|---:|")
    for c in codes:
        w = [runs[(r, c)][0] / ps for r in reps]
        u = [runs[(r, c)][1] / ps for r in reps]
        rw = [runs[(r, c)][0] / runs[(r, "pnc")][0] for r in reps]
        ru = [runs[(r, c)][1] / runs[(r, "pnc")][1] for r in reps]
        print(f"| {labels.get(c, c)} | {stat(w, ns)} | {stat(u, ns)} | {stat(rw, f2)} "
              f"| {stat(ru, f2)} |")
    loads = [v[2] for v in runs.values()]
    print(f"load average (1 min) during the runs: {min(loads):.1f}–{max(loads):.1f}")


def main(argv):
    cmds = {"cbgeo-input": (cbgeo_input, 3), "pnc-result": (pnc_result, 1),
            "cbgeo-result": (cbgeo_result, 1), "check": (check, 3), "summary": (summary, 3)}
    if len(argv) < 2 or argv[1] not in cmds or len(argv) - 2 != cmds[argv[1]][1]:
        sys.exit(__doc__)
    return cmds[argv[1]][0](*argv[2:]) or 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
