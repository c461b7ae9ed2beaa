#!/bin/sh
# Figures of docs/garments.md "Strain": where tryon's dressing stretches every shipped garment in
# S, M and L (tryon-bench-dress --strain-report), without the last spreading rounds (--spread 0,
# the dressing as it was) and with them (the default), and the jeans M's dressing time, the two
# alternating three times on 2 threads.
# Usage: docs/figures/corners_figures.sh BUILD_DIR   (a Release build)
set -eu
build=${1:?usage: $0 BUILD_DIR}
bench="$build/garments/tryon-bench-dress"
pat="$(dirname "$0")/../../garments/patterns"
all="$pat/tshirt.json $pat/jeans.json $pat/skirt.json $pat/dress.json"
export OMP_WAIT_POLICY=passive OMP_NUM_THREADS=2
for spread in 0 100; do
    for size in S M L; do
        echo "== --method tryon --spread $spread --size $size --strain-report, cotton"
        # shellcheck disable=SC2086
        "$bench" --method tryon --spread $spread --size $size --strain-report $all
    done
done
for run in 1 2 3; do
    for spread in 0 100; do
        echo "== jeans M time, --spread $spread, run $run"
        "$bench" --method tryon --spread $spread --size M "$pat/jeans.json" | grep '^jeans'
    done
done
echo "== --drape"
"$bench" --drape
