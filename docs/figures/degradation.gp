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
