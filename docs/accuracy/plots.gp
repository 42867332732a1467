# gnuplot script written by hydrotex_accuracy_report; run in this directory.
set terminal png size 900,600
set grid
set logscale xy
set key bottom left
set output 'error_vs_time.png'
set title 'Sphere: worst error (volume, centre of buoyancy) against time per query'
set xlabel 'time per query (us, one thread)'
set ylabel 'relative error'
plot 'plot_texture-hierarchy.dat' using 2:3 with linespoints title 'texture-hierarchy', '' using 2:3:(sprintf('%d', $1)) with labels offset 0,1 notitle, 'plot_texture-brute-force.dat' using 2:3 with linespoints title 'texture-brute-force', '' using 2:3:(sprintf('%d', $1)) with labels offset 0,1 notitle, 'plot_texture-gpu.dat' using 2:3 with linespoints title 'texture-gpu', '' using 2:3:(sprintf('%d', $1)) with labels offset 0,1 notitle, 'plot_exact.dat' using 1:2 with points pt 7 ps 2 title 'exact (mesh vs true sphere)'
set output 'time_vs_resolution.png'
set title 'Sphere: time per query against resolution'
set xlabel 'texels per side'
set ylabel 'time per query (us)'
set key top left
plot 'plot_texture-hierarchy.dat' using 1:2 with linespoints title 'texture-hierarchy', 'plot_texture-brute-force.dat' using 1:2 with linespoints title 'texture-brute-force', 'plot_texture-gpu.dat' using 1:2 with linespoints title 'texture-gpu', x**2/2000 with lines dt 2 title 'slope 2 (area)', x/20 with lines dt 3 title 'slope 1 (waterline)'
set output 'mesh_independence.png'
set title 'Sphere: time per query against triangle count'
set xlabel 'triangles'
set ylabel 'time per query (us)'
plot 'plot_tessellation.dat' using 1:2 with linespoints title 'exact', '' using 1:3 with linespoints title 'texture hierarchy 512^2', '' using 1:4 with linespoints title 'texture brute force 512^2'
