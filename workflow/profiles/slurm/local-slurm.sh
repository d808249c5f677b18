#!/usr/bin/env bash
# A one-node SLURM cluster on this host, for the tests and for trying the profile without a cluster.
#
#   workflow/profiles/slurm/local-slurm.sh install     # apt-get install slurm-wlm munge (root)
#   workflow/profiles/slurm/local-slurm.sh start DIR   # prints "export SLURM_CONF=DIR/slurm.conf"
#   workflow/profiles/slurm/local-slurm.sh stop DIR
#
# Needs root and Debian's slurm-wlm and munge (`install`; .ci/run runs it).  Everything it
# makes lives in DIR: a generated munge key, a private munged (run as the munge user, its own
# socket), slurm.conf for one node named after this host, slurmctld and slurmd (as root), their
# logs and state.  The daemons listen on free ports found at start; `start` returns once `sinfo`
# shows the node idle (or fails with the daemons' logs).  `stop` ends only the daemons whose pid
# files are in DIR.  The commands see this cluster through SLURM_CONF=DIR/slurm.conf, and, if the
# host has no /etc/slurm/slurm.conf, through a link made there (removed by `stop`): Snakemake's
# job step (snakemake-executor-plugin-slurm-jobstep) drops SLURM_* variables, SLURM_CONF too,
# before its inner srun, which then reads SLURM's default path.
set -euo pipefail

usage() { echo "usage: $0 install | start DIR | stop DIR" >&2; exit 2; }

install() {
    command -v slurmctld >/dev/null && command -v munged >/dev/null && return 0
    [[ $(id -u) -eq 0 ]] || { echo "local-slurm: installing slurm-wlm and munge needs root" >&2; exit 3; }
    command -v apt-get >/dev/null || { echo "local-slurm: no apt-get to install slurm-wlm and munge" >&2; exit 3; }
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge >/dev/null
}

[[ ${1:-} == install && $# -eq 1 ]] && { install; exit 0; }
[[ $# -eq 2 ]] || usage
action=$1
dir=$(realpath -m "$2")

ETC=/etc/slurm/slurm.conf

stop() {
    [[ -L $ETC && $(readlink "$ETC") == "$dir/slurm.conf" ]] && rm -f "$ETC"
    for name in slurmd slurmctld munged; do
        pidfile="$dir/run/$name.pid"
        [[ -f $pidfile ]] || continue
        pid=$(cat "$pidfile")
        if kill -0 "$pid" 2>/dev/null; then
            kill -TERM "$pid"
            for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
            kill -0 "$pid" 2>/dev/null && kill -KILL "$pid"
        fi
        rm -f "$pidfile"
    done
}

fail() {
    echo "local-slurm: $1" >&2
    for log in "$dir"/log/*.log; do [[ -f $log ]] && { echo "--- $log" >&2; tail -n 20 "$log" >&2; }; done
    stop
    exit 1
}

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

start() {
    [[ $(id -u) -eq 0 ]] || { echo "local-slurm: needs root (slurmd runs jobs as their users)" >&2; exit 3; }
    for cmd in slurmctld slurmd munged mungekey sinfo; do
        command -v "$cmd" >/dev/null || { echo "local-slurm: $cmd not found (apt-get install slurm-wlm munge)" >&2; exit 3; }
    done
    id munge >/dev/null 2>&1 || { echo "local-slurm: no munge user (apt-get install munge)" >&2; exit 3; }
    mkdir -p "$dir"/{run,log,state,spool,munge,munge-key}
    runuser -u munge -- test -x "$dir" || { echo "local-slurm: the munge user cannot enter $dir (a private parent folder?)" >&2; exit 3; }
    chmod 755 "$dir" "$dir/run" "$dir/munge"

    # munge: a key made now (private folder), a munged of our own with its socket in a folder all can enter
    chown munge:munge "$dir/munge" "$dir/munge-key"
    chmod 700 "$dir/munge-key"
    rm -f "$dir/munge-key/munge.key"
    mungekey --create --keyfile="$dir/munge-key/munge.key" >/dev/null
    chown munge:munge "$dir/munge-key/munge.key"
    touch "$dir/run/munged.pid" "$dir/log/munged.log"
    chown munge:munge "$dir/run/munged.pid" "$dir/log/munged.log"
    runuser -u munge -- munged --socket="$dir/munge/munge.socket" --key-file="$dir/munge-key/munge.key" \
        --pid-file="$dir/run/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge-key/munge.seed" \
        || fail "munged did not start"

    local host cpus mem ctld_port d_port
    host=$(hostname -s)
    cpus=$(nproc)
    mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 * 9 / 10 ))  # MB, a margin for the system
    ctld_port=$(free_port)
    d_port=$(free_port)
    cat > "$dir/slurm.conf" <<EOF
# one node: $host (written by workflow/profiles/slurm/local-slurm.sh)
ClusterName=noslipsim
SlurmctldHost=$host
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/%n
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
# no cgroups in a container: track job processes by parent pid, bind no tasks
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
SchedulerType=sched/backfill
ReturnToService=2
# no accounting database (squeue, not sacct, reports job states)
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
MinJobAge=300
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
# short test jobs share the cores (up to 4 per core), as many at once as Snakemake submits
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=FORCE:4
EOF
    export SLURM_CONF="$dir/slurm.conf"
    if [[ ! -e $ETC || -L $ETC && ! -e $(readlink "$ETC") ]]; then
        mkdir -p "$(dirname "$ETC")" && ln -sfn "$SLURM_CONF" "$ETC"
    elif [[ $(readlink "$ETC") != "$SLURM_CONF" ]]; then
        echo "local-slurm: $ETC belongs to another cluster: srun inside Snakemake's SLURM jobs will talk to it" >&2
    fi
    slurmctld -f "$SLURM_CONF" -i || fail "slurmctld did not start"
    slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
    for _ in $(seq 150); do
        state=$(sinfo -h -N -o %t 2>/dev/null || true)
        [[ $state == idle ]] && { echo "export SLURM_CONF=$SLURM_CONF"; return 0; }
        sleep 0.2
    done
    fail "the node is not idle after 30 s (sinfo: ${state:-no answer})"
}

case $action in
    start) start ;;
    stop) stop ;;
    *) usage ;;
esac
