#!/bin/sh
# The figures of docs/body-model.md, "The skin where parts meet": how much of the posed body's
# skin lies inside another part (tryon-probe-motion's skin_inside, skin_arms, skin_thighs: body
# vertices 2 mm out along their normal still inside the body) on arms_down, boxing_guard and the
# three clips of Debian's assimp-testmodels; test_bodyfit_contact's own count (vertices > 2 mm
# inside another part, plain skinning against the contact pass); the time of posing; then the
# garments on the lowered arms: the T-shirt M on arms_down and boxing_guard (180 frames), the tube
# shirt on arms_down, and the tube shirt on the first 300 frames of 01_01.bvh (7,000 vertices, 25
# iterations, C backend).
# usage: docs/figures/skin_figures.sh BUILD_DIR [BEFORE_BUILD_DIR]
#        BEFORE_BUILD_DIR: a Release build of the code before the contact pass; every row is run
#        on it too (test_bodyfit_contact, which needs the pass, is not)
#        TRYON_BVH_DIR: where the clips are (default /usr/share/assimp/models/BVH)
# About 10 minutes a build on 2 cores (the T-shirt rows are most of it).
set -eu
B=${1:?usage: $0 BUILD_DIR [BEFORE_BUILD_DIR]}
BEFORE=${2:-}
BVH=${TRYON_BVH_DIR:-/usr/share/assimp/models/BVH}
export OMP_WAIT_POLICY=passive

skin() { # BUILD: one row per motion; the shirt is irrelevant to the skin columns, so the smallest
    OUT=$(mktemp -d)
    for m in arms_down boxing_guard "$BVH/01_01.bvh" "$BVH/01_03.bvh" "$BVH/Boxing_Toes.bvh"; do
        "$1/sim/tryon-probe-motion" --motion "$m" --verts 200 --iterations 1 \
            > "$OUT/$(basename "$m" .bvh).csv"
    done
    python3 - "$OUT" <<'PY'
import csv, glob, os, sys
print("%-14s %6s %8s %9s %9s %9s %9s %9s" % ("motion", "frames", "frames>0", "max", "mean",
      "arms_max", "thigh_max", "thigh_mean"))
for m in ("arms_down", "boxing_guard", "01_01", "01_03", "Boxing_Toes"):
    r = list(csv.DictReader(open(os.path.join(sys.argv[1], m + ".csv"))))
    g = lambda k: [int(x[k]) for x in r]
    s, a, t = g("skin_inside"), g("skin_arms"), g("skin_thighs")
    print("%-14s %6d %8d %9d %9.1f %9d %9d %9.1f" % (m, len(r), sum(x > 0 for x in s), max(s),
          sum(s) / len(r), max(a), max(t), sum(t) / len(r)))
PY
    rm -rf "$OUT"
}

garment() { # BUILD
    row() {
        python3 -c '
import json, sys
j = json.loads(sys.stdin.read().strip().splitlines()[-1])
print("%-22s %6d %7d %6d %6.1f %6.1f %7.1f %6.2f %8.1f %7.1f" % (sys.argv[1], j["frames"],
      j["carried_frames"], j["penetrating"], j["max_pen_mm"], j["pen_free_frames_pct"],
      100 * j["max_strain"], 100 * j["p99_strain"], j["strain_ok_frames_pct"], j["ms_median"]))' "$1"
    }
    S="$1/sim/tryon-bench-sim --scene body --verts 7000 --iterations 25 --backend c --no-ref"
    echo "motion                 frames carried inside pen_mm pen0_% max_str% p99_% strain_% ms_med"
    for m in arms_down boxing_guard; do
        $S --garment garments/patterns/tshirt.json --motion $m --frames 180 | row "tshirt $m"
    done
    $S --motion arms_down | row "tube shirt arms_down"
    $S --motion "$BVH/01_01.bvh" --frames 300 | row "tube shirt 01_01 300"
}

echo "== skin inside another part, vertices a frame (tryon-probe-motion), $B"
skin "$B"
if [ -n "$BEFORE" ]; then
    echo "== the same, $BEFORE"
    skin "$BEFORE"
fi
echo "== test_bodyfit_contact (6,000 vertices; vertices > 2 mm inside another part)"
"$B/tests/bodyfit/test_bodyfit_contact" | grep '^#'
echo "== posing time (tryon-bench-skin 2000 [arms_down]: skinning and the contact pass)"
"$B/bodyfit/tryon-bench-skin" 2000 | tail -1
"$B/bodyfit/tryon-bench-skin" 2000 arms_down | tail -1
if [ -n "$BEFORE" ]; then
    echo "== the same, $BEFORE (skinning alone)"
    "$BEFORE/bodyfit/tryon-bench-skin" 2000 | tail -1
fi
echo "== garments, $B"
garment "$B"
if [ -n "$BEFORE" ]; then
    echo "== garments, $BEFORE"
    garment "$BEFORE"
fi
