#!/bin/sh
# Cost of one Newton iteration of dealii_fracture versus the number of dofs, and the share
# of the assembly spent inside the material plugin (docs/dealii_demo.md, Speed; goal: plugin
# <= 10 % of the assembly).
#
#   bench_newton.sh BUILD_DIR CARD [MAX_REFINEMENT=6] [REGULARISATION=none] [TIMEOUT_S=900]
#                   [DIM=2] [SOLVER=direct] [ENTRY=batched]
#
# First prints the cost of one plugin call alone (bench_dealii_plugin_call, built with
# PNC_BUILD_BENCH), so the share can be read against the kernel's own cost. The direct and
# the iterative linear solver side by side, with repeats: bench_solvers.py next to this file.
# A mesh that does not finish within TIMEOUT_S prints "timeout" and ends the scan.
#
# Single-edge notch (coarse cell 0.5 mm, 128 cells) refined uniformly r = 2..MAX times
# (r = 4: 69k dofs, 5: 0.27M, 6: 1.05M; with DIM=3 a slab, r = 1..MAX: 8.8k dofs, 60k, ...);
# two load steps, to u = 0.2 mm (damage onset at the notch tip) and on to 0.25 mm
# (D_max ~ 0.03), so the Newton iterations of the second step have loading points. Prints
# one CSV line per mesh: dofs, Newton iterations, assembly s/iteration, solve s/iteration
# (UMFPACK or the iterative solver, SOLVER), plugin share of the assembly. The nonlocal
# regularisation adds its averaging cost (reported separately in the JSON as nonlocal_s);
# the default here measures the plain assembly.
#
# ENTRY (Material/Entry, D311): batched (default) or point runs the scan with that plugin
# entry. ENTRY=ab compares the two instead (D313): per mesh, runs alternate point (A) and
# batched (B) in the order A B B A, AB_ROUNDS times (default 2: 8 runs), and one CSV line
# gives the ratio batched / point of neighbouring runs (A B, B A, ...) as median [min, max],
# for the assembly time per assembly and for the timed material region (plugin_s, which
# includes the composition when the law is composed), plus each entry's median ns per point.
set -e
BUILD=${1:?build dir}
CARD=${2:?card}
MAX=${3:-6}
REG=${4:-none}
TMO=${5:-900}
DIM=${6:-2}
SOLVER=${7:-direct}
ENTRY=${8:-batched}
case "$ENTRY" in batched | point | ab) ;; *) echo "ENTRY: '$ENTRY': must be batched, point or ab" >&2; exit 2 ;; esac
ROUNDS=${AB_ROUNDS:-2}
EXE=$BUILD/examples/dealii_fracture/dealii_fracture
SRC=$(dirname "$0")/../../examples/dealii_fracture
"$BUILD/bench/bench_dealii_plugin_call" "$CARD" | /usr/bin/python3 -c '
import json, sys
j = json.load(sys.stdin)
e, d = j["elastic_point"], j["damaging_point"]
print("# plugin call alone: %.0f ns (elastic point), %.0f ns (damaging point), steady_clock %.0f ns"
      % (e["ns_per_call_with_tangent"], d["ns_per_call_with_tangent"], j["steady_clock_now_ns"]))
print("# batched entry, 256 points a call: %.0f ns per point (elastic), %.0f ns (damaging)"
      % (e["ns_per_point_batched_256_with_tangent"], d["ns_per_point_batched_256_with_tangent"]))'
WORK=$(mktemp -d "${TMPDIR:-/tmp}/bench_newton.XXXXXX") # created exclusively, removed on exit
trap 'rm -rf "$WORK"' EXIT
# One run of the demo on refinement $1 with entry $2, its --json to $3.
run_one() {
  timeout "$TMO" "$EXE" "$SRC/short.prm" --json --set "Material/Card=$CARD" --set "Mesh/Adaptive=false" \
    --set "Mesh/Global refinements=$1" --set "Loading/Path=0, 0.2, 0.25" --set "Loading/Step=0.2" \
    --set "Regularisation/Type=$REG" --set "Geometry/Dimension=$DIM" --set "Output/VTU every=0" --set "Output/Plot=false" \
    --set "Newton/Tolerance=1e-8" --set "Newton/Max iterations=30" --set "Solver/Type=$SOLVER" \
    --set "Material/Entry=$2" --set "Output/Directory=$WORK/out" 2>/dev/null >"$3"
}
r=2
[ "$DIM" = 3 ] && r=1
if [ "$ENTRY" = ab ]; then
  echo "dofs,pairs,assembly_ratio_median,assembly_ratio_min,assembly_ratio_max,material_ratio_median,material_ratio_min,material_ratio_max,point_assembly_ns_per_point,batched_assembly_ns_per_point"
  while [ "$r" -le "$MAX" ]; do
    k=0
    files=""
    i=0
    while [ "$i" -lt "$ROUNDS" ]; do
      for e in point batched batched point; do
        k=$((k + 1))
        run_one "$r" "$e" "$WORK/ab_$k.json" || { echo "refinement $r: timeout or failure (limit ${TMO} s)"; exit 0; }
        files="$files $e:$WORK/ab_$k.json"
      done
      i=$((i + 1))
    done
    # shellcheck disable=SC2086 # the list of entry:file words is meant to split
    /usr/bin/python3 -c '
import json, statistics, sys
runs = []
for a in sys.argv[1:]:
    e, f = a.split(":", 1)
    j = json.load(open(f)); t = j["timing"]
    pts = j["cells"] * (4 if j["dimension"] == 2 else 8)
    runs.append((e, t["assembly_s"] / t["assemblies"], t["plugin_s"] / t["assemblies"], pts, j["dofs"]))
ra, rm = [], []
for x, y in zip(runs[0::2], runs[1::2]):  # neighbours: (A, B) or (B, A)
    a, b = (x, y) if x[0] == "point" else (y, x)
    ra.append(b[1] / a[1]); rm.append(b[2] / a[2])
ns = lambda e: 1e9 * statistics.median(r[1] for r in runs if r[0] == e) / runs[0][3]
print("%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.0f,%.0f" % (runs[0][4], len(ra),
      statistics.median(ra), min(ra), max(ra), statistics.median(rm), min(rm), max(rm),
      ns("point"), ns("batched")))' $files
    r=$((r + 1))
  done
  exit 0
fi
echo "dofs,newton_iterations,assembly_s_per_iteration,solve_s_per_iteration,plugin_share_of_assembly,nonlocal_s,assembly_ns_per_point,wall_s"
while [ "$r" -le "$MAX" ]; do
  run_one "$r" "$ENTRY" "$WORK/run.json" || { echo "refinement $r: timeout or failure (limit ${TMO} s)"; break; }
  /usr/bin/python3 -c '
import json, sys
j = json.load(open(sys.argv[1])); t = j["timing"]
pts = j["cells"] * (4 if j["dimension"] == 2 else 8)
print("%d,%d,%.4g,%.4g,%.3f,%.3g,%.0f,%.1f" % (j["dofs"], t["newton_iterations"],
      t["assembly_s"] / t["assemblies"], t["solve_s"] / max(1, t["newton_iterations"]),
      t["plugin_share_of_assembly"], t["nonlocal_s"],
      1e9 * t["assembly_s"] / t["assemblies"] / pts, j["wall_time_s"]))' "$WORK/run.json"
  r=$((r + 1))
done
