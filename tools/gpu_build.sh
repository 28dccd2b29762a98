#!/bin/sh
# Configures and builds the engine with its GPU backend (CUDA where a toolkit
# is found, CMakeLists.txt) into BUILD, the output into LOG; tools/gpu_check.sh
# and tools/gpu_lease.sh build with it. SECONDS_CAP (optional) limits the build.
#   PY=python3 tools/gpu_build.sh BUILD LOG [SECONDS_CAP]
set -e
PY=${PY:-python3}
BUILD=$1
LOG=$2
CAP=${3:-0}
[ -n "$BUILD" ] && [ -n "$LOG" ] || { echo "usage: tools/gpu_build.sh BUILD LOG [SECONDS_CAP]" >&2; exit 2; }
cd "$(dirname "$0")/.."
cmake -S . -B "$BUILD" -DPython3_EXECUTABLE="$(command -v "$PY")" \
      -Dpybind11_DIR="$("$PY" -m pybind11 --cmakedir)" -DCMAKE_BUILD_TYPE=Release >"$LOG" 2>&1
grep icerubble "$LOG" || true
if [ "$CAP" -gt 0 ]; then
  timeout "$CAP" cmake --build "$BUILD" -j"$(nproc)" >>"$LOG" 2>&1 || { tail -60 "$LOG"; exit 1; }
else
  cmake --build "$BUILD" -j"$(nproc)" >>"$LOG" 2>&1 || { tail -60 "$LOG"; exit 1; }
fi
