#!/usr/bin/env bash
# Issue 22's second cliff case: examples/07-pin-on-plate/case-refined.toml (Gmsh Tet4 made here
# from the example's .geo files: 147 648 dofs, 2 205 multipliers), its first three steps
# (end = 0.075: the press and two slides). Runs a baseline binary and this build in the same
# command and prints the dual set-up and factorisation seconds, their ratio, the QP, the peak
# RSS, and which history columns differ (wall_seconds aside). ~1.8 GiB each; needs gmsh.
#   bench/cliff/pin.sh BASELINE_BINARY
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
baseline=${1:?usage: $0 BASELINE_BINARY}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ex=$root/examples/07-pin-on-plate
gmsh -3 -format msh41 -setnumber hc 0.22e-3 "$ex/pin.geo" -o "$work/pin-refined.msh" >/dev/null
gmsh -3 -format msh41 -setnumber hc 0.17e-3 "$ex/plate.geo" -o "$work/plate-refined.msh" >/dev/null
sed -e 's/^end = 3.025 .*/end = 0.075/' "$ex/case-refined.toml" >"$work/case.toml"
export OPENBLAS_NUM_THREADS=1
for who in baseline current; do
  bin=$baseline
  [[ $who == current ]] && bin=$root/build/bin/thermocontact
  /usr/bin/time -v "$bin" run "$work/case.toml" --output "$work/$who" >/dev/null 2>"$work/$who.time"
done
python3 - "$work" <<'PY'
import csv, json, re, sys
w = sys.argv[1]
for k in ("baseline", "current"):
    s = json.load(open(f"{w}/{k}/summary.json"))
    t = s["wall_seconds"]
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)",
                        open(f"{w}/{k}.time").read()).group(1))
    print(f"{k:8s} total {sum(t.values()):6.1f} s  dual set-up {t['dual_setup']:6.2f} s  "
          f"factorisation {t['factorization']:6.2f} s  (ratio {t['dual_setup'] / t['factorization']:.2f})"
          f"  qp {t['qp']:6.2f} s  QP iterations {s['qp_iterations']}  dofs {s['dofs']}"
          f"  multipliers {s['multipliers']}  peak RSS {rss / 2**20:.2f} GiB")
a, b = (list(csv.DictReader(open(f"{w}/{k}/history.csv"))) for k in ("baseline", "current"))
print("history columns that differ:",
      [c for c in a[0] if c != "wall_seconds" and any(x[c] != y[c] for x, y in zip(a, b))])
PY
