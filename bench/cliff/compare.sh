#!/usr/bin/env bash
# Runs a baseline binary and this build on one case in the same command (growth.sh, pin.sh)
# and prints, for each, the dual set-up and factorisation seconds, their ratio, the QP, the
# peak RSS, and the history columns that differ (wall_seconds aside; none: identical).
#   bench/cliff/compare.sh BASELINE_BINARY CASE.toml WORK_DIR
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
baseline=$1 case=$2 work=$3
export OPENBLAS_NUM_THREADS=1
for who in baseline current; do
  bin=$baseline
  [[ $who == current ]] && bin=$root/build/bin/thermocontact
  /usr/bin/time -v "$bin" run "$case" --output "$work/$who" >/dev/null 2>"$work/$who.time"
done
python3 - "$work" <<'PY'
import csv, json, re, sys
w = sys.argv[1]
for k in ("baseline", "current"):
    s = json.load(open(f"{w}/{k}/summary.json"))
    t = s["wall_seconds"]
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)",
                        open(f"{w}/{k}.time").read()).group(1))
    print(f"{k:8s} total {sum(x for n, x in t.items() if n != 'total'):6.1f} s  dual set-up {t['dual_setup']:6.2f} s  "
          f"factorisation {t['factorization']:6.2f} s  (ratio {t['dual_setup'] / t['factorization']:.2f})"
          f"  qp {t['qp']:6.2f} s  QP iterations {s['qp_iterations']}  dofs {s['dofs']}"
          f"  multipliers {s['multipliers']}  peak RSS {rss / 2**20:.2f} GiB")
a, b = (list(csv.DictReader(open(f"{w}/{k}/history.csv"))) for k in ("baseline", "current"))
print("history columns that differ:",
      [c for c in a[0] if c != "wall_seconds" and any(x[c] != y[c] for x, y in zip(a, b))])
PY
