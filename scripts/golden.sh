#!/usr/bin/env bash
# Golden outputs for refactoring (issue 19): the history.csv of every example and every valid
# case under tests/cases, recorded before a change and compared byte for byte after it.
#   scripts/golden.sh record DIR    runs them all, keeps each history.csv under DIR
#   scripts/golden.sh compare DIR   runs them again and reports each history that differs
# Byte equality holds on one machine and one build (BLAS, compiler): record and compare there.
# The column wall_seconds (a clock) is left out of the comparison.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:-}
dir=${2:-}
if [[ ($mode != record && $mode != compare) || -z $dir ]]; then
  echo "usage: $0 record|compare DIR" >&2
  exit 2
fi
bin=build/bin/thermocontact
without_clock() {  # the CSV without its wall_seconds column
  awk -F, -v OFS=, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "wall_seconds") c = i }
    { if (c) { for (i = c; i < NF; ++i) $i = $(i + 1); NF-- } print }' "$1"
}
export OPENBLAS_NUM_THREADS=1
cases=(examples/*/case.toml tests/cases/valid/*.toml tests/cases/verification/*.toml
       tests/cases/feti/*.toml tests/cases/restart/*.toml)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$dir"
differ=0
for c in "${cases[@]}"; do
  name=$(echo "${c%.toml}" | tr '/' '_')
  if ! "$bin" run "$c" --output "$work/$name" >"$work/$name.log" 2>&1; then
    echo "FAILED to run: $c (see below)"; tail -3 "$work/$name.log"; differ=1; continue
  fi
  if [[ $mode == record ]]; then
    cp "$work/$name/history.csv" "$dir/$name.csv"
    echo "recorded $c"
  elif cmp -s <(without_clock "$work/$name/history.csv") <(without_clock "$dir/$name.csv"); then
    echo "same     $c"
  else
    echo "DIFFERS  $c"; differ=1
  fi
done
exit $differ
