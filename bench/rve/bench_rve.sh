#!/usr/bin/env bash
# LAMMPS through pnc (supervised child, C library) vs the plain `lmp` binary: timesteps/s of
# the same input on the coarse-grained PP melt, 1500 and 12000 beads, on 1 and 2 MPI ranks
# (pnc on 2 ranks: its stage server under mpirun, decision D16).
#
# Every comparison is interleaved (A B B A A B ...: A = lmp, B = pnc) and repeated REPS times,
# so that both runners see the same machine load; the ratio pnc/lmp of steps/s is taken per
# repetition (the A and B of one pair) and reported as median and range. The whole-process
# CPU time (user + sys of the process and its children, /usr/bin/time) is reported too: on a
# shared machine it is steadier than wall time.
#
# Usage: bench/rve/bench_rve.sh [PNC_EXE] [OUTDIR] [REPS]
#   PNC_EXE  default build-rve/app/pnc
#   OUTDIR   keeps the run folders, logs and runs.txt (default: a mktemp -d folder, removed)
#   REPS     repetitions per (size, ranks) (default: env REPS, else 5)
# Env: STEPS (timed steps at 1500 beads, default 3000; 12000 beads run STEPS/4), WARMUP
#   (untimed Langevin steps before them, default 1000; 12000 beads run WARMUP/4).
# Prints one line per run, then a Markdown table of the ratios.
set -euo pipefail
PNC=$(realpath "${1:-build-rve/app/pnc}")
REPS=${3:-${REPS:-5}}
STEPS=${STEPS:-3000}
WARMUP=${WARMUP:-1000}
HERE=$(cd "$(dirname "$0")" && pwd)
case $REPS in '' | *[!0-9]*) echo "bench_rve.sh: REPS='$REPS' must be a positive integer" >&2; exit 2 ;; esac
for n in "$STEPS" "$WARMUP"; do
  case $n in '' | *[!0-9]*) echo "bench_rve.sh: STEPS='$STEPS', WARMUP='$WARMUP' must be integers" >&2; exit 2 ;; esac
done
if [ -n "${2:-}" ]; then
  mkdir -p "$2"
  OUT=$(mktemp -d "$(realpath "$2")/bench-rve.XXXXXX")
else
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
fi
for exe in "$PNC" /usr/bin/time; do
  [ -x "$exe" ] || { echo "bench_rve.sh: $exe: not an executable" >&2; exit 2; }
done
command -v lmp >/dev/null || { echo "bench_rve.sh: lmp not on PATH" >&2; exit 2; }

rate() { # steps/s from the last "Loop time of T on P procs for N steps" of a log
  awk '/^Loop time of/ {t=$4; n=$9} END {if (t > 0) printf "%.2f", n/t; else print "nan"}' "$1"
}
# run_one DIR VARIANT RANKS STEPS WARMUP TAG: one timed run; prints "steps/s wall cpu" or "nan nan nan"
run_one() {
  local d=$1 v=$2 ranks=$3 steps=$4 warmup=$5 tag=$6 log cmd
  log="$tag.log"
  if [ "$v" = lmp ]; then
    cmd=(lmp -in "$HERE/bench.in" -var data rve.data -var ff forcefield.lmp -var steps "$steps"
      -var warmup "$warmup" -log "$log" -screen none -nocite)
    [ "$ranks" -gt 1 ] && cmd=(mpirun --allow-run-as-root --oversubscribe -np "$ranks" "${cmd[@]}")
  else
    cmd=("$PNC" rve lammps "$HERE/bench.in" --var data=rve.data --var ff=forcefield.lmp
      --var "steps=$steps" --var "warmup=$warmup" --log "$log" --ranks "$ranks")
  fi
  if (cd "$d" && /usr/bin/time -f "%e %U %S" -o "$tag.time" "${cmd[@]}" >"$tag.out" 2>&1); then
    local wall user sys
    read -r wall user sys <"$d/$tag.time"
    echo "$(rate "$d/$log") $wall $(awk -v u="$user" -v s="$sys" 'BEGIN {printf "%.2f", u + s}')"
  else
    echo "bench_rve.sh: $tag failed, see $d/$tag.out" >&2
    echo "nan nan nan"
  fi
}

