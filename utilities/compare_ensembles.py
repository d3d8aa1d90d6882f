#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Compare two `armour ensemble` tables measure by measure (docs/placement.md, "tight against loose").

    compare_ensembles.py A/ensemble.csv B/ensemble.csv [--names "tight 0.625" "loose 0.603"] [--min-s S]

Prints a markdown table: per measure, the mean +- sample standard deviation of each ensemble over
its members that finished (status "done", values not NaN), and the difference of the means over its
standard error, (mean_A - mean_B) / sqrt(sd_A^2 / n_A + sd_B^2 / n_B) (Welch's statistic): beyond
about 2 in magnitude the two ensembles differ by more than their spread explains.

With --min-s S the storm damage is measured again over the units placed at least S metres up the
slope (their placed `s`, member-*/analysis/units.csv), from each storm run's per-unit displacements
(member-*/storm-*/analysis/units.csv, displacement_dn): units past 0.2, 0.5 and 1 Dn, the largest
and the mean displacement, one value per storm run. Standard library only.
"""
import glob
import os
import argparse
import csv
import math
import sys

KEYS = ("member", "packing", "packing_seed", "storm", "storm_seed", "status")


def load(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"error: {path}: cannot read it ({e.strerror}); give the ensemble.csv of `armour ensemble`")
    if not rows or "status" not in rows[0]:
        sys.exit(f"error: {path}: not an ensemble.csv of `armour ensemble` (no rows, or no status column)")
    return [r for r in rows if r["status"] == "done"]


def stats(rows, name):
    values = []
    for r in rows:
        try:
            v = float(r[name])
        except (KeyError, ValueError):
            continue
        if math.isfinite(v):
            values.append(v)
    n = len(values)
    if n == 0:
        return math.nan, math.nan, 0
    mean = sum(values) / n
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else 0.0
    return mean, sd, n


def welch(m1, s1, n1, m2, s2, n2):
    if n1 < 2 or n2 < 2:
        return math.nan
    se = math.sqrt(s1 * s1 / n1 + s2 * s2 / n2)
    if se == 0.0:
        return 0.0 if m1 == m2 else math.copysign(math.inf, m1 - m2)
    return (m1 - m2) / se


def region_rows(csv_path, min_s):
    """One row per storm run: the damage of the units placed at least min_s up the slope."""
    folder = os.path.dirname(os.path.abspath(csv_path))
    rows = []
    for member in sorted(glob.glob(os.path.join(folder, "member-*"))):
        try:
            with open(os.path.join(member, "analysis", "units.csv"), newline="") as f:
                placed = {r["unit"]: float(r["s"]) for r in csv.DictReader(f)}
        except OSError:
            continue  # a member whose placement failed
        for run in sorted(glob.glob(os.path.join(member, "storm-*", "analysis", "units.csv"))):
            with open(run, newline="") as f:
                d = [float(r["displacement_dn"]) for r in csv.DictReader(f) if placed.get(r["unit"], -math.inf) >= min_s]
            if not d:
                sys.exit(f"error: {run}: no unit placed {min_s} m or more up the slope; give a smaller --min-s")
            rows.append({"units": len(d), "moved_0.2dn": sum(x > 0.2 for x in d), "moved_0.5dn": sum(x > 0.5 for x in d),
                         "moved_1dn": sum(x > 1.0 for x in d), "max_displacement_dn": max(d),
                         "mean_displacement_dn": sum(d) / len(d)})
    if not rows:
        sys.exit(f"error: {folder}: no storm run with an analysis (member-*/storm-*/analysis/units.csv); "
                 "--min-s needs an ensemble run with --storm")
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("--names", nargs=2, default=None, help="column titles of the two ensembles")
    p.add_argument("--min-s", type=float, default=None,
                   help="storm damage over the units placed at least this far up the slope (m)")
    o = p.parse_args()
    if o.min_s is not None:
        a, b = region_rows(o.a, o.min_s), region_rows(o.b, o.min_s)
    else:
        a, b = load(o.a), load(o.b)
    names = o.names or [o.a, o.b]
    measures = [k for k in (a or b)[0].keys() if k not in KEYS] if (a or b) else []
    if o.min_s is not None:
        print(f"storm damage over the units placed {o.min_s} m or more up the slope, one value per storm run\n")
    print(f"| measure (mean +- sd) | {names[0]} (n = {len(a)}) | {names[1]} (n = {len(b)}) | difference / its standard error |")
    print("|---|---:|---:|---:|")
    for k in measures:
        m1, s1, n1 = stats(a, k)
        m2, s2, n2 = stats(b, k)
        print(f"| {k} | {m1:.4g} +- {s1:.2g} | {m2:.4g} +- {s2:.2g} | {welch(m1, s1, n1, m2, s2, n2):+.2f} |")


if __name__ == "__main__":
    main()
