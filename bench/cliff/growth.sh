#!/usr/bin/env bash
# Issue 22's growth case at ×3: example 06 refined three times in every direction (master
# 24×90×18, slave 18×18×18: 200 336 dofs with the temperature, 1 083 multipliers), plain
# Newmark, 30 steps of 0.01 s. Runs a baseline binary and this build in the same command and
# prints, for each, the dual set-up and factorisation seconds, their ratio, the QP, the peak
# RSS, and whether the histories are identical (all columns but wall_seconds). ~3.2 GiB each.
#   bench/cliff/growth.sh BASELINE_BINARY
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
baseline=${1:?usage: $0 BASELINE_BINARY}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e 's/cells = \[8, 30, 6\]/cells = [24, 90, 18]/' -e 's/cells = \[6, 6, 6\]/cells = [18, 18, 18]/' \
  -e 's/^end = 1.0/end = 0.3/' -e 's/^step = 0.01/step = 0.01\ncontact_scheme = "plain"/' \
  "$root/examples/06-thesis-frictional-heating/case.toml" >"$work/case.toml"
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
def rows(k):
    r = list(csv.reader(open(f"{w}/{k}/history.csv")))
    c = r[0].index("wall_seconds")
    return [x[:c] + x[c + 1:] for x in r]
print("history.csv identical (all columns but wall_seconds):", rows("baseline") == rows("current"))
PY
