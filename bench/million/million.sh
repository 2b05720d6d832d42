#!/usr/bin/env bash
# Issue 22's million-dof goal: the chapter-7 example (examples/06-thesis-frictional-heating, its
# default dynamic scheme) refined by factor K in every direction, the first STEPS steps of its
# τ = 0.01 s (default 10: the approach, the impact at step 7 and three steps in contact), one
# run per K with this build. K = 2, 3, 4, 5.3 give 62 712, 200 336, 461 800 and 1 046 232 dofs
# (with the temperature). Prints per K the dofs, the multipliers, the peak RSS, the set-up
# (wall time before step 1: assembly, factorisations), the mean and the largest step time, the
# phases, and the growth exponent of the mean step time between consecutive K and over all.
#   bench/million/million.sh [STEPS] [K ...]        e.g. million.sh 10 2 3 4 5.3
# Extra arguments to thermocontact run go in TC_ARGS. Needs ~14 GiB at K = 5.3.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
steps=${1:-10}
shift || true
ks=("$@")
[[ ${#ks[@]} -gt 0 ]] || ks=(2 3 4 5.3)
work=${TC_BENCH_WORK:-$(mktemp -d)}
[[ -n ${TC_BENCH_WORK:-} ]] || trap 'rm -rf "$work"' EXIT
ex=$root/examples/06-thesis-frictional-heating/case.toml
end=$(python3 -c "print(round(0.01 * $steps, 6))")
export OPENBLAS_NUM_THREADS=1
for k in "${ks[@]}"; do
  read -r master slave < <(python3 -c "
k = $k
print(','.join(str(round(c * k)) for c in (8, 30, 6)), round(6 * k))")
  sed -e "s/cells = \[8, 30, 6\]/cells = [$master]/" -e "s/cells = \[6, 6, 6\]/cells = [$slave, $slave, $slave]/" \
    -e "s/^end = 1.0/end = $end/" "$ex" >"$work/k$k.toml"
  /usr/bin/time -v "$root/build/bin/thermocontact" run "$work/k$k.toml" --output "$work/out-k$k" \
    --force ${TC_ARGS:-} >"$work/k$k.log" 2>"$work/k$k.time"
done
python3 - "$work" "${ks[@]}" <<'PY'
import csv, json, math, re, sys
w, ks = sys.argv[1], sys.argv[2:]
rows = []
for k in ks:
    s = json.load(open(f"{w}/out-k{k}/summary.json"))
    t = [float(x["wall_seconds"]) for x in list(csv.DictReader(open(f"{w}/out-k{k}/history.csv")))[1:]]
    tm = open(f"{w}/k{k}.time").read()
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", tm).group(1)) / 2**20
    m, sec = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:\d+:)?(\d+):([\d.]+)", tm).groups()
    wall = 60 * int(m) + float(sec)
    mean = sum(t) / len(t)
    rows.append((s["dofs"], mean))
    print(f"K = {k}: {s['dofs']} dofs, {s['multipliers']} multipliers, {s['subdomains']} subdomains, "
          f"peak RSS {rss:.2f} GiB, wall {wall:.1f} s, set-up {wall - sum(t):.1f} s, "
          f"{len(t)} steps: mean {mean:.2f} s/step, largest {max(t):.2f} s, status {s['status']}")
    print("    phases (s):", ", ".join(f"{n} {v:.2f}" for n, v in s["wall_seconds"].items() if v >= 0.01))
for (n0, t0), (n1, t1) in zip(rows, rows[1:]):
    print(f"growth {n0} → {n1} dofs: mean step time as dofs^{math.log(t1 / t0) / math.log(n1 / n0):.2f}")
if len(rows) > 2:
    print(f"growth {rows[0][0]} → {rows[-1][0]} dofs: dofs^"
          f"{math.log(rows[-1][1] / rows[0][1]) / math.log(rows[-1][0] / rows[0][0]):.2f}")
PY
