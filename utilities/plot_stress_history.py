#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plot the extreme stresses of a deformable run over time (issue 26; `armour deform`).

    plot_stress_history.py STRESS_HISTORY.csv OUT.png [--title TEXT] [--reference NAME=MPa ...]
                           [--strength MPa] [--ms]

Reads the stress_history.csv that `armour deform` writes (time_s, then for tension, differential
and von_mises: value_Pa, element, x_m, y_m, z_m; docs/deformable-file.md) and plots the largest
principal tension sigma_1 (tension positive), the largest differential stress sigma_1 - sigma_3
and the largest von Mises stress against time, in MPa. --reference draws horizontal lines for
published values (e.g. --reference "seed 002 sigma_1=3.89" "seed 002 sigma_1 - sigma_3=9.35");
--strength draws the concrete's tensile strength (e.g. 3.5); --ms puts time in milliseconds.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"plot_stress_history: {path}: no samples (is it a stress_history.csv from armour deform?)")
    for key in ("time_s", "tension_Pa", "differential_Pa", "von_mises_Pa"):
        if key not in rows[0]:
            sys.exit(f"plot_stress_history: {path}: no column {key}; give the stress_history.csv armour deform wrote")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    ap.add_argument("--reference", nargs="*", default=[], help="NAME=MPa: a published value as a horizontal line")
    ap.add_argument("--strength", type=float, default=0.0, help="tensile strength (MPa), drawn dashed")
    ap.add_argument("--ms", action="store_true", help="time in milliseconds")
    args = ap.parse_args()
    rows = read(args.csv)
    scale = 1e3 if args.ms else 1.0
    t = [float(r["time_s"]) * scale for r in rows]
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for key, label, colour in (("tension_Pa", "largest $\\sigma_1$ (tension)", "tab:red"),
                               ("differential_Pa", "largest $\\sigma_1 - \\sigma_3$", "tab:blue"),
                               ("von_mises_Pa", "largest von Mises", "tab:grey")):
        ax.plot(t, [float(r[key]) / 1e6 for r in rows], label=label, color=colour, lw=1.2)
    styles = ["-.", ":", "--"]
    for i, ref in enumerate(args.reference):
        name, _, value = ref.rpartition("=")
        ax.axhline(float(value), color="k", ls=styles[i % len(styles)], lw=0.9, label=f"{name}: {float(value):g} MPa")
    if args.strength > 0:
        ax.axhline(args.strength, color="tab:orange", ls="--", lw=1.0, label=f"tensile strength {args.strength:g} MPa")
    ax.set_xlabel("time (ms)" if args.ms else "time (s)")
    ax.set_ylabel("stress (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    if args.title:
        ax.set_title(args.title, fontsize=10)
    fig.tight_layout()
    fig.savefig(args.png, dpi=120)
    print(f"plot_stress_history: wrote {args.png}")


if __name__ == "__main__":
    main()
