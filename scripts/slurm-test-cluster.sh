#!/usr/bin/env bash
# Starts a real single-node Slurm on this machine for the test of `packbed slurm`
# (crates/packbed-cli/tests/integration/slurm.rs), or reuses the one it started
# before. Needs root and Debian's `slurm-wlm` and `munge` packages.
#
#   scripts/slurm-test-cluster.sh [STATE_DIR]      (default /tmp/packbed-slurm)
#
# Prints `SLURM_CONF=STATE_DIR/slurm.conf` on its last line: Slurm's clients
# (sbatch, squeue, scancel, sinfo) find this cluster through that variable.
# Exit codes: 0 cluster up; 3 cannot be started here (not root, a program
# missing: the reason on stderr); 1 start-up failed (the daemons' logs are in
# STATE_DIR).
#
# What it takes in a container (learnt on Debian 12, Slurm 22.05):
# - munge: the package's postinst creates /etc/munge/munge.key (owner munge,
#   mode 0400); without it `mungekey --create` makes one. munged runs as the
#   `munge` user and needs /run/munge owned by it.
# - no systemd and cgroups Slurm must not touch: ProctrackType
#   proctrack/linuxproc, TaskPlugin task/none, JobAcctGatherType none. Slurm
#   22.05 then starts without a cgroup.conf (it knows no CgroupPlugin=disabled:
#   "cannot find cgroup plugin for disabled"); should slurmd fail to start
#   anyway (newer Slurm, other cgroup layouts), a cgroup.conf with
#   CgroupPlugin=disabled is written beside slurm.conf and slurmd started again.
# - `MpiDefault=none` still logs "can not load PMIx library" errors: harmless.
# - the first `sinfo` may show the node `unknown` or `down` for a second or two.
# - NodeName and SlurmctldHost must be `hostname -s`; CPUs the real core
#   count, RealMemory below the machine's (slurmd drains a node that claims more).
# - no slurmdbd: AccountingStorageType none, so `sacct` does not work;
#   `packbed slurm --wait` does not need it.
# - everything Slurm writes (state, spool, logs, pid files) goes under STATE_DIR,
#   and the daemons run as root (SlurmUser=root, SlurmdUser=root).
set -euo pipefail

state="${1:-/tmp/packbed-slurm}"
conf="$state/slurm.conf"
export SLURM_CONF="$conf"

cannot() { echo "slurm-test-cluster: $*" >&2; exit 3; }

[ "$(id -u)" = 0 ] || cannot "not root (the daemons need root)"
for p in munged slurmctld slurmd sbatch sinfo squeue scancel; do
    command -v "$p" >/dev/null 2>&1 || PATH="$PATH:/usr/sbin:/sbin" command -v "$p" >/dev/null 2>&1 \
        || cannot "$p not found (apt-get install slurm-wlm munge)"
done
export PATH="$PATH:/usr/sbin:/sbin"

node_up() {
    local s
    s="$(timeout 10 sinfo -h -N -o '%T' 2>/dev/null | head -n1)" || return 1
    case "$s" in idle*|mixed*|allocated*|completing*) return 0 ;; *) return 1 ;; esac
}

if [ -f "$conf" ] && node_up; then
    echo "slurm-test-cluster: reusing the cluster of $conf" >&2
    echo "SLURM_CONF=$conf"
    exit 0
fi

mkdir -p "$state/spool" "$state/ctld"

# munge: one daemon per machine, shared with anything else that uses it.
if ! munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1; then
    if [ ! -s /etc/munge/munge.key ]; then
        mkdir -p /etc/munge
        if command -v mungekey >/dev/null 2>&1; then
            mungekey --create --keyfile=/etc/munge/munge.key
        else
            dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2>/dev/null
        fi
    fi
    chown munge:munge /etc/munge /etc/munge/munge.key
    chmod 0700 /etc/munge
    chmod 0400 /etc/munge/munge.key
    mkdir -p /run/munge /var/lib/munge /var/log/munge
    chown munge:munge /run/munge /var/lib/munge /var/log/munge
    chmod 0755 /run/munge
    runuser -u munge -- munged
    for _ in $(seq 50); do
        munge -n </dev/null 2>/dev/null | unmunge >/dev/null 2>&1 && break
        sleep 0.1
    done
    munge -n </dev/null | unmunge >/dev/null || { echo "slurm-test-cluster: munged did not start" >&2; exit 1; }
fi

host="$(hostname -s)"
cpus="$(nproc)"
mem_mb=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
[ "$mem_mb" -ge 256 ] || mem_mb=256

cat >"$conf" <<EOF
# Written by scripts/slurm-test-cluster.sh: one node, no cgroups, no accounting.
ClusterName=packbed-test
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
SlurmctldPort=6817
SlurmdPort=6818
AuthType=auth/munge
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/spool
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=2
MinJobAge=60
KillWait=5
InactiveLimit=0
SlurmdTimeout=60
NodeName=$host CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
rm -f "$state/cgroup.conf"

# Daemons of an earlier start (of this STATE_DIR) that no longer answer.
for d in slurmctld slurmd; do
    if [ -f "$state/$d.pid" ]; then
        pid="$(cat "$state/$d.pid")"
        if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
            kill "$pid" 2>/dev/null || true
            for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        fi
        rm -f "$state/$d.pid"
    fi
done

fail() {
    echo "slurm-test-cluster: $*" >&2
    tail -n 20 "$state/slurmctld.log" "$state/slurmd.log" >&2 2>/dev/null || true
    exit 1
}
# -c: a clean start, no jobs or state of an earlier cluster.
slurmctld -c -f "$conf" || fail "slurmctld did not start"
if ! slurmd -f "$conf"; then
    printf 'CgroupPlugin=disabled\n' >"$state/cgroup.conf"
    slurmd -f "$conf" || fail "slurmd did not start (also not with CgroupPlugin=disabled)"
fi

for _ in $(seq 60); do
    node_up && break
    sleep 0.5
done
if ! node_up; then
    sinfo -N -l >&2 || true
    fail "the node did not come up (sinfo above)"
fi
echo "slurm-test-cluster: single-node Slurm up ($host, $cpus CPUs, $conf)" >&2
echo "SLURM_CONF=$conf"
