#!/bin/sh
# The sim on the bodies a pipeline really published (docs/sim-real-motion.md, "Real motion: pinches"): each
# motion-capture clip recorded facing the camera (tryon-synth, 150 frames), run through the whole
# pipeline twice, with the recording's true bodies (tryon-truth) and with the fitter's
# (tryon-bodyfit), each session kept (tryon run --record), then tryon-bench-sim on each
# session's bodies (--motion DIR/session.lcmlog: 7,000 vertices, 25 iterations, C backend, no
# frame budget). The sessions' bodies do not depend on the load when the fitter keeps up (three
# recordings of the boxing clip gave the same bodies); the bench's counts never do.
# usage: docs/figures/session_figures.sh BUILD_DIR [CLIP...]   (default: 01_01 01_03 Boxing_Toes)
#        TRYON_BVH_DIR: where the clips are (default /usr/share/assimp/models/BVH)
# Recordings and sessions go to BUILD_DIR/session-figures (about 0.5 GB for the three clips).
set -eu
B=${1:-build}
[ $# -gt 0 ] && shift
CLIPS=${*:-01_01 01_03 Boxing_Toes}
BVH=${TRYON_BVH_DIR:-/usr/share/assimp/models/BVH}
OUT=$B/session-figures
mkdir -p "$OUT"
printf '%-12s %-8s %6s %8s %5s %7s %7s %8s %8s %7s %7s\n' clip body frames carried run pen0_% \
    pen_mm max_str% p99_str% ms_med ms_p95
for c in $CLIPS; do
  rec="$OUT/rec_$c"
  [ -f "$rec/INDEX.txt" ] || "$B/recordings/tryon-synth" --motion "$BVH/$c.bvh" --frames 150 \
      --vertices 6000 --noise on --seed 1 --out "$rec" >/dev/null
  for body in truth bodyfit; do
    s="$OUT/session_${c}_$body"
    rm -rf "$s" "$s.frames"
    "$B/launcher/tryon" run "$rec" --body "$body" --backend c --headless --out "$s.frames" \
        --png-every 100000 --record "$s" >"$s.txt" 2>&1
    "$B/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --no-ref --backend c \
        --motion "$s/session.lcmlog" 2>/dev/null | tail -n 1 >"$s.json"
    python3 - "$s.json" "$c" "$body" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
print("%-12s %-8s %6d %8d %5d %7.1f %7.1f %8.1f %8.1f %7.1f %7.1f" % (
    sys.argv[2], sys.argv[3], j["frames"], j["carried_frames"], j["carried_run"],
    j["pen_free_frames_pct"], j["max_pen_mm"], 100 * j["max_strain"], 100 * j["p99_strain"],
    j["ms_median"], j["ms_p95"]))
PY
  done
done
