#!/bin/sh
# Figures of docs/garments.md and docs/sim.md, "Pattern garments in tryon-sim": the T-shirt
# (size M, 1,109 vertices) dressed on the body model at the walk's first pose, settled, then
# simulated on the walk's first 15 frames, and the skirt (size L) on 8 frames standing (C backend;
# the T-shirt and jeans on whole motions: docs/figures/motion_figures.sh BUILD 0 PATTERN.json);
# and tryon-sim as a process dressing the T-shirt (size L) on the first body with a shape.
# Usage: docs/figures/simgar_figures.sh BUILD_DIR   (a Release build)
set -eu
build=${1:?usage: $0 BUILD_DIR}
export OMP_WAIT_POLICY=passive
echo "== test_sim_pattern (library): dressing ms, per-frame sim ms and penetration"
"$build/tests/sim/test_sim_pattern" 2>&1 | grep -E "dressed|frame|cotton:"
echo "== tryon-sim --garment tshirt.json --size L (process): the dressing line of its log"
ctest --test-dir "$build" -R '^test_sim_pattern_process$' -V 2>&1 | grep -E "dressed|garment .* vertices|frames simulated"
