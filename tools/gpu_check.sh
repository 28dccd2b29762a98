#!/bin/sh
# Builds the engine with its GPU backend on this machine (a CUDA toolkit and
# a GPU needed) and checks the GPU against the CPU (tools/gpu_check.py), then
# times it (bench/gpu_friction.py, bench/gpu_body_forces.py). Arguments: scene mesh files to check
# and time on (runs/scenes/*_mesh.h5); without, the built-in scene only.
#   PY=python3 BUILD=build-gpu THREADS="1 2 4 8 16" tools/gpu_check.sh runs/scenes/paper_ridge1_pilemu0.3_mesh.h5
set -e
PY=${PY:-python3}
BUILD=${BUILD:-build-gpu}
THREADS=${THREADS:-"1 2"}
cd "$(dirname "$0")/.."
# the bench scripts import icerubble from this checkout (a lent machine has no install)
export PYTHONPATH="$PWD${PYTHONPATH:+:$PYTHONPATH}"
start=$(date +%s)
PY="$PY" tools/gpu_build.sh "$BUILD" "$BUILD.log"
echo "built in $(( $(date +%s) - start )) s"
triad=""   # a lent machine's compiler may lack OpenMP: the bandwidth is then left out
${CXX:-g++} -O3 -fopenmp bench/stream_triad.cpp -o "$BUILD/stream_triad" && triad="--triad $BUILD/stream_triad" || true
status=0
"$PY" tools/gpu_check.py --mesh "$@" || status=1
"$PY" bench/gpu_friction.py --out "${OUT:-bench/results}/gpu_friction.json" || status=1
for mesh in "$@"; do
  "$PY" bench/gpu_body_forces.py --mesh "$mesh" --threads $THREADS $triad \
        --out "${OUT:-bench/results}/gpu_body_forces_$(basename "$mesh" .h5).json"
done
exit $status
