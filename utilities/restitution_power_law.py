#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Restitution of the penalty law on a contact whose stiffness grows with the overlap (issue 23,
item 10; docs/validation.md, "Restitution at edges and corners").

    utilities/restitution_power_law.py [--e 0.05,0.5,0.9]

The penalty law's dashpot has the damping ratio zeta of the contact's current summed stiffness K
(docs/theory.md section 6), chosen so that a contact of constant stiffness (a face) rebounds with
the material's e. At an edge the contact area, so K, grows as the overlap d, at a corner as d^2:
the force F = K d / p with p = 2 and 3 (p = 1 for a face). In units where the impact speed and
the mass are 1, the overlap y(t) obeys

    y'' + 2 zeta sqrt(p) y^((p - 1) / 2) y' + y^p = 0,   the force clamped at >= 0,

whose rebound speed does not depend on the impact speed. This prints, for each e, the zeta of
the face law and the e that the same zeta gives at an edge and at a corner. Pure Python.
"""
import argparse
import math


def rebound(zeta, p, h=2e-4):
    """Rebound speed of the unit impact (RK4 with step h) for damping ratio zeta and exponent p."""
    y, v, t = 0.0, 1.0, 0.0

    def acc(y, v):
        yy = max(y, 0.0)
        return -max(yy ** p + 2.0 * zeta * math.sqrt(p) * yy ** ((p - 1.0) / 2.0) * v, 0.0)

    while t < 200.0:
        k1y, k1v = v, acc(y, v)
        k2y, k2v = v + 0.5 * h * k1v, acc(y + 0.5 * h * k1y, v + 0.5 * h * k1v)
        k3y, k3v = v + 0.5 * h * k2v, acc(y + 0.5 * h * k2y, v + 0.5 * h * k2v)
        k4y, k4v = v + h * k3v, acc(y + h * k3y, v + h * k3v)
        y += h * (k1y + 2 * k2y + 2 * k3y + k4y) / 6.0
        v += h * (k1v + 2 * k2v + 2 * k3v + k4v) / 6.0
        t += h
        if y <= 0.0 and t > 2 * h:
            return max(-v, 0.0)
        if y > 0.0 and v < 0.0 and acc(y, v) == 0.0:  # the clamp: no force while leaving
            return -v
    return 0.0


def zeta_for(e, p):
    """The damping ratio that gives rebound e with exponent p (bisection)."""
    lo, hi = 0.0, 20.0
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if rebound(mid, p) > e:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--e", default="0.05,0.5,0.9", help="coefficients of restitution, comma-separated")
    args = parser.parse_args()
    print("| e | zeta of the face law | e at an edge (p = 2) | e at a corner (p = 3) |")
    print("|---:|---:|---:|---:|")
    for e in (float(x) for x in args.e.split(",")):
        z = zeta_for(e, 1.0)
        print(f"| {e} | {z:.4f} | {rebound(z, 2.0):.3f} | {rebound(z, 3.0):.3f} |")


if __name__ == "__main__":
    main()
