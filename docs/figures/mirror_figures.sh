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
# MIRROR_FIG_RUNS (3), MIRROR_FIG_SIM_WORK (1; 0 skips the replays), MIRROR_FIG_CAUSE (1; 0 skips
# the replays of the walk fitted with and without the pose filter and of its true bodies),
# MIRROR_FIG_BUDGETS ("default 20": tryon-sim's --frame-budget for each run, alternated in every
# round; "default" is tryon-sim's own, auto since the deadline per body; auto:MS the same with
# --deadline MS; 20 the fixed budget before it; 0 none, as before any budget). The replays (--queue all, bodies stamped long ago) give
# "default" the fixed 20 ms: docs/figures/latency_figures.sh replays at the camera's pace.
set -euo pipefail
build=${1:?usage: mirror_figures.sh BUILD_DIR [--headless-only]}
mode=${2:-}
cd "$(dirname "$0")/../.."
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
frames=${MIRROR_FIG_FRAMES:-150}
verts=${MIRROR_FIG_BODY_VERTS:-6000}
backend=${MIRROR_FIG_BACKEND:-c}
runs=${MIRROR_FIG_RUNS:-3}
budgets=${MIRROR_FIG_BUDGETS:-default 20}
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
sim_exe=$(realpath "$(bin tryon-sim)")
# A budget other than tryon-sim's default: a tryon-sim that passes it, found first by the launcher
# (TRYON_BIN_DIR); every other stage comes from BUILD_DIR.
bin_dir() {
    [ "$1" = default ] && return
    mkdir -p "$out/bin_$1"
    local opt="--frame-budget ${1%%:*}"
    [ "${1#*:}" = "$1" ] || opt="$opt --deadline ${1#*:}"
    printf '#!/bin/sh\nexec "%s" %s "$@"\n' "$sim_exe" "$opt" >"$out/bin_$1/tryon-sim"
    chmod +x "$out/bin_$1/tryon-sim"
    echo "$out/bin_$1"
}
# One line per run: the sim's and the mirror's p95 latency and drops, and the sim's own counts.
brief() {
    local logs
    logs=$(sed -n 's/^== logs: //p' "$1")
    awk -v b="$2" '$1 == "sim" && NF == 10 { s = $9; sd = $3; w = $6 } $1 == "mirror" && NF == 10 { m = $9; md = $3 }
        END { printf "== budget %s: capture -> cloth p95 %s ms, sim work p95 %s ms, sim dropped %s; ", b, s, w, sd
              printf "on screen p95 %s ms, mirror dropped %s\n", m, md }' "$1"
    grep -ho "[0-9]* superseded.*" "$logs/tryon-sim.log" | tail -n 1 | sed 's/^/   tryon-sim: /'
    # what the mirror adds after the cloth (p50s: the difference of two p95s means little)
    awk '$1 == "sim" && NF == 10 { s = $8 } $1 == "mirror" && NF == 10 { m = $8; w = $5 }
        $1 == "mirror/render" { r = $3 } $1 == "mirror/output" { o = $3 }
        END { printf "   tryon-mirror: on screen - cloth p50 %.1f ms; work p50 %s ms (render %s, output %s)\n", m - s, w, r, o }' "$1"
    rm -rf "$logs" # the launcher's logs of this run, read
}
for k in $(seq "$runs"); do
    for b in $budgets; do
        echo "== run $k of $runs, tryon-sim --frame-budget $b; before it: $(uptime)"
        dir=$(bin_dir "$b")
        if [ "$mode" != --headless-only ] && command -v xvfb-run >/dev/null; then
            echo "== tryon run in a window under Xvfb (capture -> garment on screen is the mirror's latency)"
            TRYON_BIN_DIR=$dir xvfb-run -a -s "-screen 0 1280x1024x24" "${run[@]}" | tee "$out/summary.txt"
        else
            echo "== tryon run headless: every frame read back, one PNG in 100000 written"
            TRYON_BIN_DIR=$dir "${run[@]}" --headless --out "$out" --png-every 100000 | tee "$out/summary.txt"
        fi
        brief "$out/summary.txt" "$b" | tee -a "$out/briefs.txt"
    done
done
if [ -f "$out/briefs.txt" ]; then
    echo "== every run:"
    cat "$out/briefs.txt"
fi
echo "== goals: sim latency p95 <= 50 ms (capture -> cloth), mirror latency p95 <= 66 ms"
echo "   (capture -> garment on screen), 0 dropped at 30 fps"

