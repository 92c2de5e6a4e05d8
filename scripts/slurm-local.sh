#!/usr/bin/env bash
# A one-node Slurm on this machine, for CI's cluster stage (docs/cluster.md):
#
#   scripts/slurm-local.sh start DIR   munged, slurmctld and slurmd, state and logs in DIR;
#                                      waits until the node takes jobs
#   scripts/slurm-local.sh stop DIR    stops them (every daemon started with this DIR)
#   scripts/slurm-local.sh env DIR     prints the export that points sbatch & co. at it
#
# The node has this machine's CPUs (two here) as one node, one partition, cores as
# consumable resources (a one-CPU task per core at once), no accounting and no cgroups (a
# container has none to give).  Needs Debian's slurm-wlm and munge (scripts/install-deps.sh
# --slurm) and root: slurmd starts jobs as their users.
set -euo pipefail

cmd=${1:-}
dir=${2:-}
if [[ -z $cmd || -z $dir ]]; then
    echo "usage: $0 start|stop|env DIR" >&2
    exit 2
fi
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
conf="$dir/slurm.conf"

stop_pidfile() {
    local f=$1
    [[ -f $f ]] || return 0
    local pid
    pid=$(cat "$f" 2>/dev/null || true)
    if [[ -n $pid ]] && kill -0 "$pid" 2>/dev/null; then
        kill "$pid" 2>/dev/null || true
        for _ in $(seq 50); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.1
        done
        kill -9 "$pid" 2>/dev/null || true
    fi
    rm -f "$f"
}

case $cmd in
env)
    echo "export SLURM_CONF=$conf"
    ;;
stop)
    # the jobs first (slurmd's steps), then the daemons
    if [[ -f $conf && -f $dir/slurmctld.pid ]]; then
        SLURM_CONF=$conf timeout 10 scancel --full --quiet --user="$(id -un)" 2>/dev/null || true
        # until the jobs' processes are gone (slurmd kills them; KillWait is 5 s)
        for _ in $(seq 30); do
            [[ -z $(SLURM_CONF=$conf timeout 5 squeue -h -t R,CG 2>/dev/null) ]] && break
            sleep 0.5
        done
    fi
    stop_pidfile "$dir/slurmd.pid"
    stop_pidfile "$dir/slurmctld.pid"
    stop_pidfile "$dir/munged.pid"
    if [[ -f $dir/munge-dir ]]; then
        mdir=$(cat "$dir/munge-dir")
        [[ $mdir == /tmp/lumis-munge.* ]] && rm -rf "$mdir"
        rm -f "$dir/munge-dir"
    fi
    # a job step slurmd left (slurmstepd) must not outlive the cluster
    pkill -f "slurmstepd.*" 2>/dev/null || true
    echo "slurm-local: stopped (logs in $dir)"
    ;;
start)
    for b in munged slurmctld slurmd sbatch; do
        command -v "$b" >/dev/null || {
            echo "slurm-local: $b not found: scripts/install-deps.sh --slurm" >&2
            exit 1
        }
    done
    node=$(hostname -s)
    cpus=$(nproc)
    mem=$(awk '/MemTotal/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)
    mkdir -p "$dir/state" "$dir/spool"
    # munged runs as munge: its folder must be reachable by it whatever DIR's parents allow
    mdir=$(mktemp -d /tmp/lumis-munge.XXXXXX)
    chmod 755 "$mdir"
    chown munge:munge "$mdir"
    echo "$mdir" >"$dir/munge-dir"
    cat >"$conf" <<EOF
ClusterName=lumis-ci
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
CryptoType=crypto/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
SlurmdTimeout=60
InactiveLimit=0
KillWait=5
MinJobAge=3600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=ci Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
    # munged: its own socket and pid file in DIR, so a machine's own munge is untouched
    sock="$mdir/munge.socket"
    runuser -u munge -- munged --socket="$sock" --pid-file="$mdir/munged.pid" \
        --log-file="$mdir/munged.log" --seed-file="$mdir/seed" --force
    cp "$mdir/munged.pid" "$dir/munged.pid"
    # slurm's daemons and clients find munge's socket through AuthInfo
    sed -i "s|^AuthType=auth/munge|AuthType=auth/munge\nAuthInfo=socket=$sock|" "$conf"
    SLURM_CONF=$conf slurmctld
    SLURM_CONF=$conf slurmd
    for _ in $(seq 60); do
        state=$(SLURM_CONF=$conf sinfo -h -N -o '%t' 2>/dev/null | head -1 || true)
        case $state in idle | mix | alloc) break ;; esac
        sleep 0.5
    done
    if [[ ! $state =~ ^(idle|mix|alloc)$ ]]; then
        echo "slurm-local: the node did not come up (state '$state'); logs:" >&2
        tail -n 20 "$dir/slurmctld.log" "$dir/slurmd.log" >&2 || true
        exit 1
    fi
    echo "slurm-local: node $node with $cpus CPUs up; export SLURM_CONF=$conf"
    ;;
*)
    echo "usage: $0 start|stop|env DIR" >&2
    exit 2
    ;;
esac
