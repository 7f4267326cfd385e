#!/bin/bash
# Starts a one-node Slurm cluster on localhost for the tests of the Slurm executor
# (docs/cluster.md): munged with a key made for the test, slurmctld and slurmd (2 CPUs,
# select/cons_tres, proctrack/linuxproc, no cgroups), every file under a fresh temporary
# directory. Usage: start_cluster.sh HANDLE -- writes the directory's path to the file HANDLE;
# the cluster's slurm.conf is <dir>/slurm.conf (export SLURM_CONF=<dir>/slurm.conf to use it).
# stop_cluster.sh HANDLE stops it and removes the directory. Runs as root (CI) or as a user
# (then the daemons run as that user). Exits non-zero, saying why, when the cluster does not
# come up: the tests that need it then fail with that reason.
set -euo pipefail
handle=${1:?usage: start_cluster.sh HANDLE}
for p in munged slurmctld slurmd sinfo sbatch; do
  command -v "$p" >/dev/null 2>&1 || {
    echo "start_cluster.sh: $p not found: install the Debian packages slurm-wlm and munge" >&2
    exit 1
  }
done
if [ -f "$handle" ]; then # a cluster of an earlier run that was not stopped
  "$(dirname "$0")/stop_cluster.sh" "$handle" || true
fi
dir=$(mktemp -d "${TMPDIR:-/tmp}/pnc-slurm.XXXXXX")
chmod 755 "$dir"
printf '%s\n' "$dir" >"$handle"
mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log" "$dir/run"
chmod 700 "$dir/munge"
user=$(id -un)
host=$(hostname -s)

# a munge key for this cluster only
dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$dir/munge/munge.key"
munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
  --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
  --seed-file="$dir/munge/munged.seed" || {
  echo "start_cluster.sh: munged did not start:" >&2
  cat "$dir/munge/munged.log" >&2 || true
  exit 1
}

# two free TCP ports on localhost
read -r port_ctld port_d < <(python3 - <<'PY'
import socket
s = [socket.socket() for _ in range(2)]
for x in s:
    x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])
PY
)

cat >"$dir/slurm.conf" <<CONF
# one-node test cluster written by tests/rve/slurm/start_cluster.sh
ClusterName=pnctest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$port_ctld
SlurmdPort=$port_d
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmdParameters=config_overrides
ReturnToService=2
MpiDefault=none
SchedulerParameters=sched_interval=1
MinJobAge=600
KillWait=10
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 Sockets=1 CoresPerSocket=2 ThreadsPerCore=1 State=UNKNOWN
PartitionName=pnctest Nodes=ALL Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
CONF
export SLURM_CONF="$dir/slurm.conf"
slurmctld -c -f "$SLURM_CONF" || {
  echo "start_cluster.sh: slurmctld did not start:" >&2
  tail -20 "$dir/log/slurmctld.log" >&2 || true
  exit 1
}
slurmd -f "$SLURM_CONF" -N "$host" || {
  echo "start_cluster.sh: slurmd did not start:" >&2
  tail -20 "$dir/log/slurmd.log" >&2 || true
  exit 1
}
for _ in $(seq 1 60); do
  state=$(sinfo -h -o %T 2>/dev/null | head -1 || true)
  case "$state" in
  idle*|mix*|alloc*)
    echo "start_cluster.sh: cluster up in $dir (node $host: $state; SLURM_CONF=$SLURM_CONF)"
    exit 0
    ;;
  esac
  sleep 0.5
done
echo "start_cluster.sh: the node did not become idle within 30 s (state '${state:-none}'):" >&2
tail -20 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 || true
exit 1
