#!/bin/sh
# Cost of one Newton iteration of dealii_fracture versus the number of dofs, and the share
# of the assembly spent inside the material plugin (docs/dealii_demo.md, Speed; goal: plugin
# <= 10 % of the assembly).
#
#   bench_newton.sh BUILD_DIR CARD [MAX_REFINEMENT=6] [REGULARISATION=none] [TIMEOUT_S=900]
#                   [DIM=2] [SOLVER=direct]
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
set -e
BUILD=${1:?build dir}
CARD=${2:?card}
MAX=${3:-6}
REG=${4:-none}
TMO=${5:-900}
DIM=${6:-2}
SOLVER=${7:-direct}
EXE=$BUILD/examples/dealii_fracture/dealii_fracture
SRC=$(dirname "$0")/../../examples/dealii_fracture
"$BUILD/bench/bench_dealii_plugin_call" "$CARD" | /usr/bin/python3 -c '
import json, sys
j = json.load(sys.stdin)
print("# plugin call alone: %.0f ns (elastic point), %.0f ns (damaging point), steady_clock %.0f ns"
      % (j["elastic_point"]["ns_per_call_with_tangent"],
         j["damaging_point"]["ns_per_call_with_tangent"], j["steady_clock_now_ns"]))'
WORK=$(mktemp -d "${TMPDIR:-/tmp}/bench_newton.XXXXXX") # created exclusively, removed on exit
trap 'rm -rf "$WORK"' EXIT
echo "dofs,newton_iterations,assembly_s_per_iteration,solve_s_per_iteration,plugin_share_of_assembly,nonlocal_s,assembly_ns_per_point,wall_s"
r=2
[ "$DIM" = 3 ] && r=1
while [ "$r" -le "$MAX" ]; do
  timeout "$TMO" "$EXE" "$SRC/short.prm" --json --set "Material/Card=$CARD" --set "Mesh/Adaptive=false" \
    --set "Mesh/Global refinements=$r" --set "Loading/Path=0, 0.2, 0.25" --set "Loading/Step=0.2" \
    --set "Regularisation/Type=$REG" --set "Geometry/Dimension=$DIM" --set "Output/VTU every=0" --set "Output/Plot=false" \
    --set "Newton/Tolerance=1e-8" --set "Newton/Max iterations=30" --set "Solver/Type=$SOLVER" \
    --set "Output/Directory=$WORK/out" 2>/dev/null >"$WORK/run.json" ||
    { echo "refinement $r: timeout or failure (limit ${TMO} s)"; break; }
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
