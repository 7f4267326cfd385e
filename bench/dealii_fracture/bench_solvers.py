#!/usr/bin/env python3
"""Time per Newton iteration of examples/dealii_fracture with the direct and the iterative
linear solver (docs/dealii_demo.md, Speed; decisions D250-D252).

    bench_solvers.py BUILD_DIR CARD [--repeats 3] [--cases 2d3,2d4,...] [--timeout 1800]
                     [--out results.csv]

A case is DIMENSION 'd' REFINEMENTS, optionally 't' THICKNESS (mm, 3-D), '-elastic' or
'-damaging' (default: damaging below 10^5 dofs, elastic above) and ':' the solvers to run
if not all (e.g. '3d3t2:iterative'):

  * single-edge notch 4 x 8 mm, coarse cell 0.5 mm (2-D: 136 cells; 3-D: a slab of
    thickness 1 mm, 272 cells), refined uniformly; local law (no regularisation), so each
    Newton iteration is one assembly (one plugin call per quadrature point) and one solve;
  * damaging: two displacement steps, 0 -> 0.2 mm (damage onset at the notch tip) and
    0.2 -> 0.25 mm (loading points: the consistent tangent is not symmetric, the iterative
    solver uses GMRES there);
  * elastic: one step 0 -> 0.1 mm, below damage onset (symmetric tangent: CG).

Every (case, solver) pair is run `--repeats` times, interleaved (case by case, the two
solvers alternating, the order reversed on every other repeat) so that both see the same
machine load. Per run: dofs, Newton iterations, assembly and solve seconds per Newton
iteration, their sum, the setup part of the solve (factorisation or AMG hierarchy), Krylov
iterations per solve. The summary prints the median and the range (min-max) of each time.
Python 3 standard library only; the program is run without a shell.
"""

import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

DEFAULT_CASES = "2d3,2d4,2d5,2d6,3d1,3d2,3d3:iterative,3d3t2:iterative"


def parse_case(text):
    """'<dim>d<refinements>[t<thickness mm>][-elastic|-damaging][:solver+solver]'."""
    head, _, only = text.partition(":")
    head, _, protocol = head.partition("-")
    dim = int(head[0])
    body = head[2:]
    thickness = None
    if "t" in body:
        body, thickness = body.split("t", 1)
    refinements = int(body)
    if not protocol:
        # ~10^5 dofs and more (2-D r >= 5, 3-D r >= 3) run the elastic step: the local law
        # localises into one row of elements on fine meshes and needs step cuts.
        big = (dim == 2 and refinements >= 5) or (dim == 3 and refinements >= 3)
        protocol = "elastic" if big else "damaging"
    if protocol not in ("elastic", "damaging") or dim not in (2, 3):
        raise SystemExit(f"bench_solvers.py: case '{text}': expected e.g. 2d4, 3d2-elastic, "
                         "3d3t2:iterative")
    return {"name": text, "dim": dim, "refinements": refinements, "thickness": thickness,
            "protocol": protocol, "only": only.split("+") if only else None}


