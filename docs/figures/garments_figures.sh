#!/bin/sh
# Figures of docs/garments.md: tryon-bench-dress on the shipped patterns.
# Usage: docs/figures/garments_figures.sh BUILD_DIR   (a Release build)
set -eu
build=${1:?usage: $0 BUILD_DIR}
bench="$build/garments/tryon-bench-dress"
pat="$(dirname "$0")/../../garments/patterns"
export OMP_WAIT_POLICY=passive
for threads in 1 2; do
    echo "== OMP_NUM_THREADS=$threads, size M, cotton"
    OMP_NUM_THREADS=$threads "$bench" "$pat/tshirt.json" "$pat/jeans.json" "$pat/skirt.json" \
        "$pat/dress.json"
done
echo "== jeans in denim, sizes S and L, 2 threads"
for size in S L; do
    OMP_NUM_THREADS=2 "$bench" --size $size --fabric denim "$pat/jeans.json"
done
