# regenerate: cd /tmp/sweep1280/res-1280x720/ratio && gnuplot ratio-cornell-box-1280x720.gp
set terminal pngcairo size 900,600 font ',11'
set output 'ratio-cornell-box-1280x720.png'
set title "cornell-box at 1280x720: combined, product weights" noenhanced
set logscale xy
set xlabel 'render time (s)'
set ylabel 'relMSE vs reference'
set grid xtics ytics mxtics mytics
set key outside right top noenhanced
plot 'ratio-cornell-box-1280x720.dat' index 0 with linespoints lw 2 pt 7 title "--ratio 64", 'ratio-cornell-box-1280x720.dat' index 1 with linespoints lw 2 pt 7 title "--ratio 16", 'ratio-cornell-box-1280x720.dat' index 2 with linespoints lw 2 pt 7 title "--ratio 4", 'ratio-cornell-box-1280x720.dat' index 3 with linespoints lw 2 pt 7 title "--ratio 1", 'ratio-cornell-box-1280x720.dat' index 4 with linespoints lw 2 pt 7 title "--ratio 1/4", 'ratio-cornell-box-1280x720.dat' index 5 with linespoints lw 2 pt 7 title "--ratio 1/16", 'ratio-cornell-box-1280x720.dat' index 6 with linespoints lw 2 pt 7 title "--ratio 1/64", 'ratio-cornell-box-1280x720.dat' index 7 with linespoints lw 2 pt 7 title "--ratio 1/256", 'ratio-cornell-box-1280x720.dat' index 8 with linespoints lw 2 pt 7 title "--ratio auto", 0.0734911/x with lines dt 2 lc rgb 'gray40' title "∝ 1/t"
