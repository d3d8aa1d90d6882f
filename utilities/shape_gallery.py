#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Render a gallery of unit meshes (binary or ASCII STL) to one PNG, for docs and quick checks.

usage: utilities/shape_gallery.py OUT.png MESH.stl [MESH.stl ...]

Each panel shows the unit with flat shading, equal axes (m) and its name; z is up.
Needs python3-numpy and python3-matplotlib (Debian).
"""
import struct
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_stl(path):
    """Triangles as an (n, 3, 3) array; raises ValueError naming the file if it is not STL."""
    data = Path(path).read_bytes()
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if len(data) == 84 + 50 * count:
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=count, offset=84)
            return rec["v"].astype(float)
    text = data.decode("ascii", errors="strict")
    verts = [list(map(float, line.split()[1:4])) for line in text.splitlines() if line.strip().startswith("vertex")]
    if not verts or len(verts) % 3:
        raise ValueError(f"{path}: not an STL file (no complete facets)")
    return np.array(verts).reshape(-1, 3, 3)


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    out, meshes = argv[1], argv[2:]
    cols = min(4, len(meshes))
    rows = (len(meshes) + cols - 1) // cols
    fig = plt.figure(figsize=(3.2 * cols, 3.2 * rows))
    light = np.array([0.4, -0.5, 0.77])
    for i, path in enumerate(meshes):
        tri = read_stl(path)
        ax = fig.add_subplot(rows, cols, i + 1, projection="3d")
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        normal /= np.linalg.norm(normal, axis=1, keepdims=True) + 1e-300
        shade = 0.35 + 0.65 * np.clip(normal @ (light / np.linalg.norm(light)), 0, 1)
        colours = np.outer(shade, [0.75, 0.72, 0.65])
        ax.add_collection3d(Poly3DCollection(tri, facecolors=colours, edgecolors=(0, 0, 0, 0.15), linewidths=0.2))
        lo, hi = tri.reshape(-1, 3).min(0), tri.reshape(-1, 3).max(0)
        centre, half = (lo + hi) / 2, (hi - lo).max() / 2
        for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
            setter(c - half, c + half)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=22, azim=-60)
        ax.set_title(Path(path).stem, fontsize=10)
        ax.tick_params(labelsize=6)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main(sys.argv)
