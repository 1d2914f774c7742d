#!/usr/bin/env bash
# A private single-node Slurm on this machine, for testing `texsim sweep --slurm` end to end:
# munged, slurmctld and slurmd with their key, configuration, state and logs in DIR (nothing
# outside DIR is touched; ports 16817/16818). Debian packages: slurm-wlm, munge.
#   scripts/slurm-local.sh start DIR   start and wait until the node is idle; then
#                                      `export SLURM_CONF=DIR/slurm.conf` and use sbatch/squeue
#   scripts/slurm-local.sh stop DIR    stop the three daemons
# `start` exits 77 with the reason on stderr when Slurm cannot run here (not installed, not
# root, a daemon that does not come up), so tests can skip.
set -euo pipefail
cmd=${1:-}
dir=${2:-}
[ -n "$cmd" ] && [ -n "$dir" ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }
skip() { echo "slurm-local: $*" >&2; exit 77; }

stop() {  # SIGTERM each daemon, then wait (up to 10 s) until they are gone and the ports free
  local pids=()
  for p in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
    [ -f "$p" ] && pids+=("$(cat "$p")")
  done
  [ ${#pids[@]} -gt 0 ] || return 0
  kill "${pids[@]}" 2> /dev/null || true
  for _ in $(seq 40); do
    kill -0 "${pids[@]}" 2> /dev/null || return 0
    sleep 0.25
  done
}
if [ "$cmd" = stop ]; then stop; exit 0; fi
[ "$cmd" = start ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

for tool in munged slurmctld slurmd sbatch sinfo; do
  command -v "$tool" > /dev/null || skip "$tool not found (apt-get install slurm-wlm munge)"
done
[ "$(id -u)" = 0 ] || skip "the daemons run as root here (SlurmUser=root); not root"
mkdir -p "$dir/state" "$dir/spool" "$dir/log" "$dir/munge"
dir=$(realpath "$dir")
chmod 755 "$dir" "$dir/munge"  # munged: the socket's directory must be searchable by all
head -c 1024 /dev/urandom > "$dir/munge/munge.key"
chmod 400 "$dir/munge/munge.key"
munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/sock" \
  --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
  --seed-file="$dir/munge/seed" || skip "munged did not start (see $dir/munge/munged.log)"
host=$(hostname -s)
cat > "$dir/slurm.conf" << CONF
ClusterName=texsim
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/sock
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"
slurmctld || { stop; skip "slurmctld did not start (see $dir/log/slurmctld.log)"; }
slurmd || { stop; skip "slurmd did not start (see $dir/log/slurmd.log)"; }
for _ in $(seq 40); do
  if sinfo -h -o %T 2> /dev/null | grep -qx idle; then exit 0; fi
  sleep 0.5
done
stop
skip "the node did not become idle in 20 s (see $dir/log/)"
