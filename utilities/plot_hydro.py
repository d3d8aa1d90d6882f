#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plot a storm replay: the storm at the structure and the loads and motion of each unit.

    plot_hydro.py STORM.nc BODIES.nc OUT.png [--x X] [--offset S] [--prefix PREFIX]

Top: the free-surface elevation eta(t) at x = X (default: the middle of the storm grid) from the
storm file, on the run's time axis (storm time - offset). Middle: the hydrodynamic force on each
loaded unit (x and z components, from bodies.nc's hydro_force). Bottom: each unit's displacement
from its first recorded position. Units whose hydro force is zero throughout (dry or not loaded)
are left out of the force panel.
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import netCDF4  # noqa: E402
import numpy as np  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("storm")
    parser.add_argument("bodies")
    parser.add_argument("out")
    parser.add_argument("--x", type=float, default=None, help="x of the eta time series (m)")
    parser.add_argument("--offset", type=float, default=0.0, help="storm time at run time 0 (s): hydro.storm.time_offset")
    parser.add_argument("--prefix", default="", help="only bodies whose name starts with this")
    a = parser.parse_args()

    with netCDF4.Dataset(a.storm) as s:
        xs = np.asarray(s["x"][:])
        x = a.x if a.x is not None else 0.5 * (xs[0] + xs[-1])
        if not xs[0] <= x <= xs[-1]:
            sys.exit(f"{a.storm}: --x {x} m is outside the grid {xs[0]} .. {xs[-1]} m")
        ts = np.asarray(s["time"][:]) - a.offset
        column = int(np.argmin(np.abs(xs - x)))
        eta = np.asarray(s["eta"][:, column])
    with netCDF4.Dataset(a.bodies) as b:
        t = np.asarray(b["time"][:])
        names = [str(n).strip() for n in netCDF4.chartostring(b["body_name"][:])]
        force = np.asarray(b["hydro_force"][:])
        position = np.asarray(b["position"][:])

    keep = (ts >= t[0]) & (ts <= t[-1])
    fig, ax = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    ax[0].plot(ts[keep], eta[keep], color="tab:blue")
    ax[0].set_ylabel(f"eta at x = {xs[column]:.2f} m (m)")
    ax[0].set_title(f"storm replay: {a.storm}")
    for i, name in enumerate(names):
        if not name.startswith(a.prefix):
            continue
        moved = np.linalg.norm(position[:, i, :] - position[0, i, :], axis=1)
        ax[2].plot(t, moved, label=name)
        if np.any(force[:, i, :] != 0.0):
            (line,) = ax[1].plot(t, force[:, i, 0] / 1e3, label=f"{name} x")
            ax[1].plot(t, force[:, i, 2] / 1e3, "--", color=line.get_color(), label=f"{name} z")
    ax[1].set_ylabel("hydrodynamic force (kN)")
    ax[1].legend(fontsize="small", ncol=2)
    ax[2].set_ylabel("displacement (m)")
    ax[2].set_xlabel("run time (s)")
    ax[2].legend(fontsize="small", ncol=2)
    for axis in ax:
        axis.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
