#!/usr/bin/env python3
"""The demo's --json, CSV files and VTU frames are SI (D299, D317, D318).

Runs `dealii_fracture short.prm --json` (2-D single-edge notch, ~2 s) and the same specimen as
an elastic 3-D slab on one coarse mesh (~1 s) into a fresh temporary directory, checks that
each prints its object as one line on stdout (docs/formats.md), validates the printed objects
against the schema (python3-jsonschema; the schema forbids undocumented keys and the other
dimension's keys), checks the unit rule of tests/docs/json_schemas.py on the schema, and
checks the runs' files:
- force_displacement.csv and damage_final.csv: every header ends with its SI unit (_m;
  _N_per_m, _J_per_m in 2-D; _N, _J in 3-D) or is one of the dimensionless columns and counts;
- the CSV's peak and final force, displacement, dissipated energy and work equal the JSON's
  (independently converted from the demo's mm, N/mm, mJ/mm) to the CSV's 10 digits;
- with --vtu (python3-vtk9; a frame every step): the last frame's arrays are named with their
  unit, Points=m, its points span the specimen (Width x Height (x Thickness) of the .prm in mm
  times 1e-3), its field data equal the CSV row of its step, the loaded edge's displacement_m
  is the controlled displacement (the clamped edge's 0), its cells are damage_final.csv's rows
  (centres in m, D1), the tensors stress_Pa and strain_1 have 9 components and are symmetric
  (D328), and the stresses in Pa integrate to the force: sum over cells of the 22 component
  of stress_Pa x cell size = F x Height (the equilibrium of the linear field y / Height, up
  to the Newton tolerance);
- in 3-D also W = F u / 2 of the linear elastic slab in J and, with --vtu, per cell the shear
  stresses of the undamaged orthotropic card against the tensor strain: sigma_12 = 2 C66
  eps_12, sigma_13 = 2 C55 eps_13, sigma_23 = 2 C44 eps_23 (D329; engineering shear strains
  would be off by 2), C from the card's `pnc card show --json` (CONSTANTS_JSON).
A document with a 3-D key, without a required key or with the old `units` string must be
refused.

Usage: demo_json.py --root SOURCE_DIR --demo PATH_TO_dealii_fracture --card CARD.h5
                    --constants-json CONSTANTS_JSON [--vtu]
"""
import argparse
import copy
import csv
import json
import pathlib
import re
import subprocess
import sys
import tempfile

# tests/common/vtk_read.py (imported where VTK is needed: it imports vtk)
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "common"))


def run(demo, prm, card, out, sets):
    """dealii_fracture PRM --json with the card, into OUT: (the printed object, its CSV rows)."""
    args = [demo, prm, "--json", "--set", f"Material/Card={card}", "--set",
            f"Output/Directory={out}", "--set", "Output/Plot=false", "--set", "Output/VTU every=1"]
    for x in sets:
        args += ["--set", x]
    r = subprocess.run(args, capture_output=True, text=True, timeout=240)
    if r.returncode != 0:
        sys.exit(f"demo_json: {' '.join(args)} exited {r.returncode}:\n{r.stderr}")
    # docs/formats.md: every --json object is one line on stdout
    if r.stdout.count("\n") != 1 or not r.stdout.endswith("\n"):
        sys.exit(f"demo_json: {' '.join(args)} printed {r.stdout.count(chr(10))} lines on "
                 f"stdout, not one JSON line:\n{r.stdout[:400]}")
    with open(pathlib.Path(out, "force_displacement.csv"), newline="") as f:
        return json.loads(r.stdout), list(csv.DictReader(f))


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def prm_number(path, entry):
    """The number of 'set ENTRY = x' in a .prm (the first one), or None."""
    for line in pathlib.Path(path).read_text().splitlines():
        m = re.match(r"\s*set\s+%s\s*=\s*([-+0-9.eE]+)" % re.escape(entry), line)
        if m:
            return float(m.group(1))
    return None


# The CSV columns without a unit: dimensionless numbers, counts and words (D317).
PLAIN = {"step", "max_damage", "max_fracture", "newton_iterations", "cuts", "dofs", "control",
         "omega"}


def header_problems(name, header, dim):
    """Columns of HEADER not named by the SI rule of a DIM-D run."""
    suffix = r"_(m|N_per_m|J_per_m)" if dim == 2 else r"_(m|N|J)"
    return [f"{dim}-D {name}: column {c!r} has no SI unit suffix ({suffix}$) and is not "
            f"dimensionless" for c in header
            if not (c in PLAIN or re.fullmatch(r"D[1-3]", c) or re.search(suffix + "$", c))]


