#!/usr/bin/env bash
# The dissertation's TI sweep (docs/theory.md §4.1-4.4; its published parameter table) on the equilibrated RVE of a
# `pnc characterize` run (pure polymer).
set -euo pipefail
PNC=${PNC:-build/app/pnc}
CHAR=${1:?usage: ti_from_characterize.sh CHARACTERIZE_OUT_DIR [OUT]}
OUT=${2:-$CHAR/thermo_ti}
"$PNC" thermo ti --from "$CHAR" --out "$OUT" --jobs 2 --resume --json > "$OUT.json"
echo "summary: $OUT.json; results: $OUT/ti.h5; plots: $OUT/plots/"
