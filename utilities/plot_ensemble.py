#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Plot the spread of an ensemble (issue 9; docs/user-guide.md, "Ensembles").

    plot_ensemble.py ENSEMBLE.csv [OUT.png]

Reads the one-row-per-member table `armour ensemble` writes and draws one panel per measure:
every member as a dot (coloured by its packing, so the spread of the storm realisations on one
packing shows against the spread between packings), the mean as a line and mean +- one standard
deviation as a band, over the members that finished. With storm members, the damage measures
(storm_*) are drawn; otherwise the pack measures. OUT.png defaults to ensemble.png beside the CSV.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

LABELS = {
    "storm_moved_0.2dn": "units moved > 0.2 Dn",
    "storm_moved_0.5dn": "units moved > 0.5 Dn",
    "storm_moved_1dn": "units moved > 1 Dn",
    "storm_rocking_units": "rocking units",
    "storm_max_displacement_dn": "max displacement (Dn)",
    "storm_mean_displacement_dn": "mean displacement (Dn)",
    "storm_delta_rms_m": "delta_rms (m)",
    "storm_total_displacement_m": "total displacement (m)",
    "storm_p2_q_tensor_after": "P2 (Q tensor) after",
    "delta_rms_m": "delta_rms from release (m)",
    "p2_q_tensor": "P2 (Q tensor)",
    "packing_density": "packing density",
    "layer_thickness_m": "layer thickness (m)",
    "porosity": "porosity",
    "coordination_number": "coordination number",
    "max_displacement_dn": "max move from release (Dn)",
}


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    path = argv[1]
    out = argv[2] if len(argv) > 2 else os.path.join(os.path.dirname(os.path.abspath(path)), "ensemble.png")
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r.get("status", "done") == "done"]
    if not rows:
        sys.exit(f"{path}: no finished member to plot")
    storm = any(r.get("storm") for r in rows)
    names = [n for n in rows[0] if n in LABELS and n.startswith("storm_") == storm]
    packings = sorted({int(r.get("packing", r["member"])) for r in rows})
    colour = {p: plt.cm.tab10(i % 10) for i, p in enumerate(packings)}
    cols = 3
    lines = math.ceil(len(names) / cols)
    fig, axes = plt.subplots(lines, cols, figsize=(4.2 * cols, 2.8 * lines), squeeze=False)
    for ax, name in zip(axes.flat, names):
        values = [float(r[name]) for r in rows]
        finite = [v for v in values if math.isfinite(v)]
        for k, (r, v) in enumerate(zip(rows, values)):
            ax.plot(k, v, "o", color=colour[int(r.get("packing", r["member"]))], ms=5)
        if finite:
            mean = sum(finite) / len(finite)
            std = math.sqrt(sum((v - mean) ** 2 for v in finite) / (len(finite) - 1)) if len(finite) > 1 else 0.0
            ax.axhspan(mean - std, mean + std, color="0.85", zorder=0)
            ax.axhline(mean, color="k", lw=1)
            ax.set_title(f"{LABELS[name]}\n{mean:.3g} +- {std:.2g}", fontsize=9)
        ax.set_xlabel("member")
        ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    fig.suptitle(f"{os.path.basename(os.path.dirname(os.path.abspath(path)))}: {len(rows)} members, "
                 f"{len(packings)} packings (colour)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv)
