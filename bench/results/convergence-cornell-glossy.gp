# regenerate: cd /work/main/bench/results && gnuplot convergence-cornell-glossy.gp
set terminal pngcairo size 900,600 font ',11'
set output 'convergence-cornell-glossy.png'
set title "cornell-glossy: relMSE vs render time" noenhanced
set logscale xy
set xlabel 'render time (s)'
set ylabel 'relMSE vs reference'
set grid xtics ytics mxtics mytics
set key outside right top noenhanced
plot 'convergence-cornell-glossy.dat' index 0 with linespoints lw 2 pt 7 title "pt", 'convergence-cornell-glossy.dat' index 1 with linespoints lw 2 pt 7 title "pt-no-light-sampling", 'convergence-cornell-glossy.dat' index 2 with linespoints lw 2 pt 7 title "rb", 'convergence-cornell-glossy.dat' index 3 with linespoints lw 2 pt 7 title "combined-paper", 'convergence-cornell-glossy.dat' index 4 with linespoints lw 2 pt 7 title "combined-product", 'convergence-cornell-glossy.dat' index 5 with linespoints lw 2 pt 7 title "combined-product-no-light-sampling", 0.0171179/x with lines dt 2 lc rgb 'gray40' title "∝ 1/t"
