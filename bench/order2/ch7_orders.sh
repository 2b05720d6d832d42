#!/usr/bin/env bash
# The chapter-7 example (examples/06-thesis-frictional-heating, every default, its lumped M_θ:
# row sums on Hex8/Hex27, HRZ on Hex20) meshed with ELEMENT cells at K times its cells per
# direction, one run each, then a table of the contact forces (mean over t ≥ 0.5 s, sliding),
# the heat generated, the thermal energy and the largest θ at t = 1 s, the dofs and the wall
# time (bench/RESULTS.md, "The ch. 7 example at first and second order").
#   bench/order2/ch7_orders.sh "Hex8 1" "Hex8 2" "Hex27 1" ...
# TC_BIN names another binary (a copy, so that a rebuild of build/ cannot change a long run);
# TC_SET passes one more --set to every run (e.g. "physics.thermal_expansion=false").
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
work=${TC_BENCH_WORK:-$(mktemp -d)}
bin=${TC_BIN:-$root/build/bin/thermocontact}
extra=()
[[ -z ${TC_SET:-} ]] || extra=(--set "$TC_SET")
[[ -n ${TC_BENCH_WORK:-} ]] || trap 'rm -rf "$work"' EXIT
for spec in "$@"; do
  read -r el k <<<"$spec"
  read -r master slave < <(python3 -c "k = $k
print(','.join(str(round(c * k)) for c in (8, 30, 6)), round(6 * k))")
  sed -e "s/cells = \[8, 30, 6\]/cells = [$master], element = \"$el\"/" \
    -e "s/cells = \[6, 6, 6\]/cells = [$slave, $slave, $slave], element = \"$el\"/" \
    -e "s/^every = 25/every = 1000/" \
    "$root/examples/06-thesis-frictional-heating/case.toml" >"$work/case-$el-$k.toml"
  OPENBLAS_NUM_THREADS=1 "$bin" run "$work/case-$el-$k.toml" "${extra[@]}" \
    --output "$work/out-$el-$k" --force >"$work/log-$el-$k.txt" 2>&1 || echo "FAILED $el $k (log: $work/log-$el-$k.txt)"
done
python3 - "$work" <<'PY'
import csv, glob, json, sys
rows = []
for d in glob.glob(sys.argv[1] + "/out-*"):
    el, k = d.rsplit("/out-", 1)[1].rsplit("-", 1)
    s = json.load(open(d + "/summary.json"))
    if s["status"] != "completed":
        continue
    h = list(csv.DictReader(open(d + "/history.csv")))
    sl = [r for r in h if float(r["time"]) >= 0.5]
    mean = lambda c: sum(float(r[c]) for r in sl) / len(sl)
    last = h[-1]
    rows.append((el, float(k), s["dofs"], mean("contact_normal_force"), mean("contact_tangential_force"),
                 float(last["heat_generated"]), float(last["thermal_energy"]), float(last["max_temperature"]),
                 s["wall_seconds"]["total"]))
print("| element | K | dofs | N, mean t ≥ 0.5 s [N] | T, mean [N] | heat generated [J] | thermal energy [J] | max θ [K] | wall [s] |")
print("|---|---|---|---|---|---|---|---|---|")
for r in sorted(rows):
    print(f"| {r[0]} | {r[1]:g} | {r[2]} | {r[3]:.6g} | {r[4]:.6g} | {r[5]:.6g} | {r[6]:.6g} | {r[7]:.5g} | {r[8]:.1f} |")
PY
