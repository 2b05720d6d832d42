#!/usr/bin/python3
"""Plots of a run's history.csv: energies, temperatures, reactions, iterations per step.

    /usr/bin/python3 scripts/plot_history.py OUTDIR [-o FILE.png]

Uses Debian's python3-matplotlib (installed by scripts/setup.sh).
"""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_history(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("outdir")
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args()
    h = read_history(os.path.join(args.outdir, "history.csv"))
    t = h["time"]
    contact = max(abs(v) for v in h.get("contact_normal_force", [0.0])) > 0
    fig, ax = plt.subplots(3 if contact else 2, 2, figsize=(11, 10.5 if contact else 7))
    a = ax[0][0]
    for k in ("kinetic_energy", "strain_energy", "external_work"):
        a.plot(t, h[k], label=k.replace("_", " "))
    a.set_title("mechanical energy [J]")
    a.legend()
    a = ax[0][1]
    a.plot(t, h["max_temperature"], label="max")
    a.plot(t, h["min_temperature"], label="min")
    a.set_title("temperature [K]")
    a.legend()
    a = ax[1][0]
    reactions = [k for k in h if k.startswith("reaction_")]
    for k in reactions:
        if max(abs(v) for v in h[k]) > 0:
            a.plot(t, h[k], label=k[len("reaction_"):])
    a.set_title("support reactions [N]")
    if reactions:
        a.legend(fontsize="small")
    a = ax[1][1]
    a.plot(t, h["thermal_energy"], label="thermal energy [J]")
    a.set_title("thermal energy Σ∫ρc_p(θ−θ₀) [J]")
    for k, name in (("heat_film", "lost through films"), ("heat_radiation", "lost by radiation")):
        if k in h and max(abs(v) for v in h[k]) > 0:  # columns of runs since issue 21
            a.plot(t, h[k], label=name + " [J]")
            a.legend(fontsize="small")
    if contact:  # forces and their ratio (= 𝔉 while sliding), iterations per step
        a = ax[2][0]
        a.plot(t, h["contact_normal_force"], label="normal")
        a.plot(t, h["contact_tangential_force"], label="tangential")
        a.set_title("contact forces [N]")
        a.legend()
        r = a.twinx()
        ratio = [ft / fn if fn > 0 else float("nan")
                 for ft, fn in zip(h["contact_tangential_force"], h["contact_normal_force"])]
        r.plot(t, ratio, "k:", label="tangential / normal")
        r.set_ylabel("tangential / normal")
        a = ax[2][1]
        a.plot(t, h["qp_iterations"], label="QP iterations")
        a.plot(t, h["coupling_iterations"], label="coupling iterations")
        a.set_yscale("log")
        a.set_title("iterations per step")
        a.legend()
    for a in ax.flat:
        a.set_xlabel("time [s]")
        a.grid(alpha=0.3)
    fig.tight_layout()
    out = args.output or os.path.join(args.outdir, "history.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
