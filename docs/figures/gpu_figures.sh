#!/bin/bash
# The GPU figures of docs/sim.md ("On a GPU"): on a machine with an OpenCL GPU, the sim's tests
# both ways (one work-group, pass by pass) and tryon-bench-sim's body and drape scenes on the GPU
# both ways and on the C backend. Prints a line per run; the JSON lines go to BUILD_DIR/gpu-figures.
# usage: docs/figures/gpu_figures.sh BUILD_DIR   (a Release build; clinfo -l should list the GPU:
#        NVIDIA's driver needs /etc/OpenCL/vendors/nvidia.icd naming libnvidia-opencl.so.1)
set -u
B=${1:?usage: $0 BUILD_DIR}
OUT=$B/gpu-figures
mkdir -p "$OUT"
export OMP_WAIT_POLICY=passive
echo "== the sim's tests on the OpenCL device, one work-group and pass by pass"
for m in 0 1; do
    for t in test_cl_backend test_cl_collide test_sim_golden test_sim_drape test_sim_follow \
             test_sim_support test_sim_carry test_sim_motion test_sim_recover test_sim_stability; do
        printf '%-22s TRYON_CL_PASSES=%s: ' "$t" "$m"
        if TRYON_CL_PASSES=$m "$B/tests/sim/$t" > "$OUT/$t-$m.log" 2>&1; then echo passed
        else echo "FAILED ($OUT/$t-$m.log)"; fi
    done
done
grep -h "hash\|max |dx|" "$OUT"/test_sim_golden-1.log "$OUT"/test_cl_backend-1.log
line() { python3 -c '
import json, sys
for l in sys.stdin:
    if l.startswith("{"):
        d = json.loads(l)
        print("%-60s %6d vertices  ms median %7.2f  p95 %7.2f  strain %.2f / %.2f %%  inside %d  settle %d" % (
            d["device"][:60], d["verts"], d["ms_median"], d["ms_p95"], 100 * d["max_strain"],
            100 * d["p99_strain"], d["penetrating"], d["settle_frames"]))'; }
run() { "$B/sim/tryon-bench-sim" --iterations 25 --no-ref "$@" 2>/dev/null | tail -n 1 |
        tee -a "$OUT/bench.jsonl" | line; }
: > "$OUT/bench.jsonl"
echo "== body scene, the shirt (7,105 vertices), all motions"
for m in 0 1 0 1; do TRYON_CL_PASSES=$m run --scene body --verts 7000 --backend opencl; done
run --scene body --verts 7000 --backend c
OMP_NUM_THREADS=2 run --scene body --verts 7000 --backend c
echo "== body scene, 150 frames, by garment size"
for n in 2000 3000 4000 5000 7000; do
    for m in 0 1; do TRYON_CL_PASSES=$m run --scene body --verts $n --frames 150 --backend opencl; done
done
echo "== drape scene by size"
for n in 2000 7056 15000 30000 60000; do
    for m in 0 1; do TRYON_CL_PASSES=$m run --scene drape --verts $n --backend opencl; done
    run --scene drape --verts $n --backend c
done
