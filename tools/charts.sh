#!/usr/bin/env bash
# Turns the CSV files of `jetrace-bench study` into the SVG charts of
# docs/ACCURACY.md (gnuplot, Debian package gnuplot-nox).
#
#   tools/charts.sh                  run the full study, then chart it
#   tools/charts.sh --quick          run the quick study (under a minute)
#   tools/charts.sh --csv DIR        chart existing CSV files from DIR
#   options: --out DIR (default docs/charts), --bench PATH (default
#            build/tools/jetrace-bench), --repeats N (study runs per variant)
# The CSV files are copied next to the charts (DIR/data) so every chart can
# be redrawn without rerunning the study.
set -euo pipefail
cd "$(dirname "$0")/.."

csv="" out="docs/charts" bench="build/tools/jetrace-bench" quick="" repeats=5
while [[ $# -gt 0 ]]; do
  case "$1" in
    --csv) csv="${2:?--csv needs a directory}"; shift 2 ;;
    --out) out="${2:?--out needs a directory}"; shift 2 ;;
    --bench) bench="${2:?--bench needs a path}"; shift 2 ;;
    --repeats) repeats="${2:?--repeats needs a number}"; shift 2 ;;
    --quick) quick="--quick"; shift ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "charts.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
command -v gnuplot >/dev/null || { echo "charts.sh: gnuplot not found (apt-get install gnuplot-nox)" >&2; exit 1; }

if [[ -z "$csv" ]]; then
  [[ -x "$bench" ]] || { echo "charts.sh: $bench not built (cmake --build build --target jetrace-bench)" >&2; exit 1; }
  csv="$(mktemp -d)"
  trap 'rm -rf "$csv"' EXIT
  "$bench" study $quick --repeats "$repeats" --out "$csv"
fi
for f in integrators spring resolver tunnelling grid_cell track_size cars pareto; do
  [[ -s "$csv/$f.csv" ]] || { echo "charts.sh: $csv/$f.csv missing or empty" >&2; exit 1; }
