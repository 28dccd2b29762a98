#!/bin/bash
# Everything a lent GPU machine is for, in one call that fits a short lease
# (docs/gpu.md): the build, tools/gpu_check.py, the CPU step by thread count
# and the GPU's stages and whole steps on the paper mesh
# (bench/gpu_body_forces.py), then the paper scene's run on the GPU
# (bench/gpu_paper_run.py) with what time is left; bench/gpu_step_profile.py
# (each kernel's time, Nsight Compute) right after the checks, since what the
# next change should be is read from it. Each part is capped so the
# parts after it still run; logs go to $OUT (or runs/lease).
# The demo's CPU run (item 12's reference) runs in the background on cores of
# its own beside the checks, which use the GPU and a few cores.
# Where a rest state of the paper scene was carried (REST, made on the CPU by
# bench/paper_peak.py --settle-only), the last part loads the fast preset from it
# instead (bench/paper_peak.py --rest) to TRAVEL mm (1: ~410 s on an H200 at
# code 4d0a7ef): no settle on the lease. Its run file comes back too, so the
# run is kept where its summary fails. At most 8 files come back from $OUT:
# this writes 8 (the build's log stays on the machine, its tail printed if it fails).
#   BUDGET=540 PY=python3 tools/gpu_lease.sh   (carry runs/scenes: the demo's and paper ridge 1's pile and mesh;
#                                               and the rest state's file, $REST below: not its folder, where
#                                               the CPU's study runs go, beyond a carry's 64 MiB)
PY=${PY:-python3}
BUILD=${BUILD:-build-gpu}
BUDGET=${BUDGET:-540}        # seconds for the whole script
OUT=${OUT:-runs/lease}
MESH=${MESH:-runs/scenes/paper_ridge1_pilemu0.3_mesh.h5}
REST=${REST:-runs/bench/paper_peak/ridge1_2mm/rest_fast.checkpoint.h5}
TRAVEL=${TRAVEL:-1}
cd "$(dirname "$0")/.."
mkdir -p "$OUT"
t0=$(date +%s)
left() { echo $(( BUDGET - ($(date +%s) - t0) )); }
cap() { local c=$1 l; l=$(left); [ "$l" -lt "$c" ] && c=$l; [ "$c" -lt 1 ] && c=1; echo "$c"; }
# PYTHONPATH: the bench scripts import icerubble from this checkout (no install there)
export PYTHONUNBUFFERED=1 PATH="$PATH:/usr/local/cuda/bin" PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}"
echo "== machine"; nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm --format=csv
nproc; command -v nvcc && nvcc --version | tail -2
# two threads on one core read as poor scaling (the lease of 2026-11-30: 1.33x on 2 threads)
command -v lscpu >/dev/null && lscpu | grep -E "^(Thread|Core|Socket|NUMA node\(s\)|Model name)" 
echo "== build ($(left) s left)"
PY="$PY" tools/gpu_build.sh "$BUILD" /tmp/gpu_build.log "$(cap 300)" || exit 1
echo "built in $(( $(date +%s) - t0 )) s"
"$PY" -c "from icerubble.engine import gpu; print('gpu available:', gpu.available(), gpu.why_unavailable() if not gpu.available() else gpu.device_name())"
triad=()
${CXX:-g++} -O3 -fopenmp bench/stream_triad.cpp -o "$BUILD/stream_triad" && triad=(--triad "$BUILD/stream_triad")
echo "== demo on the CPU, in the background (4 threads)"
rm -rf /tmp/demo_cpu
OMP_NUM_THREADS=4 timeout "$(cap 330)" "$PY" tools/gpu_check.py --demo-cpu-run /tmp/demo_cpu >/tmp/demo_cpu.log 2>&1 &
demo_pid=$!
echo "== tools/gpu_check.py, items 1-11 ($(left) s left)"
status=0
OMP_NUM_THREADS=8 timeout "$(cap 200)" "$PY" tools/gpu_check.py --mesh "$MESH" --demo skip 2>&1 | tee "$OUT/gpu_check.log" \
  | grep -v "^\[ok\]" ; [ "${PIPESTATUS[0]}" = 0 ] || status=1
grep -c "^\[ok\]" "$OUT/gpu_check.log" | sed 's/^/checks ok: /'
echo "== bench/gpu_step_profile.py: each kernel's time ($(left) s left)"
timeout "$(cap 150)" "$PY" bench/gpu_step_profile.py --mesh "$MESH" --out "$OUT/gpu_step_profile.json" 2>&1 | tail -4
echo "== item 12, the demo ($(left) s left)"
wait $demo_pid; tail -1 /tmp/demo_cpu.log
cpu=$(ls /tmp/demo_cpu/demo_cpu.h5 2>/dev/null)
if [ -n "$cpu" ]; then
  timeout "$(cap 150)" "$PY" tools/gpu_check.py --demo only --demo-cpu-result "$cpu" 2>&1 | tee "$OUT/demo.log" | tail -3
  [ "${PIPESTATUS[0]}" = 0 ] || status=1
else status=1; fi
echo "== bench/gpu_body_forces.py ($(left) s left)"
timeout "$(cap 150)" "$PY" bench/gpu_body_forces.py --mesh "$MESH" --threads 1 2 4 8 16 "${triad[@]}" \
  --out "$OUT/gpu_body_forces.json" 2>&1 | tee "$OUT/gpu_body_forces.log" | grep -v "^triad"
if [ -f "$REST" ]; then
  echo "== the paper scene, fast, on the GPU from the carried rest state, to $TRAVEL mm ($(left) s left)"
  timeout "$(cap 9999)" "$PY" bench/paper_peak.py --device cuda --rest "$REST" --only fast --travel-mm "$TRAVEL" \
    >"$OUT/paper_peak.log" 2>&1
  echo "exit $? after $(( $(date +%s) - t0 )) s"; grep -v "^\s*$" "$OUT/paper_peak.log" | tail -8
  cp bench/results/paper_peak_cuda.json "$OUT/" 2>/dev/null
  cp "runs/bench/paper_peak/ridge1_${TRAVEL}mm_cuda/fast.h5" "$OUT/paper_fast_cuda.h5" 2>/dev/null
  # a run the cap stopped left its checkpoint (in place of the two files above): a later lease
  # carrying it back to that folder resumes it, where its build is byte for byte this one's
  cp "runs/bench/paper_peak/ridge1_${TRAVEL}mm_cuda/fast.checkpoint.h5" "$OUT/" 2>/dev/null
else
  echo "== the paper scene on the GPU, fast, to 20 mm ($(left) s left)"
  timeout "$(cap 9999)" "$PY" bench/gpu_paper_run.py --device cuda --preset fast --travel-mm 20 >"$OUT/paper_run.log" 2>&1
  echo "exit $? after $(( $(date +%s) - t0 )) s"; grep -v "^\s*$" "$OUT/paper_run.log" | tail -8
  cp runs/gpu_paper_run/*/gpu_paper_run.json "$OUT/" 2>/dev/null
fi
exit $status
