# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared helpers of the wave-tank smoke tests: generate a case, run it, report wall time."""

import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
CASES = os.path.abspath(os.path.join(HERE, ".."))
REPO = os.path.abspath(os.path.join(CASES, ".."))
sys.path.insert(0, os.path.join(CASES, "tools"))
import analyse  # noqa: E402,F401

SKIP = 77  # CTest SKIP_RETURN_CODE


def generate(params, out, armour=None, extra=()):
    cmd = [sys.executable, os.path.join(CASES, "tools", "make_case.py"), os.path.join(CASES, params),
           "-o", out] + list(extra)
    if armour:
        cmd += ["--armour", armour]
    subprocess.run(cmd, check=True)


def run(case, np=1):
    """Run the case's `run` script; raise with its output if it fails. Returns wall time (s)."""
    cmd = [os.path.join(case, "run")] + (["-np", str(np)] if np > 1 else [])
    t0 = time.time()
    res = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.time() - t0
    print(res.stdout)
    if res.returncode != 0:
        raise SystemExit(f"FAIL: {' '.join(cmd)} exited with {res.returncode}")
    return wall


def sdk_wave_library():
    sdk = os.environ.get("ARMOUR_OPENFOAM_SDK", os.path.join(REPO, "build", "openfoam-sdk"))
    lib = os.path.join(sdk, "lib", "libwaveModels.so")
    return lib if os.path.isfile(lib) else None
