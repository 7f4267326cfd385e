#!/usr/bin/env bash
# LAMMPS through pnc (supervised child, C library) vs the plain `lmp` binary: timesteps/s of
# the same input on the coarse-grained PP melt, 1500 and 12000 beads, on 1 and 2 MPI ranks
# (pnc on 2 ranks: its stage server under mpirun, decision D16). Prints a Markdown table.
# Usage: bench/rve/bench_rve.sh [PNC_EXE] [OUTDIR]
set -euo pipefail
PNC=$(realpath "${1:-build-rve/app/pnc}")
OUT=${2:-/tmp/pnc-bench-rve}
HERE=$(cd "$(dirname "$0")" && pwd)
STEPS=${STEPS:-3000}
mkdir -p "$OUT"
rate() { # steps/s from the last "Loop time of T on P procs for N steps" of a log
  awk '/^Loop time of/ {t=$4; n=$9} END {printf "%.0f", n/t}' "$1"
}
echo "| beads | runner | ranks | steps/s |"
echo "|---|---|---|---|"
for chains in 75 600; do
  beads=$((chains * 20))
  d="$OUT/b$beads"
  "$PNC" rve build --chains $chains --density 1.5 --seed 1 --out "$d" 2>/dev/null
  steps=$STEPS
  [ $beads -gt 5000 ] && steps=$((STEPS / 4))
  (cd "$d" && lmp -in "$HERE/bench.in" -var data rve.data -var ff forcefield.lmp \
     -var steps $steps -log lmp1.log -screen none -nocite)
  (cd "$d" && "$PNC" rve lammps "$HERE/bench.in" --var data=rve.data --var ff=forcefield.lmp \
     --var steps=$steps --log pnc1.log 2>/dev/null)
  (cd "$d" && mpirun --allow-run-as-root --oversubscribe -np 2 lmp -in "$HERE/bench.in" \
     -var data rve.data -var ff forcefield.lmp -var steps $steps -log lmp2.log -screen none \
     -nocite >/dev/null 2>&1) || true
  (cd "$d" && "$PNC" rve lammps "$HERE/bench.in" --var data=rve.data --var ff=forcefield.lmp \
     --var steps=$steps --log pnc2.log --ranks 2 2>/dev/null) || true
  r1=$(rate "$d/lmp1.log"); p1=$(rate "$d/pnc1.log")
  echo "| $beads | lmp | 1 | $r1 |"
  echo "| $beads | pnc rve lammps | 1 | $p1 (ratio $(awk -v a=$p1 -v b=$r1 'BEGIN{printf "%.3f", a/b}')) |"
  if [ -f "$d/lmp2.log" ]; then
    r2=$(rate "$d/lmp2.log")
    echo "| $beads | lmp (mpirun) | 2 | $r2 |"
    if [ -f "$d/pnc2.log" ]; then
      p2=$(rate "$d/pnc2.log")
      echo "| $beads | pnc rve lammps --ranks 2 | 2 | $p2 (ratio $(awk -v a=$p2 -v b=$r2 'BEGIN{printf "%.3f", a/b}')) |"
    fi
  fi
done