def frame_problems(out, dim, rows, cells, box_m, close):
    """The last VTU frame of OUT against the CSV ROWS and CELLS (damage_final.csv) and the
    specimen BOX_M."""
    import xml.etree.ElementTree as ET
    import vtk
    from vtk_read import TENSOR_IJ, tensor_problems
    fails = []
    sets = ET.parse(pathlib.Path(out, "solution.pvd")).getroot().findall("./Collection/DataSet")
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(pathlib.Path(out, sets[-1].get("file"))))
    r.Update()
    g = r.GetOutput()
    fd, pd = g.GetFieldData(), g.GetPointData()
    ua = fd.GetAbstractArray("units")
    units = dict(ua.GetValue(k).split("=", 1) for k in range(ua.GetNumberOfValues()))
    fk = "force_N_per_m" if dim == 2 else "force_N"
    want = {"Points": "m", "displacement_m": "m", fk: "N/m" if dim == 2 else "N",
            "stress_Pa": "Pa", "D1_1": "1", "strain_1": "1"}
    for name, unit in want.items():
        if units.get(name) != unit:
            fails.append(f"{dim}-D frame: units[{name}] = {units.get(name)}, not {unit}")
    b = g.GetBounds()
    for k, span in enumerate(box_m):
        # float32 coordinates: 6e-8 relative
        close(f"{dim}-D frame: extent along x{k + 1} (m)", b[2 * k + 1] - b[2 * k], span, 1e-6)
    step = int(fd.GetArray("step_index").GetTuple1(0))
    row = rows[step]
    close(f"{dim}-D frame step {step}: displacement_m", fd.GetArray("displacement_m").GetTuple1(0),
          float(row["displacement_m"]), 1e-9)
    F = fd.GetArray(fk).GetTuple1(0)
    close(f"{dim}-D frame step {step}: {fk}", F, float(row[fk]), 1e-9)
    u, s = pd.GetArray("displacement_m"), pd.GetArray("stress_Pa")
    if u is None:
        return fails + [f"{dim}-D frame: no displacement_m point array"]
    tensors = [p for name in ("stress_Pa", "strain_1")
               for p in tensor_problems(pd.GetArray(name), f"{dim}-D frame: {name}")]
    if tensors:
        return fails + tensors
    # the loaded edge (largest x2) moves by the controlled displacement, the bottom edge not
    pts = g.GetPoints()
    y = [pts.GetPoint(i)[1] for i in range(g.GetNumberOfPoints())]
    top = [u.GetComponent(i, 1) for i in range(len(y)) if y[i] > b[3] - 1e-6 * box_m[1]]
    bottom = [u.GetComponent(i, 1) for i in range(len(y)) if y[i] < b[2] + 1e-6 * box_m[1]]
    u_load = fd.GetArray("displacement_m").GetTuple1(0)
    for v in (min(top), max(top)):  # float32 values: 6e-8 relative
        close(f"{dim}-D frame: displacement_m along x2 on the loaded edge", v, u_load, 1e-6)
    if max(abs(v) for v in bottom) > 1e-6 * abs(u_load):
        fails.append(f"{dim}-D frame: the clamped edge moves: {max(abs(v) for v in bottom)} m")
    # the last frame is the last step (VTU every 1): its cells are damage_final.csv's rows, in
    # the same order (active cells), the centres to the CSV's 6 digits, D1 to float32
    if step == len(rows) - 1:
        if len(cells) != g.GetNumberOfCells():
            fails.append(f"{dim}-D: {len(cells)} rows in damage_final.csv, "
                         f"{g.GetNumberOfCells()} cells in the last frame")
        d1 = pd.GetArray("D1_1")
        for c in range(min(len(cells), g.GetNumberOfCells())):
            cb = g.GetCell(c).GetBounds()
            for k, x in enumerate("xyz"[:dim]):
                mid = 0.5 * (cb[2 * k] + cb[2 * k + 1])
                if abs(float(cells[c][x + "_m"]) - mid) > 1e-5 * box_m[k]:
                    fails.append(f"{dim}-D damage_final.csv row {c}: {x}_m = "
                                 f"{cells[c][x + '_m']}, the frame's cell centre is {mid} m")
                    break
            dv = d1.GetTuple1(g.GetCell(c).GetPointId(0))
            if abs(float(cells[c]["D1"]) - dv) > 1e-5:
                fails.append(f"{dim}-D damage_final.csv row {c}: D1 {cells[c]['D1']}, frame {dv}")
    else:
        fails.append(f"{dim}-D: the last frame is step {step}, not the last step {len(rows) - 1}")
    # VTK's numpy layer (ParaView's Python Calculator) sees a 3 x 3 tensor per point; its trace
    # is the sum of the diagonal components (float32 values summed in float64: 1e-6 of the
    # largest component)
    from vtk.numpy_interface import algorithms as alg
    from vtk.numpy_interface import dataset_adapter as dsa
    st = dsa.WrapDataObject(g).PointData["stress_Pa"]
    if st.shape != (g.GetNumberOfPoints(), 3, 3):
        fails.append(f"{dim}-D frame: stress_Pa seen by VTK's numpy layer as {st.shape}")
    else:
        tr = alg.trace(st)
        for i in range(0, g.GetNumberOfPoints(), max(1, g.GetNumberOfPoints() // 50)):
            diag = [s.GetComponent(i, TENSOR_IJ.index(ii)) for ii in ("11", "22", "33")]
            if abs(tr[i] - sum(diag)) > 1e-6 * max(abs(x) for x in s.GetTuple9(i)):
                fails.append(f"{dim}-D frame point {i}: trace(stress_Pa) {tr[i]}, "
                             f"the diagonal sums to {sum(diag)}")
                break
    # each cell is a patch of its own (its points carry its averaged stress): the cell size
    # from its bounds (axis-parallel cells), the stress at its first point
    total = 0.0
    for c in range(g.GetNumberOfCells()):
        cb = g.GetCell(c).GetBounds()
        size = 1.0
        for k in range(dim):
            size *= cb[2 * k + 1] - cb[2 * k]
        total += s.GetComponent(g.GetCell(c).GetPointId(0), TENSOR_IJ.index("22")) * size
    # Newton: |residual| <= 1e-8 |f_int|, times |y/H| <= sqrt(dofs) ~ 1e2 over F; float32
    # stresses and points 1e-7: 1e-4 relative
    close(f"{dim}-D frame: sum of stress_Pa 22 x cell size / Height (= {fk})",
          total / box_m[1], F, 1e-4)
    return fails


def shear_problems(out, constants):
    """The last VTU frame of the elastic 3-D run in OUT: per cell sigma_ij = 2 C eps_ij on the
    three shear components of the undamaged orthotropic card (D329). CONSTANTS: name -> Pa."""
    import xml.etree.ElementTree as ET
    import vtk
    from vtk_read import TENSOR_IJ
    sets = ET.parse(pathlib.Path(out, "solution.pvd")).getroot().findall("./Collection/DataSet")
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(pathlib.Path(out, sets[-1].get("file"))))
    r.Update()
    g = r.GetOutput()
    s, e = g.GetPointData().GetArray("stress_Pa"), g.GetPointData().GetArray("strain_1")
    fails, bites = [], 0
    for c in range(g.GetNumberOfCells()):
        p = g.GetCell(c).GetPointId(0)
        sv, ev = s.GetTuple9(p), e.GetTuple9(p)
        scale = max(abs(x) for x in sv)
        for ij, cname in (("12", "C66"), ("13", "C55"), ("23", "C44")):
            k = TENSOR_IJ.index(ij)
            want = 2.0 * constants[cname] * ev[k]
            # float32 cell averages of 8 quadrature values each: a few 1e-7 of the cell's
            # largest stress component
            if abs(sv[k] - want) > 1e-5 * scale:
                fails.append(f"3-D cell {c}: stress_Pa {ij} = {sv[k]} Pa, 2 {cname} strain_1 "
                             f"{ij} = {want} Pa")
            bites += abs(sv[k]) > 0.1 * scale
    if bites == 0:  # a factor 2 must show: some shear stress of at least 0.1 of the largest
        fails.append("3-D: no cell with a shear stress to check the tensor strain against")
    return fails[:5]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True)
    ap.add_argument("--demo", required=True)
    ap.add_argument("--card", required=True)
    ap.add_argument("--constants-json", required=True,
                    help="`pnc card show --json` of CARD (the shear moduli, D329)")
    ap.add_argument("--vtu", action="store_true", help="check the VTU frames (python3-vtk9)")
    a = ap.parse_args()
    root = pathlib.Path(a.root).resolve()
    sys.path.insert(0, str(root / "tests" / "docs"))
    from json_schemas import unit_problems  # noqa: E402 (also checks python3-jsonschema)
    from jsonschema import Draft202012Validator

    schema = json.loads((root / "docs" / "schemas" / "dealii-demo.schema.json").read_text())
    Draft202012Validator.check_schema(schema)
    failures = unit_problems(schema, "dealii-demo.schema.json")
    short = str(root / "examples" / "dealii_fracture" / "short.prm")
    # 3-D: the same specimen as a slab, one coarse mesh, elastic (no damage below 0.1 mm)
    elastic_3d = ["Geometry/Dimension=3", "Mesh/Global refinements=0", "Mesh/Adaptive=false",
                  "Regularisation/Type=none", "Loading/Path=0, 0.1"]
    v = Draft202012Validator(schema)
    # the specimen in m: Width x Height (x Thickness) of short.prm in mm (the 3-D thickness is
    # the default of parameters.prm), 1 mm = 1e-3 m
    w, h = prm_number(short, "Width"), prm_number(short, "Height")
    t = prm_number(root / "examples" / "dealii_fracture" / "parameters.prm", "Thickness")
    boxes = {2: [1e-3 * w, 1e-3 * h], 3: [1e-3 * w, 1e-3 * h, 1e-3 * t]}

    def close(label, got, want, tol=1e-5):
        if abs(got - want) > tol * max(abs(want), 1e-30):
            failures.append(f"{label}: {got}, {want} expected")

    with tempfile.TemporaryDirectory(prefix="pnc_demo_json_") as d:
        runs = {2: run(a.demo, short, a.card, f"{d}/out2", []),
                3: run(a.demo, short, a.card, f"{d}/out3", elastic_3d)}
        for dim, (doc, rows) in runs.items():
            out = f"{d}/out{dim}"
            failures.extend(header_problems("force_displacement.csv", rows[0].keys(), dim))
            cells = read_csv(pathlib.Path(out, "damage_final.csv"))
            failures.extend(header_problems("damage_final.csv", cells[0].keys(), dim))
            if a.vtu:
                failures.extend(frame_problems(out, dim, rows, cells, boxes[dim], close))
        if a.vtu:
            consts = json.loads(pathlib.Path(a.constants_json).read_text())["constants"]
            if any(consts[k]["units"] != "Pa" for k in ("C44", "C55", "C66")):
                failures.append("the card's shear moduli are not in Pa")
            elif float(runs[3][1][-1]["max_damage"]) != 0.0:
                failures.append("the 3-D slab damaged: no elastic shear check")
            else:
                failures.extend(shear_problems(f"{d}/out3",
                                               {k: v["value"] for k, v in consts.items()}))

    for dim, (doc, rows) in runs.items():
        failures += [f"{dim}-D: {'/'.join(map(str, e.absolute_path))}: {e.message}"
                     for e in v.iter_errors(doc)]
        if doc.get("dimension") != dim:
            failures.append(f"the {dim}-D run reports dimension {doc.get('dimension')}")
            continue
        # the CSV (SI since D317, 10 significant digits: 5e-10 relative) holds the JSON's
        # numbers, which summary() converts from the demo's mm, N/mm, mJ/mm on its own
        fk, ek = ("N_per_m", "J_per_m") if dim == 2 else ("N", "J")
        force = [float(x["force_" + fk]) for x in rows]
        peak = max(range(len(rows)), key=lambda i: abs(force[i]))
        tol = 1e-9
        close(f"CSV peak force_{fk}", force[peak], doc[f"peak_load_{fk}"], tol)
        close("CSV displacement_m at the peak", float(rows[peak]["displacement_m"]),
              doc["displacement_at_peak_m"], tol)
        close(f"CSV final force_{fk}", force[-1], doc[f"final_load_{fk}"], tol)
        close("CSV final displacement_m", float(rows[-1]["displacement_m"]),
              doc["final_displacement_m"], tol)
        close(f"CSV final dissipated_{ek}", float(rows[-1]["dissipated_" + ek]),
              doc[f"dissipated_energy_{ek}"], tol)
        close(f"CSV final external_work_{ek}", float(rows[-1]["external_work_" + ek]),
              doc[f"external_work_{ek}"], tol)
        if dim == 3:
            # linear elastic slab: the work is F u / 2 in SI (N x m = J), and all of it stored
            w = 0.5 * doc["final_load_N"] * doc["final_displacement_m"]
            close("3-D external_work_J (= F u / 2)", doc["external_work_J"], w, 1e-6)
            close("3-D elastic_energy_J (= F u / 2)", doc["elastic_energy_J"], w, 1e-6)
    doc, doc3 = runs[2][0], runs[3][0]
    # the check bites: the other dimension's key, a required key removed, the old `units` string
    for broken in (dict(doc, peak_load_N=doc["peak_load_N_per_m"] / 1e3),
                   dict(doc3, peak_load_N_per_m=doc3["peak_load_N"] * 1e3),
                   {k: x for k, x in doc.items() if k != "dissipated_energy_J_per_m"},
                   dict(copy.deepcopy(doc), units="mm, MPa")):
        if v.is_valid(broken):
            failures.append(f"a broken document passed: {sorted(set(broken) ^ set(doc))}")
    if failures:
        print("demo_json: FAILED\n  " + "\n  ".join(failures))
        return 1
    print(f"demo_json: the 2-D and 3-D demo's --json are SI and valid against "
          f"dealii-demo.schema.json (2-D peak {doc['peak_load_N_per_m']:.6g} N/m at "
          f"{doc['displacement_at_peak_m']:.6g} m; 3-D {doc3['final_load_N']:.6g} N)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
