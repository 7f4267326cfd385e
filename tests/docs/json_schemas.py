#!/usr/bin/env python3
"""The --json outputs of pnc match the JSON Schemas shipped in docs/schemas/ (D238).

Runs `pnc synth`, `pnc fit`, `pnc card show`, `pnc card export --format json`, `pnc material
drive`, `pnc card tables`, `pnc gimp run` (a 1-s bar impact in 3-D, 5 steps of the 2-D plate)
and `pnc status` (a plan written here), and in builds with LAMMPS `pnc rve build`, `pnc characterize` (8 chains, short
stages, an extension and a shear both ways), `pnc thermo ti` (a 12-chain melt, 2 lambda points), `pnc thermo
persistence` (a 4-bead harmonic chain), `pnc thermo work` (with python3-h5py) and `pnc gimp
couple` (the short Case I run) in a fresh temporary directory and validates each printed
object against its schema (python3-jsonschema, Draft 2020-12; the schemas forbid keys they do
not describe, so a new key must be documented). Also checks the unit rule on every schema:
each number has a `unit` annotation, and a key whose unit is neither `1` (dimensionless, a
count) nor `units` (stated by a sibling `units` key) ends with the unit spelled as a suffix
(`Pa` -> `_Pa`, `J/m^3` -> `_J_per_m3`, `N m^2` -> `_N_m2`). A broken document (a key removed,
a key added) must be refused, so the check is shown to bite.

Usage: json_schemas.py --root SOURCE_DIR --pnc PATH_TO_PNC [--with-rve] [--with-thermo]
                       [--with-escm]
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
    """`Pa` -> `_Pa`, `J/m^3` -> `_J_per_m3`, `1/s` -> `_per_s`, `N m^2` -> `_N_m2`."""
    if unit.startswith("1/"):
        unit = unit[1:]
    return ("_" + unit.replace("/", "_per_").replace("^", "").replace(" ", "_")).replace("__", "_")


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


def card_export_output(pnc, d, shown, failures):
    """`pnc card export card.h5 --format json` (it has no --json: the format is the JSON). Its
    PROPS state their units per entry (D299): Pa for the stiffness constants, 1 for alpha, and
    the values are the card's, as `pnc card show` prints them in the same units."""
    r = subprocess.run([pnc, "card", "export", "card.h5", "--format", "json"], cwd=d,
                       capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        raise SystemExit(f"json_schemas: pnc card export exited {r.returncode}:\n{r.stderr}")
    ex = json.loads(r.stdout)
    for p in ex["props"]:
        c = shown["constants"].get(p["name"])
        if c is not None and c["value"] is not None and (p["units"] != c["units"] or p["value"] != c["value"]):
            failures.append(f"card export: {p['name']} = {p['value']} {p['units']}, card show "
                            f"says {c['value']} {c['units']}")
    return ex


def rve_build_output(pnc, d, failures):
    """`pnc rve build` of 10 chains x 10 beads; its numbers are SI too: the default build asks
    0.9 g/cm^3 (= 900 kg/m^3) and keeps non-bonded atoms at least 2 Angstrom (2e-10 m) apart,
    in a cubic box."""
    rb = run_json(pnc, ["rve", "build", "--chains", "10", "--beads", "10", "--out", "rve"], d)
    if abs(rb["density_kg_per_m3"] / 900.0 - 1) > 1e-9:
        failures.append(f"rve build: density_kg_per_m3 {rb['density_kg_per_m3']} != 900")
    if not 2e-10 <= rb["min_nonbonded_distance_m"] < 1e-9:
        failures.append(f"rve build: min_nonbonded_distance_m {rb['min_nonbonded_distance_m']}"
                        " is not in [2e-10, 1e-9) m")
    if max(rb["box_m"]) - min(rb["box_m"]) > 1e-12 * max(rb["box_m"]) or max(rb["box_m"]) > 1e-7:
        failures.append(f"rve build: box_m {rb['box_m']} is not a cube of nanometres in m")
    return rb


# The smallest characterization that runs every stage (build, equilibration, phase check, one
# case, fit): tests/rve/test_characterize_cli.cpp's tiny recipe with shorter stages (~10 s).
TINY_RECIPE = {
    "name": "schema", "seed": 3, "build": {"chains": 8},
    "equilibrate": {"pushoff_steps": 200, "hot_steps": 300, "cool_steps": 200,
                    "langevin_chunk_steps": 100, "langevin_max_chunks": 2, "npt_steps": 300,
                    "final_steps": 100},
    "deform": {"cases": [2, 6, 9], "strain_max": 0.03, "steps": 3, "timestep_fs": 1.0,
               "hold_steps": 100, "sample_every": 10, "blocks": 4},
    "phase_check": {"enabled": True, "steps": 1000, "sample_every": 5, "cavitation_steps": 100},
    "analysis": {"moving_average": 1}}


def characterize_output(pnc, d, failures):
    """`pnc characterize` of TINY_RECIPE (exit 4, a card "not usable", is a complete output);
    its numbers are SI (D284): a polymer melt near 0.9 g/cm^3 in kg/m^3, pressures in Pa."""
    pathlib.Path(d, "tiny.json").write_text(json.dumps(TINY_RECIPE))
    # one rank, one unit at a time: MPI ranks that wait on each other on a busy machine cost
    # more than they gain on 160 atoms
    ch = run_json(pnc, ["characterize", "tiny.json", "--out", "char", "--no-plots", "--ranks", "1",
                        "--equilibrate-ranks", "1", "--jobs", "1"], d)
    rho = ch["equilibrated"]["density_kg_per_m3"]
    if not 300 < rho < 1500:
        failures.append(f"characterize: density_kg_per_m3 {rho} is not a melt's in kg/m^3")
    if not 1e-10 < ch["equilibrated"]["min_distance_m"] < 1e-9:
        failures.append("characterize: min_distance_m is not Angstroms in m")
    # cases 6 and 9 shear the 1-2 plane both ways: compared side by side (D428)
    pairs = ch["statistics"].get("sense_pairs", [])
    if [p["cases"] for p in pairs] != [[6, 9]]:
        failures.append(f"characterize: statistics.sense_pairs {pairs} is not the pair [6, 9]")
    return ch


def thermo_outputs(pnc, d, failures):
    """`pnc thermo ti` on a 12-chain melt (built, minimised and written as a restart here;
    two lambda points, 80 steps each) and `pnc thermo persistence` on a 4-bead harmonic chain
    (the inputs of tests/thermo); a few seconds each. Their numbers are SI (D280)."""
    run_json(pnc, ["rve", "build", "--chains", "12", "--beads", "10", "--out", "melt"], d)
    pathlib.Path(d, "prep.lmp").write_text(
        "units real\natom_style molecular\nread_data melt/rve.data\ninclude melt/forcefield.lmp\n"
        "minimize 1e-4 1e-6 200 2000\nvelocity all create 300 5 dist gaussian\n"
        "write_restart melt.restart\n")
    r = subprocess.run([pnc, "rve", "lammps", "prep.lmp", "--log", "prep.log"], cwd=d,
                       capture_output=True, text=True, timeout=120)
    if r.returncode != 0:
        raise SystemExit(f"json_schemas: pnc rve lammps prep.lmp exited {r.returncode}:\n{r.stderr}")
    ti = run_json(pnc, ["thermo", "ti", "--restart", "melt.restart", "--vol", "0,0.005", "--dev",
                        "none", "--points", "2", "--equil-steps", "20", "--prod-steps", "60",
                        "--sample-every", "10", "--blocks", "3", "--no-plots", "--out", "ti"], d)
    pe = run_json(pnc, ["thermo", "persistence", "--chain", "harmonic", "--supports", "roller",
                        "--angle-k", "500", "--spring-k", "100", "--pull-distance", "1", "--rates",
                        "0.002,0.004", "--timestep", "1", "--hold-steps", "200", "--no-plots",
                        "--out", "pers"], d)
    # SI: kT at 300 K in J; the box of 120 beads at ~0.9 g/cm^3 is a few nm^3; 1 A/fs = 1e5 m/s;
    # the harmonic chain's k_theta l0 = 2 K l0 = 1530 kcal/mol A in N m^2
    if abs(ti["kT_J"] / (1.380649e-23 * 300) - 1) > 1e-12:
        failures.append(f"thermo ti: kT_J {ti['kT_J']} is not k_B 300 K in J")
    if not all(1e-27 < s["volume_m3"] < 1e-25 for s in ti["states"]):
        failures.append("thermo ti: volume_m3 is not a few nm^3 in m^3")
    if abs(pe["rates"][0]["rate_m_per_s"] - 200.0) > 1e-9:
        failures.append(f"thermo persistence: rate_m_per_s {pe['rates'][0]['rate_m_per_s']} != 200")
    if abs(pe["expected_EI_continuum_N_m2"] / (1530 * 4184 / 6.02214076e23 * 1e-10) - 1) > 1e-12:
        failures.append("thermo persistence: expected_EI_continuum_N_m2 is not 1530 kcal/mol A")
    out = [("thermo-ti.schema.json", "thermo ti", ti),
           ("thermo-persistence.schema.json", "thermo persistence", pe)]
    work = work_output(pnc, d, failures)
    return out + [("thermo-work.schema.json", "thermo work", work)]


def work_output(pnc, d, failures):
    """`pnc thermo work` on a run directory made here as tests/thermo/test_work.cpp makes one:
    `pnc synth`'s six cases as cases.h5, recipe.json with the temperature, and the equilibrated
    box (8000 A^3) in equilibrate/final.h5, written with h5py (python3-h5py, a test dependency
    installed by scripts/common.sh: missing, the test fails). Its numbers are SI (D280)."""
    try:
        import h5py
    except ImportError:
        sys.exit("json_schemas: python3-h5py is missing (scripts/common.sh installs it)")
    run = pathlib.Path(d, "work_run")
    (run / "equilibrate").mkdir(parents=True)
    run_json(pnc, ["synth", "--points", "20", "--out", str(run / "cases.h5")], d)
    (run / "recipe.json").write_text(json.dumps({"deform": {"temperature": 300}}))
    with h5py.File(run / "equilibrate" / "final.h5", "w") as f:
        f["/trace"] = [[300.0, 0, 0, 0, 0.8, 8000.0]] * 2
    doc = run_json(pnc, ["thermo", "work", "--from", str(run), "--out", "work"], d)
    if abs(doc["volume_m3"] / 8e-27 - 1) > 1e-12:
        failures.append(f"thermo work: volume_m3 {doc['volume_m3']} is not 8000 A^3 in m^3")
    for c in doc["cases"]:
        t = c["total"]
        if abs(t["dA_J"] - t["da_J_per_m3"] * doc["volume_m3"]) > 1e-12 * abs(t["dA_J"]):
            failures.append(f"thermo work: case {c['case']}: dA_J is not V0 da_J_per_m3")
    return doc


def status_output(pnc, d, failures):
    """`pnc status` of a plan written here: a replica done (its state file records seconds,
    seconds_build, seconds_equilibrate), a case that failed on an input error, a fit pending.
    The JSON has the times under SI keys (D283). Exit code 1: a failed unit."""
    run = pathlib.Path(d, "campaign")
    (run / "state" / "replica_1").mkdir(parents=True)
    unit = {"group": "replica_1", "join": False, "ranks": 1, "inputs": [], "outputs": []}
    plan = {"format": "pnc plan v1 (docs/cluster.md)", "command": "characterize", "parameters": {},
            "units": [dict(unit, id="replica_1/build", kind="replica", needs=[]),
                      dict(unit, id="replica_1/case_1", kind="case", group="case_1",
                           needs=["replica_1/build"]),
                      dict(unit, id="fit", kind="fit", group="fit", join=True,
                           needs=["replica_1/case_1"])]}
    (run / "plan.json").write_text(json.dumps(plan))
    (run / "state" / "replica_1" / "build.json").write_text(json.dumps(
        {"state": "done", "host": "h", "pid": 1, "started_s": 100.0, "ended_s": 112.5,
         "detail": {"seconds_build": 2.5, "seconds_equilibrate": 10.0, "seconds": 12.5}}))
    (run / "state" / "replica_1" / "case_1.json").write_text(json.dumps(
        {"state": "failed", "host": "h", "pid": 2, "message": "bad", "detail": {"error": {
            "exit_code": 1, "what": "x", "source": "r.json", "field": "f", "value": "v",
            "rule": "r"}, "seconds": 0.5}}))
    r = subprocess.run([pnc, "status", str(run), "--json"], capture_output=True, text=True,
                       timeout=60)
    if r.returncode != 1 or not r.stdout.strip():
        raise SystemExit(f"json_schemas: pnc status exited {r.returncode} (1 expected: a failed "
                         f"unit):\n{r.stderr}")
    doc = json.loads(r.stdout)
    detail = doc["units"][0]["detail"]
    if detail != {"build_wall_s": 2.5, "equilibrate_wall_s": 10.0, "wall_s": 12.5}:
        failures.append(f"status: the done unit's detail {detail} is not its times under SI keys")
    return doc


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True)
    ap.add_argument("--pnc", required=True)
    ap.add_argument("--with-rve", action="store_true",
                    help="pnc has the rve commands (LAMMPS)")
    ap.add_argument("--with-thermo", action="store_true",
                    help="pnc has the thermo commands (LAMMPS): check thermo ti and persistence")
    ap.add_argument("--with-escm", action="store_true",
                    help="pnc has gimp couple (LAMMPS): check the short Case I run")
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

    root = pathlib.Path(a.root).resolve()
    drive = root / "examples" / "drive" / "uniaxial_stress_lur.toml"
    bar = root / "examples" / "gimp" / "bar_impact_3d.json"
    plate = root / "examples" / "gimp" / "plate_hole_tension.json"
    with tempfile.TemporaryDirectory(prefix="pnc_json_schemas_") as d:
        # (schema, what was run, the printed object)
        outputs = [
            ("synth.schema.json", "synth",
             run_json(a.pnc, ["synth", "--points", "40", "--out", "d.csv"], d)),
            ("fit.schema.json", "fit",
             run_json(a.pnc, ["fit", "--data", "d.csv", "--out", "card.h5", "--no-plots"], d)),
            ("card-show.schema.json", "card show", run_json(a.pnc, ["card", "show", "card.h5"], d)),
            ("card-export.schema.json", "card export", None),
            ("material-drive.schema.json", "material drive",
             run_json(a.pnc, ["material", "drive", "card.h5", "--path", str(drive), "--out",
                              "drive.csv", "--no-plot"], d)),
            ("card-tables.schema.json", "card tables",
             run_json(a.pnc, ["card", "tables", "--out", "t.h5"], d)),
            ("gimp-run.schema.json", "gimp run (3-D)",
             run_json(a.pnc, ["gimp", "run", str(bar), "--out", "gimp", "--quiet", "--no-plot"], d)),
            ("gimp-run.schema.json", "gimp run (2-D)",
             run_json(a.pnc, ["gimp", "run", str(plate), "--out", "gimp2", "--quiet", "--no-plot",
                              "--max-steps", "5"], d)),
        ]
        shown = next(doc for _, lbl, doc in outputs if lbl == "card show")
        outputs = [(n, lbl, card_export_output(a.pnc, d, shown, failures) if doc is None else doc)
                   for n, lbl, doc in outputs]
        # D281: energies and reactions per metre of thickness in 2-D, and the keys say so
        for label, doc in ((lbl, doc) for _, lbl, doc in outputs if lbl.startswith("gimp run")):
            plane = doc["dimension"] == 2
            if ("energy_J_per_m" in doc) != plane or ("reactions_N_per_m" in doc) != plane:
                failures.append(f"{label}: energy/reaction keys do not follow the dimension")
        if a.with_rve:  # pnc status, rve build and characterize exist only in builds with LAMMPS
            outputs.append(("status.schema.json", "status", status_output(a.pnc, d, failures)))
            outputs.append(("rve-build.schema.json", "rve build", rve_build_output(a.pnc, d, failures)))
            outputs.append(("characterize.schema.json", "characterize",
                            characterize_output(a.pnc, d, failures)))
        if a.with_thermo:
            outputs += thermo_outputs(a.pnc, d, failures)
        if a.with_escm:
            outputs.append(("gimp-couple.schema.json", "gimp couple", run_json(
                a.pnc, ["gimp", "couple", str(root / "examples" / "escm" / "case1_lj_tension.json"),
                        "--out", "couple", "--short", "--quiet", "--no-plot"], d)))
    for name, label, doc in outputs:
        v = validator(name)
        for e in v.iter_errors(doc):
            failures.append(f"{label}: {'/'.join(map(str, e.absolute_path))}: {e.message}")
        # the check bites: a required key removed, an undocumented key added
        broken = copy.deepcopy(doc)
        broken.pop(v.schema["required"][-1])
        if v.is_valid(broken):
            failures.append(f"{label}: a document without '{v.schema['required'][-1]}' passed")
        broken = copy.deepcopy(doc)
        broken["undocumented_key_m"] = 1.0
        if v.is_valid(broken):
            failures.append(f"{label}: a document with an undocumented key passed")
    if failures:
        print("json_schemas: FAILED\n  " + "\n  ".join(failures))
        return 1
    print(f"json_schemas: {len(outputs)} outputs valid against docs/schemas/ "
          f"(jsonschema {importlib.metadata.version('jsonschema')}), unit rule holds in {len(store) // 2} schemas")
    return 0


if __name__ == "__main__":
    sys.exit(main())
