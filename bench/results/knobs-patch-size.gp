# regenerate: cd /work/main/bench/results && gnuplot knobs-patch-size.gp
set terminal pngcairo size 900,600 font ',11'
set output 'knobs-patch-size.png'
set title "cornell-glossy, combined product: --patch-size" noenhanced
set logscale xy
set xlabel 'render time (s)'
set ylabel 'relMSE vs reference'
set grid xtics ytics mxtics mytics
set key outside right top noenhanced
plot 'knobs-patch-size.dat' index 0 with linespoints lw 2 pt 7 title "--patch-size default", 'knobs-patch-size.dat' index 1 with linespoints lw 2 pt 7 title "--patch-size 0.1", 'knobs-patch-size.dat' index 2 with linespoints lw 2 pt 7 title "--patch-size 0.07", 'knobs-patch-size.dat' index 3 with linespoints lw 2 pt 7 title "--patch-size 0.035", 'knobs-patch-size.dat' index 4 with linespoints lw 2 pt 7 title "--patch-size 0.025", 'knobs-patch-size.dat' index 5 with linespoints lw 2 pt 7 title "--patch-size 0.0175", 0.00457758/x with lines dt 2 lc rgb 'gray40' title "∝ 1/t"
