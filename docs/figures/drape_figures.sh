#!/bin/sh
# Figures of docs/garments.md "Bending", "Drape test", "Strain", "Which size fits", "Stability
# map" and the skirt and the dress on the walk: each fabric's Cusick drape coefficient (1, 3 and
# 10 sweeps), tryon's dressing of every shipped garment and size, the jeans' dressing time
# (alternating with a build of the previous commit when BASE_BUILD is set), the size picked on
# the three body shapes, the stability map of both methods on the skirt, and the skirt and the
# dress on the walk (60 frames, then the whole clip).
# Usage: docs/figures/drape_figures.sh BUILD_DIR   (a Release build; BASE_BUILD=DIR optional)
set -eu
build=${1:?usage: $0 BUILD_DIR}
bench="$build/garments/tryon-bench-dress"
sim="$build/sim/tryon-bench-sim"
pat="$(dirname "$0")/../../garments/patterns"
all="$pat/tshirt.json $pat/jeans.json $pat/skirt.json $pat/dress.json"
export OMP_WAIT_POLICY=passive OMP_NUM_THREADS=2
for it in 1 3 10; do
    echo "== --drape --iterations $it"
    "$bench" --drape --iterations $it
done
for size in S M L; do
    echo "== --method tryon --size $size, cotton"
    # shellcheck disable=SC2086
    "$bench" --method tryon --size $size $all
done
for run in 1 2 3; do
    echo "== jeans M time, run $run"
    "$bench" --method tryon --size M "$pat/jeans.json" | grep '^jeans'
    if [ -n "${BASE_BUILD:-}" ]; then
        "$BASE_BUILD/garments/tryon-bench-dress" --method tryon --size M "$pat/jeans.json" |
            grep '^jeans' | sed 's/^/base /'
    fi
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
for g in skirt dress; do
    for frames in 60 0; do
        echo "== $g on the walk, frames $frames (0: the whole clip)"
        if [ "$frames" = 0 ]; then f=""; else f="--frames $frames"; fi
        # shellcheck disable=SC2086
        "$sim" --scene body --verts 7000 --iterations 25 --backend c --no-ref \
            --garment "$pat/$g.json" --motion walk $f | tail -n 1
    done
done
