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
