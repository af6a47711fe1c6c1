#!/usr/bin/env bash
# Stop the test cluster of tests/workflow/slurm/start_cluster.sh by PID: slurmd, slurmctld, then munged.
# Leaves packages, /etc/slurm/slurm.conf and the logs in /var/log/slurm in place.
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
