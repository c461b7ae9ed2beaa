#!/usr/bin/env bash
# The pipeline's latency on the walk at 30 fps, all four stages real (docs/mirror.md, "Figures
# today"): `tryon run` headless (or in a window under Xvfb with --window), PIPELINE_FIG_RUNS
# rounds (4), each round alternating the variants of PIPELINE_FIG_VARIANTS ("default before
# nice0"):
#   default  the launcher's and stages' defaults
#   before   tryon-sim and tryon-bodyfit with --queue latest (only the newest frame waits) and the
#            mirror at --mirror-nice 0: the configuration before the queues of two and the niceness
#   nice0    the defaults with --mirror-nice 0
# One line a run: the load average before it, then per stage (bodyfit, sim, mirror) the frames
# dropped and the latency p95 from capture over the whole session, then the same after the
# summary's warm-up (the first 15 frames: docs/pipeline.md, "The latency summary"), and the
# sim's count of frames published with a vertex inside the fitted body or over the strain goals.
#   docs/figures/pipeline_figures.sh BUILD_DIR [--window]
set -euo pipefail
build=$(realpath "${1:?usage: pipeline_figures.sh BUILD_DIR [--window]}")
view=${2:-}
cd "$(dirname "$0")/../.."
. docs/figures/walk_session.sh
runs=${PIPELINE_FIG_RUNS:-4}
variants=${PIPELINE_FIG_VARIANTS:-default before nice0}
rec=$(walk_recording)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir -p "$out/before"
printf '#!/bin/sh\nexec "%s" --queue latest "$@"\n' "$(bin tryon-sim)" >"$out/before/tryon-sim"
printf '#!/bin/sh\nexec "%s" --queue latest "$@"\n' "$(bin tryon-bodyfit)" \
    >"$out/before/tryon-bodyfit"
chmod +x "$out/before/tryon-sim" "$out/before/tryon-bodyfit"
one() {
    local dir="" extra=() v=(--headless --out "$out/frames" --png-every 100000)
    case $1 in
    before) dir=$out/before extra=(--mirror-nice 0) ;;
    nice0) extra=(--mirror-nice 0) ;;
    esac
    [ "$view" = --window ] && v=()
    local load
    load=$(cut -d' ' -f1 /proc/loadavg)
    local cmd=("$(bin tryon)" run "$rec" --body bodyfit --backend c "${v[@]}" "${extra[@]}")
    if [ "$view" = --window ]; then
        TRYON_BIN_DIR=$dir xvfb-run -a -s "-screen 0 1280x1024x24" "${cmd[@]}" >"$out/run.txt" 2>&1
    else
        TRYON_BIN_DIR=$dir "${cmd[@]}" >"$out/run.txt" 2>&1
    fi
    awk -v n="$1, load $load" '
        $1 ~ /^(bodyfit|sim|mirror)$/ && NF == 10 { r = r sprintf(" %s %s dropped, p95 %s ms;", $1, $3, $9) }
        /warm-up/ { w = 1 }
        w && $1 ~ /^(sim|mirror)$/ && NF == 6 { s = s sprintf(" %s %s, %s ms;", $1, $3, $5) }
        END { print n ":" r " after warm-up:" s }' "$out/run.txt"
    # the cloth as published, from the sim's log (docs/sim.md, "tryon-sim")
    local logs
    logs=$(sed -n 's/^== logs: //p' "$out/run.txt")
    if [ -n "$logs" ] && [ -f "$logs/tryon-sim.log" ]; then
        sed -n 's/^tryon-sim: cloth as published: /    cloth: /p' "$logs/tryon-sim.log"
        case $logs in */tryon-run-*) rm -rf "$logs" ;; esac
    fi
}
for k in $(seq "$runs"); do
    for v in $variants; do
        one "$v"
    done
done
