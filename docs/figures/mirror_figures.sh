#!/usr/bin/env bash
# The mirror's figures (docs/mirror.md): one frame's cost at 640x480 and 1280x720, and the
# pipeline's latency on the walk recording at 30 fps through `tryon run`: capture -> cloth
# published (tryon-sim's latency) and capture -> garment on screen (tryon-mirror's, in a window
# under Xvfb, or headless with --headless-only), MIRROR_FIG_RUNS times, each with the load
# average before it and each stage's CPU time. Then tryon-sim's work on the fitted bodies of one
# recorded session, replayed one by one (--queue all): the same bodies whatever the machine's load,
# so settle rounds and strain retries compare across builds.
#   docs/figures/mirror_figures.sh BUILD_DIR [--headless-only]
# Environment: MIRROR_FIG_FRAMES (150), MIRROR_FIG_BODY_VERTS (6000), MIRROR_FIG_BACKEND (c),
# MIRROR_FIG_BODY (bodyfit: all four stages real; truth: the recording's true body),
# MIRROR_FIG_RUNS (3), MIRROR_FIG_SIM_WORK (1; 0 skips the replay).
set -euo pipefail
build=${1:?usage: mirror_figures.sh BUILD_DIR [--headless-only]}
mode=${2:-}
cd "$(dirname "$0")/../.."
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
frames=${MIRROR_FIG_FRAMES:-150}
verts=${MIRROR_FIG_BODY_VERTS:-6000}
backend=${MIRROR_FIG_BACKEND:-c}
runs=${MIRROR_FIG_RUNS:-3}
export LP_NUM_THREADS=${LP_NUM_THREADS:-1} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}

echo "== one frame, headless (tryon-bench-mirror, LP_NUM_THREADS=$LP_NUM_THREADS)"
for size in 640x480 1280x720; do
    "$(bin tryon-bench-mirror)" --size "$size" --frames 200
done

rec="$build/recordings/figures_walk_${frames}_${verts}"
if [ ! -f "$rec/INDEX.txt" ]; then
    echo "== recording: $frames frames of 'walk' -> $rec"
    "$(bin tryon-synth)" --out "$rec" --motion walk --frames "$frames" --vertices "$verts" >/dev/null
fi

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
run=("$(bin tryon)" run "$rec" --body "${MIRROR_FIG_BODY:-bodyfit}" --backend "$backend")
for k in $(seq "$runs"); do
    echo "== run $k of $runs; before it: $(uptime)"
    if [ "$mode" != --headless-only ] && command -v xvfb-run >/dev/null; then
        echo "== tryon run in a window under Xvfb (capture -> garment on screen is the mirror's latency)"
        xvfb-run -a -s "-screen 0 1280x1024x24" "${run[@]}" | tee "$out/summary.txt"
    else
        echo "== tryon run headless: every frame read back, one PNG in 100000 written"
        "${run[@]}" --headless --out "$out" --png-every 100000 | tee "$out/summary.txt"
    fi
done
echo "== goals: sim latency p95 <= 50 ms (capture -> cloth), mirror latency p95 <= 66 ms"
echo "   (capture -> garment on screen), 0 dropped at 30 fps"

[ "${MIRROR_FIG_SIM_WORK:-1}" = 1 ] || exit 0
echo "== tryon-sim's work on one session's fitted bodies, every body in order (--queue all)"
"${run[@]}" --headless --record "$out/session" --png-every 100000 >"$out/recorded.txt"
prefix=$(sed -n 's/^== latency per stage (TIMING, \(.*\)):$/\1/p' "$out/recorded.txt")
bodies=$(sed -n 's/.*published \([0-9]*\) bodies.*/\1/p' "$out/session/tryon-bodyfit.log" | tail -n 1)
url="udpm://239.255.76.67:$((7700 + RANDOM % 200))?ttl=0&recv_buf_size=8388608"
TRYON_LCM_URL=$url TRYON_CHANNEL_PREFIX=$prefix timeout 300 "$(bin tryon-sim)" --backend "$backend" \
    --queue all --frames "$bodies" --stats "$out/sim.csv" 2>"$out/sim.log" &
sim=$!
sleep 1
lcm-logplayer -s 0.25 -e "${prefix}BODY" -l "$url" "$out/session/session.lcmlog" >/dev/null
wait "$sim" || echo "tryon-sim did not take all $bodies bodies: $(tail -n 3 "$out/sim.log")"
grep "made in" "$out/sim.log" || true
tail -n +2 "$out/sim.csv" | cut -d, -f11 | sort -n >"$out/ms.txt"
awk '{ ms[NR] = $1 } END { printf "%d bodies: work ms p50 %.1f p95 %.1f; ", NR, ms[int(NR / 2) + 1],
    ms[int(NR * 0.95) + 1] }' "$out/ms.txt"
awk -F, 'NR > 1 { n++; sum += $11; settle += $3; full += ($3 >= 50); sr += $5 }
    END { printf "mean %.1f; settle rounds mean %.1f, bodies at 50 rounds %d; strain retries %d\n",
          sum / n, settle / n, full, sr }' "$out/sim.csv"
