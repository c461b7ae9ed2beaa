#!/usr/bin/env bash
# The pipeline's latency by cause (docs/mirror.md, "Latency by cause"): counts and CPU time that
# the machine's load does not change, then the sim's deadline against fixed budgets.
#   docs/figures/latency_figures.sh BUILD_DIR
# 1. The walk's fitted bodies, recorded once (capture at 10 fps, tryon-bodyfit --queue all: no
#    frame dropped, the same bodies whatever the load), kept in
#    BUILD_DIR/recordings/latency_fitted_walk_FRAMES_VERTS/session.lcmlog.
# 2. Those bodies played to tryon-sim alone at 30 fps (`tryon pace`: each body stamped as captured
#    now and sent after its recorded fitting latency), --queue latest as live, for each
#    --frame-budget in LATENCY_FIG_BUDGETS, alternated LATENCY_FIG_RUNS times: bodies superseded,
#    frames over their budget, settle rounds, the cloth published settling and its strain, CPU ms
#    a frame (every thread: load does not change it), work and capture -> cloth p95 (load does).
# 2b. The same bodies, every one (--queue all, 8 fps, no budget): the settle rounds by how far
#    the body moved since the one before (its median vertex, --stats body_move_mm), then with
#    --settle-floor MM for each MM of LATENCY_FIG_FLOORS ("1.5 2"): the rounds of a body that
#    moved less than the fitter's noise skipped, and what that does to the strain.
# 3. One pipeline run (`tryon run --headless --record`, all four stages real): each stage's CPU
#    ms a frame, and where the frames' time went, stage by stage (`tryon path` on its log).
# Environment: LATENCY_FIG_FRAMES (150), LATENCY_FIG_BODY_VERTS (6000), LATENCY_FIG_RUNS (2),
# LATENCY_FIG_BUDGETS ("auto 20 0"; auto:MS is auto with --deadline MS), LATENCY_FIG_MOTION (1;
# 0 skips part 2b), LATENCY_FIG_PIPELINE (1; 0 skips part 3).
set -euo pipefail
build=${1:?usage: latency_figures.sh BUILD_DIR}
cd "$(dirname "$0")/../.."
bin() { find "$build" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
frames=${LATENCY_FIG_FRAMES:-150}
verts=${LATENCY_FIG_BODY_VERTS:-6000}
runs=${LATENCY_FIG_RUNS:-2}
budgets=${LATENCY_FIG_BUDGETS:-auto 20 0}
export LP_NUM_THREADS=${LP_NUM_THREADS:-1} OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
tryon=$(bin tryon)

rec="$build/recordings/figures_walk_${frames}_${verts}"
if [ ! -f "$rec/INDEX.txt" ]; then
    echo "== recording: $frames frames of 'walk' -> $rec"
    "$(bin tryon-synth)" --out "$rec" --motion walk --frames "$frames" --vertices "$verts" >/dev/null
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

fitted="$build/recordings/latency_fitted_walk_${frames}_${verts}"
if [ ! -f "$fitted/session.lcmlog" ]; then
    echo "== the walk's bodies fitted once (10 fps, tryon-bodyfit --queue all) -> $fitted"
    mkdir -p "$out/wrap"
    printf '#!/bin/sh\nexec "%s" --queue all "$@"\n' "$(realpath "$(bin tryon-bodyfit)")" \
        >"$out/wrap/tryon-bodyfit"
    chmod +x "$out/wrap/tryon-bodyfit"
    rm -rf "$fitted"
    TRYON_BIN_DIR=$out/wrap "$tryon" run "$rec" --rate 10 --body bodyfit --backend c --headless \
        --record "$fitted" --png-every 100000 >"$out/fitted.txt"
    rm -rf "$fitted/depth" "$fitted"/frame_*.png # the bodies are what is replayed
fi
bodies=$(sed -n 's/.*published \([0-9]*\) bodies.*/\1/p' "$fitted/tryon-bodyfit.log")

# bus: a private URL and channel prefix for tryon-sim and tryon pace.
bus() {
    export TRYON_LCM_URL=udpm://239.255.76.67:$((7700 + RANDOM % 200))?ttl=0\&recv_buf_size=8388608
    export TRYON_CHANNEL_PREFIX=LATFIG$$_
}
# paced BUDGET: the fitted bodies at 30 fps into tryon-sim --frame-budget BUDGET; one line.
paced() {
    bus
    local opt=(--frame-budget "${1%%:*}")
    [ "${1#*:}" = "$1" ] || opt+=(--deadline "${1#*:}")
    timeout 120 "$(bin tryon-sim)" --backend c "${opt[@]}" --frames "$bodies" \
        --stats "$out/sim.csv" 2>"$out/sim.log" &
    local sim=$!
    "$(bin tryon-profile)" --live $((bodies / 30 + 4)) >"$out/profile.txt" 2>&1 &
    local profile=$!
    sleep 1
    "$tryon" pace "$fitted/session.lcmlog" --fps 30 >/dev/null
    wait "$sim" || echo "   tryon-sim: $(tail -n 2 "$out/sim.log")"
    wait "$profile" || true
    unset TRYON_LCM_URL TRYON_CHANNEL_PREFIX
    local sup over
    sup=$(sed -n 's/.*simulated, \([0-9]*\) superseded.*/\1/p' "$out/sim.log")
    over=$(sed -n 's/.*settling, \([0-9]*\) over their budget.*/\1/p' "$out/sim.log")
    printf '== --frame-budget %s: superseded %s, over budget %s; ' "$1" "$sup" "$over"
    awk '$1 == "sim" && NF == 10 { printf "capture -> cloth p50 %s p95 %s ms; ", $8, $9 }' \
        "$out/profile.txt"
    # CSV: 2 state, 3 settle rounds, 5 strain retries, 8 max strain, 11 ms total, 12 cpu, 13 budget
    tail -n +2 "$out/sim.csv" | sort -t, -k12 -n | awk -F, '{ c[NR] = $12 }
        END { printf "cpu ms p50 %.1f p95 %.1f; ", c[int(NR / 2) + 1], c[int(NR * 0.95) + 1] }'
    tail -n +2 "$out/sim.csv" | sort -t, -k11 -n | awk -F, '{ w[NR] = $11 }
        END { printf "work p50 %.1f p95 %.1f ms\n", w[int(NR / 2) + 1], w[int(NR * 0.95) + 1] }'
    awk -F, 'NR > 1 { n++; cpu += $12; settle += $3; any += ($3 > 0); sr += $5; cut += ($2 == 3)
                      o3 += ($8 > 0.03); m = $8 > m ? $8 : m; b += $13 }
        END { printf "   %d frames: cpu ms mean %.1f, settle rounds mean %.1f (bodies with any %d), strain retries %d, budget mean %.1f ms; published settling %d, over 3 %% strain %d, worst %.2f %%\n",
              n, cpu / n, settle / n, any, sr, b / n, cut, o3, 100 * m }' "$out/sim.csv"
}
echo "== the fitted walk's $bodies bodies at 30 fps into tryon-sim alone (tryon pace)"
for k in $(seq "$runs"); do
    for b in $budgets; do
        echo "== round $k of $runs; before it: $(uptime)"
        paced "$b"
    done
