#!/usr/bin/env bash
# Start a real single-node SLURM cluster on this machine (recipe: /work/shared/slurm-local.md):
# munged, slurmctld and slurmd from Debian's packages, detached from the caller's process group,
# one partition "debug" holding this node. Idempotent: installs only what is missing, rewrites
# /etc/slurm/slurm.conf only if it changed, starts only daemons that are not running, then waits
# until the node is idle. Needs root. Stop with tests/workflow/slurm/stop_cluster.sh, which puts back
# what this script changed: the first start records the machine's prior state in $STATE
# (a slurm.conf of its own, the munge key) so that the stop can restore it; a slurm.conf left
# behind makes every later `scontrol` (and Snakemake's SLURM plugin) wait for a controller.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
T0=$(date +%s.%N)
die() { echo "start_cluster: $*" >&2; exit 1; }
alive() { [ -s "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }  # alive PIDFILE

PATH=/usr/sbin:/usr/bin:/sbin:/bin:$PATH
[ "$(id -u)" -eq 0 ] || die "must run as root (installs packages, writes /etc/slurm, runs daemons)"

# --- packages
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null \
   || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    command -v apt-get >/dev/null || die "SLURM is not installed and apt-get is not available"
    echo "start_cluster: installing slurmctld slurmd slurm-client munge"
    # exit 3: the packages could not be had (no registry), which the test reports as a skip
    apt-get update -qq || { echo "start_cluster: apt-get update failed" >&2; exit 3; }
    apt-get install -y -qq --no-install-recommends slurmctld slurmd slurm-client munge >/dev/null \
        || { echo "start_cluster: apt-get install slurmctld slurmd slurm-client munge failed" >&2; exit 3; }
fi

# --- the machine's state before the first start (after the packages, which may bring a munge key)
STATE=/var/lib/tensegrity-slurm-test   # read by stop_cluster.sh
MARK='# Written by tests/'                # the first line of a slurm.conf this script wrote (any version)
if [ ! -d "$STATE" ]; then
    mkdir -p "$STATE.new"
    if [ -s /etc/slurm/slurm.conf ] && ! head -1 /etc/slurm/slurm.conf | grep -q "^$MARK"; then
        cp -p /etc/slurm/slurm.conf "$STATE.new/slurm.conf"    # the machine's own: put back on stop
    fi
    [ -s /etc/munge/munge.key ] || touch "$STATE.new/created-munge-key"
    mv "$STATE.new" "$STATE"
fi

# --- munge
[ -s /etc/munge/munge.key ] || dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
chown munge:munge /etc/munge/munge.key && chmod 400 /etc/munge/munge.key
mkdir -p /run/munge && chown munge:munge /run/munge && chmod 755 /run/munge
if ! alive /run/munge/munged.pid; then
    setsid runuser -u munge -- /usr/sbin/munged </dev/null >/dev/null 2>&1 || die "munged failed to start"
fi
for _ in $(seq 50); do munge -n </dev/null | unmunge >/dev/null 2>&1 && break; sleep 0.1; done
munge -n </dev/null | unmunge >/dev/null 2>&1 || die "munge does not answer (see /var/log/munge/munged.log)"

# --- slurm.conf
H=$(hostname -s)
CPUS=$(nproc)
MEM=$(( $(free -m | awk '/^Mem:/{print $2}') - 512 ))
[ "$MEM" -gt 0 ] || die "cannot read the machine's memory from free -m"
CONF=$(cat <<EOF
# Written by tests/workflow/slurm/start_cluster.sh: a single-node test cluster (see /work/shared/slurm-local.md).
ClusterName=localcluster
SlurmctldHost=${H}(127.0.0.1)
SlurmUser=root
AuthType=auth/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
ReturnToService=2
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmdSpoolDir=/var/spool/slurmd
StateSaveLocation=/var/spool/slurmctld
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MinJobAge=300
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
NodeName=${H} NodeAddr=127.0.0.1 CPUs=${CPUS} RealMemory=${MEM} State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
)
mkdir -p /etc/slurm /var/spool/slurmd /var/spool/slurmctld /var/log/slurm
if [ "$(cat /etc/slurm/slurm.conf 2>/dev/null)" != "$CONF" ]; then
    if [ -s "$STATE/slurm.conf" ]; then
        echo "start_cluster: replacing /etc/slurm/slurm.conf (kept in $STATE; stop_cluster.sh puts it back)"
    fi
    # daemons running with another configuration are restarted with this one
    for f in /run/slurmd.pid /run/slurmctld.pid; do
        if alive "$f"; then kill "$(cat "$f")"; fi
    done
    for _ in $(seq 50); do alive /run/slurmd.pid || alive /run/slurmctld.pid || break; sleep 0.2; done
    printf '%s\n' "$CONF" >/etc/slurm/slurm.conf
fi

# --- slurmctld, slurmd (each daemonizes itself and writes its pid file)
if ! alive /run/slurmctld.pid; then
    setsid /usr/sbin/slurmctld </dev/null >/dev/null 2>&1 || die "slurmctld failed to start (see /var/log/slurm/slurmctld.log)"
fi
if ! alive /run/slurmd.pid; then
    setsid /usr/sbin/slurmd </dev/null >/dev/null 2>&1 || die "slurmd failed to start (see /var/log/slurm/slurmd.log)"
fi

# --- wait until the node is idle (or mixed/allocated: jobs of an earlier run)
state=""
for i in $(seq 60); do
    state=$(sinfo -h -n "$H" -o %T 2>/dev/null | head -1 || true)
    case "$state" in
        idle|mixed|allocated) break ;;
        drained|draining|down|down\*|drained\*) [ "$i" -eq 10 ] && scontrol update nodename="$H" state=resume 2>/dev/null || true ;;
    esac
    sleep 0.5
done
case "$state" in
    idle|mixed|allocated) ;;
    *) die "node $H is '${state:-unknown}' after 30 s, not idle; $(scontrol show node "$H" 2>&1 | grep -i reason || true)
  see /var/log/slurm/slurmctld.log and /var/log/slurm/slurmd.log" ;;
esac
printf 'start_cluster: node %s %s (CPUs=%s RealMemory=%s MB), slurmctld pid %s, slurmd pid %s, in %.1f s\n' \
    "$H" "$state" "$CPUS" "$MEM" "$(cat /run/slurmctld.pid)" "$(cat /run/slurmd.pid)" \
    "$(awk -v a="$T0" -v b="$(date +%s.%N)" 'BEGIN{print b - a}')"
