#!/usr/bin/env python3
"""The --json outputs of pnc match the JSON Schemas shipped in docs/schemas/ (D238).

Runs `pnc synth`, `pnc fit`, `pnc card show`, `pnc material drive`, `pnc card tables`,
`pnc rve build` and `pnc gimp run` (a 1-s bar impact) in a fresh temporary
directory and validates each printed object against its schema (python3-jsonschema, Draft
2020-12; the schemas forbid keys they do not describe, so a new key must be documented). Also
checks the unit rule on every schema: each number has a `unit` annotation, and a key whose unit
is neither `1` (dimensionless, a count) nor `units` (stated by a sibling `units` key) ends with
the unit spelled as a suffix (`Pa` -> `_Pa`, `J/m^3` -> `_J_per_m3`). A broken document (a key
removed, a key added) must be refused, so the check is shown to bite.

Usage: json_schemas.py --root SOURCE_DIR --pnc PATH_TO_PNC
"""
import argparse
import copy
import importlib.metadata
import json
import pathlib
import subprocess
import sys
import tempfile

try:
    from jsonschema import Draft202012Validator, RefResolver
except ImportError:
    sys.exit("json_schemas: python3-jsonschema is missing (scripts/common.sh installs it)")


def suffix(unit):
    """`Pa` -> `_Pa`, `J/m^3` -> `_J_per_m3`, `1/s` -> `_per_s`."""
    if unit.startswith("1/"):
        unit = unit[1:]
    return ("_" + unit.replace("/", "_per_").replace("^", "")).replace("__", "_")


def unit_problems(schema, where, key=None, problems=None, block=""):
    """Numbers without a unit annotation, unit-bearing keys without the unit's suffix (or
    inside a block whose key has it: `energy_J: {kinetic, ...}`)."""
    if problems is None:
        problems = []
    if not isinstance(schema, dict):
        return problems
    types = schema.get("type", [])
    types = [types] if isinstance(types, str) else types
    items = schema.get("items", {})
    item_types = items.get("type", []) if isinstance(items, dict) else []
    numeric = any(t in ("number", "integer") for t in types) or (
        "array" in types and any(t in ("number", "integer") for t in
                                 ([item_types] if isinstance(item_types, str) else item_types)))
    if numeric and key is not None:
        unit = schema.get("unit")
        if unit is None:
            problems.append(f"{where}: number without a `unit` annotation")
        elif (unit not in ("1", "units") and not key.startswith("^")
              and not key.endswith(suffix(unit)) and not block.endswith(suffix(unit))):
            problems.append(f"{where}: unit {unit} but the key does not end with {suffix(unit)}")
    for name, sub in schema.get("properties", {}).items():
        unit_problems(sub, f"{where}.{name}", name, problems, key or "")
    for pattern, sub in schema.get("patternProperties", {}).items():
        unit_problems(sub, f"{where}.<{pattern}>", pattern, problems, key or "")
    if isinstance(schema.get("additionalProperties"), dict):
        unit_problems(schema["additionalProperties"], f"{where}.<any>", "<any>", problems,
                      key or "")
    for name, sub in schema.get("$defs", {}).items():
        unit_problems(sub, f"{where}#{name}", None, problems)
    if isinstance(items, dict) and "properties" in items:
        unit_problems(items, f"{where}[]", None, problems)
    return problems


