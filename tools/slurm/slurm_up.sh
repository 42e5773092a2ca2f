#!/usr/bin/env bash
# @file slurm_up.sh
# @brief Starts a single-node Slurm cluster on this machine (munged, slurmctld, slurmd), all of it under DIR.
#
# Usage: tools/slurm/slurm_up.sh DIR        (e.g. build/slurm; `make slurm-up`)
#
# Writes DIR/slurm.conf for one node, this machine (`hostname -s`, reached at
# 127.0.0.1) with the CPUs `nproc` reports, in one default partition
# `campaign`, and starts the daemons directly (no systemd), as root:
#   munged     key, socket, seed under DIR/munge/ (not /etc/munge, /run/munge)
#   slurmctld  state under DIR/state/
#   slurmd     spool under DIR/spool/
# with pid files under DIR/run/ and logs under DIR/log/. It then waits (at
# most SLURM_UP_TIMEOUT seconds, default 30) until the node takes jobs and
# prints one line:
#   slurm: up (node NAME, N CPUs), SLURM_CONF=DIR/slurm.conf
# Point the Slurm commands at the cluster with that SLURM_CONF.
#
# Idempotent: when the daemons of this DIR already run with the same
# configuration it only checks the node and prints the same line; a daemon
# that died is started again; a changed configuration (other CPU count or
# memory) restarts the Slurm daemons. Where Slurm cannot start it prints one
# line naming the cause and the log to read, stops what it started, and
# exits 1 (2 for a usage error).
#
# Ports: SLURM_CTLD_PORT (default 6817) and SLURMD_PORT (default 6818), for
# when another cluster holds the usual ones.
set -euo pipefail

here=$(cd -- "$(dirname -- "$0")" && pwd)
# shellcheck source=tools/slurm/slurm_lib.sh
. "$here/slurm_lib.sh"

if [ $# -ne 1 ] || [ -z "$1" ]; then
  echo "usage: $0 DIR" >&2
  exit 2
fi

timeout_s=${SLURM_UP_TIMEOUT:-30}
ctld_port=${SLURM_CTLD_PORT:-6817}
slurmd_port=${SLURMD_PORT:-6818}
for v in "$timeout_s" "$ctld_port" "$slurmd_port"; do
  case "$v" in ''|*[!0-9]*) echo "slurm: SLURM_UP_TIMEOUT, SLURM_CTLD_PORT and SLURMD_PORT must be whole numbers (got '$v')" >&2; exit 2 ;; esac
done

started=()   # daemons this run started, stopped again if the start fails

