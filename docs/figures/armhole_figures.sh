#!/bin/sh
# The bound armholes' figures in docs/sim-history.md ("Bound armholes"): the body scene (the cloth
# headline: 7,000 vertices, 25 iterations, C backend) and the arms-down motions, per run the
# frames that ran settle rounds, the frames retried for their strain, carried frames, max / p99
# strain, points inside, ms median / p95. Settle frames, strain and carried frames are
# deterministic; the times are for a quiet machine.
# usage: docs/figures/armhole_figures.sh BUILD_DIR [OTHER_BENCH ...] [-- ROUNDS]
#        OTHER_BENCH: more tryon-bench-sim binaries (e.g. built before the binding or with
#        SHIRT_ARMHOLE_M 0), run alternated with BUILD_DIR's so that their times compare;
#        ROUNDS: how many times the body scene is run per binary (default 3).
# Environment: ARMHOLE_FIG_SIMS="TRYON_SIM ..." also records one session of the pipeline on the
# walk recording (tryon run --record, as docs/figures/mirror_figures.sh does) and replays its
# fitted bodies one by one into BUILD_DIR's tryon-sim and each of these (--queue all): the same
# bodies for all, so their settle rounds and strain retries compare.
set -eu
B=${1:-build}
[ $# -gt 0 ] && shift
BENCHES="$B/sim/tryon-bench-sim"
ROUNDS=3
while [ $# -gt 0 ]; do
    if [ "$1" = -- ]; then
        ROUNDS=${2:-3}
        break
    fi
    BENCHES="$BENCHES $1"
    shift
done
export OMP_WAIT_POLICY=passive
row() { python3 -c "
import json, sys
j = json.loads(sys.stdin.read())
print('%-28s %-13s %6d %6d %8d %8d %8.2f %6.2f %6d %7.2f %7.2f' % (sys.argv[1][-28:], sys.argv[2],
      j['frames'], j['settle_frames'], j['strain_retried_frames'], j['carried_frames'],
      100 * j['max_strain'], 100 * j['p99_strain'], j['penetrating'], j['ms_median'],
      j['ms_p95']))" "$1" "$2"; }
printf '%-28s %-13s %6s %6s %8s %8s %8s %6s %6s %7s %7s\n' binary motion frames settle \
    retried carried max_str% p99% inside ms_med ms_p95
i=0
while [ "$i" -lt "$ROUNDS" ]; do
    for b in $BENCHES; do
        "$b" --scene body --verts 7000 --iterations 25 --backend c --no-ref | tail -n 1 |
            row "$b" body
    done
    i=$((i + 1))
done
for m in arms_down boxing_guard twist; do
    for b in $BENCHES; do
        "$b" --scene body --verts 7000 --iterations 25 --backend c --no-ref --motion "$m" \
            --frames 180 | tail -n 1 | row "$b" "$m"
    done
done

[ -n "${ARMHOLE_FIG_SIMS:-}" ] || exit 0
bin() { find "$B" -maxdepth 3 -type f -name "$1" -perm -u+x | head -n 1; }
rec="$B/recordings/figures_walk_150_6000"
[ -f "$rec/INDEX.txt" ] ||
    "$(bin tryon-synth)" --out "$rec" --motion walk --frames 150 --vertices 6000 >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$(bin tryon)" run "$rec" --body bodyfit --backend c --headless --record "$out/session" \
    --png-every 100000 >"$out/recorded.txt"
prefix=$(sed -n 's/^== latency per stage (TIMING, \(.*\)):$/\1/p' "$out/recorded.txt")
bodies=$(sed -n 's/.*published \([0-9]*\) bodies.*/\1/p' "$out/session/tryon-bodyfit.log" | tail -n 1)
echo "== one session's $bodies fitted bodies replayed into each tryon-sim (--queue all)"
for sim in "$(bin tryon-sim)" $ARMHOLE_FIG_SIMS; do
    url="udpm://239.255.76.67:$((7700 + $$ % 200))?ttl=0&recv_buf_size=8388608"
    TRYON_LCM_URL=$url TRYON_CHANNEL_PREFIX=$prefix timeout 300 "$sim" --backend c --queue all \
        --frames "$bodies" --stats "$out/sim.csv" 2>"$out/sim.log" &
    pid=$!
    sleep 1
    lcm-logplayer -s 0.25 -e "${prefix}BODY" -l "$url" "$out/session/session.lcmlog" >/dev/null
    wait "$pid" || echo "$sim did not take all $bodies bodies: $(tail -n 3 "$out/sim.log")"
    awk -F, -v sim="$sim" 'NR > 1 { n++; sum += $11; settle += $3; full += ($3 >= 50); sr += $5 }
        END { printf "%s: %d bodies, work ms mean %.1f; settle rounds mean %.1f, bodies at 50 " \
              "rounds %d; strain retries %d\n", sim, n, sum / n, settle / n, full, sr }' "$out/sim.csv"
done
