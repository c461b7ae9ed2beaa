#!/bin/sh
# The real-motion figures in docs/sim-real-motion.md ("Real motion"): tryon-bench-sim on the scripted motions
# that real motion spends its time in and on the three CMU / boxing clips of Debian's
# assimp-testmodels, 7,000 vertices, 25 iterations, C backend; each run's final JSON line is kept
# in $OUT/motion.jsonl and a table of the figures the issue asks for is printed.
# usage: docs/figures/motion_figures.sh BUILD_DIR [CLIP_FRAMES|map] [PATTERN.json [SIZE]]
#        CLIP_FRAMES: 0 (default) = whole clips (after the scene's 1 s turn-in from the A-pose);
#        N = their first N frames (a quick look)
#        PATTERN.json: the sewing pattern (garments/patterns) worn instead of the shirt
#        (tryon-bench-sim --garment, size SIZE, default M), the whole "all" scene run too, into
#        $OUT/motion-NAME-SIZE.jsonl, with the share of sleeve / trouser-leg vertices within 5 cm
#        of their limb (first frame and worst frame; docs/garments.md, "Pattern garments on the
#        moving body")
#        TRYON_BVH_DIR: where the clips are (default /usr/share/assimp/models/BVH)
#        STRAIN_RETRY=-1: the strain retries off (tryon-bench-sim --strain-retry -1), to see
#        what the frame's own iterations reach; the table's last columns count the frames
#        retried for their strain and those that took settle rounds
#        map: only the stability map's motion axes (arm angle: arms_down, trunk bend speed:
#        bend_forward 1 Hz / bend_fast 0.7 s, wrist speed: fast_swing) against the time step
#        (10, 25, 50 steps a frame) for each solver, 90 frames each, into $OUT/map.jsonl
set -eu
B=${1:-build}
CLIP_FRAMES=${2:-0}
GARMENT=${3:-}
SIZE=${4:-M}
BENCH=$B/sim/tryon-bench-sim
OUT=$B/motion-figures
BVH=${TRYON_BVH_DIR:-/usr/share/assimp/models/BVH}
mkdir -p "$OUT"
table() { python3 - "$1" <<'PY'
import json, os, sys
rows = [json.loads(line) for line in open(sys.argv[1])]
limbs = any("garment" in j for j in rows)
print("%-16s %-6s %5s %6s %8s %6s %8s %9s %9s %8s %8s" % ("motion", "solver", "iters", "frames",
      "carried", "run", "pen0_%", "strain_%", "max_str%", "pen_mm", "ms_med") + " ms_p95 retried settle" +
      ("  verts limb0_% limb_min%" if limbs else ""))
for j in rows:
    line = "%-16s %-6s %5d %6d %8d %6d %8.1f %9.1f %9.1f %8.1f %8.1f %6.1f %7d %6d" % (
        os.path.basename(j["motion"])[:16], j["solver"], j["iterations"], j["frames"],
        j["carried_frames"], j["carried_run"], j["pen_free_frames_pct"],
        j["strain_ok_frames_pct"], 100 * j["max_strain"], j["max_pen_mm"], j["ms_median"],
        j["ms_p95"], j["strain_retried_frames"], j["settle_frames"])
    if limbs:  # the sleeves' share near the arms, else the trouser legs' near the legs
        first = j["sleeve_near_first"] if j["sleeve_verts"] else j["leg_near_first"]
        worst = j["sleeve_near_min"] if j["sleeve_verts"] else j["leg_near_min"]
        line += " %6d %7.1f %9.1f" % (j["verts"], 100 * first, 100 * worst)
    print(line)
PY
}
if [ "$CLIP_FRAMES" = map ]; then
    : > "$OUT/map.jsonl"
    for solver in tryon seed; do
        for it in 10 25 50; do
            for m in arms_down bend_forward bend_fast fast_swing; do
                "$BENCH" --scene body --verts 7000 --iterations "$it" --backend c --no-ref \
                    --solver "$solver" --motion "$m" --frames 90 | tail -n 1 >> "$OUT/map.jsonl"
            done
        done
    done
    table "$OUT/map.jsonl"
    exit 0
fi
: "${JSONL:=$OUT/motion.jsonl}"
WEAR=""
if [ -n "$GARMENT" ]; then
    JSONL=$OUT/motion-$(basename "$GARMENT" .json)-$SIZE.jsonl
    WEAR="--garment $GARMENT --size $SIZE"
fi
: > "$JSONL"
# shellcheck disable=SC2086 # WEAR is two options or none
run() { "$BENCH" --scene body --verts 7000 --iterations 25 --backend c --no-ref $WEAR \
    ${STRAIN_RETRY:+--strain-retry "$STRAIN_RETRY"} "$@" |
    tail -n 1 >> "$JSONL"; }

# a pattern garment: the headline's scene first (still, arm raise, turn, walk, fast swing)
if [ -n "$GARMENT" ]; then
    run --motion all
fi

# scripted: one 6 s take each (arms_down and boxing_guard: 1.5 s in, 3 s held, 1.5 s out)
for m in arms_down boxing_guard bend_forward bend_side twist bend_fast; do
    run --motion "$m" --frames 180
done
for c in 01_01 01_03 Boxing_Toes; do
    if [ "$CLIP_FRAMES" -gt 0 ]; then
        run --motion "$BVH/$c.bvh" --frames "$CLIP_FRAMES"
    else
        run --motion "$BVH/$c.bvh"
    fi
done

# the table: frames, carried (longest run), % frames without penetration, % frames within the
# strain bounds, worst published strain and depth, ms median / p95
table "$JSONL"