# fail MESSAGE: one line on stderr, the daemons this run started stopped, exit 1.
fail() {
  echo "slurm: $*" >&2
  local i
  for ((i = ${#started[@]} - 1; i >= 0; i--)); do
    slurm_stop "${started[i]}" || true
  done
  exit 1
}

# The packages: a missing program names the package group that brings it.
for prog in munged mungekey munge unmunge slurmctld slurmd sinfo scontrol free flock; do
  command -v "$prog" >/dev/null 2>&1 ||
    fail "'$prog' is not installed (install the packages: tools/build/deps.sh slurm)"
done

slurm_layout "$1"
# slurm.conf takes a value up to the first blank: no blanks in DIR.
case "$SL_DIR" in *[[:space:]]*) fail "DIR must not contain blanks (slurm.conf cannot hold them): $SL_DIR" ;; esac
# A Unix socket path is at most 107 bytes.
if [ "${#SL_MUNGE_SOCKET}" -gt 107 ]; then
  fail "DIR is too deep for munge's socket path ($SL_MUNGE_SOCKET): use a shorter DIR"
fi
mkdir -p -- "$SL_RUN" "$SL_LOG" "$SL_STATE" "$SL_SPOOL" "$SL_MUNGE"
# munged refuses a key or socket directory that others can write to; jobs of
# any user run their script from a folder under the spool. DIR itself is the
# caller's and keeps its mode.
chmod 0755 -- "$SL_RUN" "$SL_LOG" "$SL_MUNGE" "$SL_SPOOL"
chmod 0700 -- "$SL_STATE"

# One start-up at a time per DIR (a second caller waits, then finds it up).
# The daemons are started with fd 9 closed, or they would hold the lock.
exec 9>"$SL_RUN/slurm_up.lock"
flock -w 120 9 || fail "another slurm_up.sh holds $SL_RUN/slurm_up.lock"

# ---------------------------------------------------------------- the node
node=$(hostname -s 2>/dev/null) || node=
cpus=$(nproc)
mem_total_mb=$(free -m | awk '/^Mem:/ { print $2 }') || mem_total_mb=
[ -n "$node" ] || fail "'hostname -s' gave no host name"
case "$mem_total_mb" in ''|*[!0-9]*) fail "cannot read the memory size from 'free -m'" ;; esac
# A little under the total: slurmd drains a node whose memory is below the
# configured RealMemory, and the kernel keeps some for itself.
real_mem_mb=$((mem_total_mb * 95 / 100))

# ---------------------------------------------------------------- slurm.conf
conf_new=$SL_CONF.new
cat > "$conf_new" <<EOF
# Single-node Slurm cluster of this machine, written by tools/slurm/slurm_up.sh
# at every start-up (edits are lost). Everything lives under $SL_DIR.
ClusterName=trn
# The node is reached at 127.0.0.1, so no host name needs to resolve.
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$SL_MUNGE_SOCKET

StateSaveLocation=$SL_STATE
SlurmdSpoolDir=$SL_SPOOL
SlurmctldPidFile=$(slurm_pidfile slurmctld)
SlurmdPidFile=$(slurm_pidfile slurmd)
SlurmctldLogFile=$(slurm_logfile slurmctld)
SlurmdLogFile=$(slurm_logfile slurmd)
SlurmctldDebug=info
SlurmdDebug=info

# No cgroups and no systemd: processes are tracked through /proc, tasks are
# not bound or confined.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobContainerType=job_container/none
MpiDefault=none
# No mail is sent from here (the default mail program is not installed).
MailProg=/bin/true

# No slurmdbd: no accounting storage. Finished jobs are appended to a text file.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/filetxt
JobCompLoc=$SL_LOG/jobcomp.log

# One array task per CPU, side by side.
SchedulerType=sched/backfill
# Start pending tasks as soon as CPUs free up: without this, array tasks wait
# for a scheduling pass every 3 s (batch_sched_delay's default).
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MaxArraySize=100001
MaxJobCount=200000
MinJobAge=300
ReturnToService=2

NodeName=$node NodeAddr=127.0.0.1 NodeHostname=$node CPUs=$cpus RealMemory=$real_mem_mb State=UNKNOWN
PartitionName=campaign Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF

# usable STATE: the node takes jobs (busy counts: an array may be running).
usable() { case "$1" in idle|mixed|allocated|completing) return 0 ;; *) return 1 ;; esac; }

report_up() { echo "slurm: up (node $node, $cpus CPUs), SLURM_CONF=$SL_CONF"; }

all_live() {
  slurm_live_pid munged >/dev/null && slurm_live_pid slurmctld >/dev/null &&
    slurm_live_pid slurmd >/dev/null
}

if [ -f "$SL_CONF" ] && cmp -s -- "$conf_new" "$SL_CONF"; then
  rm -f -- "$conf_new"
  # Already up with this DIR and this configuration: check the node only.
  if all_live && usable "$(slurm_node_state "$node")"; then
    report_up
    exit 0
  fi
else
  if slurm_live_pid slurmctld >/dev/null || slurm_live_pid slurmd >/dev/null; then
    echo "slurm: the configuration changed, restarting slurmctld and slurmd" >&2
    "$here/slurm_down.sh" --keep-jobs --keep-munge "$SL_DIR" >&2
  fi
  mv -f -- "$conf_new" "$SL_CONF"
