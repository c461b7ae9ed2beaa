#!/usr/bin/env bash
# The mirror in a window under Xvfb (docs/mirror.md, "The window under Xvfb"):
#   docs/figures/window_figures.sh BUILD_DIR [BEFORE_DIR]
# Variants, alternated run by run:
#   glx     BUILD_DIR's tryon-mirror as it is (SDL's GLX on X11: MIT-SHM)
#   egl     the same with SDL_VIDEO_X11_FORCE_EGL=1 (the window through EGL, as before: every
#           picture sent over the X socket)
#   before  BEFORE_DIR's tryon-mirror (a build of an older commit: a folder holding its
#           tryon-mirror, e.g. BEFORE_BUILD/mirror), when given
#   headless  BUILD_DIR's tryon-mirror --headless (no X server at all), for reference
# Each window run has its own Xvfb (-screen 0 1280x1024x24, as xvfb-run in
# pipeline_figures.sh --window), whose CPU (user + system, /proc/PID/stat) is read around the run.
# 1. A recorded session (mirrorcpu_figures.sh's, recorded once at 10 fps) played at 30 fps by
#    lcm-logplayer into tryon-mirror alone, WINDOW_FIG_RUNS times (3): the mirror's and Xvfb's
#    CPU over the replay, frames drawn, TIMING mirror/render, mirror/output (the swap in a
#    window) and mirror/cpu p50 (tryon-profile), the swap's p95 (the TIMING logged).
# 2. The window idle for 5 s (no message): the event loop's CPU, the mirror's and Xvfb's.
# 3. The pipeline (`tryon run` on the walk, all four stages real, --record), WINDOW_FIG_RUNS times:
#    per variant the load average before, sim and mirror frames dropped and latency p95 over the
#    session and after the summary's warm-up (its first 15 frames), Xvfb's CPU, and the mirror's
#    work on its first three frames with a garment (`tryon path --each`), the swap's p50 and p95.
# Environment: WINDOW_FIG_RUNS (3), WINDOW_FIG_PARTS ("1 2 3").
set -euo pipefail
build=$(realpath "${1:?usage: window_figures.sh BUILD_DIR [BEFORE_DIR]}")
before=${2:+$(realpath "$2")}
cd "$(dirname "$0")/../.."
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
runs=${WINDOW_FIG_RUNS:-3}
parts=${WINDOW_FIG_PARTS:-1 2 3}
variants="glx egl${before:+ before} headless"
export LP_NUM_THREADS=${LP_NUM_THREADS:-1} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
tick=$(getconf CLK_TCK)
cpu_ms() { awk -v t="$tick" '{ printf "%d", ($14 + $15) * 1000 / t }' "/proc/$1/stat"; }
out=$(mktemp -d)
xpid=
stop_x() {
    if [ -n "$xpid" ]; then
        kill -TERM "$xpid" 2>/dev/null || true
        wait "$xpid" 2>/dev/null || true
        xpid=
    fi
}
trap 'stop_x; rm -rf "$out"' EXIT
# Xvfb on a free display (-displayfd); DISPLAY set for what follows
start_x() {
    rm -f "$out/display"
    Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$out/display" >/dev/null 2>&1 &
    xpid=$!
    for _ in $(seq 50); do
        [ -s "$out/display" ] && break
        sleep 0.1
    done
    export DISPLAY=:$(head -n 1 "$out/display")
}
# the variant's tryon-mirror and its environment
mirror_of() { [ "$1" = before ] && echo "$before/tryon-mirror" || bin tryon-mirror; }
# SDL's hint forced to EGL for egl; unset otherwise (an older build sets it itself)
egl_env() { [ "$1" = egl ] && echo SDL_VIDEO_X11_FORCE_EGL=1 || echo -u SDL_VIDEO_X11_FORCE_EGL; }

# The mirror's TIMING in an LCM log (lcm-logger's format; timing_t after its 8-byte
# fingerprint): the swap's time (substage "output") p50 and p95 over the frames, ms.
swap_p95() {
    python3 - "$1" <<'EOF'
import struct, sys
data, i, out = open(sys.argv[1], 'rb').read(), 0, []
while i + 28 <= len(data):
    _, _, _, clen, dlen = struct.unpack('>IqqII', data[i:i + 28])
    ch, d = data[i + 28:i + 28 + clen], data[i + 28 + clen:i + 28 + clen + dlen]
    i += 28 + clen + dlen
    if not ch.endswith(b'TIMING'):
        continue
    n, = struct.unpack('>i', d[8:12])
    if d[12:12 + n - 1] != b'mirror':
        continue
    p = 12 + n + 36
    ns, = struct.unpack('>i', d[p:p + 4])
    p, names = p + 4, []
    for _ in range(ns):
        n, = struct.unpack('>i', d[p:p + 4])
        names.append(d[p + 4:p + 3 + n])
        p += 4 + n
    vals = dict(zip(names, struct.unpack('>%df' % ns, d[p:p + 4 * ns])))
    out.append(vals.get(b'output', 0.0))
out.sort()
q = lambda f: out[int(f * (len(out) - 1))] if out else float('nan')
print('swap (output) p50 %.2f p95 %.2f ms over %d frames' % (q(.5), q(.95), len(out)))
EOF
}

rec="$build/recordings/figures_walk_150_6000"
if [ ! -f "$rec/INDEX.txt" ]; then
    "$(bin tryon-synth)" --out "$rec" --motion walk --frames 150 --vertices 6000 >/dev/null
fi

