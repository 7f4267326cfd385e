#!/usr/bin/env bash
# Peer comparison: the same 2-D elastic problem in pnc's GIMP solver and in CB-Geo mpm.
#
#   bench/peer/cbgeo_compare.sh CBGEO_SRC [OUTDIR]
#
# CBGEO_SRC  a CB-Geo mpm source tree (for a bare git snapshot:
#            mkdir DIR && git --git-dir=REPO archive HEAD | tar -x -C DIR)
# OUTDIR     keeps CB-Geo's build (OUTDIR/cbgeo-build, reused by later runs), the run folders,
#            times.txt and summary.txt (default: a mktemp -d folder, removed at the end)
# Env: PNC (pnc executable, default <repo>/build/app/pnc), REPS (interleaved rounds, default 5),
#      JOBS (CB-Geo build jobs, default 2; the build runs under nice -n 10), CBGEO_BUILD (build
#      folder of CB-Geo, default OUTDIR/cbgeo-build; an existing one is reused), CBGEO_ELEMENTS
#      (CB-Geo's shape functions to run: "gimp" = ED2Q16G, "linear" = ED2Q4; default both).
#
# Without a source tree, or when CB-Geo does not configure or build, the script prints
# "skipped: ..." (naming the missing dependency when CMake names one) and exits 0.
# The problem: bench/peer/column_gravity.json (an elastic column on a fixed base settling under
# its own weight). CB-Geo gets the same grid, particles, law, time step and number of steps
# (bench/peer/peer_tool.py cbgeo-input); both results are checked against each other and the
# static solution (1 %), then the runs are timed in interleaved rounds (pnc, CB-Geo GIMP,
# CB-Geo linear; then the reverse order; REPS rounds): whole-process wall and CPU time
# (user + sys) per particle-step, median and range of the ratio CB-Geo / pnc per round. bench/README.md "Peer comparison: CB-Geo mpm" has the numbers.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
PNC=${PNC:-$ROOT/build/app/pnc}
REPS=${REPS:-5}
JOBS=${JOBS:-2}
ELEMENTS=${CBGEO_ELEMENTS:-gimp linear}
INPUT=$HERE/column_gravity.json
TOOL=$HERE/peer_tool.py
skip() {
  echo "skipped: $*"
  exit 0
}
for e in $ELEMENTS; do
  case $e in gimp | linear) ;; *) echo "cbgeo_compare.sh: CBGEO_ELEMENTS: '$e' is not gimp or linear" >&2; exit 2 ;; esac
done
for n in "$REPS" "$JOBS"; do
  case $n in '' | *[!0-9]* | 0) echo "cbgeo_compare.sh: REPS='$REPS', JOBS='$JOBS' must be positive integers" >&2; exit 2 ;; esac
done

src=${1:-}
[ -n "$src" ] || skip "no CB-Geo source tree; give the path of a CB-Geo mpm source tree" \
  "(bench/peer/cbgeo_compare.sh CBGEO_SRC [OUTDIR])"
[ -d "$src" ] || skip "$src is not a directory; give the path of a CB-Geo mpm source tree"
src=$(realpath "$src")
grep -qs 'project(mpm' "$src/CMakeLists.txt" ||
  skip "$src/CMakeLists.txt does not declare project(mpm); give the path of a CB-Geo mpm source tree"
[ -x "$PNC" ] || { echo "cbgeo_compare.sh: PNC=$PNC is not an executable (set PNC)" >&2; exit 2; }
for tool in cmake c++ python3 h5dump /usr/bin/time; do
  command -v "$tool" >/dev/null || skip "$tool not found (h5dump: apt-get install hdf5-tools)"
done

if [ -n "${2:-}" ]; then
  mkdir -p "$2"
  OUT=$(realpath "$2")
else
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
fi

# --- CB-Geo build: serial (no MPI, hence no KaHIP), no VTK/Partio/MKL, no unit tests ---
bdir=${CBGEO_BUILD:-$OUT/cbgeo-build}
mkdir -p "$bdir"
gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
[ -f "$bdir/CMakeCache.txt" ] && gen=()
if ! cmake -S "$src" -B "$bdir" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DMPM_BUILD_TESTING=OFF \
  -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON -DCMAKE_DISABLE_FIND_PACKAGE_VTK=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_Partio=ON -DCMAKE_DISABLE_FIND_PACKAGE_MKL=ON \
  >"$bdir/configure.log" 2>&1; then
  missing=$(grep -m1 -oE 'Could NOT find [A-Za-z0-9_]+( \(missing: [^)]*\))?|package configuration file provided by "[^"]+"' \
    "$bdir/configure.log" || true)
  skip "CB-Geo mpm did not configure (${missing:+missing dependency: $missing; }see $bdir/configure.log)" \
    "(Debian: apt-get install libboost-filesystem-dev libboost-system-dev libeigen3-dev libhdf5-dev)"
