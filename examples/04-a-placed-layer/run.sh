#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Example 04, run and checked: `run.sh [ARMOUR] [OUT]` (defaults: armour on the PATH, ./out).
# Places the smoke variant of seed 000's Core-Loc trunk (cases/placement/coreloc-trunk-smoke.yaml:
# 11 units of 1 m^3 in 3 rows on 150 rocks of a 4H:3V face), measures it, and runs the placed
# scene dry for 2 s: a placed pack starts at rest.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../setup.sh" "$@"   # $armour, and $out made and entered
cp "$here/../../cases/placement/coreloc-trunk-smoke.yaml" ./layer.yaml
"$armour" --log-level warn place layer.yaml --set contact.solver=constraint
cat layer-out/placement.txt
"$armour" --log-level warn analyse layer-placed.yaml --output analysis
"$armour" --log-level warn run layer-placed.yaml --duration 2 -o dry
# The pack as placed is at rest: 2 s of running moves no unit by 1 mm.
/usr/bin/python3 - <<'PY'
import csv, math
start = {r["unit"]: (float(r["x_m"]), float(r["y_m"]), float(r["z_m"])) for r in csv.DictReader(open("layer-out/units.csv"))}
end = {r["name"]: (float(r["x"]), float(r["y"]), float(r["z"])) for r in csv.DictReader(open("dry/final_state.csv"))}
moves = [math.dist(start[u], end[u]) for u in start]
assert len(moves) == 11, len(moves)
assert max(moves) < 0.001, f"a placed unit moved {max(moves)} m in 2 s"
print(f"11 units placed; in 2 s of running the largest move is {max(moves) * 1000:.3f} mm")
PY
echo "example 04: OK (the placed scene $out/layer-placed.yaml, its tables in $out/layer-out and $out/analysis)"
