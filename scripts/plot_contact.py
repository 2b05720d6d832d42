#!/usr/bin/python3
"""The contact pressure (and tangential traction) along x on a 2D slave body, from its .vtu.

    /usr/bin/python3 scripts/plot_contact.py SLAVE.vtu [--hertz R E NU] [-o F.png]

--hertz overlays the plane-strain Hertz profile p₀√(1 − x²/a²) of a cylinder of radius R on a
body of the same material (E* = E/(2(1 − ν²))), for the load P = contact_normal_force in the
last row of history.csv beside the .vtu: a = √(4PR/(πE*)), p₀ = 2P/(πa).
"""
import argparse
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_field import read_vtu  # noqa: E402  (the .vtu reader, every encoding)


def point_arrays(path):
    vtu = read_vtu(path)
    return vtu["Points"], vtu["PointData"]


def last_row(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: float(v) for k, v in rows[-1].items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("vtu")
    ap.add_argument("--hertz", nargs=3, type=float, metavar=("R", "E", "NU"))
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args()
    xyz, fields = point_arrays(args.vtu)
    p = fields["contact_pressure"]
    on = p > 0
    order = np.argsort(xyz[on, 0])
    x, pn = xyz[on, 0][order], p[on][order]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(x * 1e3, pn / 1e6, "o", ms=4, label="contact_pressure (nodal λ_n)")
    if "tangential_traction" in fields:
        t = np.linalg.norm(fields["tangential_traction"][on][order], axis=1)
        if t.max() > 0:
            ax.plot(x * 1e3, t / 1e6, "s", ms=3, label="|tangential_traction|")
    title = os.path.basename(args.vtu)
    if args.hertz:
        radius, e, nu = args.hertz
        load = last_row(os.path.join(os.path.dirname(args.vtu), "history.csv"))[
            "contact_normal_force"]
        e_star = e / (2 * (1 - nu * nu))
        a = math.sqrt(4 * load * radius / (math.pi * e_star))
        p0 = 2 * load / (math.pi * a)
        xs = np.linspace(-a, a, 400)
        ax.plot(xs * 1e3, p0 * np.sqrt(np.clip(1 - (xs / a) ** 2, 0, None)) / 1e6, "-",
                label=f"Hertz: a = {a * 1e3:.2f} mm, p₀ = {p0 / 1e6:.0f} MPa")
        title = f"P = {load / 1e6:.2f} MN/m"
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("[MPa]")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    out = args.output or os.path.splitext(args.vtu)[0] + "_contact.png"
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
