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


_TYPES = {"Float64": "<f8", "Int64": "<i8", "UInt8": "u1", "Int32": "<i4"}


def read_vtu(path):
    """The arrays of a .vtu of any of thermocontact's encodings ([output] format, compression):
    {"Points": (n, 3), "Cells": {name: array}, "PointData": {...}, "CellData": {...}}.

    ASCII arrays are parsed from the text; appended ones (raw, or zlib blocks after VTK's
    header [blocks, block size, last partial size, compressed sizes], UInt64) from the bytes
    after the '_' of <AppendedData>, as ParaView reads them.
    """
    import struct
    import zlib

    with open(path, "rb") as f:
        data = f.read()
    at = data.find(b"<AppendedData")
    xml = data if at < 0 else data[:at] + b"</VTKFile>\n"
    base = -1 if at < 0 else data.index(b"_", at) + 1
    root = ET.fromstring(xml)
    compressed = root.get("compressor") == "vtkZLibDataCompressor"

    def values(da):
        dtype = np.dtype(_TYPES[da.get("type")])
        if da.get("format") != "appended":
            return np.array(da.text.split(), dtype=float).astype(dtype)
        pos = base + int(da.get("offset"))
        if not compressed:
            (n,) = struct.unpack_from("<Q", data, pos)
            return np.frombuffer(data, dtype, n // dtype.itemsize, pos + 8)
        blocks, _, _ = struct.unpack_from("<3Q", data, pos)
        sizes = struct.unpack_from(f"<{blocks}Q", data, pos + 24)
        start, raw = pos + 24 + 8 * blocks, b""
        for size in sizes:
            raw += zlib.decompress(data[start:start + size])
            start += size
        return np.frombuffer(raw, dtype)

    out = {"Cells": {}, "PointData": {}, "CellData": {}}
    out["Points"] = values(root.find(".//Points/DataArray")).reshape(-1, 3)
    for section in ("Cells", "PointData", "CellData"):
        node = root.find(f".//{section}")
        for da in [] if node is None else node.findall("DataArray"):
            n = int(da.get("NumberOfComponents", "1"))
            v = values(da)
            out[section][da.get("Name")] = v.reshape(-1, n) if n > 1 else v
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("vtu")
    ap.add_argument("--field", default="temperature")
    ap.add_argument("--scale", type=float, default=0.0)
    ap.add_argument("--title", default=None)
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args()
    vtu = read_vtu(args.vtu)
    pts = vtu["Points"]
    conn, offs = vtu["Cells"]["connectivity"], vtu["Cells"]["offsets"]
    point, cell = vtu["PointData"], vtu["CellData"]
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