done

# every_body FLOOR: every body into tryon-sim --queue all --frame-budget 0 --settle-floor FLOOR
every_body() {
    bus
    timeout 120 "$(bin tryon-sim)" --backend c --queue all --frame-budget 0 --frames "$bodies" \
        --settle-floor "$1" --stats "$out/all.csv" 2>"$out/all.log" &
    local sim=$!
    sleep 1
    "$tryon" pace "$fitted/session.lcmlog" --fps 8 >/dev/null
    wait "$sim" || echo "   tryon-sim: $(tail -n 2 "$out/all.log")"
    unset TRYON_LCM_URL TRYON_CHANNEL_PREFIX
    # 2 state, 3 settle rounds, 5 strain retries, 8 max strain, 9 max penetration mm, 12 cpu ms
    awk -F, -v f="$1" 'NR > 1 { n++; s += $3; sr += $5; cpu += $12; st += ($2 == 3); o3 += ($8 > 0.03)
                                m = $8 > m ? $8 : m; p = $9 > p ? $9 : p }
        END { printf "   --settle-floor %s mm: settle rounds %.1f a body, strain retries %d, cpu %.1f ms a body; published settling %d, over 3 %% strain %d, worst %.2f %%; penetration worst %.2f mm\n",
              f, s / n, sr, cpu / n, st, o3, 100 * m, p }' "$out/all.csv"
}
if [ "${LATENCY_FIG_MOTION:-1}" = 1 ]; then
    echo "== every body (--queue all, 8 fps, --frame-budget 0): settle rounds by the body's motion"
    every_body 0
    # 3 settle rounds, 14 body_move_mm (-1: the first body)
    awk -F, 'NR > 1 && $14 >= 0 { m = $14; b = m < 1 ? "0-1" : m < 1.5 ? "1-1.5" : m < 2 ? "1.5-2" : m < 3 ? "2-3" : ">= 3"
             n[b]++; s[b] += $3; any[b] += ($3 > 0); all += $3 }
        END { for (b in n) printf "   moved %-5s mm: %3d bodies, settle rounds %.1f a body (%d with any), %.1f %% of all rounds\n",
              b, n[b], s[b] / n[b], any[b], 100 * s[b] / all }' "$out/all.csv" | sort
    for f in ${LATENCY_FIG_FLOORS:-1.5 2}; do
        every_body "$f"
    done
fi

[ "${LATENCY_FIG_PIPELINE:-1}" = 1 ] || exit 0
echo "== the pipeline, headless, all four stages real; before it: $(uptime)"
"$tryon" run "$rec" --body bodyfit --backend c --headless --out "$out" --png-every 100000 \
    --record "$out/session" >"$out/run.txt"
sed -n '/^stage /,/^{/p' "$out/run.txt"
# CPU ms a frame: the launcher's CPU seconds over the frames each stage put out
awk '$1 ~ /^(capture|bodyfit|sim|mirror)$/ && NF == 10 { f[$1] = $2 }
     /CPU time per stage/ { cpu = 1 } cpu && $1 ~ /^tryon-/ { s = substr($1, 7); c[s] = $2 }
     END { for (s in f) if (s in c) printf "   %-8s %6.1f ms CPU a frame (%s s over %d frames)\n", s, 1000 * c[s] / f[s], c[s], f[s] }' \
    "$out/run.txt" | sort
"$tryon" path "$out/session/session.lcmlog"
