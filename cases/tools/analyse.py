#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Read the sampled output of a wave-tank case (probes, forces) written by make_case.py's
function objects.

    analyse.py CASE_DIR            summary: gauge maxima, peak structure force, still-water error
"""

import json
import os
import re
import sys

import numpy as np

_NUM = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _time_dirs(case, fo):
    base = os.path.join(case, "postProcessing", fo)
    if not os.path.isdir(base):
        raise FileNotFoundError(f"{base}: no output of function object '{fo}' (did the run finish?)")
    return [os.path.join(base, d) for d in sorted(os.listdir(base), key=float)]


def read_probes(case, fo, field):
    """(t, values[n_t, n_probes], locations[n_probes, 3]) of a probes function object (all restarts)."""
    ts, vals, locs = [], [], []
    for d in _time_dirs(case, fo):
        path = os.path.join(d, field)
        locs = []
        with open(path) as fh:
            for line in fh:
                if line.startswith("#"):
                    m = re.match(r"#\s*Probe\s+\d+\s*\((.*)\)", line)
                    if m:
                        locs.append([float(x) for x in m.group(1).split()])
                    continue
                nums = [float(x) for x in _NUM.findall(line)]
                if nums:
                    ts.append(nums[0])
                    vals.append(nums[1:])
    t = np.array(ts)
    v = np.array(vals)
    order = np.argsort(t, kind="stable")
    return t[order], v[order], np.array(locs)


def read_forces(case, fo="structureForces"):
    """(t, total[n_t, 3]) of a forces function object."""
    ts, tot = [], []
    for d in _time_dirs(case, fo):
        with open(os.path.join(d, "force.dat")) as fh:
            for line in fh:
                if line.startswith("#"):
                    continue
                nums = [float(x) for x in _NUM.findall(line)]
                if len(nums) >= 4:
                    ts.append(nums[0])
                    tot.append(nums[1:4])
    return np.array(ts), np.array(tot)


def case_info(case):
    with open(os.path.join(case, "case.json")) as fh:
        return json.load(fh)


def gauge_elevations(case):
    """{x: (t, eta)}: surface elevation (m above SWL) at each gauge from the alpha.water column.

    eta = sum_k alpha_k dz - h over the cells of the column (probe points at the cell centres of a
    uniform column from the bed to the top, so the sum is the exact water volume per unit area).
    """
    info = case_info(case)
    t, v, _ = read_probes(case, "gauges", "alpha.water")
    out, col = {}, 0
    for g in info["gauges"]:
        n = g["n"]
        out[g["x"]] = (t, np.sum(v[:, col:col + n], axis=1) * g["dz"] - info["swl"])
        col += n
    return out


def still_water_error(case, t_min):
    """Largest relative error |p - rho g (SWL - z)| / (rho g (SWL - z)) over the pressure probes
    below the SWL and the sampled times >= t_min; also returns the table of the last sample."""
    info = case_info(case)
    t, p, locs = read_probes(case, "pressure", "p")
    sel = t >= t_min
    if not np.any(sel):
        raise ValueError(f"{case}: no pressure samples after t = {t_min} s")
    rho, g, swl = info["rho_water"], info["g"], info["swl"]
    z = locs[:, 2]
    below = z < swl
    ref = rho * g * (swl - z[below])
    err = np.abs(p[sel][:, below] - ref) / ref
    table = list(zip(z[below], p[-1, below], ref))
    return float(err.max()), table


def main(argv):
    if len(argv) != 2:
        print(__doc__)
        return 2
    case = argv[1]
    try:
        for x, (t, eta) in gauge_elevations(case).items():
            i = int(np.argmax(eta))
            print(f"gauge x = {x} m: max eta = {eta[i]:.4f} m at t = {t[i]:.2f} s, min eta = {eta.min():.4f} m")
    except FileNotFoundError as e:
        print(e)
    try:
        t, f = read_forces(case)
        i = int(np.argmax(f[:, 0]))
        print(f"structure: peak Fx = {f[i, 0]:.6g} N at t = {t[i]:.2f} s (Fz there {f[i, 2]:.6g} N)")
    except FileNotFoundError as e:
        print(e)
    try:
        err, table = still_water_error(case, 0.0)
        print(f"still water: max relative error of p vs rho g (SWL - z): {100 * err:.3f} %")
    except FileNotFoundError:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
