#!/bin/sh
# Figures of docs/garments.md "Strain", "Drape test" and "Which size fits": tryon's dressing of
# every shipped garment and size (1 and 3 sweeps a step), each fabric's Cusick drape coefficient
# (1, 3 and 10 sweeps), the size picked on the three body shapes and the stability map (seam
# stiffness x time step) of both methods on the skirt.
# Usage: docs/figures/garments_fit_figures.sh BUILD_DIR   (a Release build)
set -eu
build=${1:?usage: $0 BUILD_DIR}
bench="$build/garments/tryon-bench-dress"
pat="$(dirname "$0")/../../garments/patterns"
all="$pat/tshirt.json $pat/jeans.json $pat/skirt.json $pat/dress.json"
export OMP_WAIT_POLICY=passive OMP_NUM_THREADS=2
for it in 1 3; do
    for size in S M L; do
        echo "== --method tryon --iterations $it --size $size, cotton"
        # shellcheck disable=SC2086
        "$bench" --method tryon --iterations $it --size $size $all
    done
done
for it in 1 3 10; do
    echo "== --drape --iterations $it"
    "$bench" --drape --iterations $it
done
for shape in 0 1 2; do
    echo "== --method tryon --pick-size --shape $shape, cotton"
    # shellcheck disable=SC2086
    "$bench" --method tryon --pick-size --shape $shape $all
done
for method in seed tryon; do
    echo "== --method $method --stability --spacing 0.03, skirt, cotton"
    "$bench" --method $method --stability --spacing 0.03 "$pat/skirt.json"
done
