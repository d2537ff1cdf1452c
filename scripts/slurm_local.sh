#!/usr/bin/env bash
# A real single-node Slurm on this machine, as root: for trying `enact sweep --executor slurm`
# and for the sweep tests (docs/experiments.md, "Sweeps").
#   scripts/slurm_local.sh start [STATE_DIR]   writes STATE_DIR/slurm.conf (default
#                                              /tmp/enact-slurm), starts munged (a munge key made
#                                              when missing), slurmctld and slurmd; prints the
#                                              SLURM_CONF to export
#   scripts/slurm_local.sh stop [STATE_DIR]    stops the three by their pid files
# One node (localhost, this machine's CPUs), one partition `debug`, no accounting;
# proctrack/linuxproc and task/none (no cgroups needed). Needs slurm-wlm and munge
# (scripts/setup.sh).
set -euo pipefail
command="${1:-}"
state="$(realpath -m "${2:-${ENACT_SLURM_STATE:-/tmp/enact-slurm}}")"

usage() { echo "usage: $0 start|stop [STATE_DIR]" >&2; exit 2; }

stop_pid() {  # stop_pid FILE NAME: the process of FILE, TERM then KILL after 5 s
  local file="$1" name="$2" pid
  [[ -f "$file" ]] || return 0
  pid="$(cat "$file")"
  if [[ -n "$pid" ]] && kill -0 "$pid" 2>/dev/null; then
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null || true
    echo "slurm_local.sh: $name (pid $pid) stopped"
  fi
  rm -f "$file"
}

case "$command" in
  start)
    [[ $(id -u) -eq 0 ]] || { echo "slurm_local.sh: needs root (slurmd runs the jobs as their users)" >&2; exit 1; }
    for exe in munged slurmctld slurmd sbatch; do
      command -v "$exe" >/dev/null || { echo "slurm_local.sh: $exe is not installed: apt-get install slurm-wlm munge (scripts/setup.sh)" >&2; exit 1; }
    done
    mkdir -p "$state"/{spool,ctld,munge,log}
    chmod 700 "$state/munge"
    cpus="$(nproc)"
    # the node as slurmd sees it (its memory in MB)
    memory_mb="$(awk '/MemTotal/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)"
    cat > "$state/slurm.conf" <<EOF
# written by scripts/slurm_local.sh: a single-node Slurm for enact's sweeps
ClusterName=enact-local
SlurmctldHost=localhost
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldPort=${ENACT_SLURMCTLD_PORT:-6817}
SlurmdPort=${ENACT_SLURMD_PORT:-6818}
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/spool
SlurmctldLogFile=$state/log/slurmctld.log
SlurmdLogFile=$state/log/slurmd.log
SlurmUser=root
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=30
KillWait=5
InactiveLimit=0
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
    # munge: a key when there is none, its socket in the state folder
    key="$state/munge/munge.key"
    [[ -f "$key" ]] || { dd if=/dev/urandom of="$key" bs=1 count=1024 status=none; chmod 400 "$key"; }
    socket="$state/munge/munge.socket"
    if ! { [[ -f "$state/munged.pid" ]] && kill -0 "$(cat "$state/munged.pid")" 2>/dev/null; }; then
      munged --force --key-file="$key" --socket="$socket" --pid-file="$state/munged.pid" --log-file="$state/log/munged.log" --seed-file="$state/munge/munge.seed"
    fi
    # Slurm's munge plugin finds the socket through the configuration
    echo "AuthInfo=socket=$socket" >> "$state/slurm.conf"
    export SLURM_CONF="$state/slurm.conf"
    if ! { [[ -f "$state/slurmctld.pid" ]] && kill -0 "$(cat "$state/slurmctld.pid")" 2>/dev/null; }; then slurmctld -f "$SLURM_CONF" -i; fi
    if ! { [[ -f "$state/slurmd.pid" ]] && kill -0 "$(cat "$state/slurmd.pid")" 2>/dev/null; }; then slurmd -f "$SLURM_CONF"; fi
    # ready: the node idle in the partition
    for _ in $(seq 100); do
      if sinfo -h -N -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
        echo "slurm_local.sh: Slurm is up (node localhost, $cpus CPUs, partition debug); state in $state"
        echo "export SLURM_CONF=$SLURM_CONF"
        exit 0
      fi
      sleep 0.2
    done
    echo "slurm_local.sh: Slurm did not become ready in 20 s; logs in $state/log (stop it: $0 stop $state)" >&2
    exit 1
    ;;
  stop)
    stop_pid "$state/slurmd.pid" slurmd
    stop_pid "$state/slurmctld.pid" slurmctld
    stop_pid "$state/munged.pid" munged
    ;;
  *) usage ;;
esac
