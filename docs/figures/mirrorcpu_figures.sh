#!/usr/bin/env bash
# The mirror's CPU a frame (docs/mirror.md, "The mirror's CPU a frame"), with an older build
# alongside when BEFORE_DIR is given (a folder holding that build's tryon-mirror and
# tryon-bench-mirror), alternated run by run:
#   docs/figures/mirrorcpu_figures.sh BUILD_DIR [BEFORE_DIR]
# 1. tryon-bench-mirror --size WxH --frames 200 at 640x480 and 1280x720: the frame drawn, its
#    read-back and the person's image apart (an older bench prints one figure with all three).
# 2. One pipeline session on the walk recording, recorded once (`tryon run --record`, capture at
#    10 fps so that the sim keeps up: the same DEPTH, BODY and CLOTH whatever the load), kept in
#    BUILD_DIR/recordings/mirrorcpu_session/session.lcmlog; then played at 3x (30 fps) by
#    lcm-logplayer to one headless tryon-mirror (--png-every 100000, as tryon run --headless)
#    on a private bus, MIRRORCPU_FIG_RUNS times (2) per build: TIMING mirror/cpu p50 and p95
#    (tryon-profile: a frame drawn, llvmpipe's thread too), frames drawn, and the process's CPU
#    (user + system) over the session less an idle start-up (EGL, shaders), per DEPTH played.
# 3. The pipeline (`tryon run` on the walk, all four stages real, headless, --png-every 100000),
#    MIRRORCPU_FIG_RUNS times per build (the older tryon-mirror through TRYON_BIN_DIR, every
#    other stage from BUILD_DIR): TIMING mirror/cpu p50, frames drawn and dropped, the launcher's
#    CPU seconds for tryon-mirror.
# Environment: MIRRORCPU_FIG_RUNS (2), MIRRORCPU_FIG_FRAMES (150), MIRRORCPU_FIG_BODY_VERTS (6000).
set -euo pipefail
build=${1:?usage: mirrorcpu_figures.sh BUILD_DIR [BEFORE_DIR]}
before=${2:-}
cd "$(dirname "$0")/../.."
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
runs=${MIRRORCPU_FIG_RUNS:-2}
frames=${MIRRORCPU_FIG_FRAMES:-150}
verts=${MIRRORCPU_FIG_BODY_VERTS:-6000}
export LP_NUM_THREADS=${LP_NUM_THREADS:-1} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
after=$(dirname "$(realpath "$(bin tryon-mirror)")")
builds=("$after")
[ -n "$before" ] && builds+=("$(realpath "$before")")

echo "== one frame, headless (tryon-bench-mirror, LP_NUM_THREADS=$LP_NUM_THREADS), $(date -u +%H:%M) UTC"
for size in 640x480 1280x720; do
    for b in "${builds[@]}"; do
        echo "-- $b, load average $(cut -d' ' -f1 /proc/loadavg)"
        "$b/tryon-bench-mirror" --size "$size" --frames 200 | sed -n 2,3p
    done
done

rec="$build/recordings/figures_walk_${frames}_${verts}"
if [ ! -f "$rec/INDEX.txt" ]; then
    "$(bin tryon-synth)" --out "$rec" --motion walk --frames "$frames" --vertices "$verts" >/dev/null
fi
session="$build/recordings/mirrorcpu_session"
if [ ! -f "$session/session.lcmlog" ]; then
    echo "== recording one session -> $session"
    out=$(mktemp -d)
    "$(bin tryon)" run "$rec" --rate 10 --headless --out "$out" --png-every 100000 \
        --record "$session" | grep -E '^(sim|mirror) ' || true
    rm -rf "$out"
fi
log="$session/session.lcmlog"
prefix=$(grep -a -o -m 1 'RUN[0-9]*_CLOTH' "$log" | head -n 1 | sed 's/CLOTH$//')
depths=$frames # tryon-capture at 10 fps publishes every frame of the recording

# The mirror of build $1 on the private bus: its CPU seconds (user + system, read from /proc
# before it is stopped) over the replay, or over 2 s idle when $2 is "idle"; with the replay,
# frames drawn and tryon-profile's mirror lines.
tick=$(getconf CLK_TCK)
replay() {
    local dir=$1 out cpu prof=
    out=$(mktemp -d)
    export TRYON_LCM_URL="udpm://239.255.76.67:$((7700 + $$ % 1000))?ttl=0&recv_buf_size=8388608"
    export TRYON_CHANNEL_PREFIX=$prefix
    if [ "$2" != idle ]; then
        "$(bin tryon-profile)" --live 60 >"$out/profile.txt" 2>&1 &
        prof=$!
    fi
    "$dir/tryon-mirror" --headless --out "$out" --png-every 100000 >"$out/mirror.txt" 2>&1 &
    local mirror=$!
    sleep 1
    if [ "$2" = idle ]; then
        sleep 1
    else
        timeout 60 lcm-logplayer --speed=3 --lcm-url="$TRYON_LCM_URL" \
            --regexp="${prefix}(DEPTH|BODY|CLOTH)" "$log" >/dev/null 2>&1 || true
        sleep 0.5
    fi
    cpu=$(awk -v t="$tick" '{ print ($14 + $15) / t }' "/proc/$mirror/stat")
    kill -TERM "$mirror" 2>/dev/null || true
    wait "$mirror" || true
    if [ -n "$prof" ]; then
        kill -INT "$prof" 2>/dev/null || true
        wait "$prof" || true
    fi
    if [ "$2" = idle ]; then
        echo "$cpu"
    else
        drawn=$(grep -o '[0-9]* frames drawn' "$out/mirror.txt" | cut -d' ' -f1)
        echo "$cpu s CPU; $drawn frames drawn; $(grep -E '^mirror ' "$out/profile.txt" |
            awk '{ printf "mirror work p50 %s p95 %s ms", $5, $6 }'); $(grep 'mirror/cpu' "$out/profile.txt" | sed 's/^ *//')"
    fi
    rm -rf "$out"
}

echo "== the session replayed at 30 fps into tryon-mirror alone ($depths DEPTH), $(date -u +%H:%M) UTC"
for r in $(seq "$runs"); do
    for b in "${builds[@]}"; do
        idle=$(replay "$b" idle)
        res=$(replay "$b" play)
        total=${res%% s CPU*}
        echo "-- $b, load average $(cut -d' ' -f1 /proc/loadavg): start-up $idle s; $res"
        awk -v t="$total" -v i="$idle" -v n="$depths" \
            'BEGIN { printf "   CPU less start-up: %.2f s, %.2f ms a DEPTH\n", t - i, 1000 * (t - i) / n }'
    done
done

echo "== the pipeline (tryon run, headless, all four stages real), $(date -u +%H:%M) UTC"
for r in $(seq "$runs"); do
    for b in "${builds[@]}"; do
        out=$(mktemp -d)
        echo "-- $b, load average $(cut -d' ' -f1 /proc/loadavg)"
        env -u TRYON_LCM_URL -u TRYON_CHANNEL_PREFIX TRYON_BIN_DIR="$b" "$(bin tryon)" run "$rec" \
            --body bodyfit --backend c --headless --out "$out" --png-every 100000 2>/dev/null |
            grep -E '^(sim|mirror) |mirror/cpu|tryon-mirror ' || true
        rm -rf "$out"
    done
done
