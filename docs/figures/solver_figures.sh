#!/bin/sh
# The solver refactor's check (docs/sim.md, "How the solver is organised"): the golden hashes, and
# the body-scene figures of both backends, which a change to the solver's code organisation must
# leave unchanged. With OLD_BENCH (a tryon-bench-sim built before the change) the non-timing
# figures are compared exactly, the instructions of 4 frames counted (valgrind) and the median
# frame times alternated old / new three times.
# usage: docs/figures/solver_figures.sh BUILD_DIR [OLD_BENCH]
set -eu
B=${1:-build}
OLD=${2:-}
OUT=$B/solver-figures
mkdir -p "$OUT"
"$B/tests/sim/test_sim_golden" | grep '^#'
# the per-10-frame table's strain, p99, penetration and state columns, the per-motion table, and
# the JSON's non-timing fields
figures() {
    OMP_WAIT_POLICY=passive "$1" --scene body --verts 7000 --iterations 25 --backend "$2" \
        --no-ref --cache-dir "$OUT" > "$3.txt" 2>&1
    awk 'NF >= 10 && $1 ~ /^[0-9]+-[0-9]+$/ {print $1, $6, $7, $8, $9, $10}
         NF == 9 && $1 !~ /^motion/ {print $1, $2, $3}' "$3.txt" > "$3.fig"
    tail -n 1 "$3.txt" | tr ',' '\n' | grep -E '"(max_strain|p99_strain|penetrating|max_pen_mm|recovered_frames|diverged_frames|settle_frames|strain_retried_frames|pen_free_frames_pct|strain_ok_frames_pct|carried_frames)"' >> "$3.fig"
    printf '%s %s: %s\n' "$1" "$2" "$(tail -n 1 "$3.txt" | tr ',' '\n' | grep -E '"ms_(median|p95)"' | tr '\n' ' ')"
}
for backend in c opencl; do
    figures "$B/sim/tryon-bench-sim" $backend "$OUT/new-$backend"
    if [ -n "$OLD" ]; then
        figures "$OLD" $backend "$OUT/old-$backend"
        if cmp -s "$OUT/old-$backend.fig" "$OUT/new-$backend.fig"; then
            echo "$backend: figures identical"
        else
            echo "$backend: figures DIFFER"; diff "$OUT/old-$backend.fig" "$OUT/new-$backend.fig" || true
        fi
    fi
done
if [ -n "$OLD" ] && command -v valgrind > /dev/null; then
    # instructions, which the machine's load does not change (4 frames, 1 thread)
    for bin in "$OLD" "$B/sim/tryon-bench-sim"; do
        printf 'instructions, %s: ' "$bin"
        OMP_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$OUT/callgrind.out" \
            "$bin" --scene body --verts 7000 --iterations 25 --backend c --no-ref --frames 4 \
            --cache-dir "$OUT" 2>&1 > /dev/null | grep -o 'Collected : [0-9]*'
    done
fi
if [ -n "$OLD" ]; then
    for r in 1 2 3; do
        for bin in "$OLD" "$B/sim/tryon-bench-sim"; do
            printf 'C, 1 thread, %s: ' "$bin"
            OMP_NUM_THREADS=1 "$bin" --scene body --verts 7000 --iterations 25 --backend c \
                --no-ref --cache-dir "$OUT" | tail -n 1 | tr ',' '\n' | grep '"ms_median"'
        done
    done
fi
