#!/usr/bin/env bash
# Start-up of a serial run: `thermocontact info` (MPI_Init, PETSc, no case) and `check` of a
# small case, N times each, this build against a baseline binary in turn (so that the load of
# the machine is shared), medians and the ratio.
#   bench/startup/startup.sh [BASELINE_BINARY] [N]
set -euo pipefail
cd "$(dirname "$0")/../.."
new=build/bin/thermocontact
base=${1:-}
n=${2:-11}
case_file=tests/cases/valid/quasistatic.toml
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR + 1) / 2)]}'; }
time_of() { /usr/bin/time -f "%e" "$@" > /dev/null 2> /tmp/startup.$$ || true; tail -n 1 /tmp/startup.$$; }
for what in info check; do
  args=("$what"); [ "$what" = check ] && args+=("$case_file")
  : > /tmp/startup-new.$$; : > /tmp/startup-base.$$
  for _ in $(seq "$n"); do
    time_of "$new" "${args[@]}" >> /tmp/startup-new.$$
    [ -n "$base" ] && time_of "$base" "${args[@]}" >> /tmp/startup-base.$$
  done
  m_new=$(median < /tmp/startup-new.$$)
  if [ -n "$base" ]; then
    m_base=$(median < /tmp/startup-base.$$)
    echo "$what: this build ${m_new} s, baseline ${m_base} s, ratio $(awk "BEGIN {printf \"%.2f\", $m_base / $m_new}")× (median of $n)"
  else
    echo "$what: this build ${m_new} s (median of $n)"
  fi
done
rm -f /tmp/startup.$$ /tmp/startup-new.$$ /tmp/startup-base.$$
