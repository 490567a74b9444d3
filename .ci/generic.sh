#!/usr/bin/env bash
# CI stage: the quick loop once more with numba compiling for a generic x86-64/aarch64
# CPU instead of this host's (NUMBA_CPU_NAME=generic), in a cache folder of its own, so
# that a result hinging on the host's instruction set (FMA contraction, vector widths,
# summation order) shows up here before it does on a user's machine.
set -euo pipefail
cd "$(dirname "$0")/.."
export NUMBA_CPU_NAME=generic
export MECHDYN_TEST_CACHE=fresh          # compile every scene for this target
python -m pytest -q -n auto -m "not slow" tests mechdyn
