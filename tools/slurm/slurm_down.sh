#!/usr/bin/env bash
# @file slurm_down.sh
# @brief Stops the single-node Slurm cluster that slurm_up.sh started under DIR.
#
# Usage: tools/slurm/slurm_down.sh [--keep-jobs] [--keep-munge] DIR   (`make slurm-down`)
#
# Cancels the cluster's jobs (so no job step outlives its slurmd), then stops
# slurmd, slurmctld and munged, each from its pid file under DIR/run/: SIGTERM,
# then SIGKILL if it is still there after 15 s. A daemon already stopped, a
# stale pid file or a DIR that never held a cluster is fine. The state under
# DIR (slurm.conf, munge key, slurmctld state, logs) is kept for the next
# slurm_up.sh. Prints one line, e.g. "slurm: down (stopped slurmd slurmctld munged)".
#   --keep-jobs   leave queued and running jobs to the next start
#   --keep-munge  leave munged running (slurm_up.sh restarting Slurm only)
set -euo pipefail

here=$(cd -- "$(dirname -- "$0")" && pwd)
# shellcheck source=tools/slurm/slurm_lib.sh
. "$here/slurm_lib.sh"

keep_jobs=0
keep_munge=0
while [ $# -gt 0 ]; do
  case "$1" in
    --keep-jobs) keep_jobs=1; shift ;;
    --keep-munge) keep_munge=1; shift ;;
    -*) echo "usage: $0 [--keep-jobs] [--keep-munge] DIR" >&2; exit 2 ;;
    *) break ;;
  esac
done
if [ $# -ne 1 ] || [ -z "$1" ]; then
  echo "usage: $0 [--keep-jobs] [--keep-munge] DIR" >&2
  exit 2
fi
if [ ! -d "$1" ]; then
  echo "slurm: down (no cluster under $1)"
  exit 0
fi
slurm_layout "$1"

# Cancel every job of this cluster while slurmctld and slurmd still run, and
# wait (15 s at most) until none is left running or completing.
if [ "$keep_jobs" -eq 0 ] && slurm_live_pid slurmctld >/dev/null; then
  mapfile -t job_ids < <(timeout 10 squeue -h -o '%i' 2>/dev/null || true)
  if [ ${#job_ids[@]} -gt 0 ]; then
    timeout 10 scancel -- "${job_ids[@]}" 2>/dev/null || true
    for ((i = 0; i < 75; i++)); do
      [ -z "$(timeout 10 squeue -h -t RUNNING,COMPLETING -o '%i' 2>/dev/null || true)" ] && break
      sleep 0.2
    done
  fi
fi

stopped=()
stop() {
  if slurm_stop "$1"; then stopped+=("$1"); fi
}

stop slurmd
stop slurmctld
[ "$keep_munge" -eq 1 ] || stop munged

if [ ${#stopped[@]} -gt 0 ]; then
  echo "slurm: down (stopped ${stopped[*]})"
else
  echo "slurm: down (nothing was running)"
fi
