#!/bin/sh
# Figures of docs/garments.md, "Pattern garments on the moving body": the T-shirt and the jeans
# (size M, about 7,000 vertices) on the body scene's motions, the scripted ones real motion
# spends its time in and the three motion-capture clips (motion_figures.sh with a garment), the
# T-shirt L with the arms down, the cloth error of both on the first 150 frames of the body
# scene, and the short takes of test_sim_pattern.
# Usage: docs/figures/wear_figures.sh BUILD_DIR   (a Release build; about 25 minutes on 2 cores)
set -eu
build=${1:?usage: $0 BUILD_DIR}
here=$(dirname "$0")
export OMP_WAIT_POLICY=passive
for g in tshirt jeans; do
    echo "== $g M: docs/figures/motion_figures.sh $build 0 garments/patterns/$g.json M"
    sh "$here/motion_figures.sh" "$build" 0 "garments/patterns/$g.json" M
done
echo "== tshirt L, arms down"
"$build/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --backend c --no-ref \
    --garment garments/patterns/tshirt.json --size L --motion arms_down --frames 180 | tail -n 1
for g in tshirt jeans; do
    echo "== $g M, cloth error against the converged reference (still and the arm raise)"
    "$build/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --backend c \
        --garment "garments/patterns/$g.json" --frames 150 --motion all | tail -n 6
done
for g in jeans skirt; do
    echo "== $g M on two seconds of the walk (docs/garments.md, \"The jeans on the walk\")"
    "$build/sim/tryon-bench-sim" --scene body --verts 7000 --iterations 25 --backend c --no-ref \
        --garment "garments/patterns/$g.json" --motion walk --frames 60 | tail -n 1
done
echo "== test_sim_pattern: sewn, held, the T-shirt on half a second of the walk"
"$build/tests/sim/test_sim_pattern" 2>&1 | grep -E "cotton:|OK|FAILED"
