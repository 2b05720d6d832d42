#!/bin/sh
# valgrind memcheck on a small contact case (tests/cases/restart/sliding-2d.toml: dynamic,
# friction, frictional heating, conductance; 40 steps), three ways: a whole run, a run stopped
# after step 17, and its --restart (the checkpoint read). Exit code 3 on any memcheck error or
# leak of ours; Open MPI's own leaks at MPI_Init/Finalize are suppressed
# (tests/valgrind/openmpi.supp explains them). Then the same whole run with PETSc's
# -malloc_debug -malloc_dump (PETSc objects not destroyed, or corrupted, are reported at
# PetscFinalize). Logs in build/valgrind/. Usage: scripts/valgrind.sh [BUILD_DIR]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
bin=$build/bin/thermocontact
case_file=$root/tests/cases/restart/sliding-2d.toml
logs=$build/valgrind
rm -rf "$logs" && mkdir -p "$logs"
vg() {
  name=$1
  shift
  valgrind --leak-check=full --show-leak-kinds=definite,indirect,possible \
    --errors-for-leak-kinds=definite,indirect,possible --error-exitcode=3 --num-callers=40 \
    --suppressions="$root/tests/valgrind/openmpi.supp" --log-file="$logs/$name.log" \
    "$bin" "$@" >"$logs/$name.out" 2>&1 || return $?
}
status=0
vg whole run "$case_file" --output "$logs/whole" || status=$?
echo "whole run: exit $status"
s=0
vg stopped run "$case_file" --output "$logs/split" --stop-after 17 || s=$?
echo "stopped after step 17: exit $s (1 expected: stopped)"
[ "$s" -eq 1 ] || status=3
s=0
vg restart run "$case_file" --restart "$logs/split" || s=$?
echo "restart: exit $s"
[ "$s" -eq 0 ] || status=3
grep -h "ERROR SUMMARY" "$logs"/*.log
s=0
"$bin" run "$case_file" --output "$logs/malloc" -malloc_debug -malloc_dump \
  >"$logs/malloc_debug.out" 2>&1 || s=$?
echo "-malloc_debug -malloc_dump: exit $s, $(grep -c '\[ 0\]' "$logs/malloc_debug.out" || true) lines of PETSc memory reports"
[ "$s" -eq 0 ] || status=3
exit $status
