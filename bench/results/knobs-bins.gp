# regenerate: cd /work/main/bench/results && gnuplot knobs-bins.gp
set terminal pngcairo size 900,600 font ',11'
set output 'knobs-bins.png'
set title "cornell-glossy, combined product: --bins" noenhanced
set logscale xy
set xlabel 'render time (s)'
set ylabel 'relMSE vs reference'
set grid xtics ytics mxtics mytics
set key outside right top noenhanced
plot 'knobs-bins.dat' index 0 with linespoints lw 2 pt 7 title "--bins default", 'knobs-bins.dat' index 1 with linespoints lw 2 pt 7 title "--bins 64", 'knobs-bins.dat' index 2 with linespoints lw 2 pt 7 title "--bins 96", 'knobs-bins.dat' index 3 with linespoints lw 2 pt 7 title "--bins 192", 'knobs-bins.dat' index 4 with linespoints lw 2 pt 7 title "--bins 256", 'knobs-bins.dat' index 5 with linespoints lw 2 pt 7 title "--bins 384", 0.00457758/x with lines dt 2 lc rgb 'gray40' title "∝ 1/t"
