# Scaling plots of bench/compare. Called with dir (the .dat files) and img (output directory).
set terminal pngcairo size 640,420 font "sans,10"
set grid
set fit quiet nolog
set key top left

set output img."/scaling_size.png"
set title "Whitted scene, one sample per pixel center, 2 threads"
set xlabel "image size (Mpixels)"
set ylabel "seconds"
f(x) = a * x
a = 0.1
fit f(x) dir."/size.dat" using 1:2 via a
plot dir."/size.dat" using 1:2 with linespoints pt 7 title "render", \
     dir."/size.dat" using 1:3 with linespoints pt 5 title "whole process", \
     f(x) with lines dt 2 title "linear fit through 0 (render)"

set output img."/scaling_triangles.png"
set title "Bunny instanced N times (one mesh, N Embree instances)"
set xlabel "triangles after instancing"
set logscale x
set ylabel "render ms per frame"
set y2label "peak RSS (MiB)"
set ytics nomirror
set y2tics
set yrange [0:*]
set y2range [0:*]
plot dir."/tri.dat" using 1:2 with linespoints pt 7 axes x1y1 title "render ms", \
     dir."/tri.dat" using 1:4 with linespoints pt 5 axes x1y2 title "peak RSS (MiB)"
unset logscale x
unset y2label
unset y2tics
set ytics mirror
set autoscale y

set output img."/scaling_threads.png"
set title "Speed-up with threads (2 cores)"
set xlabel "threads"
set ylabel "speed-up over 1 thread"
set xrange [0.5:2.5]
set yrange [0:2.2]
set xtics 1
set key top left
plot x with lines dt 2 lc rgb "gray" title "ideal", \
     dir."/thr.dat" using 1:(t1 = ($1 == 1 ? $2 : t1), t1 / $2) with linespoints pt 7 title "Whitted scene (render s)", \
     dir."/thr.dat" using 1:(b1 = ($1 == 1 ? $3 : b1), $3 / b1) with linespoints pt 5 title "bunny primary rays (Mrays/s)"
set autoscale x
set autoscale y
set xtics autofreq

set output img."/scaling_coins.png"
set title "Bunny, perspective, N coins (radius 0.04)"
set xlabel "coins"
set ylabel "render ms per frame"
set logscale x 2
set xrange [0.5:*]
set yrange [0:*]
plot dir."/coin.dat" using ($1 == 0 ? 0.5 : $1):2 with linespoints pt 7 title "render ms (0 coins drawn at 0.5)"
