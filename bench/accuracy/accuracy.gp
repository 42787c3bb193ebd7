# bench/accuracy.sh's plot: gnuplot -e "dat='...'; out='...'" bench/accuracy/accuracy.gp
set terminal pngcairo size 1200,500
set output out
set multiplot layout 1,2 title 'Triangle tests: the trade (bench/results/accuracy.md)'
set title 'kd kernels (bunny00): time per primary frame against escapes'
set xlabel 'ms per primary frame (1 thread, shared machine)'
set ylabel 'escaping vertex-aimed inside rays (%)'
set grid
set key top right
plot dat index 0 using 1:2 with points pt 7 ps 1.5 title 'watertight', \
     dat index 0 using 1:2:3 with labels offset 0,1 notitle, \
     dat index 1 using 1:2 with points pt 5 ps 1.5 title 'projected', \
     dat index 1 using 1:2:3 with labels offset 0,-1 notitle
set title 'UV sphere: escapes per placement (s: scale, o: offset)'
set xlabel 'placement'
set ylabel 'escaping vertex-aimed inside rays (%)'
set xtics rotate by -45
set yrange [-1:*]
plot dat index 2 using 1:2:xtic(3) with linespoints pt 7 title 'kd mft watertight', \
     dat index 3 using 1:2 with linespoints pt 5 title 'kd mft projected', \
     dat index 4 using 1:2 with linespoints pt 9 title 'bvh-mft projected', \
     dat index 5 using 1:2 with linespoints pt 11 title 'Embree (robust)'
unset multiplot
