#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Example 01, run and checked: `run.sh [ARMOUR] [OUT]` (defaults: armour on the PATH, ./out).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../setup.sh" "$@"   # $armour, and $out made and entered
cp "$here/block-on-a-slope.yaml" ./
"$armour" --log-level warn run block-on-a-slope.yaml
# Distance travelled along the face in 1 s: 0 for "sticks", a t^2 / 2 = 0.8775 m for "slides".
/usr/bin/python3 - <<'PY'
import csv, math
rows = {r["name"]: r for r in csv.DictReader(open("block-on-a-slope-out/final_state.csv"))}
start = {"sticks": (7.776348, 4.447303), "slides": (7.776348, 4.447303)}
g, tan = 9.81, 0.5
sin, cos = tan / math.hypot(1, tan), 1 / math.hypot(1, tan)
for name, mu in (("sticks", 0.75), ("slides", 0.3)):
    x, z = float(rows[name]["x"]), float(rows[name]["z"])
    along = -((x - start[name][0]) * cos + (z - start[name][1]) * sin)  # down the face, m
    expected = 0.0 if mu > tan else 0.5 * g * (sin - mu * cos) * 1.0**2
    print(f"{name:7s} friction {mu}: moved {along:.4f} m down the face, expected {expected:.4f} m")
    # At rest to 1 mm (the 0.1 mm drop onto the face and the contact's give), or the slide to 1 %.
    tolerance = 0.001 if mu > tan else 0.01 * expected
    assert abs(along - expected) <= tolerance, (name, along, expected)
PY
echo "example 01: OK (frames in $out/block-on-a-slope-out/bodies.pvd)"
