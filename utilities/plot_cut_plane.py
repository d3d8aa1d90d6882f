#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""A cut plane through a deformable frame, coloured by a stress (issue 26; seed 002 Figs. 3-5).

    plot_cut_plane.py FRAME.vtu OUT.png [--field sigma_1] [--origin X Y Z] [--normal X Y Z]
                      [--range LO HI] [--title TEXT]

Reads a VTU frame written by `armour deform` (frames/frame_NNNNNN.vtu; docs/deformable-file.md),
cuts it with the plane through --origin with normal --normal (default: the plane y = 0), and
draws the cut polygons coloured by the element field --field in MPa: sigma_1 (largest principal
stress, tension positive, seed 002's convention), sigma_3, differential_stress (sigma_1 - sigma_3)
or von_mises. The plot's axes are the plane's own: for a plane normal to y, x across and z up.
Python 3 with VTK 9 (Debian python3-vtk9) and matplotlib.
"""
import argparse
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

try:
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError:
    sys.exit("plot_cut_plane: needs VTK for Python 3 (Debian: apt-get install python3-vtk9)")


def plane_axes(normal):
    """Two unit axes spanning the plane: the horizontal one first, then 'up' (z where it can be)."""
    n = normal / np.linalg.norm(normal)
    up = np.array([0.0, 0.0, 1.0])
    if abs(n @ up) > 0.9:
        up = np.array([0.0, 1.0, 0.0])
    u = np.cross(up, n)
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    return u, v


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("vtu")
    ap.add_argument("png")
    ap.add_argument("--field", default="sigma_1", help="element field: sigma_1, sigma_3, differential_stress, von_mises")
    ap.add_argument("--origin", nargs=3, type=float, default=[0.0, 0.0, 0.0])
    ap.add_argument("--normal", nargs=3, type=float, default=[0.0, 1.0, 0.0])
    ap.add_argument("--range", nargs=2, type=float, default=None, help="colour range (MPa)")
    ap.add_argument("--title", default="")
    args = ap.parse_args()

    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.vtu)
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfCells() == 0:
        sys.exit(f"plot_cut_plane: {args.vtu}: no cells (is it a frame from armour deform?)")
    if grid.GetCellData().GetArray(args.field) is None:
        names = [grid.GetCellData().GetArrayName(i) for i in range(grid.GetCellData().GetNumberOfArrays())]
        sys.exit(f"plot_cut_plane: {args.vtu}: no element field '{args.field}'; the fields are: {', '.join(names)}")
    plane = vtk.vtkPlane()
    plane.SetOrigin(*args.origin)
    plane.SetNormal(*args.normal)
    cutter = vtk.vtkCutter()
    cutter.SetCutFunction(plane)
    cutter.SetInputData(grid)
    cutter.Update()
    cut = cutter.GetOutput()
    if cut.GetNumberOfCells() == 0:
        sys.exit(f"plot_cut_plane: the plane through {args.origin} normal to {args.normal} misses the mesh")
    values = vtk_to_numpy(cut.GetCellData().GetArray(args.field)) / 1e6
    points = vtk_to_numpy(cut.GetPoints().GetData())
    u, v = plane_axes(np.array(args.normal, dtype=float))
    polygons = []
    for c in range(cut.GetNumberOfCells()):
        ids = cut.GetCell(c).GetPointIds()
        p = points[[ids.GetId(k) for k in range(ids.GetNumberOfIds())]]
        polygons.append(np.column_stack([p @ u, p @ v]))
    lo, hi = args.range if args.range else (float(values.min()), float(values.max()))
    fig, ax = plt.subplots(figsize=(7.0, 6.0))
    collection = PolyCollection(polygons, array=values, cmap="jet", edgecolors="face", linewidths=0.2)
    collection.set_clim(lo, hi)
    ax.add_collection(collection)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("along the plane (m)")
    ax.set_ylabel("up the plane (m)")
    bar = fig.colorbar(collection, ax=ax, shrink=0.8)
    bar.set_label(f"{args.field} (MPa)")
    ax.set_title(args.title or f"{args.vtu}: {args.field} on the plane through {args.origin}", fontsize=9)
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    print(f"plot_cut_plane: wrote {args.png} ({cut.GetNumberOfCells()} cut cells, {args.field} {values.min():.3g} to "
          f"{values.max():.3g} MPa)")


if __name__ == "__main__":
    main()
