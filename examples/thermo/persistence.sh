#!/usr/bin/env bash
# Steered bending (docs/theory.md §4.5). First the chain whose stiffness is known by construction
# (angle harmonic, theta0 = 180 deg, K = 500 kcal/mol/rad^2: EI = 1721 kcal/mol*A for the printed ratio F L^3/(48 d), D67,
# on 4 beads, 1530 in the continuum limit), then the dissertation's protocol on the
# coarse-grained PP chain (4 beads, spring 10 kcal/mol/A^2, rates 0.01-0.1 A/fs).
set -euo pipefail
PNC=${PNC:-build/app/pnc}
OUT=${1:-out/thermo_persistence}
mkdir -p "$OUT"
"$PNC" thermo persistence --chain harmonic --supports roller --angle-k 500 --bond-k 300 --spring-k 100 \
  --pull-distance 3 --rates 0.0005,0.001,0.0015,0.002 --timestep 1 --hold-steps 1000 \
  --sample-every 2 --out "$OUT/harmonic" --resume --json > "$OUT/harmonic.json"
"$PNC" thermo persistence --chain pp --out "$OUT/pp" --resume --json > "$OUT/pp.json"
echo "results: $OUT/harmonic/persistence.h5, $OUT/pp/persistence.h5 (+ EI_vs_rate.png)"
