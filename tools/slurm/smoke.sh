#!/usr/bin/env bash
# @file smoke.sh
# @brief Smoke test of the single-node Slurm cluster: a 4-task job array whose tasks each write their index.
#
# Usage: tools/slurm/smoke.sh DIR     (`make slurm-smoke`)
#
# Brings the cluster up with slurm_up.sh DIR (a no-op when it is up), submits
# `sbatch --array=0-3 --wait` whose task i writes i to DIR/smoke/task-i.id
# (and its start and end times), then checks the four files. Prints one line,
# "slurm smoke: pass (...)" or "slurm smoke: fail (...)", with the times taken
# and how many tasks ran at once, and exits 0 or 1. The array must finish
# within SLURM_SMOKE_TIMEOUT seconds (default 120). The cluster is left up.
set -euo pipefail

here=$(cd -- "$(dirname -- "$0")" && pwd)
# shellcheck source=tools/slurm/slurm_lib.sh
. "$here/slurm_lib.sh"

if [ $# -ne 1 ] || [ -z "$1" ]; then
  echo "usage: $0 DIR" >&2
  exit 2
fi
limit=${SLURM_SMOKE_TIMEOUT:-120}
tasks=4

now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

t_start=$(now)
if ! "$here/slurm_up.sh" "$1"; then
  echo "slurm smoke: fail (slurm_up.sh could not bring Slurm up)"
  exit 1
fi
t_up=$(now)
slurm_layout "$1"

out=$SL_DIR/smoke
rm -rf -- "$out"
mkdir -p -- "$out"
# The task script: sleeps a second so that tasks sharing the node overlap.
cat > "$out/task.sh" <<'EOF'
#!/usr/bin/env bash
set -euo pipefail
start=$(date +%s.%N)
sleep 1
printf '%s\n' "$SLURM_ARRAY_TASK_ID" > "$SMOKE_OUT/task-$SLURM_ARRAY_TASK_ID.id"
printf '%s %s\n' "$start" "$(date +%s.%N)" > "$SMOKE_OUT/task-$SLURM_ARRAY_TASK_ID.time"
EOF
chmod 0755 -- "$out/task.sh"

# sbatch --wait returns when every task has ended, with the highest task
# exit status. Output files go where the caller says; their folder must exist.
sbatch_rc=0
SMOKE_OUT=$out timeout "$limit" sbatch --array="0-$((tasks - 1))" --wait --parsable \
  --job-name=trn-smoke --partition=campaign --ntasks=1 --cpus-per-task=1 --time=5 \
  --chdir="$out" --output="$out/task-%a.out" --error="$out/task-%a.out" \
  "$out/task.sh" > "$out/sbatch.out" 2>&1 || sbatch_rc=$?
t_end=$(now)
times="up $(secs "$t_start" "$t_up") s, array $(secs "$t_up" "$t_end") s, total $(secs "$t_start" "$t_end") s"

problems=()
[ "$sbatch_rc" -eq 0 ] || problems+=("sbatch exited $sbatch_rc: $(tail -n 1 "$out/sbatch.out")")
for ((i = 0; i < tasks; i++)); do
  f=$out/task-$i.id
  if [ ! -f "$f" ]; then
    problems+=("task $i wrote nothing (read $out/task-$i.out)")
  elif [ "$(cat -- "$f")" != "$i" ]; then
    problems+=("task $i wrote '$(head -c 40 -- "$f")'")
  fi
done
if [ ${#problems[@]} -gt 0 ]; then
  echo "slurm smoke: fail (${problems[*]}; $times)"
  exit 1
fi

# The most tasks that ran at once, from their start and end times.
at_once=$(cat -- "$out"/task-*.time | awk '
  { ev[n++] = $1 " 1"; ev[n++] = $2 " -1" }
  END {
    # Sort the events by time (an end before a start at the same time).
    for (i = 1; i < n; i++)
      for (j = i; j > 0; j--) {
        split(ev[j - 1], a, " "); split(ev[j], b, " ")
        if (a[1] + 0 > b[1] + 0 || (a[1] == b[1] && a[2] > b[2])) { t = ev[j]; ev[j] = ev[j - 1]; ev[j - 1] = t } else break
      }
    for (i = 0; i < n; i++) { split(ev[i], e, " "); c += e[2]; if (c > m) m = c }
    print m
  }')
echo "slurm smoke: pass ($tasks/$tasks array tasks, job $(head -n 1 "$out/sbatch.out"), up to $at_once at once; $times)"
