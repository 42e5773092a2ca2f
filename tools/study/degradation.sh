#!/usr/bin/env bash
# @file degradation.sh
# @brief `make degradation`: navigation against the number of vision tiles the coordinator uses.
#
# Usage: tools/study/degradation.sh BIN OUT   (BIN: the build's bin folder, OUT: the results folder)
# Flies the whole default descent, no faults, with --vision-tiles N for each N of
# DEG_TILES (default 40 30 20 10 5) and each seed of DEG_SEEDS (default 1..5),
# two runs at a time, and writes OUT/degradation.dat (one row per N: mean and
# worst final error, mean and worst error after convergence, mean matches per
# frame, mean frames, runs that lost their navigation), OUT/degradation.md (the
# same as a table) and OUT/degradation.png (gnuplot). Each run's folder stays
# under OUT/runs/ with its summary.json and events.log.
set -euo pipefail
bin=$1
out=$2
tiles=${DEG_TILES:-"40 30 20 10 5"}
seeds=${DEG_SEEDS:-"1 2 3 4 5"}
mkdir -p "$out/runs"

for n in $tiles; do
  for s in $seeds; do
    echo "$n $s"
  done
done | xargs -P 2 -n 2 sh -c '
  # $0: the program, $1: the results folder, $2: tiles, $3: seed (xargs appends the last two)
  "$0" --quiet --vision-tiles "$2" --seed "$3" --out "$1/runs/n$2-s$3" > /dev/null ||
    { echo "degradation: the run with $2 tiles, seed $3 failed" >&2; exit 255; }
  echo "degradation: $2 tiles, seed $3 flown"' "$bin/trn_mission" "$out"

dat="$out/degradation.dat"
md="$out/degradation.md"
echo "# tiles final_mean_m final_worst_m conv_mean_m conv_worst_m matches_per_frame frames lost runs" > "$dat"
{
  echo "| vision tiles | final error, mean / worst (m) | worst error after convergence, mean / worst (m) | matches per frame | frames | runs that lost navigation |"
  echo "|---|---|---|---|---|---|"
} > "$md"
for n in $tiles; do
  files=()
  for s in $seeds; do
    files+=("$out/runs/n$n-s$s/summary.json")
  done
  row=$(jq -s -r '
    def mean(f): (map(f) | add) / length;
    [ (.[0].vision_tiles_used),
      mean(.final_position_error_m), (map(.final_position_error_m) | max),
      mean(.max_position_error_after_convergence_m), (map(.max_position_error_after_convergence_m) | max),
      mean(.matches_per_frame_mean), mean(.frames), (map(.mission_lost) | add), length ]
    | @tsv' "${files[@]}")
  echo "$row" >> "$dat"
  echo "$row" | awk -F'\t' '{ printf "| %d | %.2f / %.2f | %.2f / %.2f | %.1f | %.1f | %d of %d |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9 }' >> "$md"
done

cat > "$out/degradation.gp" <<'GP'
# Run in this folder: gnuplot degradation.gp
set terminal pngcairo size 900,520 noenhanced
set output 'degradation.png'
set title 'Navigation against the vision tiles used (default descent, no faults)'
set xlabel 'vision tiles the coordinator uses'
set ylabel 'position error (m, log scale)'
set y2label 'matches per frame'
set logscale y
set ytics nomirror
set y2tics
set y2range [0:*]
set grid
set key top center
set xrange [0:42]
plot 'degradation.dat' using 1:2 with linespoints title 'final error, mean', \
     '' using 1:3 with linespoints title 'final error, worst seed', \
     '' using 1:5 with linespoints title 'worst error after convergence, worst seed', \
     '' using 1:6 axes x1y2 with linespoints title 'matches per frame, mean (right axis)'
GP
(cd "$out" && gnuplot degradation.gp < /dev/null) || echo "degradation: gnuplot failed; the table is in $md" >&2
cat "$md"
echo "degradation: results in $out/ (degradation.md, degradation.dat, degradation.png)"
