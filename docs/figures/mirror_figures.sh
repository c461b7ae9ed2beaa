#!/usr/bin/env bash
# The mirror's figures (docs/mirror.md): one frame's cost at 640x480 and 1280x720, and the
# pipeline's latency on the walk recording at 30 fps through `tryon run`: capture -> cloth
# published (tryon-sim's latency) and capture -> garment on screen (tryon-mirror's, in a window
# under Xvfb, or headless with --headless-only).
#   docs/figures/mirror_figures.sh BUILD_DIR [--headless-only]
# Environment: MIRROR_FIG_FRAMES (150), MIRROR_FIG_BODY_VERTS (6000), MIRROR_FIG_BACKEND (c),
# MIRROR_FIG_BODY (bodyfit: all four stages real; truth: the recording's true body).
set -euo pipefail
build=${1:?usage: mirror_figures.sh BUILD_DIR [--headless-only]}
mode=${2:-}
cd "$(dirname "$0")/../.."
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
frames=${MIRROR_FIG_FRAMES:-150}
verts=${MIRROR_FIG_BODY_VERTS:-6000}
backend=${MIRROR_FIG_BACKEND:-c}
export LP_NUM_THREADS=${LP_NUM_THREADS:-1} OMP_WAIT_POLICY=passive

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
if [ "$mode" != --headless-only ] && command -v xvfb-run >/dev/null; then
    echo "== tryon run in a window under Xvfb (capture -> garment on screen is the mirror's latency)"
    xvfb-run -a -s "-screen 0 1280x1024x24" "${run[@]}" | tee "$out/summary.txt"
else
    echo "== tryon run headless: every frame read back, one PNG in 100000 written"
    "${run[@]}" --headless --out "$out" --png-every 100000 | tee "$out/summary.txt"
fi
echo "== goals: sim latency p95 <= 50 ms (capture -> cloth), mirror latency p95 <= 66 ms"
echo "   (capture -> garment on screen), 0 dropped at 30 fps"
