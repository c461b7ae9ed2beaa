#!/bin/sh
# The causes behind the motion-capture clips' strain (docs/sim-real-motion.md, "Real motion: the causes"):
# tryon-probe-motion on the three clips of Debian's assimp-testmodels (7,000-vertex shirt, 25
# iterations, C backend), one CSV a clip in $OUT, then the frames over the strain goals (max > 3 %
# or p99 > 1 %) by what the body does: thigh flexion (the angle between thigh and trunk), trunk
# bend, upper arm against the trunk, and skin passing through itself at the thighs and the arms;
# then the march with its joint rotations scaled (tryon-bench-sim --motion walk@0.5,AMOUNT: the
# thighs raised 34, 52, 69, 86 degrees), the cause reproduced without motion capture.
# usage: docs/figures/clips_figures.sh BUILD_DIR [CLIP_FRAMES]   (0 or none: whole clips)
#        TRYON_BVH_DIR: where the clips are (default /usr/share/assimp/models/BVH)
set -eu
B=${1:-build}
FRAMES=${2:-0}
OUT=$B/clips-figures
BVH=${TRYON_BVH_DIR:-/usr/share/assimp/models/BVH}
mkdir -p "$OUT"
for c in 01_01 01_03 Boxing_Toes; do
    if [ "$FRAMES" -gt 0 ]; then
        "$B/sim/tryon-probe-motion" --motion "$BVH/$c.bvh" --frames "$FRAMES" > "$OUT/$c.csv"
    else
        "$B/sim/tryon-probe-motion" --motion "$BVH/$c.bvh" > "$OUT/$c.csv"
    fi
done
python3 - "$OUT" <<'PY'
import csv, os, sys
out = sys.argv[1]
def f(x, k): return float(x[k])
def bad(x): return f(x, "max_strain_pct") > 3 or f(x, "p99_pct") > 1
axes = [("thigh flexion, deg", lambda x: max(f(x, "thigh_l_deg"), f(x, "thigh_r_deg")),
         [0, 15, 30, 45, 60, 90, 180]),
        ("trunk bend, deg", lambda x: f(x, "bend_deg"), [0, 10, 20, 30, 40, 60, 180]),
        ("upper arm to trunk (lower arm), deg",
         lambda x: min(f(x, "arm_l_deg"), f(x, "arm_r_deg")), [0, 10, 20, 40, 90, 180]),
        ("skin inside at the thighs, vertices", lambda x: f(x, "skin_thighs"), [0, 1, 20, 60, 1e9]),
        ("skin inside at the arms, vertices", lambda x: f(x, "skin_arms"), [0, 1, 20, 60, 1e9])]
for c in ("01_01", "01_03", "Boxing_Toes"):
    rows = [x for x in csv.DictReader(open(os.path.join(out, c + ".csv")))][30:]  # after the turn-in
    print("%s: %d frames after the turn-in, %d over the goals, %d carried; root <= %.2f m/s" % (
        c, len(rows), sum(map(bad, rows)), sum(x["state"] == "4" for x in rows),
        max(f(x, "root_speed") for x in rows)))
    for name, key, edges in axes:
        print("  by %s" % name)
        for lo, hi in zip(edges[:-1], edges[1:]):
            g = [x for x in rows if lo <= key(x) < hi]
            if not g:
                continue
            n = sum(int(x["over"]) for x in g) or 1
            part = lambda k: 100.0 * sum(int(x[k]) for x in g) / n
            print("    %5g-%-5g %4d frames  over the goals %5.1f %%  max %5.1f %%  springs > 3 %%: "
                  "%6.1f a frame, top/middle/hem %3.0f/%3.0f/%3.0f %%, front %3.0f %%, near the "
                  "thighs %3.0f %%" % (lo, hi, len(g), 100.0 * sum(map(bad, g)) / len(g),
                  max(f(x, "max_strain_pct") for x in g), n / len(g) if n > 1 else 0.0,
                  part("over_top"), part("over_mid"), part("over_hem"), part("over_front"),
                  part("near_l_thigh") + part("near_r_thigh")))
print("\nfailing frames by the thigh's flexion (frames), and by the thigh's skin inside the body:")
print("| clip | frames | failing | thigh 0-15 deg | 15-30 | 30-45 | 45-60 | past 60 | > 60 thigh skin vertices inside | none inside |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
share = lambda g: "%.0f %% (%d)" % (100.0 * sum(map(bad, g)) / len(g), len(g)) if g else "-"
thigh = lambda x: max(f(x, "thigh_l_deg"), f(x, "thigh_r_deg"))
for c in ("01_01", "01_03", "Boxing_Toes"):
    rows = [x for x in csv.DictReader(open(os.path.join(out, c + ".csv")))][30:]
    cells = [share([x for x in rows if lo <= thigh(x) < hi])
             for lo, hi in ((0, 15), (15, 30), (30, 45), (45, 60), (60, 1000))]
    print("| %s | %d | %.0f %% | %s | %s | %s |" % (c, len(rows), 100.0 * sum(map(bad, rows)) /
          len(rows), " | ".join(cells), share([x for x in rows if f(x, "skin_thighs") > 60]),
          share([x for x in rows if f(x, "skin_thighs") == 0])))
PY
echo "the march, thighs raised further (tryon-bench-sim --motion walk@0.5,AMOUNT --frames 120):"
for a in 1 1.5 2 2.5; do
    "$B/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --backend c --no-ref \
        --motion "walk@0.5,$a" --frames 120 | tail -n 1 | python3 -c "
import json, sys
j = json.loads(sys.stdin.read())
print('  amount $a: max %.1f %%, p99 %.2f %%, frames within 3 %% / 1 %% %.1f %%, inside %d, carried %d' % (
    100 * j['max_strain'], 100 * j['p99_strain'], j['strain_ok_frames_pct'], j['penetrating'],
    j['carried_frames']))"
done
