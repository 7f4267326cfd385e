#!/usr/bin/env python3
"""The demo's --json is SI and matches docs/schemas/dealii-demo.schema.json (D299).

Runs `dealii_fracture short.prm --json` (2-D single-edge notch, ~2 s) and the same specimen as
an elastic 3-D slab on one coarse mesh (~1 s) into a fresh temporary directory, checks that
each prints its object as one line on stdout (docs/formats.md), validates the printed objects
against the schema (python3-jsonschema; the schema forbids undocumented keys and the other
dimension's keys), checks the unit rule of tests/docs/json_schemas.py on the
schema, and checks the SI values against the runs' own force_displacement.csv, which stays in
mm, N/mm and mJ/mm (2-D) or N and mJ (3-D): 1 N/mm = 1000 N/m, 1 mm = 1e-3 m, 1 mJ/mm = 1 J/m,
1 mJ = 1e-3 J; in 3-D also W = F u / 2 of the linear elastic slab in J. A document with a 3-D
key, without a required key or with the old `units` string must be refused.

Usage: demo_json.py --root SOURCE_DIR --demo PATH_TO_dealii_fracture --card CARD.h5
"""
import argparse
import copy
import csv
import json
import pathlib
import subprocess
import sys
import tempfile


def run(demo, prm, card, out, sets):
    """dealii_fracture PRM --json with the card, into OUT: (the printed object, its CSV rows)."""
    args = [demo, prm, "--json", "--set", f"Material/Card={card}", "--set",
            f"Output/Directory={out}", "--set", "Output/Plot=false"]
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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True)
    ap.add_argument("--demo", required=True)
    ap.add_argument("--card", required=True)
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
    with tempfile.TemporaryDirectory(prefix="pnc_demo_json_") as d:
        runs = {2: run(a.demo, short, a.card, f"{d}/out2", []),
                3: run(a.demo, short, a.card, f"{d}/out3", elastic_3d)}

    def close(label, got, want, tol=1e-5):
        if abs(got - want) > tol * max(abs(want), 1e-30):
            failures.append(f"{label}: {got} in the JSON, {want} expected")

    for dim, (doc, rows) in runs.items():
        failures += [f"{dim}-D: {'/'.join(map(str, e.absolute_path))}: {e.message}"
                     for e in v.iter_errors(doc)]
        if doc.get("dimension") != dim:
            failures.append(f"the {dim}-D run reports dimension {doc.get('dimension')}")
            continue
        # the SI numbers are the CSV's (mm; N/mm and mJ/mm in 2-D, N and mJ in 3-D) times the
        # unit factors: 1 N/mm = 1e3 N/m, 1 mJ/mm = 1 J/m, 1 mJ = 1e-3 J, 1 mm = 1e-3 m
        fu, eu = ("N_per_mm", "mJ_per_mm") if dim == 2 else ("N", "mJ")
        fk, ek = ("N_per_m", "J_per_m") if dim == 2 else ("N", "J")
        to_f, to_e = (1e3, 1.0) if dim == 2 else (1.0, 1e-3)
        force = [float(x["force_" + fu]) for x in rows]
        peak = max(range(len(rows)), key=lambda i: abs(force[i]))
        close(f"peak_load_{fk}", doc[f"peak_load_{fk}"], to_f * force[peak])
        close("displacement_at_peak_m", doc["displacement_at_peak_m"],
              1e-3 * float(rows[peak]["displacement_mm"]))
        close(f"final_load_{fk}", doc[f"final_load_{fk}"], to_f * force[-1])
        close("final_displacement_m", doc["final_displacement_m"],
              1e-3 * float(rows[-1]["displacement_mm"]))
        close(f"dissipated_energy_{ek}", doc[f"dissipated_energy_{ek}"],
              to_e * float(rows[-1]["dissipated_" + eu]))
        close(f"external_work_{ek}", doc[f"external_work_{ek}"],
              to_e * float(rows[-1]["external_work_" + eu]))
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
