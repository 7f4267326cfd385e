#!/usr/bin/env bash
# Short TI on the demo RVE: shows the pipeline, not converged physics (4000 + 4000 steps per
# lambda point instead of the dissertation's 60000 + 20000).
set -euo pipefail
PNC=${PNC:-build/app/pnc}
OUT=${1:-out/thermo_ti_quick}
mkdir -p "$(dirname "$OUT")"
"$PNC" thermo ti --demo --out "$OUT" --vol 0,0.005 --dev 0.005 \
  --equil-steps 4000 --prod-steps 4000 --jobs 2 --resume --json > "$OUT.json"
echo "summary: $OUT.json; results: $OUT/ti.h5; plots: $OUT/plots/"
