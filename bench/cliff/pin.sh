#!/usr/bin/env bash
# Issue 22's second cliff case: examples/07-pin-on-plate/case-refined.toml (Gmsh Tet4 made here
# from the example's .geo files: 147 648 dofs, 2 205 multipliers), its first three steps
# (end = 0.075: the press and two slides). Runs a baseline binary and this build in the same
# command and prints the dual set-up and factorisation seconds, their ratio, the QP, the peak
# RSS, and which history columns differ (compare.sh). ~1.8 GiB each; needs gmsh.
#   bench/cliff/pin.sh BASELINE_BINARY
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
baseline=${1:?usage: $0 BASELINE_BINARY}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ex=$root/examples/07-pin-on-plate
gmsh -3 -format msh41 -setnumber hc 0.22e-3 "$ex/pin.geo" -o "$work/pin-refined.msh" >/dev/null
gmsh -3 -format msh41 -setnumber hc 0.17e-3 "$ex/plate.geo" -o "$work/plate-refined.msh" >/dev/null
sed -e 's/^end = 3.025 .*/end = 0.075/' "$ex/case-refined.toml" >"$work/case.toml"
"$root/bench/cliff/compare.sh" "$baseline" "$work/case.toml" "$work"
