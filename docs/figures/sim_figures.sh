#!/bin/sh
# The sim figures in docs/sim.md: runs tryon-bench-sim, keeps each final JSON line in
# $OUT/*.jsonl, and draws docs/figures/sim_*.png with gnuplot.
# usage: docs/figures/sim_figures.sh BUILD_DIR [SECTION...]   (e.g. build; sections: body iters
#        verts stability, all by default; a section left out keeps its data from an earlier run)
set -eu
B=${1:-build-sima}
[ $# -gt 0 ] && shift
SECTIONS=${*:-body iters verts stability}
want() { case " $SECTIONS " in *" $1 "*) return 0 ;; *) return 1 ;; esac; }
BENCH=$B/sim/tryon-bench-sim
OUT=$B/sim-figures
FIG=$(dirname "$0")
mkdir -p "$OUT"
run() { "$BENCH" --cache-dir "$OUT" "$@" | tail -n 1; }

# 1. the headline: body scene, all motions (16.5 s), 7,000 vertices, 25 iterations
if want body; then
: > "$OUT/body.jsonl"
run --scene body --verts 7000 --iterations 25 --solver tryon --backend c --window-ref \
    >> "$OUT/body.jsonl"
run --scene body --verts 7000 --iterations 25 --solver tryon --backend opencl \
    >> "$OUT/body.jsonl" || true
run --scene body --verts 7000 --frames 60 --iterations 25 --solver seed --backend c \
    >> "$OUT/body.jsonl"
fi

# 2. iterations 5..60, body scene (7,000 vertices, 150 frames), one reference for all (200);
#    the C backend also against references restarted from its own state every 10 frames
if want iters; then
: > "$OUT/iters.jsonl"
# (the seed only at 25: it searches contacts every step and retries diverged frames with 2x
# and 4x the iterations, minutes per run here)
for it in 5 10 15 25 40 60; do
  run --scene body --verts 7000 --frames 150 --iterations $it \
      --solver tryon --backend c --window-ref >> "$OUT/iters.jsonl"
  run --scene body --verts 7000 --frames 150 --iterations $it \
      --solver tryon --backend opencl >> "$OUT/iters.jsonl" || true
done
run --scene body --verts 7000 --frames 60 --iterations 25 \
    --solver seed --backend c >> "$OUT/iters.jsonl"
fi

# 3. vertices 2K..30K, drape scene (3 s), 25 iterations
if want verts; then
: > "$OUT/verts.jsonl"
for n in 2000 4000 7056 15000 30000; do
  W=; [ $n = 7056 ] && W=--window-ref  # Bullet's size: also the windowed error
  run --scene drape --verts $n --iterations 25 --solver tryon --backend c $W >> "$OUT/verts.jsonl"
  run --scene drape --verts $n --iterations 25 --solver tryon --backend opencl \
      >> "$OUT/verts.jsonl" || true
done
for n in 2000 7056; do
  run --scene drape --verts $n --iterations 25 --solver seed --backend c >> "$OUT/verts.jsonl"
done
# Bullet's soft-body cloth on the same drape (tryon-bench-bullet, when libbullet-dev is there):
# one step per frame, 25 solver iterations, the cloth's thickness as its margin (4 mm), and the
# margin Bullet needs to keep the sheet out of the sphere at one step a frame (20 mm)
: > "$OUT/bullet.jsonl"
if [ -x "$B/sim/tryon-bench-bullet" ]; then
  for n in 2000 4000 7056 15000 30000; do
    "$B/sim/tryon-bench-bullet" --verts $n --iterations 25 | tail -n 1 >> "$OUT/bullet.jsonl"
  done
  "$B/sim/tryon-bench-bullet" --verts 7056 --iterations 25 --margin-mm 20 | tail -n 1 \
      >> "$OUT/bullet.jsonl"
fi
fi

# 4. stability map: drape, 1,024 vertices, 1 s; step size (iterations) x stretch stiffness
if want stability; then
: > "$OUT/stability.jsonl"
for s in tryon seed; do
  for it in 5 10 25 50; do
    for k in 100 1000 10000 100000; do
      run --scene drape --verts 1024 --frames 30 --iterations $it --stretch $k --solver $s \
          --backend c --no-ref >> "$OUT/stability.jsonl"
    done
  done
done
fi

# jsonl -> whitespace tables for gnuplot
python3 - "$OUT" <<'PY'
import json, sys, os
out = sys.argv[1]
def rows(name):
    return [json.loads(l) for l in open(os.path.join(out, name)) if l.startswith('{')]
