#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The generator and the run script fail loudly.

  * make_case.py refuses a bad parameter with exit code 2 and a message naming the key and value;
  * `run` on a case whose blockMeshDict is broken exits non-zero and shows the FOAM FATAL ERROR.

    test_run_fails.py OUTPUT_DIR
"""
import os
import subprocess
import sys

import smokelib


def main():
    ok = True
    out = os.path.join(sys.argv[1], "nwt2d-broken")
    gen = [sys.executable, os.path.join(smokelib.CASES, "tools", "make_case.py"),
           os.path.join(smokelib.CASES, "nwt2d", "still.json"), "-o", out]
    res = subprocess.run(gen + ["--set", "tank.depth=12.1"], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    print(res.stdout.strip())
    if res.returncode != 2 or "tank.depth" not in res.stdout or "12.1" not in res.stdout:
        print("FAIL: a depth off the cell faces must be refused naming tank.depth = 12.1")
        ok = False
    subprocess.run(gen, check=True)
    bmd = os.path.join(out, "system", "blockMeshDict")
    with open(bmd) as fh:
        text = fh.read()
    with open(bmd, "w") as fh:
        fh.write(text.replace("hex (0 1 2 3 4 5 6 7)", "hex (0 1 2 3 4 5 6 9)"))  # vertex 9: absent
    res = subprocess.run([os.path.join(out, "run")], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True)
    print(res.stdout.strip()[-1500:])
    if res.returncode == 0 or "FOAM FATAL" not in res.stdout or "blockMesh" not in res.stdout:
        print("FAIL: a broken blockMeshDict must make `run` exit non-zero showing the FOAM FATAL ERROR")
        ok = False
    print("PASS" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
