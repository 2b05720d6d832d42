#!/usr/bin/env bash
# Issue 22's "no cliff" goal: the refined pin-on-plate's time per step against the coarse one's,
# both for the first STEPS steps (default 13: the press and three strokes), one after the other
# with this build, THREADS BLAS threads (default 1). Two pairs of examples/07-pin-on-plate, Gmsh
# Tet4 made here from the example's .geo files (hc of the pin's face / of the plate's track):
#   PAIR=example (default): the committed case (0.5 / 0.4 mm: 15 108 dofs, 492 multipliers)
#     against case-refined.toml (0.22 / 0.17 mm: 147 648 dofs, 2 205 multipliers), 9.8× the dofs;
#   PAIR=issue: the sizes issue 22 names (29 064 dofs, 492 multipliers against 145 060 dofs,
#     1 740 multipliers): 0.5 / 0.303 mm (29 276 dofs, 492 multipliers) against 0.25 / 0.168 mm
#     (147 792 dofs, 1 743 multipliers), 5.05× the dofs and 3.54× the multipliers (the issue's
#     4.99× and 3.54×).
# Prints, per case, the wall seconds of the first step (it holds the dual set-up), the mean of
# the others, and the refined/coarse ratio of both. BASELINE=<binary> runs it too, before this
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
mesh() {  # mesh NAME PIN_HC PLATE_HC: NAME-pin.msh, NAME-plate.msh
  gmsh -3 -format msh41 -setnumber hc "$2" "$ex/pin.geo" -o "$work/$1-pin.msh" >/dev/null
  gmsh -3 -format msh41 -setnumber hc "$3" "$ex/plate.geo" -o "$work/$1-plate.msh" >/dev/null
}
case ${PAIR:-example} in
  example)
    mesh refined 0.22e-3 0.17e-3
    cp "$ex/pin.msh" "$work/coarse-pin.msh"
    cp "$ex/plate.msh" "$work/coarse-plate.msh"
    ;;
  issue)
    mesh refined 0.25e-3 0.168e-3
    mesh coarse 0.5e-3 0.303e-3
    ;;
  *) echo "PAIR must be example or issue" >&2; exit 2 ;;
esac
for c in coarse refined; do  # the committed case with this pair's meshes
  sed -e "s/^end = 3.025 .*/end = $end/" -e "s/\"pin.msh\"/\"$c-pin.msh\"/" \
    -e "s/\"plate.msh\"/\"$c-plate.msh\"/" "$ex/case.toml" >"$work/$c.toml"
done
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
