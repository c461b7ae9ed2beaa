#!/usr/bin/env bash
# The demo that `./setup.sh` ends with: the pipeline on a recording, each stage its own process
# talking over LCM, and the per-stage latency it measured. Stages not built yet are named, not
# faked.
#   scripts/demo.sh [BUILD_DIR]
# Environment: TRYON_DEMO_MOTION (walk), TRYON_DEMO_FRAMES (90), TRYON_DEMO_BACKEND (c: faster
# than PoCL's CPU OpenCL on a machine without a GPU; opencl where one is), TRYON_DEMO_BODY_VERTS
# (6000: the body detail the camera supports, docs/sim.md "Body detail and the shape error"),
# TRYON_DEMO_RETRY_BUDGET (tryon-sim --retry-budget, ms; 0 = none, the default), TRYON_DEMO_BODY
# (fit: tryon-bodyfit fits the depth frames, the default; truth: tryon-truth publishes the
# recording's true body, the reference), TRYON_LCM_URL.
set -euo pipefail
build=${1:-build}
cd "$(dirname "$0")/.."
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
motion=${TRYON_DEMO_MOTION:-walk}
frames=${TRYON_DEMO_FRAMES:-90}
backend=${TRYON_DEMO_BACKEND:-c}
body_verts=${TRYON_DEMO_BODY_VERTS:-6000}
retry_budget=${TRYON_DEMO_RETRY_BUDGET:-0}
body_stage=${TRYON_DEMO_BODY:-fit}

echo "== bus: a full-size depth frame over LCM"
"$(bin tryon-bus-check)"

missing=()
for exe in tryon-synth tryon-capture tryon-truth tryon-sim tryon-profile tryon-bodyfit \
    tryon-mirror tryon; do
    [ -n "$(bin "$exe")" ] || missing+=("$exe")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "== not built: ${missing[*]}"
fi
body_exe=tryon-bodyfit
[ "$body_stage" = truth ] && body_exe=tryon-truth
for exe in tryon-synth tryon-capture "$body_exe" tryon-sim tryon-profile; do
    if [ -z "$(bin "$exe")" ]; then
        echo "== $exe is missing: the pipeline demo needs it" >&2
        exit 1
    fi
done

rec="$build/recordings/demo_${motion}_${frames}_${body_verts}"
if [ ! -f "$rec/INDEX.txt" ]; then
    echo "== recording: $frames frames of '$motion' (a body of $body_verts vertices) through the" \
        "simulated Kinect v1 -> $rec"
    "$(bin tryon-synth)" --out "$rec" --motion "$motion" --frames "$frames" \
        --vertices "$body_verts" >/dev/null
fi

# Every stage on its own channel prefix, so a demo never talks to another pipeline on this host.
export TRYON_CHANNEL_PREFIX=DEMO$$_ OMP_WAIT_POLICY=passive
log="$build/demo.lcmlog"
out=$(mktemp -d)
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    rm -rf "$out"
}
trap cleanup EXIT
wait_line() { # FILE TEXT: until a process says it listens (10 s at most)
    for _ in $(seq 100); do grep -q "$2" "$1" 2>/dev/null && return 0; sleep 0.1; done
    echo "== timed out waiting for '$2' in $1" >&2
    cat "$1" >&2
    return 1
}

rm -f "$log"
scripts/bus_logger.sh "$(bin tryon-bus-check)" --quiet --channel "${TRYON_CHANNEL_PREFIX}.*" \
    "$log" >"$out/logger.txt" 2>&1 &
pids+=($!)
"$(bin tryon-sim)" --backend "$backend" --frames "$frames" --retry-budget "$retry_budget" \
    ${TRYON_DEMO_SIM_STATS:+--stats "$TRYON_DEMO_SIM_STATS"} >"$out/sim.txt" 2>&1 &
pids+=($!)
sim=$!
if [ "$body_stage" = truth ]; then
    "$(bin tryon-truth)" --recording "$rec" --frames "$frames" >"$out/body.txt" 2>&1 &
    ready="frames of ground truth"
    body_words="tryon-truth (the recording's true body, the reference)"
else
    "$(bin tryon-bodyfit)" --frames "$frames" --vertices "$body_verts" \
        ${TRYON_DEMO_SMOOTH:+--smooth "$TRYON_DEMO_SMOOTH"} >"$out/body.txt" 2>&1 &
    ready="listening on"
    body_words="tryon-bodyfit (the body fitted to each depth frame)"
fi
pids+=($!)
wait_line "$out/sim.txt" "waiting for"
wait_line "$out/body.txt" "$ready"
sleep 0.5 # lcm-logger has no ready line

echo "== pipeline: tryon-capture (fakenect replay, 30 fps) -> $body_words"
echo "   -> tryon-sim ($backend backend); log: $log"
"$(bin tryon-capture)" --source freenect --uri "$rec" --rate realtime --frames "$frames" --quiet
status=0
for _ in $(seq 600); do kill -0 "$sim" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$sim" 2>/dev/null; then
    echo "== tryon-sim did not finish its $frames frames within 60 s" >&2
    status=1
fi
sleep 0.3
for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null || true; done
wait || true
pids=()
sed 's/^/   /' "$out/body.txt" "$out/sim.txt"

echo "== per-stage latency (tryon-profile --log $log):"
"$(bin tryon-profile)" --log "$log"

# The whole product in one command: tryon run starts every stage itself, the mirror included
# (docs/pipeline.md, "tryon"): a window where a display works, else a video and a few PNGs.
if [ -n "$(bin tryon)" ] && [ -n "$(bin tryon-mirror)" ]; then
    show="$build/demo_mirror"
    rm -rf "$show" && mkdir -p "$show"
    headless=(--headless --out "$show" --png-every 10 --video "$show/demo.mp4")
    unset TRYON_CHANNEL_PREFIX # tryon picks its own private prefix
    run_body=bodyfit
    [ "$body_stage" = truth ] && run_body=truth
    run=("$(bin tryon)" run "$rec" --body "$run_body" --backend "$backend")
    if [ -n "${DISPLAY:-}" ] && echo "== tryon run: the mirror in a window" &&
        "${run[@]}"; then
        :
    else
        echo "== tryon run: no working display; the mirror writes a video and every tenth frame as a PNG"
        "${run[@]}" "${headless[@]}" || status=1
        echo "== the mirror's output: $show/demo.mp4 and $(find "$show" -name '*.png' | wc -l)" \
            "PNG frames in $show"
    fi
fi
exit $status
