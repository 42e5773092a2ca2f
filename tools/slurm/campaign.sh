#!/usr/bin/env bash
# @file campaign.sh
# @brief Flies a fault-injection campaign as a Slurm job array on the single-node cluster, then merges its shards.
#
# Usage: tools/slurm/campaign.sh SLURM_DIR CAMPAIGN_BIN SPEC OUT TASKS   (`make campaign-slurm`)
#
# Brings the cluster up (slurm_up.sh SLURM_DIR), writes the array script with
# `trn_campaign sbatch` (task i flies shard i/TASKS into OUT/shard-i, all of
# them sharing the world cache OUT/world), submits it, waits until no task of
# the job is left (polling squeue every second, at most
# SLURM_CAMPAIGN_TIMEOUT seconds, default 7200), checks that every shard wrote
# its report, and merges the shards into OUT/merged with `trn_campaign merge`.
# Prints the merged report; exits 1 naming the shard and its Slurm log when a
# task failed. The cluster is left up (make slurm-down stops it).
set -euo pipefail

if [ $# -ne 5 ]; then
  echo "usage: $0 SLURM_DIR CAMPAIGN_BIN SPEC OUT TASKS" >&2
  exit 2
fi
slurm_dir=$1 bin=$2 spec=$3 out=$4 tasks=$5
here=$(cd -- "$(dirname -- "$0")" && pwd)
limit=${SLURM_CAMPAIGN_TIMEOUT:-7200}

"$here/slurm_up.sh" "$slurm_dir"
export SLURM_CONF
SLURM_CONF=$(cd -- "$slurm_dir" && pwd)/slurm.conf

mkdir -p "$out"
script=$("$bin" sbatch "$spec" --out "$out" --tasks "$tasks")
id=$(sbatch --parsable "$script")
id=${id%%;*}
echo "campaign-slurm: job $id submitted ($tasks array tasks, $script)"
start=$(date +%s)
while [ -n "$(squeue -h -j "$id" -o %i 2>/dev/null)" ]; do
  if [ $(( $(date +%s) - start )) -gt "$limit" ]; then
    echo "campaign-slurm: job $id still running after ${limit} s: cancelled" >&2
    scancel "$id" || true
    exit 1
  fi
  sleep 1
done
echo "campaign-slurm: job $id done in $(( $(date +%s) - start )) s"

failed=0
for ((i = 0; i < tasks; i++)); do
  if [ ! -f "$out/shard-$i/report.json" ]; then
    log=$(ls "$out"/slurm-"$id"_"$i".out 2>/dev/null || true)
    echo "campaign-slurm: shard $i has no report (read ${log:-slurm-${id}_$i.out in $out})" >&2
    failed=1
  fi
done
[ "$failed" -eq 0 ] || exit 1

shards=()
for ((i = 0; i < tasks; i++)); do shards+=("$out/shard-$i"); done
"$bin" merge --out "$out/merged" "${shards[@]}"
echo "campaign-slurm: merged report in $out/merged/"
