#!/usr/bin/env bash
# Stop the test cluster of tests/workflow/slurm/start_cluster.sh by PID: slurmd, slurmctld, then munged;
# then put the machine back as start_cluster.sh found it: its own /etc/slurm/slurm.conf restored, or
# the test's removed (left behind, it makes every `scontrol`, and with it Snakemake's SLURM plugin,
# wait about 10 s for a controller that is not there), and the munge key removed if the start made it.
# Keeps the Debian packages (idle without a slurm.conf) and the logs in /var/log/slurm.
set -uo pipefail
alive() { [ -s "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }
for f in /run/slurmd.pid /run/slurmctld.pid /run/munge/munged.pid; do
    if alive "$f"; then
        pid=$(cat "$f"); kill "$pid"
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
        if kill -0 "$pid" 2>/dev/null; then
            echo "stop_cluster: $f (pid $pid) still running after 10 s; sending SIGKILL" >&2
            kill -9 "$pid"
        fi
        echo "stop_cluster: stopped $(basename "$f" .pid) (pid $pid)"
    fi
done

# --- restore the configuration (also after an older start_cluster.sh that kept no state)
STATE=/var/lib/tensegrity-slurm-test
MARK='# Written by tests/'
ours() { [ -f "$1" ] && head -1 "$1" | grep -q "^$MARK"; }
if [ -s "$STATE/slurm.conf" ]; then
    cp -p "$STATE/slurm.conf" /etc/slurm/slurm.conf && echo "stop_cluster: restored /etc/slurm/slurm.conf"
elif ours /etc/slurm/slurm.conf; then
    rm -f /etc/slurm/slurm.conf && echo "stop_cluster: removed the test's /etc/slurm/slurm.conf"
fi
if [ -f /etc/slurm/slurm.conf.bak ]; then   # an older start_cluster.sh kept the previous file here
    if ours /etc/slurm/slurm.conf.bak; then rm -f /etc/slurm/slurm.conf.bak
    elif [ ! -e /etc/slurm/slurm.conf ]; then mv /etc/slurm/slurm.conf.bak /etc/slurm/slurm.conf
    fi
fi
if [ -f "$STATE/created-munge-key" ]; then
    rm -f /etc/munge/munge.key && echo "stop_cluster: removed the munge key start_cluster.sh made"
fi
rm -rf "$STATE"
