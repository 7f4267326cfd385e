#!/usr/bin/env python3
"""The demo's --json is SI and matches docs/schemas/dealii-demo.schema.json (D299).

Runs `dealii_fracture short.prm --json` (2-D single-edge notch, ~2 s) into a fresh temporary
directory, validates the printed object against the schema (python3-jsonschema; the schema
forbids undocumented keys and, in 2-D, the 3-D keys), checks the unit rule of
tests/docs/json_schemas.py on the schema, and checks the SI values against the run's own
force_displacement.csv, which stays in mm, N/mm and mJ/mm: 1 N/mm = 1000 N/m, 1 mm = 1e-3 m,
1 mJ/mm = 1 J/m. A document with a 3-D key or without a required key must be refused.

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
    with tempfile.TemporaryDirectory(prefix="pnc_demo_json_") as d:
        r = subprocess.run([a.demo, str(root / "examples" / "dealii_fracture" / "short.prm"),
                            "--json", "--set", f"Material/Card={a.card}",
                            "--set", f"Output/Directory={d}/out", "--set", "Output/Plot=false"],
                           capture_output=True, text=True, timeout=240)
        if r.returncode != 0:
            sys.exit(f"demo_json: dealii_fracture exited {r.returncode}:\n{r.stderr}")
        doc = json.loads(r.stdout)
        with open(pathlib.Path(d, "out", "force_displacement.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
    v = Draft202012Validator(schema)
    failures += [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in v.iter_errors(doc)]
    if doc.get("dimension") != 2:
        failures.append("short.prm is expected to be a 2-D run")

    # the SI numbers are the CSV's (mm, N/mm, mJ/mm) times the unit factors
    def close(label, got, want, tol=1e-5):
        if abs(got - want) > tol * max(abs(want), 1e-30):
            failures.append(f"{label}: {got} in the JSON, {want} from the CSV")

    force = [float(x["force_N_per_mm"]) for x in rows]
    peak = max(range(len(rows)), key=lambda i: abs(force[i]))
    close("peak_load_N_per_m", doc["peak_load_N_per_m"], 1e3 * force[peak])
    close("displacement_at_peak_m", doc["displacement_at_peak_m"],
          1e-3 * float(rows[peak]["displacement_mm"]))
    close("final_load_N_per_m", doc["final_load_N_per_m"], 1e3 * force[-1])
    close("final_displacement_m", doc["final_displacement_m"],
          1e-3 * float(rows[-1]["displacement_mm"]))
    close("dissipated_energy_J_per_m", doc["dissipated_energy_J_per_m"],
          float(rows[-1]["dissipated_mJ_per_mm"]))
    close("external_work_J_per_m", doc["external_work_J_per_m"],
          float(rows[-1]["external_work_mJ_per_mm"]))
    # the check bites: a 3-D key in a 2-D document, a required key removed
    for broken in (dict(doc, peak_load_N=doc["peak_load_N_per_m"] / 1e3),
                   {k: x for k, x in doc.items() if k != "dissipated_energy_J_per_m"},
                   dict(copy.deepcopy(doc), units="mm, MPa")):
        if v.is_valid(broken):
            failures.append(f"a broken document passed: {sorted(set(broken) ^ set(doc))}")
    if failures:
        print("demo_json: FAILED\n  " + "\n  ".join(failures))
        return 1
    print(f"demo_json: the 2-D demo's --json is SI and valid against dealii-demo.schema.json "
          f"(peak {doc['peak_load_N_per_m']:.6g} N/m at {doc['displacement_at_peak_m']:.6g} m)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