[ "${MIRROR_FIG_SIM_WORK:-1}" = 1 ] || exit 0
# replay SESSION_DIR BUDGET: the session's BODY messages, one by one, into a tryon-sim
# (--queue all): settle rounds, retries, the published strain and the sim's work.
replay() {
    local prefix bodies url opt=()
    prefix=$(cat "$1/prefix")
    bodies=$(cat "$1"/tryon-bodyfit.log "$1"/tryon-truth.log 2>/dev/null |
        sed -n 's/.*published \([0-9]*\) bodies.*/\1/p' | tail -n 1 || true)
    url="udpm://239.255.76.67:$((7700 + RANDOM % 200))?ttl=0&recv_buf_size=8388608"
    [ "$2" = default ] || opt=(--frame-budget "${2%%:*}")
    [ "${2#*:}" = "$2" ] || opt+=(--deadline "${2#*:}")
    echo "== tryon-sim --frame-budget $2"
    TRYON_LCM_URL=$url TRYON_CHANNEL_PREFIX=$prefix timeout 300 "$(bin tryon-sim)" --backend "$backend" \
        --queue all --frames "$bodies" --stats "$out/sim.csv" "${opt[@]}" 2>"$out/sim.log" &
    local sim=$!
    sleep 1
    lcm-logplayer -s 0.25 -e "${prefix}BODY" -l "$url" "$1/session.lcmlog" >/dev/null
    wait "$sim" || echo "tryon-sim did not take all $bodies bodies: $(tail -n 3 "$out/sim.log")"
    grep "made in" "$out/sim.log" || true
    tail -n +2 "$out/sim.csv" | cut -d, -f11 | sort -n >"$out/ms.txt"
    awk '{ ms[NR] = $1 } END { printf "%d bodies: work ms p50 %.1f p95 %.1f; ", NR, ms[int(NR / 2) + 1],
        ms[int(NR * 0.95) + 1] }' "$out/ms.txt"
    awk -F, 'NR > 1 { n++; sum += $11; settle += $3; any += ($3 > 0); full += ($3 >= 50); sr += $5 }
        END { printf "mean %.1f; settle rounds mean %.1f, bodies with any %d, at 50 rounds %d; strain retries %d\n",
              sum / n, settle / n, any, full, sr }' "$out/sim.csv"
    # the cloth published: settling (cut short by the budget), and its worst strain
    awk -F, 'NR > 1 { n++; cut += ($2 == 3); s += $8; o2 += ($8 > 0.02); o3 += ($8 > 0.03); m = $8 > m ? $8 : m }
        END { printf "   published settling %d; max strain mean %.2f %%, over 2 %% %d, over 3 %% %d, worst %.2f %%\n",
              cut, 100 * s / n, o2, o3, 100 * m }' "$out/sim.csv"
}
# record NAME [tryon run options]: a headless session kept in $out/NAME (session.lcmlog, logs, the
# channel prefix in NAME/prefix).
record() {
    local name=$1
    shift
    "$@" --headless --record "$out/$name" --png-every 100000 >"$out/$name.txt"
    sed -n 's/^== latency per stage (TIMING, \(.*\)):$/\1/p' "$out/$name.txt" >"$out/$name/prefix"
}
echo "== tryon-sim's work on one session's fitted bodies, every body in order (--queue all)"
record session "${run[@]}"
for b in $budgets; do
    replay "$out/session" "$b"
done

[ "${MIRROR_FIG_CAUSE:-1}" = 1 ] || exit 0
# Why the fitted walk settles: the same walk's bodies, none dropped (capture at 10 fps,
# tryon-bodyfit --queue all: the same bodies whatever the load), fitted with the published pose's
# filter (its default) and without, and the recording's true bodies; each replayed without a
# budget.
echo "== the settle rounds' cause: fitted (filter on, off) and true bodies, no frame budget"
for smooth in on off; do
    mkdir -p "$out/fit_$smooth"
    printf '#!/bin/sh\nexec "%s" --queue all --smooth %s "$@"\n' "$(realpath "$(bin tryon-bodyfit)")" \
        "$smooth" >"$out/fit_$smooth/tryon-bodyfit"
    chmod +x "$out/fit_$smooth/tryon-bodyfit"
    TRYON_BIN_DIR=$out/fit_$smooth record "fitted_$smooth" "$(bin tryon)" run "$rec" --rate 10 \
        --body bodyfit --backend "$backend"
    echo "== bodies fitted, tryon-bodyfit --smooth $smooth"
    replay "$out/fitted_$smooth" 0
done
record truth "$(bin tryon)" run "$rec" --rate 10 --body truth --backend "$backend"
echo "== the recording's true bodies (tryon-truth)"
replay "$out/truth" 0
