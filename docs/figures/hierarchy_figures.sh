#!/bin/sh
# The strain-limit hierarchy's figures in docs/sim-real-motion.md ("Real motion") and docs/sim-history-5.md
# ("Bends: the hierarchy's levels"): the scripted motions and the clips' first CLIP_FRAMES frames
# without the strain retries (docs/figures/motion_figures.sh with STRAIN_RETRY=-1), then with
# them, then the body scene (--motion all, 495 frames) ROUNDS times, each round alternating the
# build with BASE_BUILD_DIR's (a build of the code before, for the times on a shared machine).
# Frame counts, strain and depth do not depend on the load; the times do.
# usage: docs/figures/hierarchy_figures.sh BUILD_DIR [BASE_BUILD_DIR] [CLIP_FRAMES] [ROUNDS]
#        CLIP_FRAMES: default 300; ROUNDS: default 2
set -eu
B=${1:-build}
BASE=${2:-}
CLIP_FRAMES=${3:-300}
ROUNDS=${4:-2}
HERE=$(dirname "$0")
OUT=$B/hierarchy-figures
mkdir -p "$OUT"
export OMP_WAIT_POLICY=passive

motions() { # BUILD NAME: the no-retry and the retry tables of BUILD
    echo "== $2: without the strain retries"
    STRAIN_RETRY=-1 JSONL=$OUT/$2-noretry.jsonl "$HERE/motion_figures.sh" "$1" "$CLIP_FRAMES"
    echo "== $2: with the strain retries (the default)"
    JSONL=$OUT/$2-retry.jsonl "$HERE/motion_figures.sh" "$1" "$CLIP_FRAMES"
}
motions "$B" new
if [ -n "$BASE" ]; then
    motions "$BASE" base
fi

echo "== the body scene (--motion all, 495 frames), alternated"
printf '%-5s %5s %8s %8s %7s %7s %7s %7s %7s\n' build round max_pct p99_pct settle retried \
    pen ms_med ms_p95
body() { # BUILD NAME ROUND
    "$1/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --backend c --no-ref \
        --motion all --frames 495 | tail -n 1 | python3 -c '
import json, sys
j = json.loads(sys.stdin.read())
print("%-5s %5s %8.3f %8.3f %7d %7d %7d %7.2f %7.2f" % (sys.argv[1], sys.argv[2],
      100 * j["max_strain"], 100 * j["p99_strain"], j["settle_frames"],
      j["strain_retried_frames"], j["penetrating"], j["ms_median"], j["ms_p95"]))' "$2" "$3"
}
r=1
while [ "$r" -le "$ROUNDS" ]; do
    body "$B" new "$r"
    if [ -n "$BASE" ]; then
        body "$BASE" base "$r"
    fi
    r=$((r + 1))
done
