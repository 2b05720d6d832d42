#!/usr/bin/env bash
# Issue 22's million-dof goal: the chapter-7 example (examples/06-thesis-frictional-heating, its
# default dynamic scheme) refined by factor K in every direction, the first STEPS steps of its
# τ = 0.01 s (default 10: the approach, the impact at step 7 and three steps in contact). For
# each K it runs a baseline binary (if given) and this build, one after the other. K = 2, 3,
# 4, 5.3 give 62 712, 200 336, 461 800 and 1 046 232 dofs (with the temperature). Prints per
# run the dofs, the multipliers, the peak RSS, the set-up (wall time before step 1: assembly,
# factorisations), the mean and the largest step time, the phases; then the growth exponents
# of the mean step time of this build, of all steps and of steps 2–, between consecutive K and
# over all, and per K the baseline/current ratio of the mean step time.
#   bench/million/million.sh [STEPS] [K ...]        e.g. million.sh 10 2 3 4 5.3
# BASELINE=<binary> adds the baseline runs; extra arguments to `thermocontact run` go in
# TC_ARGS; TC_BENCH_WORK=<dir> keeps the runs there. BLAS threads: THREADS for this build,
# BASELINE_THREADS for the baseline (default 1 each). MPI ranks: RANKS for this build,
# BASELINE_RANKS for the baseline (default 1: no launcher; N > 1 runs `mpirun -n N
# --oversubscribe`, and the peak RSS is then that of the largest rank). SUBDOMAINS=<n> sets
# `subdomains = n` on both bodies (1: solved directly whatever "auto" would choose for the
# ranks). STEP=<τ> sets the time step (default 0.01; the run ends at STEPS·τ): issue 39's case
# is `STEP=0.03 million.sh 10 5.5`, 1 173 136 dofs, 10 steps through the onset of sliding at
# t = 0.2 s (step 7). Needs ~14.5 GiB at K = 5.3 on one rank, ~5.0 GiB per rank on 4 with
# SUBDOMAINS=1.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
steps=${1:-10}
shift || true
ks=("$@")
[[ ${#ks[@]} -gt 0 ]] || ks=(2 3 4 5.3)
work=${TC_BENCH_WORK:-$(mktemp -d)}
[[ -n ${TC_BENCH_WORK:-} ]] || trap 'rm -rf "$work"' EXIT
ex=$root/examples/06-thesis-frictional-heating/case.toml
step=${STEP:-0.01}
end=$(python3 -c "print(round($step * $steps, 6))")
whos=(current)
[[ -z ${BASELINE:-} ]] || whos=(baseline current)
for k in "${ks[@]}"; do
  read -r master slave < <(python3 -c "
k = $k
print(','.join(str(round(c * k)) for c in (8, 30, 6)), round(6 * k))")
  sed -e "s/cells = \[8, 30, 6\]/cells = [$master]/" -e "s/cells = \[6, 6, 6\]/cells = [$slave, $slave, $slave]/" \
    -e "s/^step = 0.01/step = $step/" -e "s/^end = 1.0/end = $end/" "$ex" >"$work/k$k.toml"
  [[ -z ${SUBDOMAINS:-} ]] || sed -i "s/^\(name = \"\(master\|slave\)\"\)$/\1\nsubdomains = $SUBDOMAINS/" "$work/k$k.toml"
  for who in "${whos[@]}"; do
    bin=$root/build/bin/thermocontact threads=${THREADS:-1} ranks=${RANKS:-1}
    [[ $who == current ]] || bin=$BASELINE threads=${BASELINE_THREADS:-1} ranks=${BASELINE_RANKS:-1}
    launch=()
    [[ $ranks -le 1 ]] || launch=(mpirun -n "$ranks" --oversubscribe)
    OPENBLAS_NUM_THREADS=$threads /usr/bin/time -v "${launch[@]}" "$bin" run "$work/k$k.toml" --output "$work/$who-k$k" --force ${TC_ARGS:-} \
      >"$work/$who-k$k.log" 2>"$work/$who-k$k.time"
  done
done
python3 - "$work" "${whos[*]}" "${ks[@]}" <<'PY'
import csv, json, math, re, sys
w, whos, ks = sys.argv[1], sys.argv[2].split(), sys.argv[3:]
mean = {}
for k in ks:
    for who in whos:
        d = f"{w}/{who}-k{k}"
        s = json.load(open(f"{d}/summary.json"))
        t = [float(x["wall_seconds"]) for x in list(csv.DictReader(open(f"{d}/history.csv")))[1:]]
        tm = open(f"{d}.time").read()
        rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", tm).group(1)) / 2**20
        h, m, sec = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", tm).groups()
        wall = 3600 * int(h or 0) + 60 * int(m) + float(sec)
        mean[who, k] = (s["dofs"], sum(t) / len(t), sum(t[1:]) / len(t[1:]) if len(t) > 1 else t[0])
        print(f"K = {k} {who}: {s['dofs']} dofs, {s['multipliers']} multipliers, {s['subdomains']} subdomains, "
              f"peak RSS {rss:.2f} GiB, wall {wall:.1f} s, set-up {wall - sum(t):.1f} s, {len(t)} steps: "
              f"first {t[0]:.2f} s, mean {sum(t) / len(t):.2f} s/step, mean of steps 2– {sum(t[1:]) / len(t[1:]):.2f} s, "
              f"largest of steps 2– {max(t[1:]):.2f} s, status {s['status']}")
        print("    phases (s):", ", ".join(f"{n} {v:.2f}" for n, v in s["wall_seconds"].items() if v >= 0.01))
    if "baseline" in whos:
        print(f"K = {k}: mean step time baseline / current {mean['baseline', k][1] / mean['current', k][1]:.2f}x")
# Growth exponents of the mean time per step, of all steps (the first holds the one-time set-up
# of the contact dual) and of steps 2– (the steps a longer run is made of).
def slope(a, b, c):
    return math.log(b[c] / a[c]) / math.log(b[0] / a[0])
rows = [mean["current", k] for k in ks]
for a, b in zip(rows, rows[1:]):
    print(f"growth {a[0]} → {b[0]} dofs: mean step time as dofs^{slope(a, b, 1):.2f}, "
          f"steps 2– as dofs^{slope(a, b, 2):.2f}")
if len(rows) > 2:
    print(f"growth {rows[0][0]} → {rows[-1][0]} dofs: dofs^{slope(rows[0], rows[-1], 1):.2f}, "
          f"steps 2– dofs^{slope(rows[0], rows[-1], 2):.2f}")
PY
