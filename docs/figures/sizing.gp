# Run in this folder: gnuplot sizing.gp
set terminal pngcairo size 1100,1000 noenhanced
set output 'sizing.png'
set multiplot layout 2,1
set grid
set key outside right
set xrange [0:42]
set xlabel 'vision tiles the coordinator uses'
set title 'Worst frame against vision tiles (default descent, no faults; solid TILE64, dashed Maestro)'
set ylabel 'worst frame (ms)'
set yrange [0:1100]
plot 'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 40 && $3 == 1 ? $5 : 1/0) with linespoints dt 1 title 'tile64 40 lm 1 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 40 && $3 == 2 ? $5 : 1/0) with linespoints dt 1 title 'tile64 40 lm 2 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 100 && $3 == 1 ? $5 : 1/0) with linespoints dt 1 title 'tile64 100 lm 1 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 100 && $3 == 2 ? $5 : 1/0) with linespoints dt 1 title 'tile64 100 lm 2 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 150 && $3 == 1 ? $5 : 1/0) with linespoints dt 1 title 'tile64 150 lm 1 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 150 && $3 == 2 ? $5 : 1/0) with linespoints dt 1 title 'tile64 150 lm 2 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 200 && $3 == 1 ? $5 : 1/0) with linespoints dt 1 title 'tile64 200 lm 1 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 200 && $3 == 2 ? $5 : 1/0) with linespoints dt 1 title 'tile64 200 lm 2 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 40 && $3 == 1 ? $5 : 1/0) with linespoints dt 2 title 'maestro 40 lm 1 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 40 && $3 == 2 ? $5 : 1/0) with linespoints dt 2 title 'maestro 40 lm 2 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 100 && $3 == 1 ? $5 : 1/0) with linespoints dt 2 title 'maestro 100 lm 1 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 100 && $3 == 2 ? $5 : 1/0) with linespoints dt 2 title 'maestro 100 lm 2 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 150 && $3 == 1 ? $5 : 1/0) with linespoints dt 2 title 'maestro 150 lm 1 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 150 && $3 == 2 ? $5 : 1/0) with linespoints dt 2 title 'maestro 150 lm 2 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 200 && $3 == 1 ? $5 : 1/0) with linespoints dt 2 title 'maestro 200 lm 1 Hz', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 200 && $3 == 2 ? $5 : 1/0) with linespoints dt 2 title 'maestro 200 lm 2 Hz', \
     1000 with lines dt 3 lc rgb 'black' title '1 Hz frame period', \
     500 with lines dt 3 lc rgb 'gray' title '2 Hz frame period'
set title 'Matches per frame against vision tiles (the same at 1 and 2 Hz)'
set ylabel 'matches per frame'
set yrange [0:*]
plot 'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 40 && $3 == 1 ? $6 : 1/0) with linespoints dt 1 title 'tile64 40 lm', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 100 && $3 == 1 ? $6 : 1/0) with linespoints dt 1 title 'tile64 100 lm', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 150 && $3 == 1 ? $6 : 1/0) with linespoints dt 1 title 'tile64 150 lm', \
     'sizing.dat' using 4:(strcol(1) eq "tile64" && $2 == 200 && $3 == 1 ? $6 : 1/0) with linespoints dt 1 title 'tile64 200 lm', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 40 && $3 == 1 ? $6 : 1/0) with linespoints dt 2 title 'maestro 40 lm', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 100 && $3 == 1 ? $6 : 1/0) with linespoints dt 2 title 'maestro 100 lm', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 150 && $3 == 1 ? $6 : 1/0) with linespoints dt 2 title 'maestro 150 lm', \
     'sizing.dat' using 4:(strcol(1) eq "maestro" && $2 == 200 && $3 == 1 ? $6 : 1/0) with linespoints dt 2 title 'maestro 200 lm'
unset multiplot