done
mkdir -p "$out/data"
[[ "$(cd "$csv" && pwd)" == "$(cd "$out/data" && pwd)" ]] || cp "$csv"/*.csv "$out/data/"

gnuplot <<GNUPLOT
set datafile separator ','
set datafile missing 'nan'
set terminal svg size 900,560 dynamic font 'sans,12' linewidth 1.5
set key top right box opaque
set termoption noenhanced
# Filtered rows are undefined (1/0), which would break plain lines:
# 'smooth unique' joins the defined points of a series in x order.
set grid
D = '$csv'
O = '$out'
integ(s, name) = (strcol(1) eq s && strcol(2) ne 'analytic' || strcol(1) eq s && s ne 'banked_turn') && strcol(3) eq name
ints = 'explicit semi-implicit verlet'
titles = 'explicit\\\\ Euler semi-implicit\\\\ Euler velocity\\\\ Verlet'

# ---------------------------------------------------------------- integrators
set output O.'/integrators.svg'
set multiplot layout 2,2 title 'Integrators: position error against cost (30, 60, 120, 240, 480 Hz; default verlet at 120 Hz circled)'
set logscale xy
set format y '%.0e'
set xlabel 'ns per simulated second (ns per step x Hz)'
set ylabel 'error (m)'
do for [sc in 'ballistic flight_drag ramp_jump banked_turn'] {
  set title sc.(sc eq 'banked_turn' ? ' (vs 7,680 Hz run)' : (sc eq 'flight_drag' ? ' (vs 7,680 Hz run)' : ' (vs analytic)'))
  plot for [i=1:3] D.'/integrators.csv' using 7:(integ(sc, word(ints,i)) ? (\$5 > 1e-15 ? \$5 : 1e-15) : 1/0) \
         smooth unique with linespoints title word(ints,i), \
       D.'/integrators.csv' using 7:(integ(sc, 'verlet') && \$8 == 1 ? (\$5 > 1e-15 ? \$5 : 1e-15) : 1/0) \
         with points pt 6 ps 3 lc rgb 'black' title 'default'
}
unset multiplot

# ---------------------------------------------------------------------- spring
set output O.'/spring.svg'
set title 'Undamped 1 Hz spring, 100,000 steps: largest energy / initial energy'
set logscale xy
set xlabel 'step rate (Hz)'
set ylabel 'max energy ratio'
set xtics (30, 60, 120, 240, 480)
plot for [i=1:3] D.'/spring.csv' using 2:(strcol(1) eq word(ints,i) && \$4 < 1e300 ? \$4 : 1/0) smooth unique with linespoints title word(ints,i)
set xtics autofreq

# -------------------------------------------------------------------- resolver
set output O.'/resolver.svg'
set multiplot layout 1,3 title 'Resolver in a corner of 3 x 48 thin triangles: passes x epsilon (default each-contact, 20 passes, 1/1024 m; dashed: the seed'."'".'s first-contact passes)'
unset logscale
set logscale x
set format y '%g'
set xlabel 'passes'
eps = '0 0.000244140625 0.0009765625 0.00390625 0.015625'
epsn = '0 1/4096 1/1024 1/256 1/64'
set key top right
each(m) = strcol(1) eq 'each-contact'
first(m) = strcol(1) eq 'first-contact'
set title 'deepest penetration at 60 m/s (m)'
set ylabel 'm'
plot for [i=1:5] D.'/resolver.csv' using 2:(each(0) && abs(\$3 - word(eps,i)+0) < 1e-12 ? \$4 : 1/0) smooth unique with linespoints lc i title 'eps '.word(epsn,i), \
     for [i=1:3:2] D.'/resolver.csv' using 2:(first(0) && abs(\$3 - word(eps,i)+0) < 1e-12 ? \$4 : 1/0) smooth unique with linespoints lc i dt 2 title 'first-contact, eps '.word(epsn,i)
set title 'jitter held in the corner (m/step)'
plot for [i=1:5] D.'/resolver.csv' using 2:(each(0) && abs(\$3 - word(eps,i)+0) < 1e-12 ? \$7 : 1/0) smooth unique with linespoints lc i title 'eps '.word(epsn,i), \
     for [i=1:3:2] D.'/resolver.csv' using 2:(first(0) && abs(\$3 - word(eps,i)+0) < 1e-12 ? \$7 : 1/0) smooth unique with linespoints lc i dt 2 title 'first-contact, eps '.word(epsn,i)
set title 'cost held in the corner (ns/step)'
set ylabel 'ns per step'
plot for [i=1:5] D.'/resolver.csv' using 2:(each(0) && abs(\$3 - word(eps,i)+0) < 1e-12 ? \$9 : 1/0) smooth unique with linespoints lc i title 'eps '.word(epsn,i), \
     for [i=1:3:2] D.'/resolver.csv' using 2:(first(0) && abs(\$3 - word(eps,i)+0) < 1e-12 ? \$9 : 1/0) smooth unique with linespoints lc i dt 2 title 'first-contact, eps '.word(epsn,i)
unset multiplot

# ------------------------------------------------------------------ tunnelling
set output O.'/tunnelling.svg'
set title 'Thin wall: highest speed with no pass-through at any approach (probed to 4,000 m/s)'
set logscale xy
set xlabel 'step rate (Hz)'
set ylabel 'speed (m/s)'
set xtics (30, 60, 120, 240, 480)
set key bottom right
plot D.'/tunnelling.csv' using 2:(strcol(1) eq 'discrete' ? \$3 : 1/0) smooth unique with linespoints pt 7 title 'discrete push-out', \
     D.'/tunnelling.csv' using 2:(strcol(1) eq 'swept' ? \$3 : 1/0) smooth unique with linespoints pt 5 title 'swept', \
     D.'/tunnelling.csv' using 2:(strcol(1) eq 'discrete' ? \$6 : 1/0) with lines dt 2 title 'r / dt', \
     D.'/tunnelling.csv' using 2:(strcol(1) eq 'discrete' ? \$7 : 1/0) with lines dt 3 title 'car top speed (365 m/s)', \
     D.'/tunnelling.csv' using 2:(\$8 == 1 ? \$3 : 1/0) with points pt 6 ps 3 lc rgb 'black' title 'default'
set xtics autofreq

# ------------------------------------------------------------------- grid cell
set output O.'/grid_cell.svg'
set title 'Grid cell edge on stadium (8 AI cars): cost and memory (default circled)'
set logscale x
unset logscale y
set logscale y2
set xlabel 'cell edge (m)'
set ylabel 'ns per car-step'
set y2label 'grid memory (bytes)'
set y2tics
set yrange [0:*]
set key top center
plot D.'/grid_cell.csv' using 1:6 smooth unique with linespoints pt 7 title 'ns per car-step', \
     D.'/grid_cell.csv' using 1:4 axes x1y2 smooth unique with linespoints pt 5 title 'memory', \
     D.'/grid_cell.csv' using 1:(\$7 == 1 ? \$6 : 1/0) with points pt 6 ps 3 lc rgb 'black' title 'default'
unset y2tics
unset y2label
unset logscale y2
set yrange [*:*]

# ------------------------------------------------------------------ track size
set output O.'/track_size.svg'
set multiplot layout 1,2 title 'Track size: 8 AI cars; refined = finer stadium floor, tiled = n x n stadiums'
set logscale xy
set xlabel 'triangles'
set key top left
set title 'cost'
set ylabel 'ns per car-step'
plot D.'/track_size.csv' using 3:(strcol(1) eq 'refined' ? \$7 : 1/0) smooth unique with linespoints pt 7 title 'refined', \
     D.'/track_size.csv' using 3:(strcol(1) eq 'refined_cell5' ? \$7 : 1/0) smooth unique with linespoints pt 9 title 'refined, 5 m cells', \
     D.'/track_size.csv' using 3:(strcol(1) eq 'tiled' ? \$7 : 1/0) smooth unique with linespoints pt 5 title 'tiled'
set title 'grid build'
set ylabel 'ms'
plot D.'/track_size.csv' using 3:(strcol(1) eq 'refined' ? \$6 : 1/0) smooth unique with linespoints pt 7 title 'refined', \
     D.'/track_size.csv' using 3:(strcol(1) eq 'tiled' ? \$6 : 1/0) smooth unique with linespoints pt 5 title 'tiled'
unset multiplot

# ------------------------------------------------------------------------ cars
set output O.'/cars.svg'
set title 'Cars on stadium with car-car collisions (all pairs)'
set logscale xy
set xlabel 'cars'
set ylabel 'ns'
set key top left
plot D.'/cars.csv' using 1:2 smooth unique with linespoints pt 7 title 'ns per tick (step)', \
     D.'/cars.csv' using 1:4 smooth unique with linespoints pt 5 title 'ns per tick in collide_cars', \
     D.'/cars.csv' using 1:3 smooth unique with linespoints pt 9 title 'ns per car-step'

# ---------------------------------------------------------------------- pareto
set output O.'/pareto.svg'
set multiplot layout 1,2 title 'Pareto: every variant a point, the front joined, the default circled'
set logscale xy
set key top right
set title 'integration (integrator x rate): flight with drag'
set xlabel 'ns per simulated second'
set ylabel 'position error after 4 s (m)'
plot D.'/pareto.csv' using 3:(strcol(1) eq 'integration' ? \$4 : 1/0) with points pt 7 title 'variant', \
     D.'/pareto.csv' using 3:(strcol(1) eq 'integration' && \$6 == 1 ? \$4 : 1/0) smooth unique with linespoints pt 5 title 'front', \
     D.'/pareto.csv' using 3:(strcol(1) eq 'integration' && \$5 == 1 ? \$4 : 1/0) with points pt 6 ps 3 lc rgb 'black' title 'default'
set title 'resolver (passes x epsilon): corner at 60 m/s'
set xlabel 'ns per step held in the corner'
set ylabel 'deepest penetration (m, 1e-4 = none)'
plot D.'/pareto.csv' using 3:(strcol(1) eq 'resolver' ? (\$4 > 1e-4 ? \$4 : 1e-4) : 1/0) with points pt 7 title 'variant', \
     D.'/pareto.csv' using 3:(strcol(1) eq 'resolver' && \$6 == 1 ? (\$4 > 1e-4 ? \$4 : 1e-4) : 1/0) smooth unique with linespoints pt 5 title 'front', \
     D.'/pareto.csv' using 3:(strcol(1) eq 'resolver' && \$5 == 1 ? (\$4 > 1e-4 ? \$4 : 1e-4) : 1/0) with points pt 6 ps 3 lc rgb 'black' title 'default'
unset multiplot
GNUPLOT
ls -la "$out"/*.svg
