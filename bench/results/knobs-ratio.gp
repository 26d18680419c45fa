# regenerate: cd /work/main/bench/results && gnuplot knobs-ratio.gp
set terminal pngcairo size 900,600 font ',11'
set output 'knobs-ratio.png'
set title "cornell-glossy, combined product: --ratio" noenhanced
set logscale xy
set xlabel 'render time (s)'
set ylabel 'relMSE vs reference'
set grid xtics ytics mxtics mytics
set key outside right top noenhanced
plot 'knobs-ratio.dat' index 0 with linespoints lw 2 pt 7 title "--ratio default", 'knobs-ratio.dat' index 1 with linespoints lw 2 pt 7 title "--ratio 4", 'knobs-ratio.dat' index 2 with linespoints lw 2 pt 7 title "--ratio 1", 'knobs-ratio.dat' index 3 with linespoints lw 2 pt 7 title "--ratio 1/16", 'knobs-ratio.dat' index 4 with linespoints lw 2 pt 7 title "--ratio 1/64", 0.00457758/x with lines dt 2 lc rgb 'gray40' title "∝ 1/t"
