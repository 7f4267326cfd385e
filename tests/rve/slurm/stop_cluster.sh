#!/bin/bash
# Stops the test cluster of start_cluster.sh HANDLE (its jobs, slurmd, slurmctld, munged, by
# the pid files under its directory) and removes the directory and HANDLE.
set -uo pipefail
handle=${1:?usage: stop_cluster.sh HANDLE}
[ -f "$handle" ] || exit 0
dir=$(head -1 "$handle")
case "$dir" in
*/pnc-slurm.*) ;;
*)
  echo "stop_cluster.sh: $handle does not name a test cluster directory: '$dir'" >&2
  exit 1
  ;;
esac
if [ -f "$dir/slurm.conf" ]; then
  SLURM_CONF="$dir/slurm.conf" scancel --user="$(id -un)" 2>/dev/null || true
fi
stop_pid_file() { # TERM, then KILL after 10 s
  local f=$1 pid
  [ -f "$f" ] || return 0
  pid=$(head -1 "$f")
  [ -n "$pid" ] || return 0
  kill "$pid" 2>/dev/null || return 0
  for _ in $(seq 1 100); do
    kill -0 "$pid" 2>/dev/null || return 0
    sleep 0.1
  done
  kill -9 "$pid" 2>/dev/null || true
}
stop_pid_file "$dir/run/slurmd.pid"
stop_pid_file "$dir/run/slurmctld.pid"
stop_pid_file "$dir/munge/munged.pid"
rm -rf "$dir"
rm -f "$handle"
echo "stop_cluster.sh: stopped and removed $dir"
