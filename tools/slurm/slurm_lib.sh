#!/usr/bin/env bash
# @file slurm_lib.sh
# @brief Shared helpers of the single-node Slurm scripts: the layout under DIR and daemon pid checks.
#
# Sourced by slurm_up.sh, slurm_down.sh and smoke.sh, never run. The caller
# sets `set -euo pipefail` and calls slurm_layout DIR first.

# slurm_layout DIR: makes DIR absolute (creating it) and sets the paths of
# everything the cluster keeps there (read by the scripts that source this).
# shellcheck disable=SC2034
slurm_layout() {
  mkdir -p -- "$1"
  SL_DIR=$(cd -- "$1" && pwd -P)
  SL_CONF=$SL_DIR/slurm.conf
  SL_RUN=$SL_DIR/run          # pid files and the start-up lock
  SL_LOG=$SL_DIR/log          # one log per daemon
  SL_STATE=$SL_DIR/state      # slurmctld StateSaveLocation
  SL_SPOOL=$SL_DIR/spool      # slurmd SlurmdSpoolDir
  SL_MUNGE=$SL_DIR/munge      # munge key, socket and seed
  SL_MUNGE_KEY=$SL_MUNGE/munge.key
  SL_MUNGE_SOCKET=$SL_MUNGE/munge.socket.2
  export SLURM_CONF=$SL_CONF
}

# slurm_pidfile NAME: the pid file of daemon NAME (munged, slurmctld, slurmd).
slurm_pidfile() { printf '%s/%s.pid\n' "$SL_RUN" "$1"; }

# slurm_logfile NAME: the log file of daemon NAME.
slurm_logfile() { printf '%s/%s.log\n' "$SL_LOG" "$1"; }

# slurm_live_pid NAME: prints the pid of daemon NAME and succeeds when its pid
# file names a live process that is that daemon and was started for this DIR
# (its command line holds a path under DIR), so a stale pid file or a reused
# pid is never taken for a running daemon.
slurm_live_pid() {
  local file pid argv0 cmdline
  file=$(slurm_pidfile "$1")
  [ -r "$file" ] || return 1
  pid=$(tr -dc '0-9' < "$file")
  [ -n "$pid" ] && [ -r "/proc/$pid/cmdline" ] || return 1
  cmdline=$(tr '\0' ' ' < "/proc/$pid/cmdline" 2>/dev/null) || return 1
  argv0=${cmdline%% *}
  case "${argv0##*/}" in "$1"*) ;; *) return 1 ;; esac
  case "$cmdline" in *"$SL_DIR/"*) ;; *) return 1 ;; esac
  printf '%s\n' "$pid"
}

# slurm_last_error LOGFILE: the last error or fatal line of a daemon log,
# without its time stamp; empty when there is none. Errors that every start
# logs and that do no harm are skipped: Debian's MPI plugins that find no
# PMIx library, and the state files a first start does not have yet.
slurm_last_error() {
  [ -r "$1" ] || return 0
  grep -aiE 'fatal|error' -- "$1" |
    grep -avE 'pmix|MPI: Cannot create context|state file|NOTE: Trying backup' |
    tail -n 1 | sed -E 's/^\[[^]]*\] *//' || true
}

# slurm_node_state NODE: the node's state as sinfo prints it (idle, mixed,
# down*, ...), empty when slurmctld does not answer.
slurm_node_state() {
  timeout 10 sinfo -h -N -n "$1" -o '%T' 2>/dev/null | head -n 1 || true
}

# slurm_running PID: the process exists and has not exited. A daemon is
# reparented to pid 1 and, where pid 1 does not reap (some containers), its
# exit leaves a zombie in /proc: state Z counts as gone.
slurm_running() {
  local stat
  stat=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
  stat=${stat##*) }
  [ "${stat%% *}" != Z ]
}

# slurm_stop NAME: stops daemon NAME of this DIR: SIGTERM, up to 15 s for it
# to go, then SIGKILL; removes its pid file. Succeeds when it was running.
slurm_stop() {
  local name=$1 pid i
  if ! pid=$(slurm_live_pid "$name"); then
    rm -f -- "$(slurm_pidfile "$name")"
    return 1
  fi
  kill -TERM "$pid" 2>/dev/null || true
  for ((i = 0; i < 150; i++)); do
    slurm_running "$pid" || break
    sleep 0.1
  done
  if slurm_running "$pid"; then
    echo "slurm: $name ($pid) ignored SIGTERM for 15 s, killing it" >&2
    kill -KILL "$pid" 2>/dev/null || true
  fi
  rm -f -- "$(slurm_pidfile "$name")"
}
