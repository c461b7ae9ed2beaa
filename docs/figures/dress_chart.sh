#!/bin/sh
# The chart of docs/garments.md "Speed against accuracy": each dressing method (with its own
# cloth-body collision: the seed's image space, tryon's BVH) on the T-shirt and the jeans (M,
# cotton) at mesh spacings from 4 to 1.5 cm; dressing time against the seam gap and the vertices
# more than 1 mm inside the body. Data: BUILD_DIR/dress-chart/chart.jsonl; chart:
# docs/figures/dress_chart.png.
# Usage: docs/figures/dress_chart.sh BUILD_DIR   (a Release build)
set -eu
build=${1:?usage: $0 BUILD_DIR}
bench="$build/garments/tryon-bench-dress"
pat="$(dirname "$0")/../../garments/patterns"
fig="$(dirname "$0")"
out="$build/dress-chart"
mkdir -p "$out"
export OMP_WAIT_POLICY=passive OMP_NUM_THREADS=2
: > "$out/chart.jsonl"
for method in seed tryon; do
    for spacing in 0.04 0.03 0.02 0.015; do
        "$bench" --method $method --spacing $spacing "$pat/tshirt.json" "$pat/jeans.json" |
            grep '^{' | sed "s/^{/{\"spacing\": $spacing, /" >> "$out/chart.jsonl"
    done
done
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
rows = [json.loads(l) for l in open(os.path.join(out, 'chart.jsonl'))]
print('%-8s %-6s %-6s %8s %8s %9s %11s %11s %6s' % ('pattern', 'method', 'coll', 'spacing',
      'ms', 'seam_mm', 'penetrating', 'max_strain', 'verts'))
for r in rows:
    name = os.path.basename(r['pattern']).split('.')[0]
    print('%-8s %-6s %-6s %8.3f %8.0f %9.2f %11d %11.3f %6d' % (name, r['method'],
          r['collision'], r['spacing'], r['ms'], r['seam_gap_mm'], r['penetrating'],
          r['max_strain'], r['verts']))
    with open(os.path.join(out, '%s-%s.dat' % (name, r['method'])), 'a') as f:
        f.write('%g %g %g %d %d\n' % (r['spacing'] * 100, r['ms'], r['seam_gap_mm'],
                r['penetrating'], r['verts']))
PY
gnuplot <<GP
set terminal pngcairo size 900,420 font ",10"
set output "$fig/dress_chart.png"
set key outside
set grid
set logscale x
set multiplot layout 1,2 title "dressing from flat panels (M, cotton), mesh spacing 4 to 1.5 cm (labels, cm)"
set xlabel "ms to seamed and settled (2 threads; log)"
set ylabel "seam gap, mm"
plot for [g in "tshirt-seed tshirt-tryon jeans-seed jeans-tryon"] "$out/".g.".dat" u 2:3 w lp t g, \
     for [g in "tshirt-seed jeans-seed"] "$out/".g.".dat" u 2:3:1 w labels offset 1,0.6 notitle
set ylabel "vertices > 1 mm inside the body"
plot for [g in "tshirt-seed tshirt-tryon jeans-seed jeans-tryon"] "$out/".g.".dat" u 2:4 w lp t g
unset multiplot
GP
rm -f "$out"/*.dat
echo "chart: $fig/dress_chart.png"