def run_once(exe, prm, card, case, solver, timeout, workdir):
    dim, refinements, protocol = case["dim"], case["refinements"], case["protocol"]
    path = "0, 0.2, 0.25" if protocol == "damaging" else "0, 0.1"
    step = "0.2" if protocol == "damaging" else "0.1"
    sets = {
        "Material/Card": card,
        "Mesh/Adaptive": "false",
        "Mesh/Global refinements": str(refinements),
        "Geometry/Dimension": str(dim),
        "Loading/Path": path,
        "Loading/Step": step,
        "Regularisation/Type": "none",
        "Output/VTU every": "0",
        "Output/Plot": "false",
        "Output/Directory": workdir,
        "Newton/Tolerance": "1e-8",
        "Newton/Max iterations": "30",
        "Solver/Type": "iterative" if solver.startswith("iterative") else solver,
    }
    if solver == "iterative-rebuild":  # a new AMG hierarchy at every Newton iteration (D423)
        sets["Solver/AMG reuse"] = "never"
    if case["thickness"]:
        sets["Geometry/Thickness"] = case["thickness"]
    cmd = [exe, prm, "--json"]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return {"error": f"timeout ({timeout} s)"}
    if res.returncode not in (0, 2) or not res.stdout.strip():
        return {"error": f"exit {res.returncode}: {res.stderr.strip()[-300:]}"}
    j = json.loads(res.stdout)
    t = j["timing"]
    its = max(1, t["newton_iterations"])
    ls = t["linear_solver"]
    a = t["assembly_s"] / max(1, t["assemblies"])
    s = t["solve_s"] / its
    return {
        "dofs": j["dofs"],
        "newton_iterations": t["newton_iterations"],
        "assembly_s": a,
        "solve_s": s,
        "total_s": a + s,
        "setup_s": ls["setup_s"] / its,
        "krylov_per_solve": ls["krylov_iterations"] / max(1, ls["solves"]),
        "cg_solves": ls["cg_solves"],
        "solves": ls["solves"],
        "fallbacks": ls["fallbacks"],
        "amg_setups": ls.get("amg_setups", 0),
        "amg_reuses": ls.get("amg_reuses", 0),
        # SI keys (D299): N per metre of thickness in 2-D, N in 3-D
        "peak_load": j["peak_load_N_per_m" if j["dimension"] == 2 else "peak_load_N"],
        "final_load": j["final_load_N_per_m" if j["dimension"] == 2 else "final_load_N"],
        "finished": j["finished"],
        "wall_s": j["wall_time_s"],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build")
    ap.add_argument("card")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--cases", default=DEFAULT_CASES)
    ap.add_argument("--solvers", default="direct,iterative",
                    help="any of direct, iterative (the AMG hierarchy kept over a load step's "
                    "Newton iterations, the default since D423), iterative-rebuild (a new one "
                    "at every iteration)")
    ap.add_argument("--timeout", type=float, default=1800)
    ap.add_argument("--out", default=None, help="CSV of every run")
    a = ap.parse_args()
    exe = os.path.join(a.build, "examples", "dealii_fracture", "dealii_fracture")
    here = os.path.dirname(os.path.abspath(__file__))
    prm = os.path.join(here, "..", "..", "examples", "dealii_fracture", "short.prm")
    cases = [parse_case(c) for c in a.cases.split(",") if c]
    solvers = a.solvers.split(",")
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_solvers_") as work:
        for rep in range(a.repeats):
            for case in cases:
                order = solvers if rep % 2 == 0 else list(reversed(solvers))
                for solver in order:
                    if case["only"] and solver not in case["only"]:
                        continue
                    out = run_once(exe, prm, a.card, case, solver, a.timeout, work)
                    row = {"repeat": rep, "case": case["name"], "dim": case["dim"],
                           "protocol": case["protocol"], "solver": solver, **out}
                    rows.append(row)
                    print(json.dumps(row), flush=True)
    if a.out:
        keys = sorted({k for row in rows for k in row})
        with open(a.out, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            w.writerows(rows)
    print("\n| dim | dofs | protocol | solver | Newton its | assembly s/it | solve s/it "
          "(setup) | total s/it | Krylov its/solve | runs |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for case in cases:
        dim, protocol = case["dim"], case["protocol"]
        for solver in solvers:
            mine = [x for x in rows if x["case"] == case["name"] and x["solver"] == solver]
            ok = [x for x in mine if "error" not in x]
            if not ok:
                if mine:
                    print(f"| {dim} | {case['name']} | {protocol} | {solver} | "
                          f"{mine[0]['error']} |")
                continue

            def cell(key, fmt="%.3g"):
                v = [x[key] for x in ok]
                m = statistics.median(v)
                return fmt % m if len(v) == 1 else (fmt + " (" + fmt + "-" + fmt + ")") % (
                    m, min(v), max(v))
            kry = "-" if solver == "direct" else "%.0f" % statistics.median(
                [x["krylov_per_solve"] for x in ok])
            print(f"| {dim} | {ok[0]['dofs']} | {protocol} | {solver} | "
                  f"{statistics.median([x['newton_iterations'] for x in ok]):.0f} | "
                  f"{cell('assembly_s')} | {cell('solve_s')} ({cell('setup_s')}) | "
                  f"{cell('total_s')} | {kry} | {len(ok)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
