#!/usr/bin/env bash
# Runs ctest's default set: every test but those labelled `slow`.
set -euo pipefail
cd "$(dirname "$0")/.."
# OpenMPI refuses to run as root unless told; CI runs as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ctest --test-dir build --output-on-failure -LE slow -j"$(nproc)" "$@"
