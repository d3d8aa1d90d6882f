#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Still-water tank (cases/nwt2d/still.json): after start-up, the total pressure p in the water
equals rho g (SWL - z) within 1 % at every probe (open water, porous core and under-layer).

Why 1 % (issue 6): the initial field is exactly hydrostatic (SWL on a cell face, hRef = SWL) and
nothing should move it; a wrong hRef/pressure reference, spurious currents from the absorbing
boundaries or from the porous zones would show as errors of several percent near the surface.

    test_still_water.py OUTPUT_DIR
"""
import os
import sys

import smokelib

T_STARTUP = 1.0  # (s) samples before this are start-up and not judged


def main():
    out = os.path.join(sys.argv[1], "nwt2d-still")
    smokelib.generate("nwt2d/still.json", out)
    wall = smokelib.run(out)
    err, table = smokelib.analyse.still_water_error(out, T_STARTUP)
    for z, p, ref in table:
        print(f"  z = {z:7.3f} m: p = {p:12.2f} Pa, rho g (SWL - z) = {ref:12.2f} Pa")
    print(f"still water: max relative error {100 * err:.4f} % (limit 1 %), wall time {wall:.1f} s")
    if err > 0.01:
        print("FAIL: hydrostatic pressure off by more than 1 %")
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
