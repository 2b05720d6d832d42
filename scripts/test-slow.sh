#!/usr/bin/env bash
# Runs the tests labelled `slow` (file names ending in _slow): the large peer-comparison
# instances and the long convergence studies and example runs that scripts/test.sh leaves out
# (README, "Tests"). Extra arguments go to ctest (e.g. -R FetiExample06).
set -euo pipefail
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ctest --test-dir build --output-on-failure -L slow -j"$(nproc)" --timeout 1800 "$@"
