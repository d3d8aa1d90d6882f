#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plot the per-unit measures of a pack (issue 5; docs/theory.md section 14, "Pack measures").

    plot_pack.py UNITS.csv OUTDIR [--prefix NAME] [--title TEXT]

Reads one row per unit from UNITS.csv (written by `armour analyse`; lines starting with '#' are
comments) and writes PNGs into OUTDIR, named NAME_<plot>.png (NAME defaults to the CSV's stem):

  stereonet        equal-area (Schmidt) lower-hemisphere net of the units' nose axes, referenced
                   to the average slope plane and the trunk axis (seed 000 Fig. 2c)
  contacts         the units on the slope face coloured by contact number and by maximum contact
                   force (seed 000 Fig. 2a, b)
  contact_hist     histogram of the contact number
  displacement     displacement vectors coloured by displacement / Dn (seed 000 Figs. 7-8, 10-11)
  displacement_hist  histogram of displacement / Dn with the 0.2, 0.5 and 1 Dn marks

A plot is written when its columns are present. Columns (header names; units in brackets):

  unit                  unit name or index (a label)                            required
  x, y, z               centroid in the world frame (m): x onshore, y along the trunk, z up;
                        with displacement columns, the final state's
  s, t                  centroid in the slope frame (m): up-slope and along the trunk (= y);
                        when absent the face views use x and y (a plan view)
  dn                    nominal diameter (m); draws each unit as a disc of diameter dn
  dip_deg               nose-axis dip below the slope plane, [0, 90] (deg)
  dip_azimuth_deg       in the slope plane from the trunk axis towards down-slope, [0, 360) (deg)
  stereo_x, stereo_y    Schmidt-net point in the unit disc (-); computed from dip and azimuth
                        when absent, as analysis::stereonetPoint does
  contact_number        distinct bodies touched, units and supports (-)
  max_contact_force_N   largest pair force on the unit (N)
  disp_s, disp_t        displacement along the slope frame's s and t (m); or disp_x, disp_y
  displacement_dn       |displacement| / Dn (-)
  rotation_deg          rotation between the two states (deg)

Views of the slope face are drawn as seen by someone offshore facing the slope: up-slope at the
top, the trunk axis +y (t) to the left, as the stereonet. Runs headless (Agg backend). Needs
python3-numpy and python3-matplotlib (Debian).
"""
import argparse
import csv
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402


def read_units(path):
    """Columns of the CSV as float arrays, by header name; raises SystemExit naming bad cells."""
    with open(path, newline="") as f:
        lines = [line for line in f if line.strip() and not line.lstrip().startswith("#")]
    reader = csv.DictReader(lines)
    if reader.fieldnames is None or "unit" not in [n.strip() for n in reader.fieldnames]:
        sys.exit(f"{path}: no header with a 'unit' column; see plot_pack.py --help for the columns")
    rows = list(reader)
    if not rows:
        sys.exit(f"{path}: no unit rows")
    columns = {}
    for name in reader.fieldnames:
        key = name.strip()
        values = []
        for i, row in enumerate(rows):
            cell = (row[name] or "").strip()
            try:
                values.append(float(cell) if cell != "" else math.nan)
            except ValueError:
                if key in ("name", "shape", "unit"):  # labels (armour analyse names units)
                    values = None
                    break
                sys.exit(f"{path}: row {i + 2}, column '{key}': '{cell}' is not a number")
        if values is not None:
            columns[key] = np.asarray(values)
    return columns


def has(cols, *names):
    return all(n in cols and np.isfinite(cols[n]).any() for n in names)


def schmidt(dip_deg, azimuth_deg):
    """Equal-area lower-hemisphere point (X, Y) of analysis::stereonetPoint: up-slope at the top,
    +t on the left, radius sqrt(2) sin((90 - dip) / 2)."""
    theta = np.radians(90.0 - dip_deg)
    r = math.sqrt(2.0) * np.sin(0.5 * theta)
    b = np.radians(azimuth_deg)
    return -r * np.cos(b), -r * np.sin(b)


def face_coordinates(cols):
    """Horizontal and vertical plot coordinates of the slope-face views, and axis labels."""
    if has(cols, "s", "t"):
        return cols["t"], cols["s"], "t (m, along the trunk)", "s (m, up-slope)"
    return cols["y"], cols["x"], "y (m, along the trunk)", "x (m, onshore)"


def draw_units(ax, h, v, cols, values, cmap, norm, label):
    """Units as discs of diameter dn (or points), coloured by `values`."""
    if has(cols, "dn"):
        patches = [Circle((a, b), 0.5 * d) for a, b, d in zip(h, v, cols["dn"])]
        pc = PatchCollection(patches, cmap=cmap, norm=norm, edgecolor="k", linewidth=0.3)
        pc.set_array(values)
        ax.add_collection(pc)
        mappable = pc
        pad = np.nanmax(cols["dn"])
    else:
        mappable = ax.scatter(h, v, c=values, cmap=cmap, norm=norm, s=30, edgecolor="k", linewidth=0.3)
        pad = 0.0
    ax.set_xlim(np.nanmax(h) + pad, np.nanmin(h) - pad)  # +t to the left: seen from the sea
    ax.set_ylim(np.nanmin(v) - pad, np.nanmax(v) + pad)
    ax.set_aspect("equal")
    plt.colorbar(mappable, ax=ax, label=label, shrink=0.8)


def plot_stereonet(cols, out, title):
    if has(cols, "stereo_x", "stereo_y"):
        sx, sy = cols["stereo_x"], cols["stereo_y"]
    else:
        sx, sy = schmidt(cols["dip_deg"], cols["dip_azimuth_deg"])
    fig, ax = plt.subplots(figsize=(6.4, 6.4))
    phi = np.linspace(0.0, 2.0 * math.pi, 361)
    # Net: small circles of equal dip every 10 deg and azimuth spokes every 30 deg.
    for dip in range(10, 90, 10):
        r = math.sqrt(2.0) * math.sin(math.radians(90 - dip) / 2.0)
        ax.plot(r * np.cos(phi), r * np.sin(phi), color="0.8", lw=0.6)
    for az in range(0, 360, 30):
        x, y = schmidt(np.array([0.0, 90.0]), np.array([az, az]))
        ax.plot(x, y, color="0.8", lw=0.6)
    ax.plot(np.cos(phi), np.sin(phi), color="k", lw=1.2)
    ax.plot(sx, sy, "o", ms=4, mfc="tab:red", mec="k", mew=0.3, alpha=0.8)
    ax.text(0.0, 1.05, "up-slope (270\u00b0)", ha="center", va="bottom")
    ax.text(0.0, -1.05, "down-slope (90\u00b0)", ha="center", va="top")
    ax.text(-1.05, 0.0, "+t\n(+y)\n0\u00b0", ha="right", va="center")
    ax.text(1.05, 0.0, "\u2212t\n(\u2212y)\n180\u00b0", ha="left", va="center")
    ax.set_xlim(-1.35, 1.35)
    ax.set_ylim(-1.3, 1.3)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(f"{title}: nose axes, equal-area lower hemisphere (N = {np.isfinite(sx).sum()})\n"
                 "referenced to the slope plane; centre = normal to the slope; rings every 10\u00b0 of dip",
                 fontsize=9)
    fig.savefig(out, dpi=150, bbox_inches="tight")
    plt.close(fig)


def plot_contacts(cols, out, title):
    h, v, hl, vl = face_coordinates(cols)
    panels = [c for c in ("contact_number", "max_contact_force_N") if has(cols, c)]
    fig, axes = plt.subplots(1, len(panels), figsize=(6.0 * len(panels), 6.0), squeeze=False)
    for ax, c in zip(axes[0], panels):
        if c == "contact_number":
            values = cols[c]
            lo, hi = int(np.nanmin(values)), int(np.nanmax(values))
            cmap = plt.get_cmap("viridis", hi - lo + 1)
            norm = matplotlib.colors.Normalize(lo - 0.5, hi + 0.5)
            draw_units(ax, h, v, cols, values, cmap, norm, "contact number (-)")
            ax.set_title("contact number (seed 000 Fig. 2b)")
        else:
            values = cols[c] / 1e3
            norm = matplotlib.colors.Normalize(0.0, np.nanmax(values) if np.nanmax(values) > 0 else 1.0)
            draw_units(ax, h, v, cols, values, plt.get_cmap("inferno_r"), norm, "max contact force (kN)")
            ax.set_title("maximum contact force (seed 000 Fig. 2a)")
        ax.set_xlabel(hl + ", seen from the sea")
        ax.set_ylabel(vl)
    fig.suptitle(title)
    fig.savefig(out, dpi=150, bbox_inches="tight")
    plt.close(fig)


def plot_contact_hist(cols, out, title):
    values = cols["contact_number"][np.isfinite(cols["contact_number"])].astype(int)
    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    bins = np.arange(values.min() - 0.5, values.max() + 1.5)
    ax.hist(values, bins=bins, color="tab:blue", edgecolor="k")
    ax.set_xlabel("contact number (-)")
    ax.set_ylabel("units")
    ax.set_title(f"{title}: contact number, mean {values.mean():.2f} (N = {values.size})")
    fig.savefig(out, dpi=150, bbox_inches="tight")
    plt.close(fig)


def plot_displacement(cols, out, title):
    h, v, hl, vl = face_coordinates(cols)
    if has(cols, "disp_s", "disp_t") and has(cols, "s", "t"):
        dh, dv = cols["disp_t"], cols["disp_s"]
    elif has(cols, "disp_x", "disp_y") and not has(cols, "s", "t"):
        dh, dv = cols["disp_y"], cols["disp_x"]
    else:
        return False
    fig, ax = plt.subplots(figsize=(7.0, 6.5))
    if has(cols, "dn"):
        ax.add_collection(PatchCollection([Circle((a, b), 0.5 * d) for a, b, d in zip(h, v, cols["dn"])],
                                          facecolor="0.92", edgecolor="0.6", linewidth=0.3))
        pad = np.nanmax(cols["dn"])
    else:
        pad = 0.0
    # Arrows from the initial centroid to the final one (the centroid columns are the final state).
    q = ax.quiver(h - dh, v - dv, dh, dv, cols["displacement_dn"], cmap="plasma", angles="xy", scale_units="xy",
                  scale=1.0, width=0.004)
    plt.colorbar(q, ax=ax, label="displacement / Dn (-)", shrink=0.8)
    ax.set_xlim(max(np.nanmax(h), np.nanmax(h - dh)) + pad, min(np.nanmin(h), np.nanmin(h - dh)) - pad)
    ax.set_ylim(min(np.nanmin(v), np.nanmin(v - dv)) - pad, max(np.nanmax(v), np.nanmax(v - dv)) + pad)
    ax.set_aspect("equal")
    ax.set_xlabel(hl + ", seen from the sea")
    ax.set_ylabel(vl)
    ax.set_title(f"{title}: displacement vectors (true scale), max {np.nanmax(cols['displacement_dn']):.2f} Dn")
    fig.savefig(out, dpi=150, bbox_inches="tight")
    plt.close(fig)
    return True


def plot_displacement_hist(cols, out, title):
    values = cols["displacement_dn"][np.isfinite(cols["displacement_dn"])]
    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    ax.hist(values, bins=max(10, int(math.sqrt(values.size))), color="tab:orange", edgecolor="k")
    for mark in (0.2, 0.5, 1.0):
        moved = int((values > mark).sum())
        ax.axvline(mark, color="k", ls="--", lw=0.8)
        ax.text(mark, ax.get_ylim()[1] * 0.95, f" >{mark:g} Dn: {moved}", rotation=90, va="top", fontsize=8)
    ax.set_xlabel("displacement / Dn (-)")
    ax.set_ylabel("units")
    ax.set_title(f"{title}: displacement, mean {values.mean():.3f} Dn (N = {values.size})")
    fig.savefig(out, dpi=150, bbox_inches="tight")
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", help="per-unit measures (CSV)")
    parser.add_argument("outdir", help="directory for the PNGs (created)")
    parser.add_argument("--prefix", default=None, help="file-name prefix (default: the CSV's stem)")
    parser.add_argument("--title", default=None, help="plot title (default: the prefix)")
    args = parser.parse_args()
    cols = read_units(args.csv)
    prefix = args.prefix or Path(args.csv).stem
    title = args.title or prefix
    outdir = Path(args.outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    written = []

    def out(name):
        return outdir / f"{prefix}_{name}.png"

    have_face = has(cols, "s", "t") or has(cols, "x", "y")
    if has(cols, "stereo_x", "stereo_y") or has(cols, "dip_deg", "dip_azimuth_deg"):
        plot_stereonet(cols, out("stereonet"), title)
        written.append(out("stereonet"))
    if have_face and (has(cols, "contact_number") or has(cols, "max_contact_force_N")):
        plot_contacts(cols, out("contacts"), title)
        written.append(out("contacts"))
    if has(cols, "contact_number"):
        plot_contact_hist(cols, out("contact_hist"), title)
        written.append(out("contact_hist"))
    if have_face and has(cols, "displacement_dn") and plot_displacement(cols, out("displacement"), title):
        written.append(out("displacement"))
    if has(cols, "displacement_dn"):
        plot_displacement_hist(cols, out("displacement_hist"), title)
        written.append(out("displacement_hist"))
    if not written:
        sys.exit(f"{args.csv}: none of the plots' columns are present; see plot_pack.py --help")
    for w in written:
        print(w)


if __name__ == "__main__":
    main()