if [[ " $parts " == *" 1 "* ]]; then
    session="$build/recordings/mirrorcpu_session"
    if [ ! -f "$session/session.lcmlog" ]; then
        echo "== recording one session -> $session"
        "$(bin tryon)" run "$rec" --rate 10 --headless --out "$out/frames" --png-every 100000 \
            --record "$session" | grep -E '^(sim|mirror) ' || true
    fi
    log="$session/session.lcmlog"
    prefix=$(grep -a -o -m 1 'RUN[0-9]*_CLOTH' "$log" | head -n 1 | sed 's/CLOTH$//')
    echo "== 1. the session played at 30 fps into tryon-mirror alone, $(date -u +%H:%M) UTC"
    for r in $(seq "$runs"); do
        for v in $variants; do
            export TRYON_LCM_URL="udpm://239.255.76.67:$((7700 + $$ % 1000))?ttl=0&recv_buf_size=8388608"
            export TRYON_CHANNEL_PREFIX=$prefix
            load=$(cut -d' ' -f1 /proc/loadavg)
            args=()
            if [ "$v" = headless ]; then
                args=(--headless --out "$out/frames" --png-every 100000)
            else
                start_x
            fi
            "$(bin tryon-profile)" --live 60 >"$out/profile.txt" 2>&1 &
            prof=$!
            rm -f "$out/timing.lcmlog"
            lcm-logger --lcm-url="$TRYON_LCM_URL" -c "${prefix}TIMING" "$out/timing.lcmlog" \
                >/dev/null 2>&1 &
            logger=$!
            env $(egl_env "$v") "$(mirror_of "$v")" "${args[@]}" \
                >"$out/mirror.txt" 2>&1 &
            m=$!
            sleep 1.5 # past start-up and the warm-up draw
            m0=$(cpu_ms "$m") x0=0
            [ -n "$xpid" ] && x0=$(cpu_ms "$xpid")
            timeout 60 lcm-logplayer --speed=3 --lcm-url="$TRYON_LCM_URL" \
                --regexp="${prefix}(DEPTH|BODY|CLOTH)" "$log" >/dev/null 2>&1 || true
            sleep 0.5
            m1=$(cpu_ms "$m") x1=0
            [ -n "$xpid" ] && x1=$(cpu_ms "$xpid")
            kill -TERM "$m" 2>/dev/null || true
            wait "$m" || true
            kill -INT "$prof" "$logger" 2>/dev/null || true
            wait "$prof" "$logger" || true
            stop_x
            drawn=$(grep -o '[0-9]* frames drawn' "$out/mirror.txt" | cut -d' ' -f1)
            echo "$v, load $load: mirror CPU $((m1 - m0)) ms, Xvfb CPU $((x1 - x0)) ms," \
                "$drawn frames drawn; p50 $(grep -E 'mirror/(render|output|cpu)' "$out/profile.txt" |
                    awk '{ printf "%s %s ms  ", $1, $3 }')"
            echo "   $(swap_p95 "$out/timing.lcmlog")"
        done
    done
    unset TRYON_LCM_URL TRYON_CHANNEL_PREFIX
fi

if [[ " $parts " == *" 2 "* ]]; then
    echo "== 2. the window idle for 5 s (no message), $(date -u +%H:%M) UTC"
    for v in $variants; do
        [ "$v" = headless ] && continue
        start_x
        env $(egl_env "$v") "$(mirror_of "$v")" >"$out/mirror.txt" 2>&1 &
        m=$!
        sleep 1.5
        m0=$(cpu_ms "$m") x0=$(cpu_ms "$xpid")
        sleep 5
        echo "$v: mirror CPU $(($(cpu_ms "$m") - m0)) ms, Xvfb CPU $(($(cpu_ms "$xpid") - x0)) ms"
        kill -TERM "$m" 2>/dev/null || true
        wait "$m" || true
        stop_x
    done
fi

if [[ " $parts " == *" 3 "* ]]; then
    echo "== 3. the pipeline (tryon run, the walk at 30 fps, all four stages real), $(date -u +%H:%M) UTC"
    for r in $(seq "$runs"); do
        for v in $variants; do
            load=$(cut -d' ' -f1 /proc/loadavg)
            args=()
            bindir=
            [ "$v" = before ] && bindir=$before
            if [ "$v" = headless ]; then
                args=(--headless --out "$out/frames" --png-every 100000)
            else
                start_x
            fi
            rm -rf "$out/rec"
            x0=0
            [ -n "$xpid" ] && x0=$(cpu_ms "$xpid")
            env $(egl_env "$v") TRYON_BIN_DIR="$bindir" "$(bin tryon)" run \
                "$rec" --body bodyfit --backend c "${args[@]}" --record "$out/rec" \
                >"$out/run.txt" 2>&1 || true
            x1=0
            [ -n "$xpid" ] && x1=$(cpu_ms "$xpid")
            stop_x
            first=$("$(bin tryon)" path "$out/rec/session.lcmlog" --each 2>/dev/null |
                awk '$NF == "mirror" && n++ < 3 { printf "%s ", $(NF - 2) }' || true)
            awk -v n="$v, load $load, Xvfb CPU $((x1 - x0)) ms" -v f="$first" '
                $1 ~ /^(sim|mirror)$/ && NF == 10 { r = r sprintf(" %s %s dropped, p95 %s ms;", $1, $3, $9) }
                /warm-up/ { w = 1 }
                w && $1 ~ /^(sim|mirror)$/ && NF == 6 { s = s sprintf(" %s %s, %s ms;", $1, $3, $5) }
                END { print n ":" r " after warm-up:" s " the mirror'"'"'s first frames " f "ms" }' \
                "$out/run.txt"
            echo "   $(swap_p95 "$out/rec/session.lcmlog")"
        done
    done
fi