fi

# wait_started NAME: waits (10 s at most) for daemon NAME's pid file to name
# its live process; fails with the log's last error when it does not.
wait_started() {
  local name=$1 log i
  log=$(slurm_logfile "$name")
  for ((i = 0; i < 100; i++)); do
    slurm_live_pid "$name" >/dev/null && return 0
    sleep 0.1
  done
  fail "$name did not start: $(slurm_last_error "$log") (read $log)"
}

# check_alive NAME: fails when daemon NAME died after its start.
check_alive() {
  local log
  slurm_live_pid "$1" >/dev/null && return 0
  log=$(slurm_logfile "$1")
  fail "$1 exited: $(slurm_last_error "$log") (read $log)"
}

# ---------------------------------------------------------------- munged
if ! slurm_live_pid munged >/dev/null; then
  if [ ! -s "$SL_MUNGE_KEY" ]; then
    mungekey --create --keyfile="$SL_MUNGE_KEY" ||
      fail "mungekey could not create $SL_MUNGE_KEY"
  fi
  chmod 0600 -- "$SL_MUNGE_KEY"
  log=$(slurm_logfile munged)
  # --force: a socket left behind by a munged that was killed is replaced.
  munged --force --key-file="$SL_MUNGE_KEY" --socket="$SL_MUNGE_SOCKET" \
    --pid-file="$(slurm_pidfile munged)" --log-file="$log" \
    --seed-file="$SL_MUNGE/munged.seed" >>"$log" 2>&1 9>&- ||
    fail "munged did not start: $(slurm_last_error "$log") (read $log)"
  started+=(munged)
  wait_started munged
fi
if ! munge -n -S "$SL_MUNGE_SOCKET" 2>/dev/null | unmunge -S "$SL_MUNGE_SOCKET" >/dev/null 2>&1; then
  fail "munge credentials do not verify through $SL_MUNGE_SOCKET (read $(slurm_logfile munged))"
fi

# ---------------------------------------------------------------- slurmctld
if ! slurm_live_pid slurmctld >/dev/null; then
  log=$(slurm_logfile slurmctld)
  slurmctld -f "$SL_CONF" >>"$log" 2>&1 9>&- ||
    fail "slurmctld did not start: $(slurm_last_error "$log") (read $log)"
  started+=(slurmctld)
  wait_started slurmctld
fi
deadline=$((SECONDS + timeout_s))
until [[ "$(timeout 5 scontrol ping 2>/dev/null || true)" == *"is UP"* ]]; do
  check_alive slurmctld
  [ "$SECONDS" -lt "$deadline" ] ||
    fail "slurmctld does not answer on port $ctld_port after ${timeout_s}s (read $(slurm_logfile slurmctld))"
  sleep 0.2
done

# ---------------------------------------------------------------- slurmd
if ! slurm_live_pid slurmd >/dev/null; then
  log=$(slurm_logfile slurmd)
  slurmd -f "$SL_CONF" -N "$node" >>"$log" 2>&1 9>&- ||
    fail "slurmd did not start: $(slurm_last_error "$log") (read $log)"
  started+=(slurmd)
  wait_started slurmd
fi

# ---------------------------------------------------------------- the node
state=
until usable "$state"; do
  check_alive slurmctld
  check_alive slurmd
  if [ "$SECONDS" -ge "$deadline" ]; then
    reason=$(timeout 5 sinfo -h -N -n "$node" -o '%E' 2>/dev/null | head -n 1 || true)
    fail "node $node is '${state:-unknown}' after ${timeout_s}s${reason:+ (reason: $reason)} (read $(slurm_logfile slurmd) and $(slurm_logfile slurmctld))"
  fi
  sleep 0.2
  state=$(slurm_node_state "$node")
done
report_up
