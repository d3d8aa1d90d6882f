#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Example 02, run and checked: `run.sh [ARMOUR] [OUT]` (defaults: armour on the PATH, ./out).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../setup.sh" "$@"   # $armour, and $out made and entered
cp "$here/pile.yaml" ./
"$armour" --log-level warn run pile.yaml
"$armour" --log-level warn analyse pile.yaml --state pile-out/final_state.csv --axis upper-fluke --output analysis
cat analysis/pack.txt
# At rest (every centroid slower than 1 cm/s), every unit on the bed or on another unit (contact
# number >= 1), none through the bed (its lowest cell is at z = -0.3 m).
/usr/bin/python3 - <<'PY'
import csv, math
state = list(csv.DictReader(open("pile-out/final_state.csv")))
units = list(csv.DictReader(open("analysis/units.csv")))
assert len(state) == 12 and len(units) == 12, (len(state), len(units))
fastest = max(math.hypot(float(r["vx"]), float(r["vy"]), float(r["vz"])) for r in state)
assert fastest < 0.01, f"still moving at {fastest} m/s"
assert all(int(u["contact_number"]) >= 1 for u in units), [u["contact_number"] for u in units]
assert all(float(r["z"]) > -0.3 for r in state)
print(f"12 dolosse at rest (fastest {fastest:.2e} m/s), contact numbers {sorted(int(u['contact_number']) for u in units)}")
PY
echo "example 02: OK (frames in $out/pile-out/bodies.pvd, tables in $out/analysis)"
