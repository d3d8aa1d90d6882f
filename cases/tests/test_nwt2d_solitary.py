#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The 2D solitary smoke case (cases/nwt2d/smoke.json).

  serial OUTPUT_DIR    run serial; the maximum surface elevation at the gauge 5 m from the inlet
                       is within 5 % of the target height (issue 6: Boussinesq generation on a
                       coarse mesh, dz = H/12; numerical damping over 5 m is about 1-2 %).
  parallel OUTPUT_DIR  run the same case with mpirun -np 2 (needs the corrected libwaveModels.so
                       of scripts/openfoam-sdk: Debian's crashes in parallel with solitary waves;
                       skipped with exit code 77 if absent) and compare the peak horizontal force
                       on the structure (crown wall + porous drag) with the serial run: within 1 %
                       (the decomposition only changes the linear-solver round-off order).
"""
import os
import sys

import numpy as np

import smokelib

GAUGE_X = 5.0   # (m) from the inlet
TOL_H = 0.05    # relative, issue 6
TOL_F = 0.01    # relative, issue 6


def peak_force(case):
    t, f = smokelib.analyse.read_forces(case)
    i = int(np.argmax(f[:, 0]))
    return f[i, 0], t[i]


def serial(root):
    case = os.path.join(root, "nwt2d-smoke-serial")
    smokelib.generate("nwt2d/smoke.json", case)
    wall = smokelib.run(case)
    info = smokelib.analyse.case_info(case)
    H = info["params"]["wave"]["height"]
    t, eta = smokelib.analyse.gauge_elevations(case)[GAUGE_X]
    hmax = float(eta.max())
    err = abs(hmax - H) / H
    fx, tf = peak_force(case)
    print(f"gauge x = {GAUGE_X} m: max eta = {hmax:.4f} m at t = {t[np.argmax(eta)]:.2f} s, "
          f"target H = {H} m, error {100 * err:.2f} % (limit {100 * TOL_H:.0f} %)")
    print(f"peak structure force Fx = {fx:.6g} N at t = {tf:.2f} s; wall time {wall:.1f} s")
    if err > TOL_H:
        print("FAIL: solitary wave height at the gauge is off by more than 5 %")
        return 1
    print("PASS")
    return 0


def parallel(root):
    lib = smokelib.sdk_wave_library()
    if lib is None:
        print("SKIP: the corrected libwaveModels.so (scripts/openfoam-sdk) is absent; Debian's "
              "crashes in parallel solitary runs, so the serial-vs-mpirun comparison cannot run. "
              "Build it with scripts/openfoam-sdk and rerun.")
        return smokelib.SKIP
    ref = os.path.join(root, "nwt2d-smoke-serial")
    if not os.path.isdir(os.path.join(ref, "postProcessing")):
        smokelib.generate("nwt2d/smoke.json", ref)
        smokelib.run(ref)
    case = os.path.join(root, "nwt2d-smoke-np2")
    smokelib.generate("nwt2d/smoke.json", case)
    wall = smokelib.run(case, np=2)
    f1, t1 = peak_force(ref)
    f2, t2 = peak_force(case)
    rel = abs(f2 - f1) / abs(f1)
    print(f"peak Fx serial {f1:.6g} N (t = {t1:.2f} s), np 2 {f2:.6g} N (t = {t2:.2f} s): "
          f"difference {100 * rel:.4f} % (limit {100 * TOL_F:.0f} %); parallel wall time {wall:.1f} s; "
          f"library {lib}")
    if rel > TOL_F:
        print("FAIL: serial and parallel peak forces differ by more than 1 %")
        return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in ("serial", "parallel"):
        print(__doc__)
        sys.exit(2)
    sys.exit(serial(sys.argv[2]) if sys.argv[1] == "serial" else parallel(sys.argv[2]))
