# Run in this folder: gnuplot bad_cores.gp
set terminal pngcairo size 1100,900 noenhanced
set output 'bad_cores.png'
set multiplot layout 2,1
set grid
set key outside right
set xlabel 'vision tiles gone bad'
set title 'Final position error, mean over seeds'
set ylabel 'm'
plot 'bad_cores.dat' using 4:(strcol(1) eq "tile64" && strcol(2) eq "hang" && strcol(3) eq "on" ? $5 : 1/0) with linespoints title 'tile64 hang spares on', \
     'bad_cores.dat' using 4:(strcol(1) eq "tile64" && strcol(2) eq "hang" && strcol(3) eq "off" ? $5 : 1/0) with linespoints title 'tile64 hang spares off', \
     'bad_cores.dat' using 4:(strcol(1) eq "tile64" && strcol(2) eq "shift" && strcol(3) eq "on" ? $5 : 1/0) with linespoints title 'tile64 shift spares on', \
     'bad_cores.dat' using 4:(strcol(1) eq "tile64" && strcol(2) eq "shift" && strcol(3) eq "off" ? $5 : 1/0) with linespoints title 'tile64 shift spares off', \
     'bad_cores.dat' using 4:(strcol(1) eq "maestro" && strcol(2) eq "hang" && strcol(3) eq "on" ? $5 : 1/0) with linespoints title 'maestro hang spares on', \
     'bad_cores.dat' using 4:(strcol(1) eq "maestro" && strcol(2) eq "hang" && strcol(3) eq "off" ? $5 : 1/0) with linespoints title 'maestro hang spares off', \
     'bad_cores.dat' using 4:(strcol(1) eq "maestro" && strcol(2) eq "shift" && strcol(3) eq "on" ? $5 : 1/0) with linespoints title 'maestro shift spares on', \
     'bad_cores.dat' using 4:(strcol(1) eq "maestro" && strcol(2) eq "shift" && strcol(3) eq "off" ? $5 : 1/0) with linespoints title 'maestro shift spares off'
set title 'Matches per frame, mean over seeds'
set ylabel 'matches'
plot 'bad_cores.dat' using 4:(strcol(1) eq "tile64" && strcol(2) eq "hang" && strcol(3) eq "on" ? $8 : 1/0) with linespoints title 'tile64 hang spares on', \
     'bad_cores.dat' using 4:(strcol(1) eq "tile64" && strcol(2) eq "hang" && strcol(3) eq "off" ? $8 : 1/0) with linespoints title 'tile64 hang spares off', \
     'bad_cores.dat' using 4:(strcol(1) eq "tile64" && strcol(2) eq "shift" && strcol(3) eq "on" ? $8 : 1/0) with linespoints title 'tile64 shift spares on', \
     'bad_cores.dat' using 4:(strcol(1) eq "tile64" && strcol(2) eq "shift" && strcol(3) eq "off" ? $8 : 1/0) with linespoints title 'tile64 shift spares off', \
     'bad_cores.dat' using 4:(strcol(1) eq "maestro" && strcol(2) eq "hang" && strcol(3) eq "on" ? $8 : 1/0) with linespoints title 'maestro hang spares on', \
     'bad_cores.dat' using 4:(strcol(1) eq "maestro" && strcol(2) eq "hang" && strcol(3) eq "off" ? $8 : 1/0) with linespoints title 'maestro hang spares off', \
     'bad_cores.dat' using 4:(strcol(1) eq "maestro" && strcol(2) eq "shift" && strcol(3) eq "on" ? $8 : 1/0) with linespoints title 'maestro shift spares on', \
     'bad_cores.dat' using 4:(strcol(1) eq "maestro" && strcol(2) eq "shift" && strcol(3) eq "off" ? $8 : 1/0) with linespoints title 'maestro shift spares off'
unset multiplot
