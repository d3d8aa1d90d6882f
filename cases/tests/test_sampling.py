#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""End-to-end sampling of a smoke case into a storm file the solver reads (issue 7).

    test_sampling.py {2d|3d} OUTPUT_DIR ARMOUR_EXE FOAM_PROXY_EXE [SAMPLER_LIBRARY]

Generates the smoke case (2D: cases/nwt2d/smoke.json, 3D: cases/nwt3d/smoke.json) with
make_case.py --sample (the stock surfaces/sets function objects of `foam-proxy dict`, plus the
armourSampler function object when SAMPLER_LIBRARY is given), runs it, writes the storm file
offline with `foam-proxy sample` and checks that `armour storm-file check` accepts it (and the
online one of armourSampler). Physical checks:

  2D  in the first record (t = 0.05 s, the solitary crest is still 30 m offshore of the grid) the
      pressure of every voxel at least one voxel below the still water level is rho g (SWL - z)
      within 1 % (issue 7's tolerance; the cloud set reads the cell at the voxel centre, and the
      still tank is hydrostatic to the p_rgh solver tolerance, ~1e-4 relative was seen).
  3D  in the first record (still water at the units, as in 2D) every unit face of the raw surfaces
      output has p = rho g (SWL - z_face) within 1 %, and every voxel's p in the storm file is the
      mean of rho g (SWL - z_face) over the faces binned into it within 1 % (the voxel centre is
      not used: the faces lie anywhere in a voxel 1.5 m high); the face counts per voxel equal a
      binning of the face centres done here (voxel boundaries moved down by 1e-6 of a voxel, as in
      foam-bridge's VoxelGrid: the castellated faces lie exactly on voxel boundaries).
  both, with the sampler: online (armourSampler) and offline (foam-proxy) storm files have the
      same face counts per voxel (exactly), the same record times, and p, u, w, alpha, eta and the
      Weibull fits agree to 1e-6 relative (issue 7). Both read the same double face values: the
      function object in memory, foam-proxy from the raw surfaces and sets text written with
      writePrecision 15, so the only difference left is the storage of float in the storm file
      (one float rounding, 6e-8 relative, when the two doubles fall on either side of a float).
"""
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

import smokelib

TOL_HYDRO = 0.01   # relative, issue 7 (still water, 2D and 3D)
TOL_ONLINE = 1e-6  # relative, issue 7 (online vs offline); float storage gives 6e-8
SNAP = 1e-6        # bridge::VoxelGrid::kBoundarySnap (fraction of a voxel)
FILL = 9.0e36      # netCDF default fill of float is 9.96921e+36


def ncdump(path, names):
    """Variables of a storm file as numpy arrays, via Debian's ncdump (no netCDF4 Python module)."""
    out = subprocess.run(["ncdump", "-v", ",".join(names), path], check=True, stdout=subprocess.PIPE,
                         text=True).stdout
    data = out.split("\ndata:", 1)[1]
    dims = dict((k, int(v)) for k, v in re.findall(r"\n\s*(\w+) = (\d+) ;", out.split("\ndata:")[0]))
    tdim = re.search(r"time = UNLIMITED ; // \((\d+) currently\)", out)
    if tdim:
        dims["time"] = int(tdim.group(1))
    res = {}
    for name in names:
        m = re.search(r"\n\s*" + name + r" =\s*(.*?);", data, re.S)
        vals = [float("nan") if v.strip() == "_" else float(v) for v in m.group(1).replace("\n", " ").split(",")]
        res[name] = np.array(vals)
    res["dims"] = dims
    return res


def read_raw(path):
    """A file of OpenFOAM's raw surface writer: face centres (x, y, z) and the value columns."""
    rows = np.loadtxt(path, comments="#", ndmin=2)
    return rows[:, :3], rows[:, 3:]


def bin_faces(centres, g):
    """Voxel index iz * nx + ix of each face centre (-1 outside), the rule of bridge::VoxelGrid."""
    ix = np.floor((centres[:, 0] - g["x_min"]) / g["dx"] + SNAP)
    iz = np.floor((centres[:, 2] - g["z_min"]) / g["dz"] + SNAP)
    tol = SNAP * g["trunk_length"]
    y = centres[:, 1]
    inside = ((ix >= 0) & (ix < g["nx"]) & (iz >= 0) & (iz < g["nz"]) & (y >= g["trunk_origin"] - tol)
              & (y <= g["trunk_origin"] + g["trunk_length"] + tol))
    return np.where(inside, iz * g["nx"] + ix, -1).astype(int)


def relative(a, b, floor):
    """max |a - b| / max(|b|, floor) over the finite entries (nan if none)."""
    a, b = np.asarray(a, float).ravel(), np.asarray(b, float).ravel()
    ok = np.isfinite(a) & np.isfinite(b) & (np.abs(a) < FILL) & (np.abs(b) < FILL)
    if not ok.any():
        return float("nan")
    return float(np.max(np.abs(a[ok] - b[ok]) / np.maximum(np.abs(b[ok]), floor)))


def storm_check(armour, path):
    res = subprocess.run([armour, "storm-file", "check", path], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    print(f"armour storm-file check {path}: exit {res.returncode}\n{res.stdout.strip()}")
    return res.returncode == 0


def main():
    if len(sys.argv) not in (5, 6) or sys.argv[1] not in ("2d", "3d"):
        print(__doc__)
        return 2
    dim, root, armour, proxy = sys.argv[1:5]
    sampler = sys.argv[5] if len(sys.argv) == 6 and sys.argv[5] else None
    params = "nwt2d/smoke.json" if dim == "2d" else "nwt3d/smoke.json"
    case = os.path.join(root, f"nwt{dim}-smoke-sampled")
    extra = ["--sample", "both" if sampler else "foam-proxy", "--foam-proxy", proxy]
    if sampler:
        extra += ["--sampler-library", sampler]
    smokelib.generate(params, case, armour=armour if dim == "3d" else None, extra=extra)
    wall = smokelib.run(case)
    with open(os.path.join(case, "case.json")) as fh:
        info = json.load(fh)
    g = info["sampling"]
    offline = os.path.join(case, "storm-offline.nc")
    # The case's `sample` script (make_case.py --sample): foam-proxy sample with the case.json grid.
    cmd = [os.path.join(case, "sample"), "-o", offline]
    start = time.time()
    res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(f"{' '.join(cmd)}: exit {res.returncode}, {time.time() - start:.1f} s\n{res.stdout.strip()}")
    if res.returncode != 0:
        print("FAIL: foam-proxy sample failed")
        return 1
    ok = storm_check(armour, offline)
    # The title names the sea (make_case.py), where `armour report` looks for Hs: a solitary wave
    # is named by its height, which the report must not read as a sea state ("H=" or "Hs=").
    header = subprocess.run(["ncdump", "-h", offline], check=True, stdout=subprocess.PIPE, text=True).stdout
    if ':title = "nwt' + dim + '-smoke: solitary wave of height 3.0 m"' not in header:
        print("FAIL: the storm file's title does not name the solitary wave: "
              + next((l.strip() for l in header.splitlines() if ":title" in l), "(no title)"))
        ok = False
    online = os.path.join(case, "postProcessing", "armourSampler", "storm.nc")
    if sampler:
        if not os.path.isfile(online):
            print(f"FAIL: the armourSampler function object wrote no {online}")
            return 1
        ok = storm_check(armour, online) and ok
    if not ok:
        print("FAIL: the solver does not read the storm file")
        return 1

    off = ncdump(offline, ["time", "x", "z", "p", "samples"])
    nt, nz, nx = off["dims"]["time"], off["dims"]["z"], off["dims"]["x"]
    p_off = off["p"].reshape(nt, nz, nx)
    print(f"offline storm file: {nt} records t = {off['time'][0]:.3f}..{off['time'][-1]:.3f} s, "
          f"grid {nx} x {nz}, {int((off['samples'] > 0).sum())} voxels with samples; wall time {wall:.1f} s")
    if nt < 10:
        print("FAIL: fewer than 10 records in the storm file")
        return 1
    rho, grav, swl = g["rho"], g["g"], g["swl"]

    if dim == "2d":
        z = off["z"]
        worst = 0.0
        n = 0
        for k in range(nz):
            if z[k] > swl - g["dz"]:
                continue
            hydro = rho * grav * (swl - z[k])
            for i in range(nx):
                pv = p_off[0, k, i]
                if not np.isfinite(pv) or abs(pv) > FILL:
                    continue
                worst = max(worst, abs(pv - hydro) / hydro)
                n += 1
        print(f"first record t = {off['time'][0]:.3f} s: {n} submerged voxels, max |p - rho g (SWL - z)| / "
              f"rho g (SWL - z) = {worst:.3e} (limit {TOL_HYDRO})")
        if n < nx or worst > TOL_HYDRO:
            print("FAIL: the sampled still-water pressure is not hydrostatic within 1 %")
            ok = False

    if dim == "3d":
        # Still water in the first record: per face, and per voxel against the mean over its faces.
        folder = os.path.join(case, "postProcessing", "armourSurfaces")
        first = min(os.listdir(folder), key=float)
        raw = os.path.join(folder, first, "p_units.raw")
        if not os.path.isfile(raw):
            print(f"FAIL: no {raw}: foam-proxy dict should write the surfaces as raw (double) text")
            return 1
        centres, pf = read_raw(raw)
        hydro = rho * grav * (swl - centres[:, 2])
        voxel = bin_faces(centres, g)
        face_err = float(np.max(np.abs(pf[:, 0] - hydro) / hydro))
        counts = np.bincount(voxel[voxel >= 0], minlength=nx * nz)
        mean_hydro = np.bincount(voxel[voxel >= 0], weights=hydro[voxel >= 0], minlength=nx * nz)
        has = counts > 0
        mean_hydro[has] /= counts[has]
        vox_err = relative(p_off[0].ravel()[has], mean_hydro[has], 0.0)
        print(f"first record t = {off['time'][0]:.3f} s (surfaces output {first}): {len(hydro)} unit faces, "
              f"{int((voxel >= 0).sum())} in the grid, {int(has.sum())} voxels; max |p - rho g (SWL - z)| / "
              f"rho g (SWL - z): {face_err:.3e} per face, {vox_err:.3e} per voxel mean (limit {TOL_HYDRO})")
        if not has.any() or face_err > TOL_HYDRO or not vox_err <= TOL_HYDRO:
            print("FAIL: the sampled still-water pressure on the unit faces is not hydrostatic within 1 %")
            ok = False
        if not np.array_equal(counts, off["samples"].astype(int)):
            print(f"FAIL: faces per voxel in the storm file {off['samples'].astype(int).tolist()} differ from the "
                  f"binning of the face centres {counts.tolist()}")
            ok = False

    if sampler:
        names = ["time", "p", "u", "w", "alpha", "eta", "samples"]
        if dim == "3d":
            names += ["weibull_shape", "weibull_scale"]
        on = ncdump(online, names)
        offv = ncdump(offline, names)
        if on["dims"]["time"] != nt or not np.array_equal(on["time"], offv["time"]):
            print(f"FAIL: online storm file has {on['dims']['time']} records, offline {nt}, or other times")
            return 1
        if not np.array_equal(on["samples"], offv["samples"]):
            print(f"FAIL: faces per voxel differ: online {on['samples'].astype(int).tolist()}, offline "
                  f"{offv['samples'].astype(int).tolist()}")
            ok = False
        both = np.tile((on["samples"] > 0) & (offv["samples"] > 0), nt)
        floors = {"p": rho * grav * g["dz"], "u": 1e-3, "w": 1e-3, "alpha": 1.0}  # p: near p = 0; m/s; -
        worst = {}
        for name, floor in floors.items():
            worst[name] = relative(on[name][both], offv[name][both], floor)
        worst["eta"] = float(np.max(np.abs(on["eta"] - offv["eta"])) / max(g["dz"], 1e-12))  # of a voxel height
        if dim == "3d":
            worst["weibull"] = max(relative(on["weibull_shape"], offv["weibull_shape"], 1e-12),
                                   relative(on["weibull_scale"], offv["weibull_scale"], 1e-12))
        print(f"online vs offline: {int(both.sum() // nt)} voxels x {nt} records, max relative differences " +
              ", ".join(f"{k} {v:.3e}" for k, v in worst.items()) + f" (limit {TOL_ONLINE})")
        if not all(v <= TOL_ONLINE for v in worst.values()):
            print("FAIL: online and offline storm files differ")
            ok = False

    print("PASS" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
