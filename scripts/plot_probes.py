#!/usr/bin/python3
"""The probes of a run (probes.csv, one row per step): each probe's temperature, and the
magnitude of its displacement, against time.

    /usr/bin/python3 scripts/plot_probes.py OUTDIR [--probes NAME ...] [-o FILE.png]

Uses Debian's python3-matplotlib (installed by scripts/setup.sh).
"""
import argparse
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_probes(path):
    """{column: [values]} of probes.csv, and the probes' names in order."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    columns = {k: [float(r[k]) for r in rows] for k in rows[0]}
    names = [k[: -len("_temperature")] for k in rows[0] if k.endswith("_temperature")]
    return columns, names


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("outdir")
    ap.add_argument("--probes", nargs="+", default=None)
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args()
    p, names = read_probes(os.path.join(args.outdir, "probes.csv"))
    names = args.probes or names
    t = p["time"]
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for n in names:
        ax[0].plot(t, p[f"{n}_temperature"], label=n)
        parts = [p[k] for k in p if k.startswith(f"{n}_displacement_")]
        ax[1].plot(t, [math.sqrt(sum(c[i] ** 2 for c in parts)) for i in range(len(t))], label=n)
    ax[0].set_ylabel("temperature [K]")
    ax[1].set_ylabel("|displacement| [m]")
    for a in ax:
        a.set_xlabel("time [s]")
        a.grid(True, alpha=0.3)
        a.legend(fontsize="small")
    fig.tight_layout()
    out = args.output or os.path.join(args.outdir, "probes.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
