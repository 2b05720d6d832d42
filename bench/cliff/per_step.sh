#!/usr/bin/env bash
# Issue 22's "no cliff" goal: examples/07-pin-on-plate refined (case-refined.toml, Gmsh Tet4 made
# here from the example's .geo files: 147 648 dofs, 2 205 multipliers) against the committed
# coarse case (15 108 dofs, 492 multipliers), both for the first STEPS steps (default 13: the
# press and three strokes), one after the other with this build, THREADS BLAS threads
# (default 1). Prints, per case, the wall
# seconds of the first step (it holds the factorisation and the dual set-up), the mean of the
# others, and the refined/coarse ratio of both. BASELINE=<binary> runs it too, before this
# build on each case, and prints the same for it (BASELINE_THREADS, default THREADS). Needs
# gmsh; ~1.9 GiB.
#   bench/cliff/per_step.sh [STEPS]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
steps=${1:-13}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ex=$root/examples/07-pin-on-plate
end=$(python3 -c "print(round(0.025 * $steps, 6))")
gmsh -3 -format msh41 -setnumber hc 0.22e-3 "$ex/pin.geo" -o "$work/pin-refined.msh" >/dev/null
gmsh -3 -format msh41 -setnumber hc 0.17e-3 "$ex/plate.geo" -o "$work/plate-refined.msh" >/dev/null
sed -e "s/^end = 3.025 .*/end = $end/" "$ex/case-refined.toml" >"$work/refined.toml"
sed -e "s/^end = 3.025 .*/end = $end/" "$ex/case.toml" >"$work/coarse.toml"
cp "$ex/pin.msh" "$ex/plate.msh" "$work/"
whos=(current)
[[ -z ${BASELINE:-} ]] || whos=(baseline current)
for c in coarse refined; do
  for who in "${whos[@]}"; do
    bin=$root/build/bin/thermocontact threads=${THREADS:-1}
    [[ $who == current ]] || bin=$BASELINE threads=${BASELINE_THREADS:-${THREADS:-1}}
    OPENBLAS_NUM_THREADS=$threads "$bin" run "$work/$c.toml" --output "$work/$who-$c" --force \
      >/dev/null
  done
done
python3 - "$work" "${whos[@]}" <<'PY'
import csv, json, sys
w, whos = sys.argv[1], sys.argv[2:]
for who in whos:
    r = {}
    for c in ("coarse", "refined"):
        rows = list(csv.DictReader(open(f"{w}/{who}-{c}/history.csv")))[1:]
        t = [float(x["wall_seconds"]) for x in rows]
        r[c] = (t[0], sum(t[1:]) / len(t[1:]), len(t))
        print(f"{who} {c:8s} {r[c][2]} steps: first {r[c][0]:.2f} s, "
              f"mean of the others {r[c][1]:.3f} s/step")
        phases = json.load(open(f"{w}/{who}-{c}/summary.json"))["wall_seconds"]
        print("         phases (s):", ", ".join(f"{k} {v:.2f}" for k, v in phases.items() if v >= 0.01))
    print(f"{who} refined / coarse: first step {r['refined'][0] / r['coarse'][0]:.1f}x, "
          f"later steps {r['refined'][1] / r['coarse'][1]:.1f}x, "
          f"all steps {(r['refined'][0] + r['refined'][1] * (r['refined'][2] - 1)) / (r['coarse'][0] + r['coarse'][1] * (r['coarse'][2] - 1)):.1f}x")
PY
