#!/usr/bin/env bash
# Issue 22's cliff at 1500 multipliers: example 06 refined (master 24×80×6, slave 24×24×4:
# 69 200 dofs, 1 875 multipliers once the 625 slave nodes touch), 12 steps of 0.01 s (contact
# from step 7). Runs a baseline binary and this build in the same command and prints the wall
# time, the QP, dual set-up and factorisation seconds of each, the ratio, and the largest
# relative difference of the last history row.
#   bench/cliff/cliff.sh BASELINE_BINARY
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
baseline=${1:?usage: $0 BASELINE_BINARY}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e 's/cells = \[8, 30, 6\]/cells = [24, 80, 6]/' -e 's/cells = \[6, 6, 6\]/cells = [24, 24, 4]/' \
  -e 's/^end = 1.0/end = 0.12/' "$root/examples/06-thesis-frictional-heating/case.toml" \
  >"$work/case.toml"
export OPENBLAS_NUM_THREADS=1
for who in baseline current; do
  bin=$baseline
  [[ $who == current ]] && bin=$root/build/bin/thermocontact
  "$bin" run "$work/case.toml" --output "$work/$who" >/dev/null
done
python3 - "$work" <<'PY'
import csv, json, sys
w = sys.argv[1]
s = {k: json.load(open(f"{w}/{k}/summary.json")) for k in ("baseline", "current")}
for k, v in s.items():
    t = v["wall_seconds"]
    print(f"{k:8s} total {sum(x for n, x in t.items() if n != 'total'):7.2f} s  qp {t['qp']:7.2f} s  dual set-up "
          f"{t['dual_setup']:6.2f} s  factorisation {t['factorization']:6.2f} s  "
          f"QP iterations {v['qp_iterations']}  F {v['dual_operator']}"
          f"  multipliers {v['multipliers']}  dofs {v['dofs']}")
tb, tc = (sum(x for n, x in s[k]["wall_seconds"].items() if n != "total")
          for k in ("baseline", "current"))
print(f"ratio baseline/current: {tb / tc:.1f}x")
rows = [list(csv.DictReader(open(f"{w}/{k}/history.csv")))[-1] for k in ("baseline", "current")]
keys = ["contact_normal_force", "contact_tangential_force", "strain_energy", "thermal_energy"]
print("largest relative difference, last row:",
      max(abs(float(rows[0][k]) - float(rows[1][k])) / abs(float(rows[0][k])) for k in keys))
PY
