#!/bin/sh
# Figures of docs/garments.md, "The T-shirt with the arms lowered": the T-shirt M (about 7,000
# vertices, 25 iterations, C backend) on the body scene with the arms lowered part way and all the
# way (arms_down@1,AMOUNT: AMOUNT of the 39 degrees from the A-pose's 45 to 6 degrees from
# vertical), the boxing guard and the whole scripted scene, and the tube shirt's headline on the
# same build. One row per run: frames, carried, the worst published frame's vertices > 1 mm
# inside and depth, % of frames with none, max / p99 strain, % of frames within 3 % / 1 %, ms
# median, the share of sleeve vertices near their arm in the worst frame.
# usage: docs/figures/tshirt_figures.sh BUILD_DIR   (a Release build; about 10 minutes on 2 cores)
set -eu
B=${1:?usage: $0 BUILD_DIR}
export OMP_WAIT_POLICY=passive
row() {
    python3 -c '
import json, sys
j = json.loads(sys.stdin.read().strip().splitlines()[-1])
print("%-20s %6d %7d %6d %6.1f %6.1f %7.1f %6.2f %8.1f %7.1f %6.2f" % (sys.argv[1], j["frames"],
      j["carried_frames"], j["penetrating"], j["max_pen_mm"], j["pen_free_frames_pct"],
      100 * j["max_strain"], 100 * j["p99_strain"], j["strain_ok_frames_pct"], j["ms_median"],
      j.get("sleeve_near_min", -1)))' "$1"
}
echo "motion               frames carried inside pen_mm pen0_% max_str% p99_% strain_% ms_med sleeve"
for m in arms_down@1,0.5 arms_down@1,0.7 arms_down@1,0.8 arms_down boxing_guard; do
    "$B/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --backend c --no-ref \
        --garment garments/patterns/tshirt.json --motion "$m" --frames 180 | row "tshirt $m"
done
"$B/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --backend c --no-ref \
    --garment garments/patterns/tshirt.json --motion all | row "tshirt all"
"$B/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --backend c --no-ref \
    --motion all | row "tube shirt all"