for name, key in (('iters.jsonl', 'iterations'), ('verts.jsonl', 'verts')):
    groups = {}
    for r in rows(name):
        groups.setdefault(r['solver'] + '-' + r['backend'], []).append(r)
    for g, rs in groups.items():
        with open(os.path.join(out, name.split('.')[0] + '-' + g + '.dat'), 'w') as f:
            for r in sorted(rs, key=lambda r: r[key]):
                w = r.get('cloth_error_window_mm', -1)
                f.write('%d %.3f %.3f %.5f %.5f %.2f %s\n' % (r[key], r['ms_median'],
                        r['ms_median_no_metrics'], r['max_strain'], r['p99_strain'],
                        r['cloth_error_mm'], '%.2f' % w if w >= 0 else 'NaN'))
with open(os.path.join(out, 'verts-bullet.dat'), 'w') as f:
    for r in sorted((r for r in rows('bullet.jsonl') if r['margin_mm'] == 4),
                    key=lambda r: r['verts']):
        f.write('%d %.3f %.3f %.5f %.5f %d\n' % (r['verts'], r['ms_median'], r['ms_median'],
                r['max_strain'], r['p99_strain'], r['penetrating']))
# stability map: one block per solver, x = iteration count index, y = stiffness index
for solver in ('tryon', 'seed'):
    rs = [r for r in rows('stability.jsonl') if r['solver'] == solver]
    its = sorted({r['iterations'] for r in rs})
    ks = sorted({r['stretch_n_m'] for r in rs})
    with open(os.path.join(out, 'stability-' + solver + '.dat'), 'w') as f:
        for r in rs:
            f.write('%d %d %d %.1f %d %g\n' % (its.index(r['iterations']),
                    ks.index(r['stretch_n_m']), r['diverged_frames'], 100 * r['max_strain'],
                    r['iterations'], r['stretch_n_m']))
with open(os.path.join(out, 'stability.txt'), 'w') as f:
    for r in rows('stability.jsonl'):
        f.write('%s %d %g %d %d %.4f\n' % (r['solver'], r['iterations'], r['stretch_n_m'],
                r['diverged_frames'], r['recovered_frames'], r['max_strain']))
PY

gnuplot <<GP
set terminal pngcairo size 900,420 font ",10"
set key outside
set grid
set output "$FIG/sim_iterations.png"
set multiplot layout 1,2 title "body scene, 7,000 vertices: iterations 5..60 (labels)"
set logscale x
set xlabel "ms per frame (median, all work; log)"
set ylabel "cloth error, mm (RMS to the 200-iteration reference)"
plot for [g in "tryon-c seed-c tryon-opencl"] "$OUT/iters-".g.".dat" u 2:6 w lp t g, \
     "$OUT/iters-tryon-c.dat" u 2:6:1 w labels offset 1,0.5 notitle, \
     "$OUT/iters-tryon-c.dat" u 2:7 w lp dt 2 t "tryon-c, 10-frame windows"
set ylabel "max stretch strain after 1 s"
plot for [g in "tryon-c seed-c tryon-opencl"] "$OUT/iters-".g.".dat" u 2:4 w lp t g
unset multiplot
unset logscale x
set output "$FIG/sim_vertices.png"
set multiplot layout 1,2 title "drape scene, 25 iterations: 2K..30K vertices"
set logscale xy
set xlabel "vertices"
set ylabel "ms per frame (median)"
plot for [g in "tryon-c seed-c tryon-opencl bullet"] "$OUT/verts-".g.".dat" u 1:2 w lp t g
unset logscale y
set ylabel "max stretch strain after 1 s"
plot for [g in "tryon-c seed-c tryon-opencl bullet"] "$OUT/verts-".g.".dat" u 1:4 w lp t g
unset multiplot
set output "$FIG/sim_stability.png"
unset logscale
set multiplot layout 1,2 title "stability map: drape, 1,024 vertices, 30 frames; colour = frames diverged, label = max strain %"
set xlabel "iterations per frame (time step = 33.3 ms / iterations)"
set ylabel "stretch stiffness, N/m"
set xtics ("5" 0, "10" 1, "25" 2, "50" 3)
set ytics ("100" 0, "1000" 1, "10^4" 2, "10^5" 3)
set cbrange [0:30]
set palette defined (0 "#e8f5e9", 1 "#fff59d", 30 "#c62828")
set xrange [-0.5:3.5]
set yrange [-0.5:3.5]
unset key
set title "tryon (XPBD + strain limit + tethers)"
plot "$OUT/stability-tryon.dat" u 1:2:3 w image, "" u 1:2:(sprintf("%d / %.0f%%", \$3, \$4)) w labels
set title "seed (explicit springs + Provot)"
plot "$OUT/stability-seed.dat" u 1:2:3 w image, "" u 1:2:(sprintf("%d / %.0f%%", \$3, \$4)) w labels
unset multiplot
GP
echo "figures in $FIG, data in $OUT"
