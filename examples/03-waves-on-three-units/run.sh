#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Example 03, run and checked: `run.sh [ARMOUR] [OUT]` (defaults: armour on the PATH, ./out).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../setup.sh" "$@"   # $armour, and $out made and entered
cp "$here/waves.yaml" ./
"$armour" --log-level warn storm-file synth airy --out storm.nc --x-min 0 --x-max 24 --z-min 0 --z-max 10 \
  --voxel 0.25 --swl 6 --depth 4 --height 1.5 --period 6 --duration 18 > synth.txt
"$armour" --log-level warn storm waves.yaml --storm storm.nc
"$armour" --log-level warn report waves-out > report.txt
# The dry unit never meets the water: it must not move (5 mm, its 1 mm drop onto the face aside),
# while the wave moves the wet ones by centimetres. The report must exist.
/usr/bin/python3 - <<'PY'
import csv, math
rows = {r["name"]: r for r in csv.DictReader(open("waves-out/final_state.csv"))}
x0 = {"unit_dry": (18.2221, 9.41686)}
d = math.hypot(float(rows["unit_dry"]["x"]) - x0["unit_dry"][0], float(rows["unit_dry"]["z"]) - x0["unit_dry"][1])
assert d < 0.005, f"the dry unit moved {d} m"  # its 1 mm drop onto the face aside
wet = max(math.hypot(float(rows[n]["x"]) - x, float(rows[n]["z"]) - z)
          for n, (x, z) in (("unit_deep", (10.7221, 4.41686)), ("unit_swl", (13.7221, 6.41686))))
assert wet > 0.05, f"the wet units moved only {wet} m: the water did not act"
print(f"the dry unit moved {d * 1000:.1f} mm (its 1 mm drop onto the face); the wet ones up to {wet * 1000:.1f} mm")
PY
ls waves-out/report/index.html > /dev/null
echo "example 03: OK (frames in $out/waves-out/bodies.pvd, report in $out/waves-out/report/index.html)"
