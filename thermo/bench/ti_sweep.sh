#!/usr/bin/env bash
# Wall time of the default TI sweep on the demo RVE (docs/thermo.md "Speed"): builds and
# equilibrates the demo RVE (600 beads, rve/ API), then runs `pnc thermo ti` with the
# dissertation's defaults (9 deformation states x 3 Gauss points, 60000 + 20000 steps of
# 0.5 fs per point, dH/dlambda every 100 steps (D64)), 2 points at a time on 2 cores.
# usage: thermo/bench/ti_sweep.sh [PNC_EXE] [OUT_DIR]
set -euo pipefail
PNC=${1:-build/app/pnc}
OUT=${2:-out/bench_ti_sweep}
mkdir -p "$OUT"
start=$(date +%s)
"$PNC" thermo ti --demo --out "$OUT" --jobs 2 --resume --json > "$OUT/summary.json" 2> "$OUT/stderr.txt"
end=$(date +%s)
echo "default TI sweep on the demo RVE: $((end - start)) s wall (build + equilibration + 27 lambda points, --jobs 2)"
grep -E "equilibrate/|wall time" "$OUT/stderr.txt" || true
