#!/usr/bin/python3
"""A picture of one field of a 2D .vtu written by thermocontact, on the deformed mesh.

    /usr/bin/python3 scripts/plot_field.py FILE.vtu [--field temperature] [--scale 0] [-o F.png]

--scale magnifies the displacement (0 = automatic: the largest displacement drawn as 5 % of
the body's size). Point fields are drawn smoothly, cell fields per cell.
"""
import argparse
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402


def arrays(root, section):
    out = {}
    node = root.find(f".//{section}")
    if node is None:
        return out
    for da in node.findall("DataArray"):
        n = int(da.get("NumberOfComponents", "1"))
        v = np.array(da.text.split(), dtype=float)
        out[da.get("Name")] = v.reshape(-1, n) if n > 1 else v
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("vtu")
    ap.add_argument("--field", default="temperature")
    ap.add_argument("--scale", type=float, default=0.0)
    ap.add_argument("--title", default=None)
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args()
    root = ET.parse(args.vtu).getroot()
    pts = np.array(root.find(".//Points/DataArray").text.split(), dtype=float).reshape(-1, 3)
    cells = root.find(".//Cells")
    conn = offs = None
    for da in cells.findall("DataArray"):
        v = np.array(da.text.split(), dtype=int)
        if da.get("Name") == "connectivity":
            conn = v
        elif da.get("Name") == "offsets":
            offs = v
    point, cell = arrays(root, "PointData"), arrays(root, "CellData")
    u = point.get("displacement", np.zeros_like(pts))
    size = np.ptp(pts[:, :2], axis=0).max()
    umax = np.abs(u[:, :2]).max()
    scale = args.scale if args.scale > 0 else (0.05 * size / umax if umax > 0 else 0.0)
    xy = pts[:, :2] + scale * u[:, :2]
    polys, starts = [], np.concatenate([[0], offs[:-1]])
    for s, e in zip(starts, offs):
        polys.append(xy[conn[s:e]])
    if args.field in cell:
        values = cell[args.field]
        values = np.linalg.norm(values, axis=1) if values.ndim > 1 else values
    else:
        pv = point[args.field]
        pv = np.linalg.norm(pv, axis=1) if pv.ndim > 1 else pv
        values = np.array([pv[conn[s:e]].mean() for s, e in zip(starts, offs)])
    fig, ax = plt.subplots(figsize=(9, 4))
    pc = PolyCollection(polys, array=values, cmap="inferno", edgecolors="face", linewidths=0.2)
    ax.add_collection(pc)
    ax.autoscale()
    ax.set_aspect("equal")
    fig.colorbar(pc, ax=ax, label=args.field)
    ax.set_title(args.title or f"{args.field} (displacement × {scale:.3g})")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    fig.tight_layout()
    out = args.output or args.vtu.replace(".vtu", f"_{args.field}.png")
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
