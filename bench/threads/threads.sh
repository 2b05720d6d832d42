#!/usr/bin/env bash
# Issue 39's thread-policy bench: wall time of whole runs with the default thread policy
# (OPENBLAS_NUM_THREADS unset), with 1 and with 2 BLAS threads (OPENBLAS_NUM_THREADS=1, 2), on
# the machine as it is ("idle") and with two busy processes started here (`yes > /dev/null`,
# killed at the end); then per case and load the ratio default / best of the three.
#   bench/threads/threads.sh [large | million]
# Cases: the 2D ch. 7 section (tests/cases/verification/section-2d.toml, 798 dofs, 100 dynamic
# steps) and example 06 (examples/06-thesis-frictional-heating, 100 steps); with `large` also
# example 06 refined ×3 (200 336 dofs, its first 10 steps, as bench/million). Fields written
# every 1000 steps (the history only: the solver is what is timed). `million` runs issue 39's
# 10⁶-dof case alone (example 06 ×5.5, 1 173 136 dofs, 10 steps of 0.03 s; ~16 GiB, 4 min idle).
# REPEAT=n (default 5) runs each cell n times per mode, the modes alternating and the one that
# goes first rotating from round to round, so that a drift of the load reaches every mode alike;
# each cell prints the median wall time and its spread (min–max), the median CPU time
# (user + sys: a spinning thread shows there even when the wall hides it), and default / best
# is the ratio of the medians; default/1 by round the median [min–max] of the rounds' ratios. A single sample per cell on a shared machine says little: the
# load moves by more than the effect being measured.
# BASELINE=<binary> adds a column: that binary with its own default (e.g. a build before the
# policy); BIN=<binary> replaces build/bin/thermocontact. CASES="section-2d example-06" and
# LOADS="idle busy" choose the rows, MODES="default 1 2" the columns (default/best is then
# over the modes run). Runs in a temporary directory; RAW=<file> keeps every
# sample (case load mode wall cpu). CAP=s stops a run after s seconds (timeout) and counts it
# as s, a lower bound, printed with "≥": two spinning BLAS threads beside busy processes can
# take ten times the others, and one such run would otherwise hold up the whole table.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$root/build/bin/thermocontact}
work=$(mktemp -d)
busy=()
cleanup() {
  for p in "${busy[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
repeat=${REPEAT:-5}
raw=${RAW:-$work/raw.txt}
: >"$raw"

sed -e 's/every = 25/every = 1000/' "$root/tests/cases/verification/section-2d.toml" >"$work/section-2d.toml"
grep -q '^\[output\]' "$work/section-2d.toml" || printf '\n[output]\nevery = 1000\n' >>"$work/section-2d.toml"
sed -e 's/every = 25/every = 1000/' "$root/examples/06-thesis-frictional-heating/case.toml" >"$work/example-06.toml"
cases=(section-2d example-06)
if [[ ${1:-} == large ]]; then
  sed -e 's/cells = \[8, 30, 6\]/cells = [24, 90, 18]/' -e 's/cells = \[6, 6, 6\]/cells = [18, 18, 18]/' \
    -e 's/^end = 1.0/end = 0.1/' "$work/example-06.toml" >"$work/example-06-x3.toml"
  cases+=(example-06-x3)
fi
if [[ ${1:-} == million ]]; then  # issue 39's 10⁶-dof case (bench/million: STEP=0.03 … 10 5.5)
  sed -e 's/cells = \[8, 30, 6\]/cells = [44, 165, 33]/' -e 's/cells = \[6, 6, 6\]/cells = [33, 33, 33]/' \
    -e 's/^step = 0.01/step = 0.03/' -e 's/^end = 1.0/end = 0.3/' "$work/example-06.toml" >"$work/million.toml"
  cases=(million)
fi
[[ -z ${CASES:-} ]] || read -r -a cases <<<"$CASES"
modes=(default 1 2)
[[ -z ${MODES:-} ]] || read -r -a modes <<<"$MODES"
[[ -z ${BASELINE:-} ]] || modes+=(baseline)

# One run of a case in a mode: appends "case load mode wall cpu" to the raw file.
run() {
  local case=$1 load=$2 mode=$3
  local exe=$bin env=(env -u OPENBLAS_NUM_THREADS -u OMP_NUM_THREADS)
  case $mode in
    1 | 2) env+=("OPENBLAS_NUM_THREADS=$mode") ;;
    baseline) exe=$BASELINE ;;
  esac
  local cap=() status=0
  [[ -z ${CAP:-} ]] || cap=(timeout "$CAP")
  /usr/bin/time -f '%e %U %S' -o "$work/time" "${cap[@]}" "${env[@]}" "$exe" run \
    "$work/$case.toml" --output "$work/out-$case-$mode" --force >/dev/null 2>"$work/err" ||
    status=$?
  if [[ $status -eq 124 && -n ${CAP:-} ]]; then
    echo "$case $load $mode $CAP - capped" >>"$raw"
    return
  fi
  [[ $status -eq 0 ]] || { cat "$work/err" >&2; exit 1; }
  read -r wall user sys < <(tail -1 "$work/time")
  echo "$case $load $mode $wall $(python3 -c "print(f'{$user + $sys:.2f}')")" >>"$raw"
}

# The row of a cell from the raw samples: per mode median wall [min–max] and median CPU.
row() {
  python3 - "$raw" "$1" "$2" "${modes[@]}" <<'EOF'
import statistics, sys
raw, case, load, modes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
wall, cpu, capped = {m: [] for m in modes}, {m: [] for m in modes}, set()
for line in open(raw):
    c, l, m, w, u, *flag = line.split()
    if c == case and l == load and m in wall:
        wall[m].append(float(w))
        if flag: capped.add(m)
        else: cpu[m].append(float(u))
med = {m: statistics.median(wall[m]) for m in modes}
def cell(m):
    bound = "≥" if m in capped else ""
    used = f"{statistics.median(cpu[m]):.2f}" if cpu[m] else "-"
    return f"{bound}{med[m]:.2f} [{min(wall[m]):.2f}–{bound}{max(wall[m]):.2f}] cpu {used}"
cells = [cell(m) for m in modes]
best = min(med[m] for m in ("default", "1", "2") if m in med)
# Within a round the modes ran minutes apart at most: the ratio of each round's pair is less
# exposed to the load's drift than the ratio of the medians.
pairs = ""
if "1" in wall and "default" not in capped and "1" not in capped:
    r = sorted(d / o for d, o in zip(wall["default"], wall["1"]))
    pairs = f"  |  default/1 by round {statistics.median(r):.2f} [{r[0]:.2f}–{r[-1]:.2f}]"
print(f"{case:14s} {load:5s} n={len(wall['default'])}  " + "  |  ".join(cells) +
      f"  |  default/best {med['default'] / best:.2f}" + pairs)
EOF
}

echo "machine: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs); $(date -u +%FT%TZ)"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg); $repeat alternating rounds per cell"
echo "columns: ${modes[*]} — each median wall s [min–max] and median CPU s"
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
    for ((i = 0; i < repeat; i++)); do
      n=${#modes[@]}
      for ((j = 0; j < n; j++)); do run "$c" "$load" "${modes[$(((i + j) % n))]}"; done
    done
    row "$c" "$load"
  done
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
