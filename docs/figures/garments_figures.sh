#!/bin/sh
# Figures of docs/garments.md: tryon-bench-dress on the shipped patterns, both methods.
# Usage: docs/figures/garments_figures.sh BUILD_DIR   (a Release build)
set -eu
build=${1:?usage: $0 BUILD_DIR}
bench="$build/garments/tryon-bench-dress"
pat="$(dirname "$0")/../../garments/patterns"
all="$pat/tshirt.json $pat/jeans.json $pat/skirt.json $pat/dress.json"
export OMP_WAIT_POLICY=passive
for method in seed tryon; do
    for threads in 1 2; do
        echo "== --method $method, OMP_NUM_THREADS=$threads, size M, cotton"
        # shellcheck disable=SC2086
        OMP_NUM_THREADS=$threads "$bench" --method $method $all
    done
    echo "== --method $method, jeans in denim, sizes S and L, 2 threads"
    for size in S L; do
        OMP_NUM_THREADS=2 "$bench" --method $method --size $size --fabric denim "$pat/jeans.json"
    done
done
echo "== --method tryon, every garment in sizes S and L, cotton and denim, 2 threads"
for fabric in cotton denim; do
    for size in S L; do
        # shellcheck disable=SC2086
        OMP_NUM_THREADS=2 "$bench" --method tryon --size $size --fabric $fabric $all
    done
done
