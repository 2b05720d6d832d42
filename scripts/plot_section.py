#!/usr/bin/python3
"""Temperature on a plane section x = X of 3D bodies written by thermocontact (the front view
of the thesis' figs. 7.1-7.3), one panel per written step, on the deformed mesh.

    /usr/bin/python3 scripts/plot_section.py OUT_DIR --steps 25 50 75 100 [--x 0]
        [--bodies master slave] [--field temperature] [--scale 1] [--vmin A --vmax B] [-o F.png]

OUT_DIR holds <body>_<step:06d>.vtu. The section takes the mesh nodes with |x - X| < 1e-9
(box meshes with a node plane at X) and draws their values smoothly (Gouraud) over the
(y, z) grid they form; --scale magnifies the displacement (default 1: true size).
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_field import read_vtu  # noqa: E402  (the .vtu reader, every encoding)


def read(path):
    vtu = read_vtu(path)
    return vtu["Points"], vtu["PointData"]


def section(path, x0, field, scale):
    pts, point = read(path)
    sel = np.abs(pts[:, 0] - x0) < 1e-9
    u = point.get("displacement", np.zeros_like(pts))
    y = pts[sel, 1] + scale * u[sel, 1]
    z = pts[sel, 2] + scale * u[sel, 2]
    ys, zs = np.unique(np.round(pts[sel, 1], 12)), np.unique(np.round(pts[sel, 2], 12))
    order = np.lexsort((pts[sel, 1], pts[sel, 2]))  # z-major, then y
    shape = (len(zs), len(ys))
    v = point[field][sel]
    return (y[order].reshape(shape), z[order].reshape(shape), v[order].reshape(shape))


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("out_dir")
    ap.add_argument("--steps", type=int, nargs="+", required=True)
    ap.add_argument("--x", type=float, default=0.0)
    ap.add_argument("--bodies", nargs="+", default=["master", "slave"])
    ap.add_argument("--field", default="temperature")
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--vmin", type=float, default=None)
    ap.add_argument("--vmax", type=float, default=None)
    ap.add_argument("--dt", type=float, default=None, help="step size, to label panels by time")
    ap.add_argument("--title", default=None)
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args()
    data = {(s, b): section(os.path.join(args.out_dir, f"{b}_{s:06d}.vtu"), args.x, args.field,
                            args.scale)
            for s in args.steps for b in args.bodies}
    vals = np.concatenate([d[2].ravel() for d in data.values()])
    vmin = args.vmin if args.vmin is not None else vals.min()
    vmax = args.vmax if args.vmax is not None else vals.max()
    n = len(args.steps)
    fig, axes = plt.subplots(n, 1, figsize=(9, 2.3 * n), sharex=True, squeeze=False)
    for ax, s in zip(axes[:, 0], args.steps):
        for b in args.bodies:
            y, z, v = data[(s, b)]
            pc = ax.pcolormesh(y, z, v, shading="gouraud", cmap="inferno", vmin=vmin, vmax=vmax)
        label = f"t = {s * args.dt:g} s" if args.dt else f"step {s}"
        ax.set_title(label, fontsize=9)
        ax.set_aspect("equal")
        ax.set_ylabel("z [m]")
    axes[-1, 0].set_xlabel("y [m]")
    fig.colorbar(pc, ax=axes[:, 0].tolist(), label=f"{args.field} [K]", shrink=0.8)
    if args.title:
        fig.suptitle(args.title)
    out = args.output or os.path.join(args.out_dir, f"section_{args.field}.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
