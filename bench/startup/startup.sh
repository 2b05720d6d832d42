#!/usr/bin/env bash
# Start-up of a serial run: `thermocontact info` (MPI_Init, PETSc, no case), `check` of a
# small box case and `check` of a case with two Gmsh meshes (libgmsh loaded in the reader's
# child), N times each, this build against a baseline binary in turn (so that the load of the
# machine is shared): medians of the wall and of the CPU time (user + system, children
# included), and their ratios.
#   bench/startup/startup.sh [BASELINE_BINARY] [N]
set -euo pipefail
cd "$(dirname "$0")/../.."
new=build/bin/thermocontact
base=${1:-}
n=${2:-11}
box_case=tests/cases/valid/quasistatic.toml
gmsh_case=tests/cases/restart/pin-on-plate.toml
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR + 1) / 2)]}'; }
# "wall cpu" of one run
time_of() {
  /usr/bin/time -f "%e %U %S" "$@" > /dev/null 2> /tmp/startup.$$ || true
  tail -n 1 /tmp/startup.$$ | awk '{printf "%s %.3f\n", $1, $2 + $3}'
}
ratio() { awk "BEGIN {printf \"%.2f\", $1 / $2}"; }
for what in info check check-gmsh; do
  case $what in
    info) args=(info) ;;
    check) args=(check "$box_case") ;;
    check-gmsh) args=(check "$gmsh_case") ;;
  esac
  : > /tmp/startup-new.$$; : > /tmp/startup-base.$$
  for _ in $(seq "$n"); do
    time_of "$new" "${args[@]}" >> /tmp/startup-new.$$
    [ -n "$base" ] && time_of "$base" "${args[@]}" >> /tmp/startup-base.$$
  done
  w_new=$(cut -d' ' -f1 /tmp/startup-new.$$ | median); c_new=$(cut -d' ' -f2 /tmp/startup-new.$$ | median)
  if [ -n "$base" ]; then
    w_base=$(cut -d' ' -f1 /tmp/startup-base.$$ | median); c_base=$(cut -d' ' -f2 /tmp/startup-base.$$ | median)
    echo "$what: this build ${w_new} s wall, ${c_new} s CPU; baseline ${w_base} s, ${c_base} s;" \
      "ratio $(ratio "$w_base" "$w_new")× wall, $(ratio "$c_base" "$c_new")× CPU (medians of $n)"
  else
    echo "$what: this build ${w_new} s wall, ${c_new} s CPU (medians of $n)"
  fi
done
rm -f /tmp/startup.$$ /tmp/startup-new.$$ /tmp/startup-base.$$
