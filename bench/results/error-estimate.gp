set terminal pngcairo size 720,640 noenhanced
set output 'bench/results/error-estimate.png'
set logscale xy
set xrange [1e-4:1]
set yrange [1e-4:1]
set xlabel 'measured relMSE − reference noise (filled), or two-seed variance (open)'
set ylabel 'estimated relMSE (no reference)'
set key top left
set grid
f(x) = x
set title 'error estimate against measured error, 128, short and long budgets'
plot f(x) lc rgb 'black' title 'estimated = measured', 1.5*x lc rgb 'gray' dt 2 title '×1.5', x/1.5 lc rgb 'gray' dt 2 notitle,   'bench/results/error-estimate.dat' using (strcol(4) eq "pt" ? $3 : 1/0):2 with points pt 7 ps 1.3 title 'pt',   '' using (strcol(4) eq "rb" ? $3 : 1/0):2 with points pt 5 ps 1.3 title 'rb',   '' using (strcol(4) eq "combined" ? $3 : 1/0):2 with points pt 9 ps 1.6 title 'combined',   '' using 5:2 with points pt 6 ps 1.8 lc rgb 'black' title 'x = variance from two seeds (no bias; all modes)'
