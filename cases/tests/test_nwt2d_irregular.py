#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The 2D JONSWAP smoke case (cases/nwt2d/irregular-smoke.json): OpenFOAM reads the generated
irregularMultiDirectional component lists and reproduces the sea near the paddle.

The surface elevation at the gauge 5 m from the inlet, after the ramp, is compared with the linear
superposition of the same components (the generator's model, evaluated at the gauge with the
linear dispersion relation OpenFOAM uses): the rms must agree within 15 % and the correlation must
exceed 0.8. The tolerances are loose on purpose: the seed's storm (Hs = 7 m on h = 12 m) is
strongly nonlinear (crests sharpen, troughs flatten) and the smoke mesh (dz = 0.25 m) damps the
shortest components; a wrong amplitude convention (H vs a, factor 2) or wrong phases (sign of
omega t) would fail either criterion by far.

    test_nwt2d_irregular.py OUTPUT_DIR
"""
import math
import os
import sys

import numpy as np

import smokelib
import jonswap

GAUGE_X = 5.0
TOL_RMS = 0.15
MIN_CORR = 0.8


def linear_eta(comp, x, t, h, ramp):
    g = 9.81
    eta = np.zeros_like(t)
    for H, T, ph in zip(comp["height"], comp["period"], comp["phase"]):
        L0 = g * T * T / (2 * math.pi)
        L = L0
        for _ in range(100):  # the fixed-point iteration OpenFOAM uses for the wave length
            L = L0 * math.tanh(2 * math.pi * h / L)
        eta += 0.5 * H * np.cos(2 * math.pi / L * x - 2 * math.pi / T * t + ph)
    return eta * np.clip(t / ramp, 0.0, 1.0)


def main():
    case = os.path.join(sys.argv[1], "nwt2d-irregular-smoke")
    smokelib.generate("nwt2d/irregular-smoke.json", case)
    wall = smokelib.run(case)
    info = smokelib.analyse.case_info(case)
    w = info["params"]["wave"]
    comp = jonswap.components(w["Hs"], w["Tp"], w["gamma"], w["duration"], w["seed"],
                              w["fmin_factor"], w["fmax_factor"])
    t, eta = smokelib.analyse.gauge_elevations(case)[GAUGE_X]
    x_cell = [g["x_cell"] for g in info["gauges"] if g["x"] == GAUGE_X][0]
    ref = linear_eta(comp, x_cell, t, info["swl"], w["ramp_time"])
    sel = t >= w["ramp_time"] + 2.0
    rms, rms_ref = float(np.std(eta[sel])), float(np.std(ref[sel]))
    corr = float(np.corrcoef(eta[sel], ref[sel])[0, 1])
    print(f"gauge x = {x_cell} m, t in [{t[sel][0]:.1f}, {t[sel][-1]:.1f}] s: rms OpenFOAM {rms:.3f} m, "
          f"linear {rms_ref:.3f} m (ratio {rms / rms_ref:.3f}), correlation {corr:.3f}; wall time {wall:.1f} s")
    ok = abs(rms / rms_ref - 1.0) <= TOL_RMS and corr >= MIN_CORR
    print("PASS" if ok else "FAIL: the generated sea at the gauge does not match its components")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
