#!/usr/bin/env bash
# Issue 39's thread-policy bench: wall time of whole runs with the default thread policy
# (OPENBLAS_NUM_THREADS unset), with 1 and with 2 BLAS threads (OPENBLAS_NUM_THREADS=1, 2), on
# the machine as it is ("idle") and with two busy processes started here (`yes > /dev/null`,
# killed at the end); then per case and load the ratio default / best of the three.
#   bench/threads/threads.sh [large]
# Cases: the 2D ch. 7 section (tests/cases/verification/section-2d.toml, 798 dofs, 100 dynamic
# steps) and example 06 (examples/06-thesis-frictional-heating, 100 steps); with `large` also
# example 06 refined ×3 (200 336 dofs, its first 10 steps, as bench/million). Fields written
# every 1000 steps (the history only: the solver is what is timed). REPEAT=n takes the
# fastest of n runs per cell (default 1). BASELINE=<binary> adds a column: that binary with
# its own default (e.g. a build before the policy). CASES="section-2d example-06" and
# LOADS="idle busy" choose the rows. Runs in a temporary directory.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=$root/build/bin/thermocontact
work=$(mktemp -d)
busy=()
cleanup() {
  for p in "${busy[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
repeat=${REPEAT:-1}

sed -e 's/every = 25/every = 1000/' "$root/tests/cases/verification/section-2d.toml" >"$work/section-2d.toml"
grep -q '^\[output\]' "$work/section-2d.toml" || printf '\n[output]\nevery = 1000\n' >>"$work/section-2d.toml"
sed -e 's/every = 25/every = 1000/' "$root/examples/06-thesis-frictional-heating/case.toml" >"$work/example-06.toml"
cases=(section-2d example-06)
if [[ ${1:-} == large ]]; then
  sed -e 's/cells = \[8, 30, 6\]/cells = [24, 90, 18]/' -e 's/cells = \[6, 6, 6\]/cells = [18, 18, 18]/' \
    -e 's/^end = 1.0/end = 0.1/' "$work/example-06.toml" >"$work/example-06-x3.toml"
  cases+=(example-06-x3)
fi
[[ -z ${CASES:-} ]] || read -r -a cases <<<"$CASES"
modes=(default 1 2)
[[ -z ${BASELINE:-} ]] || modes+=(baseline)

# One run: its wall time in seconds (the fastest of REPEAT).
run() {
  local case=$1 mode=$2 best=
  local exe=$bin env=(env -u OPENBLAS_NUM_THREADS -u OMP_NUM_THREADS)
  case $mode in
    1 | 2) env+=("OPENBLAS_NUM_THREADS=$mode") ;;
    baseline) exe=$BASELINE ;;
  esac
  for ((i = 0; i < repeat; i++)); do
    local t0 t1
    t0=$(date +%s.%N)
    "${env[@]}" "$exe" run "$work/$case.toml" --output "$work/out-$case-$mode" --force >/dev/null 2>"$work/err"
    t1=$(date +%s.%N)
    local t
    t=$(python3 -c "print(f'{$t1 - $t0:.2f}')")
    if [[ -z $best ]] || python3 -c "import sys; sys.exit(0 if $t < $best else 1)"; then best=$t; fi
  done
  echo "$best"
}

echo "machine: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $(date -u +%FT%TZ)"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-15s %-6s' case load
for m in "${modes[@]}"; do printf ' %9s' "$m"; done
printf ' %14s\n' "default/best"
loads=(idle busy)
[[ -z ${LOADS:-} ]] || read -r -a loads <<<"$LOADS"
for load in "${loads[@]}"; do
  if [[ $load == busy ]]; then
    for _ in 1 2; do
      yes >/dev/null &
      busy+=($!)
    done
    sleep 1
  fi
  for c in "${cases[@]}"; do
    declare -A t=()
    for m in "${modes[@]}"; do t[$m]=$(run "$c" "$m"); done
    printf '%-15s %-6s' "$c" "$load"
    for m in "${modes[@]}"; do printf ' %9s' "${t[$m]}"; done
    python3 -c "d, a, b = ${t[default]}, ${t[1]}, ${t[2]}; print(f' {d / min(d, a, b):14.2f}')"
    unset t
  done
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
