# SPDX-License-Identifier: GPL-3.0-or-later
"""Geometry of the wave-tank cases: rubble-mound layer outlines, prism STLs, armour-unit placement.

Axes: x onshore (wave direction), y along the trunk, z up; the bed is z = 0. Units: m, degree.
"""

import math
import os
import subprocess

import numpy as np


def _intersect(p1, d1, p2, d2):
    """Intersection of the lines p1 + s d1 and p2 + u d2 in the x-z plane."""
    a = np.array([[d1[0], -d2[0]], [d1[1], -d2[1]]], dtype=float)
    s, _ = np.linalg.solve(a, np.asarray(p2, float) - np.asarray(p1, float))
    return np.asarray(p1, float) + s * np.asarray(d1, float)


def mound_outline(core, offset):
    """Trapezoid (x, z) of the mound offset outward by `offset` (m) normal to each face.

    core: dict with toe_x (seaward toe of the core, m), crest_z (m), crest_width (m),
    front_cot (seaward slope, horizontal/vertical), back_cot (lee slope).
    Returns 4 vertices counter-clockwise: seaward toe, seaward crest, lee crest, lee toe (z = 0).
    """
    x0, zc, wc = core["toe_x"], core["crest_z"], core["crest_width"]
    cf, cb = core["front_cot"], core["back_cot"]
    xcs = x0 + cf * zc           # seaward end of the core crest
    xcl = xcs + wc               # lee end of the core crest
    # Each face as (point, direction, outward unit normal).
    front_d = np.array([cf, 1.0]); front_n = np.array([-1.0, cf]) / math.hypot(1.0, cf)
    crest_d = np.array([1.0, 0.0]); crest_n = np.array([0.0, 1.0])
    back_d = np.array([cb, -1.0]); back_n = np.array([1.0, cb]) / math.hypot(1.0, cb)
    front_p = np.array([x0, 0.0]) + offset * front_n
    crest_p = np.array([xcs, zc]) + offset * crest_n
    back_p = np.array([xcl, zc]) + offset * back_n
    bed_p, bed_d = np.array([0.0, 0.0]), np.array([1.0, 0.0])
    return [
        _intersect(bed_p, bed_d, front_p, front_d),
        _intersect(front_p, front_d, crest_p, crest_d),
        _intersect(crest_p, crest_d, back_p, back_d),
        _intersect(back_p, back_d, bed_p, bed_d),
    ]


def prism_triangles(outline, y0, y1, z_floor):
    """Closed, outward-oriented triangles of the convex x-z polygon `outline` extruded over [y0, y1].

    The polygon is closed below z_floor (the bed or below it) so cells touching the bed are inside.
    """
    pts = [np.array([p[0], p[1]]) for p in outline]
    pts[0] = np.array([pts[0][0], z_floor]); pts[-1] = np.array([pts[-1][0], z_floor])
    # outline runs clockwise seen from -y when going toe -> crest -> crest -> toe with z up and x
    # right; orientation is fixed below by checking each normal against the centroid.
    c2 = np.mean(pts, axis=0)
    centroid = np.array([c2[0], 0.5 * (y0 + y1), c2[1]])
    tris = []
    n = len(pts)
    v = lambda p, y: np.array([p[0], y, p[1]])
    for i in range(n):  # side quads
        a, b = pts[i], pts[(i + 1) % n]
        tris += [(v(a, y0), v(b, y0), v(b, y1)), (v(a, y0), v(b, y1), v(a, y1))]
    for i in range(1, n - 1):  # end caps (fan; the polygon is convex)
        tris.append((v(pts[0], y0), v(pts[i], y0), v(pts[i + 1], y0)))
        tris.append((v(pts[0], y1), v(pts[i], y1), v(pts[i + 1], y1)))
    out = []
    for t in tris:
        nrm = np.cross(t[1] - t[0], t[2] - t[0])
        if np.dot(nrm, np.mean(t, axis=0) - centroid) < 0.0:
            t = (t[0], t[2], t[1])
        out.append(t)
    return out


def _solid_lines(name, triangles):
    lines = [f"solid {name}"]
    for t in triangles:
        nrm = np.cross(t[1] - t[0], t[2] - t[0])
        ln = np.linalg.norm(nrm)
        nrm = nrm / ln if ln > 0 else nrm
        lines.append(f"  facet normal {nrm[0]:.9g} {nrm[1]:.9g} {nrm[2]:.9g}")
        lines.append("    outer loop")
        for p in t:
            lines.append(f"      vertex {p[0]:.9g} {p[1]:.9g} {p[2]:.9g}")
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append(f"endsolid {name}")
    return lines


