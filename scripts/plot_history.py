#!/usr/bin/python3
"""Plots of a run's history.csv: energies, temperatures, reactions, iterations per step.

    /usr/bin/python3 scripts/plot_history.py OUTDIR [-o FILE.png]

With several contact pairs (columns contact_normal_force_<name>) the contact panel shows each
pair's forces and tangential/normal ratio, and a fourth row each pair's heat.

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
    prefix = "contact_normal_force_"
    pairs = [k[len(prefix):] for k in h if k.startswith(prefix)] if contact else []
    rows = 4 if pairs else 3 if contact else 2
    fig, ax = plt.subplots(rows, 2, figsize=(11, 3.5 * rows))
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
        r = a.twinx()
        if not pairs:
            a.plot(t, h["contact_normal_force"], label="normal")
            a.plot(t, h["contact_tangential_force"], label="tangential")
            ratio = [ft / fn if fn > 0 else float("nan")
                     for ft, fn in zip(h["contact_tangential_force"], h["contact_normal_force"])]
            r.plot(t, ratio, "k:", label="tangential / normal")
        for p in pairs:
            fn, ft = h["contact_normal_force_" + p], h["contact_tangential_force_" + p]
            line = a.plot(t, fn, label=p + " normal")[0]
            a.plot(t, ft, "--", color=line.get_color(), label=p + " tangential")
            ratio = [b / n if n > 0 else float("nan") for b, n in zip(ft, fn)]
            r.plot(t, ratio, ":", color=line.get_color())
        a.set_title("contact forces [N]" + (" (dotted: tangential / normal)" if pairs else ""))
        a.legend(fontsize="small" if pairs else None)
        r.set_ylabel("tangential / normal")
        a = ax[2][1]
        a.plot(t, h["qp_iterations"], label="QP iterations")
        a.plot(t, h["coupling_iterations"], label="coupling iterations")
        a.set_yscale("log")
        a.set_title("iterations per step")
        a.legend()
    if pairs:  # each pair's frictional heat, its share to the slave, and the heat conducted
        a = ax[3][0]
        for p in pairs:
            line = a.plot(t, h["heat_generated_" + p], label=p + " generated")[0]
            a.plot(t, h["heat_to_slave_" + p], "--", color=line.get_color(),
                   label=p + " to the slave")
        a.set_title("frictional heat per pair, cumulative [J]")
        a.legend(fontsize="small")
        a = ax[3][1]
        for p in pairs:
            a.plot(t, h["heat_conducted_" + p], label=p)
        a.set_title("heat conducted slave → master per pair, cumulative [J]")
        a.legend(fontsize="small")
    for a in ax.flat:
        a.set_xlabel("time [s]")
        a.grid(alpha=0.3)
    fig.tight_layout()
    out = args.output or os.path.join(args.outdir, "history.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