def run_json(pnc, args, cwd):
    r = subprocess.run([pnc, *args, "--json"], cwd=cwd, capture_output=True, text=True,
                       timeout=120)
    if r.returncode not in (0, 4):  # 4: a card that is not usable, still a complete output
        raise SystemExit(f"json_schemas: pnc {' '.join(args)} exited {r.returncode}:\n{r.stderr}")
    return json.loads(r.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True)
    ap.add_argument("--pnc", required=True)
    ap.add_argument("--with-rve", action="store_true",
                    help="pnc has the rve commands (LAMMPS); builds without them check 6 outputs")
    a = ap.parse_args()
    a.pnc = str(pathlib.Path(a.pnc).resolve())
    schemas = pathlib.Path(a.root) / "docs" / "schemas"
    store = {}
    for p in sorted(schemas.glob("*.schema.json")):
        s = json.loads(p.read_text())
        Draft202012Validator.check_schema(s)  # the schema itself is valid
        store[s["$id"]] = s
        store[p.name] = s
    failures = []
    for name, s in store.items():
        if name.endswith(".schema.json") and "/" not in name:
            failures += unit_problems(s, name)

    def validator(name):
        s = store[name]
        return Draft202012Validator(s, resolver=RefResolver(s["$id"], s, store=store))

    drive = pathlib.Path(a.root).resolve() / "examples" / "drive" / "uniaxial_stress_lur.toml"
    bar = pathlib.Path(a.root).resolve() / "examples" / "gimp" / "bar_impact_3d.json"
    with tempfile.TemporaryDirectory(prefix="pnc_json_schemas_") as d:
        outputs = {
            "synth.schema.json": run_json(a.pnc, ["synth", "--points", "40", "--out", "d.csv"], d),
            "fit.schema.json": run_json(a.pnc, ["fit", "--data", "d.csv", "--out", "card.h5",
                                                "--no-plots"], d),
            "card-show.schema.json": run_json(a.pnc, ["card", "show", "card.h5"], d),
            "material-drive.schema.json": run_json(a.pnc, ["material", "drive", "card.h5", "--path",
                                                           str(drive), "--out", "drive.csv",
                                                           "--no-plot"], d),
            "card-tables.schema.json": run_json(a.pnc, ["card", "tables", "--out", "t.h5"], d),
            "gimp-run.schema.json": run_json(a.pnc, ["gimp", "run", str(bar), "--out", "gimp",
                                                     "--quiet", "--no-plot"], d),
        }
        if a.with_rve:
            outputs["rve-build.schema.json"] = run_json(
                a.pnc, ["rve", "build", "--chains", "10", "--beads", "10", "--out", "rve"], d)
        if a.with_rve:
            # the numbers are SI too: the default build asks 0.9 g/cm^3 (= 900 kg/m^3) and keeps
            # non-bonded atoms at least 2 Angstrom (2e-10 m) apart, in a cubic box
            rb = outputs["rve-build.schema.json"]
            if abs(rb["density_kg_per_m3"] / 900.0 - 1) > 1e-9:
                failures.append(f"rve build: density_kg_per_m3 {rb['density_kg_per_m3']} != 900")
            if not 2e-10 <= rb["min_nonbonded_distance_m"] < 1e-9:
                failures.append(f"rve build: min_nonbonded_distance_m {rb['min_nonbonded_distance_m']}"
                                " is not in [2e-10, 1e-9) m")
            if max(rb["box_m"]) - min(rb["box_m"]) > 1e-12 * max(rb["box_m"]) or max(rb["box_m"]) > 1e-7:
                failures.append(f"rve build: box_m {rb['box_m']} is not a cube of nanometres in m")
    for name, doc in outputs.items():
        v = validator(name)
        for e in v.iter_errors(doc):
            failures.append(f"{name}: {'/'.join(map(str, e.absolute_path))}: {e.message}")
        # the check bites: a required key removed, an undocumented key added
        broken = copy.deepcopy(doc)
        broken.pop(v.schema["required"][-1])
        if v.is_valid(broken):
            failures.append(f"{name}: a document without '{v.schema['required'][-1]}' passed")
        broken = copy.deepcopy(doc)
        broken["undocumented_key_m"] = 1.0
        if v.is_valid(broken):
            failures.append(f"{name}: a document with an undocumented key passed")
    if failures:
        print("json_schemas: FAILED\n  " + "\n  ".join(failures))
        return 1
    print(f"json_schemas: {len(outputs)} outputs valid against docs/schemas/ "
          f"(jsonschema {importlib.metadata.version('jsonschema')}), unit rule holds in {len(store) // 2} schemas")
    return 0


if __name__ == "__main__":
    sys.exit(main())
