#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""JONSWAP irregular sea -> OpenFOAM v1912 irregularMultiDirectional wave components.

The sea is a sum of linear components with deterministic amplitudes and seeded random phases
(the "deterministic spectral amplitude" method):

    eta(t) = sum_i a_i cos(-2 pi f_i t + phi_i),   a_i = sqrt(2 S(f_i) df),   H_i = 2 a_i

on the frequency grid f_i = i df with df = 1/duration, so the signal repeats after `duration`
seconds and every component falls exactly on a bin of the FFT of a record of that length (that is
why the test can demand Tp within one bin). OpenFOAM's irregularMultiDirectional model evaluates
eta = sum_i H_i/2 cos(k_i x - omega_i t + phase_i) at the paddle (x = 0), i.e. the same sum.

JONSWAP spectral shape (Hasselmann et al. 1973; the Goda (1988) form scaled to Hs):

    S(f) = C f^-5 exp(-5/4 (fp/f)^4) gamma^r,  r = exp(-(f - fp)^2 / (2 sigma^2 fp^2)),
    sigma = 0.07 (f <= fp), 0.09 (f > fp),

with C chosen numerically so that the discrete components carry m0 = sum S df = Hs^2/16 exactly
(Hm0 = 4 sqrt(m0) = Hs), i.e. the truncation of the tails to [fmin, fmax] is compensated.

Units: Hs (m), Tp (s), duration (s), frequencies (Hz), phases (rad), directions (degree).
"""

import argparse
import json
import math
import sys

import numpy as np


def jonswap_shape(f, fp, gamma):
    """Unscaled JONSWAP spectral shape at frequencies f (Hz) for peak fp (Hz), peak factor gamma."""
    f = np.asarray(f, dtype=float)
    sigma = np.where(f <= fp, 0.07, 0.09)
    r = np.exp(-((f - fp) ** 2) / (2.0 * sigma**2 * fp**2))
    with np.errstate(divide="ignore", over="ignore"):
        s = f**-5.0 * np.exp(-1.25 * (fp / f) ** 4) * gamma**r
    return np.where(f > 0.0, s, 0.0)


def check_params(Hs, Tp, gamma, duration, fmin_factor, fmax_factor):
    """Refuse nonsensical sea-state parameters with a message that names the bad value."""
    if not (Hs > 0.0):
        raise ValueError(f"jonswap: Hs = {Hs} m: the significant wave height must be positive")
    if not (Tp > 0.0):
        raise ValueError(f"jonswap: Tp = {Tp} s: the peak period must be positive")
    if not (1.0 <= gamma <= 20.0):
        raise ValueError(f"jonswap: gamma = {gamma}: the peak enhancement factor must be in [1, 20] "
                         "(3.3 is the JONSWAP mean)")
    if not (duration >= 10.0 * Tp):
        raise ValueError(f"jonswap: duration = {duration} s: it sets the frequency resolution 1/duration; "
                         f"use at least 10 Tp = {10 * Tp} s so the peak is resolved")
    if not (0.0 < fmin_factor < 1.0 < fmax_factor):
        raise ValueError(f"jonswap: fmin_factor = {fmin_factor}, fmax_factor = {fmax_factor}: need "
                         "0 < fmin_factor < 1 < fmax_factor (multiples of the peak frequency)")


def components(Hs, Tp, gamma=3.3, duration=1800.0, seed=1, fmin_factor=0.5, fmax_factor=3.0):
    """Components of a JONSWAP sea: dict with f (Hz), period (s), height H = 2a (m), phase (rad).

    Seeded (numpy PCG64 default_rng(seed)): the same arguments give the same components.
    """
    check_params(Hs, Tp, gamma, duration, fmin_factor, fmax_factor)
    fp = 1.0 / Tp
    df = 1.0 / duration
    i0 = max(1, int(math.ceil(fmin_factor * fp / df)))
    i1 = int(math.floor(fmax_factor * fp / df))
    f = np.arange(i0, i1 + 1) * df
    shape = jonswap_shape(f, fp, gamma)
    m0 = Hs**2 / 16.0
    S = shape * m0 / (np.sum(shape) * df)  # (m^2/Hz) scaled so sum S df = Hs^2/16
    a = np.sqrt(2.0 * S * df)
    rng = np.random.default_rng(seed)
    phase = rng.uniform(0.0, 2.0 * np.pi, size=f.size)
    return {"f": f, "period": 1.0 / f, "height": 2.0 * a, "phase": phase, "df": df, "S": S}


def surface_elevation(comp, t):
    """Linear superposition eta(t) (m) at the paddle x = 0, as OpenFOAM evaluates it (no ramp)."""
    t = np.asarray(t, dtype=float)
    omega = 2.0 * np.pi * comp["f"]
    eta = np.zeros_like(t)
    for Hi, wi, pi in zip(comp["height"], omega, comp["phase"]):
        eta += 0.5 * Hi * np.cos(-wi * t + pi)
    return eta


def spectrum_of_record(eta, dt):
    """One-sided periodogram (m^2/Hz) of a record eta sampled every dt (s): returns f, S."""
    n = len(eta)
    X = np.fft.rfft(eta - np.mean(eta))
    S = (np.abs(X) ** 2) * 2.0 * dt / n
    S[0] *= 0.5
    if n % 2 == 0:
        S[-1] *= 0.5
    f = np.fft.rfftfreq(n, dt)
    return f, S


def foam_entries(comp, direction=0.0):
    """The four irregularMultiDirectional lists (one direction per frequency) as OpenFOAM text."""
    def lst(values, fmt):
        rows = "\n".join("    (" + fmt.format(v) + ")" for v in values)
        return f"{len(values)}\n(\n{rows}\n)"
    return {
        "wavePeriods": lst(comp["period"], "{:.10g}"),
        "waveHeights": lst(comp["height"], "{:.10g}"),
        "wavePhases": lst(comp["phase"], "{:.10g}"),
        "waveDirs": lst(np.full(comp["f"].size, direction), "{:.6g}"),
    }


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--Hs", type=float, required=True, help="significant wave height Hm0 (m)")
    p.add_argument("--Tp", type=float, required=True, help="peak period (s)")
    p.add_argument("--gamma", type=float, default=3.3, help="peak enhancement factor (-)")
    p.add_argument("--duration", type=float, default=1800.0, help="repeat period = 1/df (s)")
    p.add_argument("--seed", type=int, default=1, help="seed of the random phases")
    p.add_argument("--fmin-factor", type=float, default=0.5, help="lowest frequency / fp (-)")
    p.add_argument("--fmax-factor", type=float, default=3.0, help="highest frequency / fp (-)")
    p.add_argument("--direction", type=float, default=0.0, help="wave direction from +x (degree)")
    p.add_argument("--format", choices=["foam", "json"], default="foam",
                   help="foam: the four lists as waveProperties entries; json: plain arrays")
    p.add_argument("-o", "--output", default="-", help="output file (default stdout)")
    a = p.parse_args(argv)
    try:
        comp = components(a.Hs, a.Tp, a.gamma, a.duration, a.seed, a.fmin_factor, a.fmax_factor)
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if a.format == "foam":
        text = "".join(f"{k}\n{v};\n\n" for k, v in foam_entries(comp, a.direction).items())
    else:
        text = json.dumps({k: (v.tolist() if hasattr(v, "tolist") else v) for k, v in comp.items()},
                          indent=1) + "\n"
    if a.output == "-":
        sys.stdout.write(text)
    else:
        with open(a.output + ".partial", "w") as fh:
            fh.write(text)
        import os
        os.replace(a.output + ".partial", a.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
