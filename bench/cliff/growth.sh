#!/usr/bin/env bash
# Issue 22's growth case at ×3: example 06 refined three times in every direction (master
# 24×90×18, slave 18×18×18: 200 336 dofs with the temperature, 1 083 multipliers), plain
# Newmark, 30 steps of 0.01 s. Runs a baseline binary and this build in the same command and
# prints, for each, the dual set-up and factorisation seconds, their ratio, the QP, the peak
# RSS, and the history columns that differ (compare.sh). ~3.2 GiB each.
#   bench/cliff/growth.sh BASELINE_BINARY
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
baseline=${1:?usage: $0 BASELINE_BINARY}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e 's/cells = \[8, 30, 6\]/cells = [24, 90, 18]/' -e 's/cells = \[6, 6, 6\]/cells = [18, 18, 18]/' \
  -e 's/^end = 1.0/end = 0.3/' -e 's/^step = 0.01/step = 0.01\ncontact_scheme = "plain"/' \
  "$root/examples/06-thesis-frictional-heating/case.toml" >"$work/case.toml"
"$root/bench/cliff/compare.sh" "$baseline" "$work/case.toml" "$work"