fi
echo "building CB-Geo mpm in $bdir (nice -n 10, $JOBS jobs; the first build takes long)" >&2
if ! nice -n 10 cmake --build "$bdir" -j "$JOBS" --target mpm >"$bdir/build.log" 2>&1; then
  skip "CB-Geo mpm did not build: $(grep -m1 -E 'error|Error' "$bdir/build.log" || echo "see $bdir/build.log")"
fi
MPM=$bdir/mpm

# --- inputs: pnc's JSON as is, CB-Geo's generated from it (one folder per element) ---
runs=$(mktemp -d "$OUT/runs.XXXXXX")
for e in $ELEMENTS; do
  python3 "$TOOL" cbgeo-input "$INPUT" "$runs/cbgeo-$e-input" "$e"
done
read -r particles steps < <(python3 -c 'import json,sys; p=json.load(open(sys.argv[1]));
b=p["bodies"][0]; s=p["grid"]["cell_size"]/p.get("particles_per_cell",2)
print(round((b["max"][0]-b["min"][0])/s)*round((b["max"][1]-b["min"][1])/s), p["time"]["max_steps"])' "$INPUT")

# run CODE REP: one timed run (CODE pnc or cbgeo-<element>); appends "rep code wall cpu load"
run() {
  local code=$1 rep=$2 d="$runs/$1_$2" wall user sys
  if [ "$code" = pnc ]; then
    /usr/bin/time -f "%e %U %S" -o "$d.time" "$PNC" gimp run "$INPUT" --out "$d" --threads 1 \
      --no-plot --quiet >"$d.log" 2>&1 || { echo "cbgeo_compare.sh: pnc failed, see $d.log" >&2; exit 1; }
  else
    cp -r "$runs/$code-input" "$d"
    (cd "$d" && OMP_NUM_THREADS=1 /usr/bin/time -f "%e %U %S" -o "$d.time" "$MPM" -f "$d/" \
      -i mpm.json -p 1 >"$d.log" 2>&1) || { echo "cbgeo_compare.sh: CB-Geo mpm failed, see $d.log" >&2; exit 1; }
  fi
  read -r wall user sys <"$d.time"
  echo "$rep $code $wall $(awk -v u="$user" -v s="$sys" 'BEGIN {printf "%.3f", u + s}')" \
    "$(cut -d' ' -f1 /proc/loadavg)" | tee -a "$runs/times.txt"
}

{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'); nproc $(nproc);" \
    "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); load $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# $("$PNC" --version | head -1); CB-Geo mpm from $src; REPS=$REPS"
  echo "# rep code wall_s cpu_s load1"
} | tee "$runs/times.txt"
codes="pnc"
for e in $ELEMENTS; do codes="$codes cbgeo-$e"; done
for rep in $(seq 1 "$REPS"); do
  order=$codes
  # shellcheck disable=SC2086 # codes: validated words, split on purpose
  [ $((rep % 2)) -eq 0 ] && order=$(printf '%s\n' $codes | tac | tr '\n' ' ') # A B C, C B A, ...
  for code in $order; do run "$code" "$rep"; done
done

# --- results of the first round (each CB-Geo variant against pnc), then the timings ---
python3 "$TOOL" pnc-result "$runs/pnc_1" >"$runs/pnc_result.json"
status=0
: >"$runs/summary.txt"
for e in $ELEMENTS; do
  python3 "$TOOL" cbgeo-result "$runs/cbgeo-${e}_1" >"$runs/cbgeo-${e}_result.json"
  echo "CB-Geo with the $e element:" >>"$runs/summary.txt"
  python3 "$TOOL" check "$INPUT" "$runs/pnc_result.json" "$runs/cbgeo-${e}_result.json" \
    >>"$runs/summary.txt" || status=1
done
python3 "$TOOL" summary "$runs/times.txt" "$particles" "$steps" >>"$runs/summary.txt"
cat "$runs/summary.txt"
[ -n "${2:-}" ] && echo "runs, times.txt and summary.txt in $runs"
exit $status
