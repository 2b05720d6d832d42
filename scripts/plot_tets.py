#!/usr/bin/python3
"""A field of 3D tetrahedral (Tet4) bodies written by thermocontact, on the deformed mesh: a
plane section through all bodies and, optionally, the view of a flat face of the boundary.

    /usr/bin/python3 scripts/plot_tets.py OUT_DIR --step N [--bodies plate pin] [--plane y=0]
        [--face plate:z=0] [--outline pin:z=0] [--field temperature] [--scale 1]
        [--window X0 X1 Y0 Y1] [--face-window X0 X1 Y0 Y1] [--vmin A --vmax B] [--dt T]
        [-o F.png]

OUT_DIR holds <body>_<step:06d>.vtu. The section cuts every tetrahedron that crosses the plane
(taken in the reference configuration, so a node plane there is not needed: unstructured
meshes) and draws the field, linear in each tetrahedron, exactly on the cut (Gouraud shading
of the cut polygons). --face draws the boundary facets of a body that lie on a plane (in the
reference configuration), seen along its normal; --outline draws the edges of the rim of such
a face of another body (the pin's footprint on the plate). Coordinates are the deformed ones,
x + scale·u (default scale 1: true size, so a slid body is drawn where it is). Only Tet4 cells
(VTK type 10) are read.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from plot_field import read_vtu  # noqa: E402  (the .vtu reader, every encoding)

AXES = {"x": 0, "y": 1, "z": 2}
TET_FACES = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))


def read_tets(path, field):
    vtu = read_vtu(path)
    pts, cells = vtu["Points"], vtu["Cells"]
    if np.any(cells["types"] != 10):
        raise SystemExit(f"{path}: cells other than Tet4 (VTK 10): not supported")
    tets = cells["connectivity"].reshape(-1, 4)
    point = vtu["PointData"]
    values = point[field]
    values = np.linalg.norm(values, axis=1) if values.ndim > 1 else values
    return pts, point.get("displacement", np.zeros_like(pts)), tets, values


def plane(spec):
    """'y=0' -> (1, 0.0); 'plate:z=0' -> ('plate', 2, 0.0)."""
    body = None
    if ":" in spec:
        body, spec = spec.split(":", 1)
    a, v = spec.split("=")
    return body, AXES[a.strip()], float(v)


def section(pts, u, tets, values, axis, value, scale):
    """The cut of the tetrahedra by the plane X[axis] = value: triangles in deformed coords."""
    size = np.ptp(pts, axis=0).max()
    d = pts[:, axis] - value
    d = np.where(np.abs(d) < 1e-12 * size, 1e-12 * size, d)  # nodes on the plane: just above
    cur = pts + scale * u
    xy, val, tris = [], [], []
    for tet in tets[(np.min(d[tets], axis=1) < 0) & (np.max(d[tets], axis=1) > 0)]:
        neg = [n for n in tet if d[n] < 0]
        pos = [n for n in tet if d[n] > 0]

        def cut(a, b):
            w = d[a] / (d[a] - d[b])
            return (1 - w) * cur[a] + w * cur[b], (1 - w) * values[a] + w * values[b]

        if len(neg) == 1 or len(pos) == 1:
            one, rest = (neg, pos) if len(neg) == 1 else (pos, neg)
            ring = [cut(one[0], r) for r in rest]
        else:  # a quadrilateral: (a,c) (a,d) (b,d) (b,c) is a cycle
            a, b = neg
            c, e = pos
            ring = [cut(a, c), cut(a, e), cut(b, e), cut(b, c)]
        base = len(xy)
        for p, v in ring:
            xy.append(np.delete(p, axis))
            val.append(v)
        tris.append((base, base + 1, base + 2))
        if len(ring) == 4:
            tris.append((base, base + 2, base + 3))
    return np.array(xy), np.array(val), np.array(tris)


def boundary_faces(tets):
    keys = {}
    for tet in tets:
        for f in TET_FACES:
            k = tuple(sorted(tet[list(f)]))
            keys[k] = keys.get(k, 0) + 1
    return np.array([k for k, c in keys.items() if c == 1])


def flat_face(pts, tets, axis, value):
    faces = boundary_faces(tets)
    tol = 1e-9 * np.ptp(pts, axis=0).max()
    return faces[np.all(np.abs(pts[faces, axis] - value) < tol, axis=1)]


def rim(faces):
    """The edges of a set of triangles used by one triangle only (its outline)."""
    count = {}
    for f in faces:
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            k = (min(a, b), max(a, b))
            count[k] = count.get(k, 0) + 1
    return [k for k, c in count.items() if c == 1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("out_dir")
    ap.add_argument("--step", type=int, required=True)
    ap.add_argument("--bodies", nargs="+", default=["plate", "pin"])
    ap.add_argument("--plane", default="y=0")
    ap.add_argument("--face", default=None, help="BODY:AXIS=VALUE, e.g. plate:z=0")
    ap.add_argument("--outline", default=None, help="BODY:AXIS=VALUE, e.g. pin:z=0")
    ap.add_argument("--field", default="temperature")
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--window", type=float, nargs=4, default=None)
    ap.add_argument("--face-window", type=float, nargs=4, default=None)
    ap.add_argument("--vmin", type=float, default=None)
    ap.add_argument("--vmax", type=float, default=None)
    ap.add_argument("--dt", type=float, default=None, help="step size, to label by time")
    ap.add_argument("--title", default=None)
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args()
    data = {b: read_tets(os.path.join(args.out_dir, f"{b}_{args.step:06d}.vtu"), args.field)
            for b in args.bodies}
    _, axis, value = plane(args.plane)
    cuts = {b: section(*data[b], axis, value, args.scale) for b in args.bodies}
    vals = np.concatenate([d[3] for d in data.values()])
    vmin = args.vmin if args.vmin is not None else vals.min()
    vmax = args.vmax if args.vmax is not None else vals.max()
    n = 2 if args.face else 1
    fig, axes = plt.subplots(1, n, figsize=(6.5 * n, 5), squeeze=False)
    names = [a for a in "xyz" if AXES[a] != axis]
    ax = axes[0, 0]
    for b in args.bodies:
        xy, v, tris = cuts[b]
        if len(tris):
            tc = ax.tripcolor(mtri.Triangulation(xy[:, 0], xy[:, 1], tris), v,
                              shading="gouraud", cmap="inferno", vmin=vmin, vmax=vmax)
    ax.set_aspect("equal")
    if args.window:
        ax.set_xlim(args.window[0], args.window[1])
        ax.set_ylim(args.window[2], args.window[3])
    ax.set_xlabel(f"{names[0]} [m]")
    ax.set_ylabel(f"{names[1]} [m]")
    when = f"t = {args.step * args.dt:g} s" if args.dt else f"step {args.step}"
    ax.set_title(f"{args.field}, section {args.plane}, {when}", fontsize=10)
    fig.colorbar(tc, ax=ax, label=f"{args.field} [K]" if args.field == "temperature"
                 else args.field, shrink=0.9)
    if args.face:
        ax = axes[0, 1]
        body, faxis, fvalue = plane(args.face)
        pts, u, tets, v = data[body]
        faces = flat_face(pts, tets, faxis, fvalue)
        cur = np.delete(pts + args.scale * u, faxis, axis=1)
        tc = ax.tripcolor(mtri.Triangulation(cur[:, 0], cur[:, 1], faces), v,
                          shading="gouraud", cmap="inferno", vmin=vmin, vmax=vmax)
        fnames = [a for a in "xyz" if AXES[a] != faxis]
        if args.outline:
            obody, oaxis, ovalue = plane(args.outline)
            opts, ou, otets, _ = data[obody]
            ocur = np.delete(opts + args.scale * ou, oaxis, axis=1)
            edges = rim(flat_face(opts, otets, oaxis, ovalue))
            ax.add_collection(LineCollection([ocur[list(e)] for e in edges], colors="c",
                                             linewidths=1.0, label=f"{obody} ({args.outline})"))
            ax.legend(loc="upper right", fontsize="small")
        ax.set_aspect("equal")
        if args.face_window:
            ax.set_xlim(args.face_window[0], args.face_window[1])
            ax.set_ylim(args.face_window[2], args.face_window[3])
        ax.set_xlabel(f"{fnames[0]} [m]")
        ax.set_ylabel(f"{fnames[1]} [m]")
        ax.set_title(f"{args.field} on the face {args.face}, {when}", fontsize=10)
        fig.colorbar(tc, ax=ax, label="temperature [K]" if args.field == "temperature"
                     else args.field, shrink=0.9)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    out = args.output or os.path.join(args.out_dir, f"tets_{args.field}_{args.step:06d}.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
