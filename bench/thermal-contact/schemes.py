#!/usr/bin/env python3
"""The chapter-7 examples under each dynamic contact scheme, through `thermocontact run`.

    bench/thermal-contact/schemes.py [--binary B] [--baseline OLD_BINARY] [--repeat N]

Runs examples/05 and 06 as committed (thermoelastic heating on) with the default scheme
(modified mass) and with `contact_scheme = "stabilised"` (the default until issue 18), in
turn, N times each (default 3), and, with --baseline, the same case files under an older
binary (without the initial_state key, which it cannot read: example 05's cube is then
released at rest). Prints a Markdown table: wall time
(median of the repetitions, the process as a user starts it), coupling iterations, Tresca
updates and QP iterations per step, the heat, the temperature range and T/N while sliding,
and each time as a ratio to the default's in the same command.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CASES = ["examples/05-thesis-heat-transfer/case.toml",
         "examples/06-thesis-frictional-heating/case.toml"]


def variant(text, scheme):
    if scheme is None:
        return text
    return text.replace('scheme = "dynamic"',
                        f'scheme = "dynamic"\ncontact_scheme = "{scheme}"', 1)


def run(binary, case_text, workdir):
    path = os.path.join(workdir, "case.toml")
    with open(path, "w") as f:
        f.write(case_text)
    out = os.path.join(workdir, "out")
    t0 = time.perf_counter()
    r = subprocess.run([binary, "run", path, "--output", out], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        return None, (r.stdout + r.stderr).strip().splitlines()[-1]
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))[1:]
    summary = json.load(open(os.path.join(out, "summary.json")))
    sliding = [x for x in rows if float(x["time"]) > 0.3 and float(x["contact_normal_force"]) > 0]
    ratio = [float(x["contact_tangential_force"]) / float(x["contact_normal_force"]) for x in sliding]
    n = len(rows)
    return {
        "wall": wall,
        "coupling": sum(int(x["coupling_iterations"]) for x in rows) / n,
        "friction": sum(int(x.get("friction_iterations", 0)) for x in rows) / n,
        "qp": summary["qp_iterations"] / n,
        "heat": float(rows[-1]["heat_generated"]),
        "conducted": float(rows[-1]["heat_conducted"]),
        "thermal": float(rows[-1]["thermal_energy"]),
        "tmin": min(float(x["min_temperature"]) for x in rows),
        "tmax": max(float(x["max_temperature"]) for x in rows),
        "tn": (min(ratio), max(ratio)) if ratio else (0, 0),
    }, None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default=os.path.join(ROOT, "build/bin/thermocontact"))
    ap.add_argument("--baseline")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    runs = [("modified_mass (default)", a.binary, None),
            ("stabilised", a.binary, "stabilised")]
    if a.baseline:
        runs.append(("baseline binary, its default", a.baseline, None))
    print("| case | scheme | wall [s] (median) | × default | coupling it./step | "
          "γ updates/step | QP it./step | heat generated [J] | heat conducted [J] | "
          "thermal energy [J] | θ range [K] | T/N sliding |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for case in CASES:
        text = open(os.path.join(ROOT, case)).read()
        results = {name: [] for name, _, _ in runs}
        errors = {}
        for _ in range(a.repeat):  # in turn, so that the load of the machine is shared
            for name, binary, scheme in runs:
                if name in errors:
                    continue
                case_text = variant(text, scheme)
                if binary != a.binary:  # an older binary reads no initial_state: released at rest
                    case_text = "\n".join(x for x in case_text.splitlines()
                                          if not x.startswith("initial_state") and
                                          "a thermal shock (README" not in x)
                with tempfile.TemporaryDirectory() as d:
                    res, err = run(binary, case_text, d)
                if err:
                    errors[name] = err
                else:
                    results[name].append(res)
        base = statistics.median(r["wall"] for r in results[runs[0][0]])
        for name, _, _ in runs:
            if name in errors:
                print(f"| {os.path.dirname(case)} | {name} | — | — | not run: {errors[name]} "
                      "| | | | | | | |")
                continue
            rs = results[name]
            r = rs[-1]
            wall = statistics.median(x["wall"] for x in rs)
            print(f"| {os.path.dirname(case)} | {name} | {wall:.2f} | {wall / base:.2f} | "
                  f"{r['coupling']:.2f} | {r['friction']:.1f} | {r['qp']:.0f} | {r['heat']:.4g} | "
                  f"{r['conducted']:.4g} | {r['thermal']:.4g} | {r['tmin']:.1f}–{r['tmax']:.1f} | "
                  f"{r['tn'][0]:.3f}–{r['tn'][1]:.3f} |")


if __name__ == "__main__":
    main()