def write_stl_multi(path, solids):
    """ASCII STL with one solid per (name, triangles), written atomically (OpenFOAM reads each
    solid as a region of one surface)."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    lines = []
    for name, tris in solids:
        lines += _solid_lines(name, tris)
    tmp = path + ".partial"
    with open(tmp, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    os.replace(tmp, path)


def write_stl(path, name, triangles):
    """ASCII STL with solid `name`, written atomically."""
    write_stl_multi(path, [(name, triangles)])


def read_stl_ascii(path):
    """Triangles (n, 3, 3) of an ASCII STL."""
    verts = []
    with open(path) as fh:
        for line in fh:
            s = line.split()
            if s and s[0] == "vertex":
                verts.append([float(s[1]), float(s[2]), float(s[3])])
    if not verts or len(verts) % 3:
        raise ValueError(f"{path}: no triangles (or a broken ASCII STL)")
    return np.array(verts).reshape(-1, 3, 3)


def export_unit(armour_exe, shape, volume, out_path):
    """Write one unit of `shape` with volume (m^3) as ASCII STL using `armour shape export`."""
    cmd = [armour_exe, "shape", "export", shape, "--volume", repr(float(volume)),
           "-o", out_path, "--format", "stl-ascii"]
    res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if res.returncode != 0:
        raise RuntimeError(f"`{' '.join(cmd)}` failed:\n{res.stdout}")
    return read_stl_ascii(out_path)


def _rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def place_units(unit_tris, outline, units, width):
    """Place unit copies in a staggered grid on the seaward face of `outline` (the under-layer top).

    units: rows (along the slope, from the toe up), columns (along y), spacing_slope and
    spacing_y (m, centre to centre), first_row (m along the slope from the toe to row 0),
    seed (random yaw about the slope normal), embed (fraction of the unit's normal half-extent
    pushed into the under-layer, -). Returns a list of (n, 3, 3) triangle arrays, one per unit,
    and the list of unit centres.
    """
    toe, crest = np.array(outline[0]), np.array(outline[1])
    d = crest - toe
    length = float(np.linalg.norm(d))
    theta = math.atan2(d[1], d[0])                     # slope angle above horizontal (rad)
    t_dir = np.array([math.cos(theta), 0.0, math.sin(theta)])   # up-slope direction
    n_dir = np.array([-math.sin(theta), 0.0, math.cos(theta)])  # outward slope normal
    local = unit_tris.reshape(-1, 3)
    local = local - local.mean(axis=0)
    rng = np.random.default_rng(units.get("seed", 1))
    placed, centres = [], []
    sy = units["spacing_y"]
    ncol = units["columns"]
    for r in range(units["rows"]):
        s = units.get("first_row", 0.6 * sy) + r * units["spacing_slope"]
        if s > length:
            raise ValueError(f"units: row {r} at {s:.2f} m along the slope is above the crest "
                             f"(slope length {length:.2f} m): fewer rows or a smaller spacing")
        stagger = 0.5 * sy if r % 2 else 0.0
        for c in range(ncol):
            y = 0.5 * (width - (ncol - 1) * sy) + c * sy + stagger
            if y + 0.5 * sy > width + 1e-9:
                continue   # staggered row: the last unit would cross the side wall
            yaw = rng.uniform(0.0, 2.0 * math.pi)
            R = _rot_y(-theta) @ _rot_z(yaw)
            pts = local @ R.T
            half = 0.5 * float(np.ptp(pts @ n_dir))
            base = np.array([toe[0], 0.0, toe[1]]) + s * t_dir
            centre = base + (1.0 - units.get("embed", 0.1)) * half * n_dir
            centre[1] = y
            placed.append((pts + centre).reshape(-1, 3, 3))
            centres.append(centre)
    return placed, centres


def quaternion_matrix(q):
    """Rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def place_units_from_poses(unit_tris, poses):
    """Units at given poses: list of {"position": [x, y, z] (m), "quaternion": [w, x, y, z]}
    (e.g. a settled pack from armour's placement), the shape's centroid at the position."""
    local = unit_tris.reshape(-1, 3)
    local = local - local.mean(axis=0)
    placed, centres = [], []
    for i, pose in enumerate(poses):
        if "position" not in pose or "quaternion" not in pose:
            raise ValueError(f"units.poses[{i}]: needs 'position' [x, y, z] (m) and 'quaternion' [w, x, y, z]")
        c = np.asarray(pose["position"], dtype=float)
        R = quaternion_matrix(pose["quaternion"])
        placed.append((local @ R.T + c).reshape(-1, 3, 3))
        centres.append(c)
    return placed, centres
