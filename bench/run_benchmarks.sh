#!/usr/bin/env bash
# Build the benchmarks (Release) and run them; see bench/README.md.
#
#   bench/run_benchmarks.sh [OUTDIR]
#
# OUTDIR (default: bench-results/<UTC date-time> under the build directory) receives
#   bench_ndm.json, bench_fit.json   Google Benchmark JSON (every repetition + aggregates)
#   bench_ndm.txt,  bench_fit.txt    the console tables
#   machine.txt                      date, CPU model, core count, load, git revision
#   summary.txt                      medians as ratios: kernel vs the sigma = C eps reference
#                                    loop and vs the 5 M eval/s goal; fit time vs 0.2 s
#                                    (needs python3)
# Environment:
#   BUILD_DIR   build directory (default: <repo>/build-bench)
#   REPS        repetitions per benchmark (default 5; the summary uses medians)
#   MIN_TIME    --benchmark_min_time per repetition in seconds (default 0.5)
#   FILTER      --benchmark_filter regex applied to both binaries (default: all)
#   CMAKE_ARGS  extra configure arguments (e.g. -DPNC_WITH_LAMMPS=OFF)
#   SKIP_BUILD  set to 1 to use the existing binaries
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build-bench}"
REPS="${REPS:-5}"
MIN_TIME="${MIN_TIME:-0.5}"
FILTER="${FILTER:-.}"
OUT="${1:-$BUILD_DIR/bench-results/$(date -u +%Y%m%dT%H%M%SZ)}"

if [[ "${SKIP_BUILD:-0}" != 1 ]]; then
  # shellcheck disable=SC2086 # CMAKE_ARGS is a list of arguments
  cmake -S "$REPO" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPNC_BUILD_BENCH=ON \
    -DPNC_BUILD_TESTS=OFF -DPNC_WITH_DEALII=OFF ${CMAKE_ARGS:-}
  cmake --build "$BUILD_DIR" -j"$(nproc)" --target bench_ndm bench_fit
fi
mkdir -p "$OUT"

{
  echo "date (UTC):  $(date -u '+%Y-%m-%d %H:%M:%S')"
  echo "cpu:         $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
  echo "cores:       $(nproc)"
  echo "load:        $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "git:         $(git -C "$REPO" rev-parse --short HEAD 2>/dev/null || echo unknown)$(
    git -C "$REPO" diff --quiet HEAD -- damage 2>/dev/null || echo ' (damage/ modified)')"
  echo "build:       $(grep -m1 '^CMAKE_BUILD_TYPE' "$BUILD_DIR/CMakeCache.txt" | cut -d= -f2)," \
    "$(grep -m1 '^CMAKE_CXX_COMPILER:' "$BUILD_DIR/CMakeCache.txt" | cut -d= -f2)"
  echo "repetitions: $REPS x min $MIN_TIME s"
} | tee "$OUT/machine.txt"

for b in bench_ndm bench_fit; do
  echo
  "$BUILD_DIR/bench/$b" --benchmark_format=console --benchmark_out="$OUT/$b.json" \
    --benchmark_out_format=json --benchmark_repetitions="$REPS" \
    --benchmark_min_time="$MIN_TIME" --benchmark_display_aggregates_only=true \
    --benchmark_filter="$FILTER" | tee "$OUT/$b.txt"
done

if command -v python3 >/dev/null; then
  echo
  python3 - "$OUT" <<'PY' | tee "$OUT/summary.txt"
import json, sys, os
out = sys.argv[1]
def medians(name):
    path = os.path.join(out, name)
    if not os.path.exists(path):
        return {}
    runs = json.load(open(path))["benchmarks"]
    med = {r["run_name"]: r for r in runs if r.get("aggregate_name") == "median"}
    one = {r["run_name"]: r for r in runs if r.get("run_type") == "iteration"}
    return {name: med.get(name, r) for name, r in one.items()}  # REPS=1: the single run
ndm, fit = medians("bench_ndm.json"), medians("bench_fit.json")
ref = ndm.get("reference/C_eps/stress", {}).get("time_per_eval")
ref_t = ndm.get("reference/C_eps/stress+tangent", {}).get("time_per_eval")
if ndm:
    print(f"{'NDM kernel (medians)':42s} {'ns/eval':>8s} {'M eval/s':>9s} {'x ref':>7s}"
          "  5 M/s goal (stress+tangent)")
for name, r in ndm.items():
    ns = r["time_per_eval"] * 1e9
    rate = r["items_per_second"] / 1e6
    base = ref_t if name.endswith("stress+tangent") else ref
    ratio = f"{r['time_per_eval'] / base:7.1f}" if base else "      -"
    goal = ""
    if name.startswith("ndm/") and name.endswith("stress+tangent"):
        goal = "met" if rate >= 5.0 else f"MISSED ({rate / 5.0:.0%} of goal)"
    print(f"  {name:40s} {ns:8.1f} {rate:9.2f} {ratio}  {goal}")
if fit:
    print(f"\n{'fit_ndm wall time (medians)':42s} {'ms':>8s} {'Ceres it':>9s} {'solve ms':>8s}"
          "  0.2 s goal (pnc)")
for name, r in fit.items():
    ms = r["real_time"] if r["time_unit"] == "ms" else r["real_time"] * 1e-6
    goal = ""
    if name.startswith("fit/pnc"):
        goal = f"{ms / 200:.2f} x goal, " + ("met" if ms < 200 else "MISSED")
    print(f"  {name:40s} {ms:8.1f} {r.get('ceres_iter', float('nan')):9.0f}"
          f" {r.get('solve_s', float('nan')) * 1e3:8.1f}  {goal}")
PY
fi
echo
echo "results in $OUT"
