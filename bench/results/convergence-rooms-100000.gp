# regenerate: cd /work/main/bench/results && gnuplot convergence-rooms-100000.gp
set terminal pngcairo size 900,600 font ',11'
set output 'convergence-rooms-100000.png'
set title "rooms-100000: relMSE vs render time" noenhanced
set logscale xy
set xlabel 'render time (s)'
set ylabel 'relMSE vs reference'
set grid xtics ytics mxtics mytics
set key outside right top noenhanced
plot 'convergence-rooms-100000.dat' index 0 with linespoints lw 2 pt 7 title "pt", 'convergence-rooms-100000.dat' index 1 with linespoints lw 2 pt 7 title "pt-no-light-sampling", 'convergence-rooms-100000.dat' index 2 with linespoints lw 2 pt 7 title "rb", 'convergence-rooms-100000.dat' index 3 with linespoints lw 2 pt 7 title "combined-paper", 'convergence-rooms-100000.dat' index 4 with linespoints lw 2 pt 7 title "combined-product", 'convergence-rooms-100000.dat' index 5 with linespoints lw 2 pt 7 title "combined-product-no-light-sampling", 0.0846807/x with lines dt 2 lc rgb 'gray40' title "∝ 1/t"
