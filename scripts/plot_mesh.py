#!/usr/bin/python3
"""A quick look at a mesh written by `sphsplat mesh` (PLY or OBJ): matplotlib's trisurf, shaded
by the file's vertex normals against a light, y up as in the scene.

    scripts/plot_mesh.py meshes/pour_00030.ply [-o picture.png] [--max-triangles 200000]
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import meshio
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh")
    ap.add_argument("-o", "--output", default=None, help="PNG (default: the mesh's name + .png)")
    ap.add_argument("--max-triangles", type=int, default=200000,
                    help="draw every k-th triangle beyond this many (matplotlib is slow)")
    a = ap.parse_args()
    m = meshio.read(a.mesh)
    tri = m.cells_dict["triangle"]
    p = m.points
    pd = m.point_data
    n = np.stack([pd["nx"], pd["ny"], pd["nz"]], axis=1) if "nx" in pd else pd["obj:vn"]
    if len(tri) > a.max_triangles:
        tri = tri[:: int(np.ceil(len(tri) / a.max_triangles))]
    light = np.array([0.35, 0.85, 0.4])
    light /= np.linalg.norm(light)
    shade = np.clip(n[tri].mean(axis=1) @ light, 0, 1)
    colour = np.array([0.16, 0.42, 0.78])
    colours = np.clip(colour * (0.3 + 0.7 * shade[:, None]) + 0.1 * shade[:, None] ** 8, 0, 1)
    # Scene y up -> matplotlib z up: plot (x, z, y).
    q = p[:, [0, 2, 1]]
    fig = plt.figure(figsize=(8, 6), dpi=120)
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(Poly3DCollection(q[tri], facecolors=colours, edgecolors="none"))
    lo, hi = q.min(axis=0), q.max(axis=0)
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2
    for set_lim, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        set_lim(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x [m]"), ax.set_ylabel("z [m]"), ax.set_zlabel("y [m]")
    ax.view_init(elev=25, azim=-60)
    ax.set_title(f"{os.path.basename(a.mesh)}: {len(m.cells_dict['triangle'])} triangles, {len(p)} vertices", fontsize=9)
    out = a.output or a.mesh + ".png"
    fig.savefig(out, bbox_inches="tight")
    print("wrote", out)


if __name__ == "__main__":
    main()
