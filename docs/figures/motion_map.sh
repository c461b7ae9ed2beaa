#!/bin/bash
# The stability map of docs/sim-real-motion.md ("Where each solver stops working"): each solver on the shirt
# (7,000 vertices, C backend) over the axes that break methods, each swept on its own from the
# scripted motion (tryon-bench-sim --motion NAME@SPEED,AMOUNT, docs/body-model.md):
#   arm angle to the torso  arms_down@1,A   the arms held A x 39 degrees in from the A-pose:
#                                           45 - 39 A degrees from vertical (A = 1.15: vertical)
#   trunk bend speed        bend_forward@S  30 degrees forward and back at S Hz
#   wrist speed             fast_swing@S    the swing S times as fast (S = 1: wrist 3.9 m/s)
#   time step               --iterations 10, 25, 50 steps a 33 ms frame
# 75 frames each. The outcomes (frames carried, inside, strain) do not depend on threads or load:
# MAP_JOBS runs that many at once (OMP_NUM_THREADS each: MAP_THREADS, default 2).
# usage: docs/figures/motion_map.sh BUILD_DIR   (JSON lines in BUILD_DIR/motion-figures/map.jsonl)
set -eu
B=${1:?usage: $0 BUILD_DIR}
BENCH=$B/sim/tryon-bench-sim
OUT=$B/motion-figures
mkdir -p "$OUT/map"
export OMP_WAIT_POLICY=passive OMP_NUM_THREADS=${MAP_THREADS:-2}
motions="arms_down@1,0.5 arms_down@1,0.8 arms_down@1,1 arms_down@1,1.1 arms_down@1,1.15
         bend_forward@0.5 bend_forward@1 bend_forward@1.43 bend_forward@2 bend_forward@3
         fast_swing@0.5 fast_swing@1 fast_swing@1.5 fast_swing@2"
n=0
rm -f "$OUT"/map/*.json
for solver in tryon seed; do
    for it in 10 25 50; do
        for m in $motions; do
            n=$((n + 1))
            printf '%03d %s %s %s\n' "$n" "$solver" "$it" "$m"
        done
    done
done | xargs -P "${MAP_JOBS:-1}" -L 1 sh -c '"$0" --scene body --verts 7000 --backend c \
    --no-ref --frames 75 --solver "$3" --iterations "$4" --motion "$5" 2>/dev/null |
    tail -n 1 > "$1/map/$2.json"' "$BENCH" "$OUT"
cat "$OUT"/map/*.json > "$OUT/map.jsonl"
python3 - "$OUT/map.jsonl" <<'PY'
import json, sys
print("%-7s %-6s %5s %-22s %8s %8s %9s %9s %8s" % ("axis", "solver", "iters", "motion", "carried",
      "pen0_%", "strain_%", "max_str%", "pen_mm"))
for line in open(sys.argv[1]):
    j = json.loads(line)
    name, spec = j["motion"].split("@")
    speed, _, amount = spec.partition(",")
    axis = {"arms_down": "%.0f deg" % (45 - 39 * float(amount or 1)),
            "bend_forward": "%.2f Hz" % float(speed),
            "fast_swing": "%.1f m/s" % (3.9 * float(speed))}[name]
    print("%-7s %-6s %5d %-22s %8d %8.1f %9.1f %9.1f %8.1f" % (axis, j["solver"],
          j["iterations"], j["motion"], j["carried_frames"], j["pen_free_frames_pct"],
          j["strain_ok_frames_pct"], 100 * j["max_strain"], j["max_pen_mm"]))
PY
