#!/bin/sh
# The hem over a raised thigh (docs/sim-real-motion.md, "Real motion: the causes"; the diary in
# docs/sim-history-6.md, "The hem over a raised thigh: the steps"): the march with its rotations
# doubled (walk@0.5,2: thighs to 69 degrees), 90 frames, the shirt at 7,000 vertices, C backend,
# no strain retries (what a frame's own steps reach), at 25, 50, 100 and 200 steps a frame; then
# the hem rows' perimeters at frame 81 (the thigh at its highest) at 25 and 100 steps against
# the first frame's (the shirt as made), and the hem row's springs by tens of columns.
# Counts and strains do not depend on the load; the times do.
# usage: docs/figures/hem_figures.sh BUILD_DIR
set -eu
B=${1:-build}
M=walk@0.5,2
printf '%-7s %9s %8s %9s %7s %7s\n' steps max_str% p99_% within_% settle ms_med
for it in 25 50 100 200; do
  "$B/sim/tryon-bench-sim" --scene body --verts 7000 --iterations "$it" --no-ref --backend c \
      --motion "$M" --frames 90 --strain-retry -1 2>/dev/null | tail -n 1 |
    python3 -c "
import json, sys
j = json.load(sys.stdin)
print('%-7d %9.1f %8.2f %9.1f %7d %7.1f' % ($it, 100 * j['max_strain'], 100 * j['p99_strain'],
      j['strain_ok_frames_pct'], j['settle_frames'], j['ms_median']))"
done
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
# as made: frame 0 (the steps do not matter); then frame 81 at 25 and 100 steps
for run in 0:25:0 81:25:25 81:100:100; do
  frame=${run%%:*}
  rest=${run#*:}
  (cd "$T" && "$OLDPWD/$B/sim/tryon-probe-motion" --motion "$M" --frames $((frame + 1)) \
      --verts 7000 --iterations "${rest%%:*}" --dump "$frame" >/dev/null 2>&1 &&
      mv probe-cloth.xyz "cloth_${rest#*:}.xyz")
done
python3 - "$T" <<'PY'
import math, sys
def load(f):
    d = {}
    for l in open(f):
        p = l.split()
        if len(p) >= 6 and not l.startswith('#'):
            d[(int(p[4]), int(p[5]))] = tuple(map(float, p[:3]))
    return d
rest = load(sys.argv[1] + '/cloth_0.xyz')
rows = max(r for r, _ in rest) + 1
cols = max(c for _, c in rest) + 1
def seg(d, r, c):
    return math.dist(d[(r, c)], d[(r, (c + 1) % cols)])
print('\nperimeter of the last rows, m (row 0 at the top; %d columns)' % cols)
print('%-12s' % 'steps' + ''.join('%8d' % r for r in range(rows - 5, rows)))
for name in ('0', '25', '100'):
    d = load(sys.argv[1] + '/cloth_%s.xyz' % name)
    label = 'as made' if name == '0' else name
    print('%-12s' % label + ''.join('%8.4f' % sum(seg(d, r, c) for c in range(cols))
                                    for r in range(rows - 5, rows)))
print('\nthe hem row, frame 81: mean strain (per cent) of its springs by tens of columns')
for name in ('25', '100'):
    d = load(sys.argv[1] + '/cloth_%s.xyz' % name)
    s = [seg(d, rows - 1, c) / seg(rest, rows - 1, c) - 1 for c in range(cols)]
    print('%-4s' % name + ' '.join('%+5.1f' % (100 * sum(s[i:i + 10]) / len(s[i:i + 10]))
                                   for i in range(0, cols, 10)))
PY
