set terminal pngcairo size 900,600
set output 'shadows.png'
set title 'Soft shadows: render time (x hard shadows) against RMSE to multi:256, per scene and method'
set xlabel 'render time / hard-shadow render time (log)'
set ylabel 'RMSE against multi:256 (log)'
set logscale xy
set key outside right
set grid
plot 'shadows.dat' index 0 using 1:2 with points pt 5 ps 1.3 title 'hard', 'shadows.dat' index 1 using 1:2 with points pt 6 ps 1.3 title 'edgewidth', 'shadows.dat' index 2 using 1:2 with points pt 7 ps 1.3 title 'edgewidth + leak fix', 'shadows.dat' index 3 using 1:2 with points pt 8 ps 1.3 title 'multi:N', 'shadows.dat' index 4 using 1:2 with points pt 9 ps 1.3 title 'cone:16', 'shadows.dat' index 5 using 1:2 with points pt 10 ps 1.3 title 'pyramid:16', 'shadows.dat' index 6 using 1:2 with points pt 11 ps 1.3 title 'interleaved:N (reference)', 'shadows.dat' index 7 using 1:2 with points pt 12 ps 1.3 title 'interleaved:N:nofilter (reference)', 'shadows.dat' index 8 using 1:2 with points pt 13 ps 1.3 title 'frusta:N', 'shadows.dat' index 9 using 1:2 with points pt 14 ps 1.3 title 'frusta:N:nofilter', 'shadows.dat' index 10 using 1:2 with points pt 15 ps 1.3 title 'frusta:N:refine'
