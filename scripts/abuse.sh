#!/usr/bin/env bash
# The abuse set of docs/robustness.md: every test that feeds the binary bad input, damaged or
# foreign files, signals, a full disk, a busy output directory or hostile PETSc options, and
# checks what it says and what it leaves behind (issue 20, issue 9). Under 5 minutes on the
# 2-core machine; the next round of abuse starts from it.
#   scripts/abuse.sh [extra ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ctest --test-dir build --output-on-failure -j"$(nproc)" \
  -R '^(Issue20|Issue42[A-Za-z]*|AbuseCli|Kill|Restart|NaN|Nan|MeshRobustness|Cli|Files/InvalidCase|FuzzRegression|FetiMpiCli)\.|InvalidCase' \
  "$@"
