#!/bin/bash
# Wall times of a replica campaign (bench/campaign/replicas.json: a 300-bead glass, 4 replicas,
# cases 2 and 6, --jobs 2) on this machine, interleaved so that a change of the machine's load
# hits every variant alike (bench/README.md "Campaigns: local and Slurm executors"):
#   local     pnc characterize (local executor: the 4 equilibrations 2 at a time, 1 rank each)
#   base      the same recipe with PNC_BASE, a pnc without the plan of units (equilibrations one
#             after the other on 2 ranks, the default before D241); skipped when PNC_BASE is unset
#   base1     PNC_BASE with --equilibrate-ranks 1 (one after the other on 1 rank)
#   slurm     --executor slurm --wait on a one-node test cluster (tests/rve/slurm/start_cluster.sh)
# and, from the slurm runs' state files, the executor's overhead per unit: from the moment a unit
# could start (its job's submission, or the end of the last unit it needs) to the moment it
# started. Usage: bench_campaign.sh PNC [REPS] [OUTDIR]; env PNC_BASE=/path/to/older/pnc.
set -euo pipefail
pnc=$(realpath "${1:?usage: bench_campaign.sh PNC [REPS] [OUTDIR]}")
reps=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
out=${3:-$(mktemp -d "${TMPDIR:-/tmp}/pnc-bench-campaign.XXXXXX")}
mkdir -p "$out"
recipe="$here/replicas.json"
handle="$out/cluster.handle"
"$here/../../tests/rve/slurm/start_cluster.sh" "$handle" >&2
trap '"$here/../../tests/rve/slurm/stop_cluster.sh" "$handle" >&2' EXIT
export SLURM_CONF="$(head -1 "$handle")/slurm.conf"
export PNC_SLURM_POLL_SECONDS=1
{
  echo "date: $(date -u +%FT%TZ)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2-) x $(nproc)"
  echo "load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "pnc: $("$pnc" --version)"
  [ -n "${PNC_BASE:-}" ] && echo "base: $("$PNC_BASE" --version) ($PNC_BASE)"
} >"$out/machine.txt"
variants="local slurm"
[ -n "${PNC_BASE:-}" ] && variants="base base1 local slurm"
variants=${VARIANTS:-$variants} # e.g. VARIANTS="base1 local slurm"
: >"$out/times.txt"
for rep in $(seq 1 "$reps"); do
  for v in $variants; do
    dir="$out/$v-$rep"
    case $v in
    local) cmd=("$pnc" characterize "$recipe" --out "$dir" --no-plots) ;;
    base) cmd=("$PNC_BASE" characterize "$recipe" --out "$dir" --no-plots) ;;
    base1) cmd=("$PNC_BASE" characterize "$recipe" --out "$dir" --no-plots --equilibrate-ranks 1) ;;
    slurm) cmd=("$pnc" characterize "$recipe" --out "$dir" --no-plots --executor slurm --wait) ;;
    esac
    t0=$(date +%s.%N)
    rc=0
    "${cmd[@]}" >"$dir.json" 2>"$dir.err" || rc=$?
    t1=$(date +%s.%N)
    echo "$v $rep $(echo "$t1 - $t0" | bc) rc=$rc load=$(cut -d' ' -f1 /proc/loadavg)" | tee -a "$out/times.txt" >&2
  done
done
python3 "$here/analyze_campaign.py" "$out"
echo "results in $out" >&2
