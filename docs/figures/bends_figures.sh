#!/bin/sh
# The bends' settle rounds (docs/sim-real-motion.md, "Real motion: the bends' settle rounds"; the diary in
# docs/sim-history-5.md, "Bends: the drop was not the re-search"): the whole bend_forward and
# bend_fast (495 frames, strain retries on), the real-motion tables with and without the
# retries (docs/figures/motion_figures.sh, the clips' first CLIP_FRAMES frames), then, ROUNDS
# times alternating with BASE_BUILD_DIR (a build of the code before, for the times on a shared
# machine), the body scene (--motion all) and the CPU seconds of the bends' first 180 frames.
# Frame counts, strain and depth do not depend on the load; the times do.
# usage: docs/figures/bends_figures.sh BUILD_DIR [BASE_BUILD_DIR] [CLIP_FRAMES] [ROUNDS]
#        CLIP_FRAMES: default 300; ROUNDS: default 2
set -eu
B=${1:-build}
BASE=${2:-}
CLIP_FRAMES=${3:-300}
ROUNDS=${4:-2}
HERE=$(dirname "$0")
export OMP_WAIT_POLICY=passive
summary() { python3 -c '
import json, sys
j = json.loads(sys.stdin.read().strip().splitlines()[-1])
print("%-13s frames %d within %.1f %% max %.2f %% p99 %.2f %% inside %d settle %d retried %d"
      " ms median %.1f p95 %.1f" % (j["motion"], j["frames"], j["strain_ok_frames_pct"],
      100 * j["max_strain"], 100 * j["p99_strain"], j["penetrating"], j["settle_frames"],
      j["strain_retried_frames"], j["ms_median"], j["ms_p95"]))'; }
echo "== the whole bends, retries on: $B"
for m in bend_forward bend_fast; do
    "$B"/sim/tryon-bench-sim --scene body --verts 7000 --iterations 25 --backend c --no-ref \
        --motion "$m" | summary
done
echo "== real motion, retries on"
"$HERE"/motion_figures.sh "$B" "$CLIP_FRAMES"
echo "== real motion, retries off"
STRAIN_RETRY=-1 "$HERE"/motion_figures.sh "$B" "$CLIP_FRAMES"
[ -n "$BASE" ] || exit 0
for r in $(seq "$ROUNDS"); do
    for b in "$BASE" "$B"; do
        echo "== round $r: $b"
        /usr/bin/time -f "all: %U s CPU, %e s wall" \
            "$b"/sim/tryon-bench-sim --scene body --verts 7000 --iterations 25 --backend c \
            --no-ref --motion all | summary
        for m in bend_forward bend_fast; do
            /usr/bin/time -f "$m 180 frames: %U s CPU, %e s wall" \
                "$b"/sim/tryon-bench-sim --scene body --verts 7000 --iterations 25 \
                --backend c --no-ref --motion "$m" --frames 180 > /dev/null
        done
    done
done
