#!/bin/sh
# Instructions per evaluation of bench_batch's three variants (reference sigma = C eps, batch,
# single), counted by callgrind between client requests: for machines where `perf stat` has no
# hardware counters (a VM). bench/README.md "Batched entry".
#   bench/batch_instructions.sh BUILD_DIR [SCENARIO...]   (default: pnc_3d pnc_plane pp_3d)
set -eu
build=${1:?usage: batch_instructions.sh BUILD_DIR [SCENARIO...]}
shift
[ $# -gt 0 ] || set -- pnc_3d pnc_plane pp_3d
points=1024
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for s in "$@"; do
  valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$dir/cg.$s.%p" \
    "$build/bench/bench_batch" --callgrind --points "$points" --scenario "$s" >/dev/null 2>&1
done
for f in "$dir"/cg.*.*.*; do
  tag=$(sed -n 's/^desc: Trigger: Client Request: //p' "$f")
  total=$(sed -n 's/^totals: //p' "$f")
  printf '%-40s %8.0f instructions/eval\n' "$tag" "$(echo "$total / $points" | bc -l)"
done | sort
