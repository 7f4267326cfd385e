#!/usr/bin/env bash
# Wall and CPU time of a default `pnc fit` (6 cases x 200 points, model pnc, figures and
# report included), two executables interleaved A/B/A/B... so that both see the same machine
# load; a third column times B with --no-plots (the fit alone). bench/README.md
# "pnc fit wall time" has the numbers measured with it.
#   bench/fit_wall_time.sh PNC_A PNC_B [RUNS=5]
# Prints one line per run: label, run, wall s, user+sys s (children included), load average;
# then the medians.
set -euo pipefail
a=$(realpath "$1") b=$(realpath "$2") runs=${3:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$b" synth --model pnc --out "$work/cases.h5" >/dev/null 2>&1
for i in $(seq 1 "$runs"); do
  for v in A B N; do
    d="$work/${v}_$i"
    mkdir "$d"
    case $v in A) exe=$a extra=() ;; B) exe=$b extra=() ;; N) exe=$b extra=(--no-plots) ;; esac
    (cd "$d" && /usr/bin/time -f "%e %U %S" -o time.txt "$exe" fit --data ../cases.h5 --model pnc \
      --out card.h5 "${extra[@]}" >/dev/null 2>err.txt) || true
    read -r wall user sys <"$d/time.txt"
    echo "$v $i $wall $(echo "$user + $sys" | bc) $(cut -d' ' -f1 /proc/loadavg)"
  done
done | tee "$work/all.txt"
median() { sort -n | awk '{ x[NR] = $1 } END { print (NR % 2 ? x[(NR + 1) / 2] : (x[NR / 2] + x[NR / 2 + 1]) / 2) }'; }
for v in A B N; do
  echo "$v median wall $(awk -v v=$v '$1 == v { print $3 }' "$work/all.txt" | median) s," \
    "cpu $(awk -v v=$v '$1 == v { print $4 }' "$work/all.txt" | median) s ($runs runs)"
done