{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'); nproc $(nproc);" \
    "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); REPS=$REPS STEPS=$STEPS WARMUP=$WARMUP"
  echo "# $("$PNC" --version 2>/dev/null | head -1); $(lmp -h 2>/dev/null | grep -m1 'Large-scale' || true)"
} | tee "$OUT/machine.txt"
echo "beads ranks rep variant steps_per_s wall_s cpu_s load1" | tee "$OUT/runs.txt"
for chains in 75 600; do
  beads=$((chains * 20))
  d="$OUT/b$beads"
  "$PNC" rve build --chains $chains --density 1.5 --seed 1 --out "$d" >/dev/null 2>&1
  steps=$STEPS warmup=$WARMUP
  [ $beads -gt 5000 ] && steps=$((STEPS / 4)) warmup=$((WARMUP / 4))
  for ranks in 1 2; do
    for rep in $(seq 1 "$REPS"); do
      order="lmp pnc"
      [ $((rep % 2)) -eq 0 ] && order="pnc lmp" # A B, B A, A B, ...
      for v in $order; do
        res=$(run_one "$d" "$v" "$ranks" "$steps" "$warmup" "${v}_r${ranks}_$rep")
        echo "$beads $ranks $rep $v $res $(cut -d' ' -f1 /proc/loadavg)" | tee -a "$OUT/runs.txt"
      done
    done
  done
done

# Ratios per pair, then median and range per (beads, ranks).
python3 - "$OUT/runs.txt" <<'EOF' | tee "$OUT/summary.md"
import math, statistics, sys
runs = {}
for line in open(sys.argv[1]).read().splitlines()[1:]:
    b, r, rep, v, sps, wall, cpu, load = line.split()
    runs[(int(b), int(r), int(rep), v)] = (float(sps), float(wall), float(cpu), float(load))
def fmt(xs, f="{:.3f}"):
    xs = [x for x in xs if math.isfinite(x)]
    if not xs:
        return "n/a"
    return (f + " ({}–{})").format(statistics.median(xs), f.format(min(xs)), f.format(max(xs)))
print()
print("| beads | ranks | pairs | lmp steps/s | pnc steps/s | ratio pnc/lmp steps/s"
      " | lmp CPU s | pnc CPU s | ratio pnc/lmp CPU | load avg |")
print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
for b, r in sorted({(k[0], k[1]) for k in runs}):
    reps = sorted({k[2] for k in runs if k[:2] == (b, r)})
    pairs = [(runs[(b, r, i, "lmp")], runs[(b, r, i, "pnc")]) for i in reps
             if (b, r, i, "lmp") in runs and (b, r, i, "pnc") in runs]
    rs = [p[0] / a[0] for a, p in pairs if a[0] > 0]
    rc = [p[2] / a[2] for a, p in pairs if a[2] > 0]
    loads = [x[3] for a, p in pairs for x in (a, p)]
    print(f"| {b} | {r} | {len(pairs)} | {fmt([a[0] for a, _ in pairs], '{:.0f}')}"
          f" | {fmt([p[0] for _, p in pairs], '{:.0f}')} | {fmt(rs)}"
          f" | {fmt([a[2] for a, _ in pairs], '{:.1f}')} | {fmt([p[2] for _, p in pairs], '{:.1f}')}"
          f" | {fmt(rc)} | {min(loads):.1f}–{max(loads):.1f} |")
print()
print("Medians with (min–max) over the pairs; a ratio is taken within one interleaved pair."
      " CPU = user + sys of the whole process and its children (build of the data excluded;"
      " the minimisation and the warm-up run of bench.in included).")
EOF
[ -n "${2:-}" ] && echo "runs, logs and summary.md in $OUT"
exit 0
