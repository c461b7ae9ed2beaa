#!/bin/sh
# Figures of docs/garments.md "Strain" and "Figures today": every shipped garment in S, M and L
# dressed with tryon's method (seam gap, inside, crossings, max / p99 strain, ms; where the
# strain is: --strain-report), with the default sweeps (3 while seaming, 8 under gravity) and with
# 3 throughout (the dressing before); the jeans in denim; the jeans M's dressing time, the two
# alternating five times; the drape coefficients; the size picks on the three body shapes.
# Usage: docs/figures/strain_figures.sh BUILD_DIR   (a Release build)
set -eu
build=${1:?usage: $0 BUILD_DIR}
bench="$build/garments/tryon-bench-dress"
pat="$(dirname "$0")/../../garments/patterns"
all="$pat/tshirt.json $pat/jeans.json $pat/skirt.json $pat/dress.json"
export OMP_WAIT_POLICY=passive OMP_NUM_THREADS=2
for size in S M L; do
    echo "== --method tryon --size $size --strain-report, cotton"
    # shellcheck disable=SC2086
    "$bench" --method tryon --size $size --strain-report $all
done
for size in S M L; do
    echo "== --method tryon --size $size --iterations 3, cotton"
    # shellcheck disable=SC2086
    "$bench" --method tryon --size $size --iterations 3 $all | grep -v '^{'
done
for size in S M L; do
    echo "== --method tryon --size $size --fabric denim, jeans"
    "$bench" --method tryon --size $size --fabric denim "$pat/jeans.json" | grep -v '^{'
done
for run in 1 2 3 4 5; do
    for it in default 3; do
        echo "== jeans M time, sweeps $it, run $run"
        if [ "$it" = default ]; then
            "$bench" --method tryon --size M "$pat/jeans.json" | grep '^jeans'
        else
            "$bench" --method tryon --size M --iterations 3 "$pat/jeans.json" | grep '^jeans'
        fi
    done
done
echo "== --drape"
"$bench" --drape | grep -v '^{'
for shape in 1 0 2; do
    echo "== --pick-size --shape $shape"
    # shellcheck disable=SC2086
    "$bench" --method tryon --pick-size --shape $shape $all | grep -iv '^{'
done
