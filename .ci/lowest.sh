#!/usr/bin/env bash
# CI stage "lowest versions": the dependency range pyproject.toml declares is the one
# tested. A fresh venv on the lowest supported Python (3.10) gets mechdyn[test,plot]
# with every direct dependency at its declared floor (.ci/lowest-constraints.txt), and
# runs the quick test loop. Compiled code (mechdyn's cache, numba's cache) goes to a
# work folder of its own, removed at the end: nothing is shared with the main stage.
# Exits non-zero when the install or a test fails.
set -euo pipefail
cd "$(dirname "$0")/.."

python_for_stage() {
    local candidate
    for candidate in python3.10 /root/.pyenv/versions/3.10.13/bin/python "${HOME:-/root}"/.pyenv/versions/3.10*/bin/python; do
        # a pyenv shim exists on PATH even where its version is not selected: ask it
        if "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 10))' >/dev/null 2>&1; then
            echo "$candidate"; return
        fi
    done
    echo "lowest stage: no Python 3.10 found (python3.10 on PATH or pyenv 3.10.x);" \
         "using the default python instead: the lowest Python is NOT tested" >&2
    command -v python3 || command -v python
}

PYTHON=$(python_for_stage)
work=$(mktemp -d "${TMPDIR:-/tmp}/mechdyn-lowest.XXXXXX")
trap 'rm -rf "$work"' EXIT
echo "lowest stage: $("$PYTHON" --version 2>&1) ($PYTHON), work folder $work"
start=$SECONDS

"$PYTHON" -m venv "$work/venv"
venv_python="$work/venv/bin/python"
"$venv_python" -m pip install -q --disable-pip-version-check ".[test,plot]" \
    -c .ci/lowest-constraints.txt
"$venv_python" -m pip list --disable-pip-version-check 2>/dev/null \
    | grep -iE '^(sympy|numpy|scipy|numba|llvmlite|pint|threadpoolctl|filelock|matplotlib|pillow|latex2mathml|pytest|pytest-xdist|hypothesis|dask|distributed|psutil|fmpy) ' \
    | tr -s ' ' | paste -sd, - | sed 's/^/lowest stage: installed /'
echo "lowest stage: installed in $((SECONDS - start)) s"

# a cache of the session's own (tests/conftest.py), numba's cache and temporary files in
# the work folder
mkdir -p "$work/tmp" "$work/numba"
export MECHDYN_TEST_CACHE=fresh NUMBA_CACHE_DIR="$work/numba" TMPDIR="$work/tmp"
status=0
"$venv_python" -m pytest -q -n auto -m "not slow" tests mechdyn -p no:cacheprovider || status=$?
echo "lowest stage: exit $status after $((SECONDS - start)) s (install and tests)"
exit "$status"
