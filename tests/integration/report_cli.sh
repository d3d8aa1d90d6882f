#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `armour report` on a short storm replay (docs/report.md): tests/data/scenes/wave-slope.yaml with
# an Airy storm synthesised next to a copy of it, plus one unit dropped in free fall far above the
# water (not loaded by the waves: its name does not start with the hydro prefix), run for 1 s, then
#  - report/ holds summary.json, units.csv, timeseries.csv, storm.csv, the PNGs and index.html;
#  - the falling unit is reported with the displacement free fall gives, g T^2 / 2;
#  - the counts of summary.json match units.csv, and the total displacement of timeseries.csv at
#    the end matches the sum over units.csv;
#  - the storm summary finds the synthetic wave (H = 1.5 m, T = 6 s) at the gauge;
#  - a replay by `armour storm --time-offset --set hydro.storm.offset=...` is reported with those
#    settings (bodies.nc records them), not the scene file's;
#  - a missing folder, a folder without bodies.nc, a damaged bodies.nc and one whose recorded
#    storm time offset is not a number exit with status 2 and a message naming the file and the fix.
# Arguments: the armour binary, the scenes folder, a work folder.
set -euo pipefail
armour="$1"
scenes="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$armour" --log-level warn storm-file synth airy --out "$out/storm.nc" --x-min 0 --x-max 24 --z-min 0 --z-max 10 \
  --voxel 0.25 --swl 6 --depth 4 --height 1.5 --period 6 --duration 36
# The copy: the falling unit far above the slope and the water (z = 20 m; it falls 4.9 m in 1 s).
sed 's/^  - {name: rock,/  - {name: unitdrop, shape: cube, dn: 1.0, material: concrete, position: [22, 12, 20]}\n  - {name: rock,/' \
  "$scenes/wave-slope.yaml" > "$out/scene.yaml"
grep -q "name: unitdrop" "$out/scene.yaml" || fail "could not add the falling unit to the scene copy"
"$armour" --log-level warn run "$out/scene.yaml" --threads 1 --duration 1 -o "$out/run" >/dev/null

# The report: the scene is found from bodies.nc's history; units are all bodies named unit*.
"$armour" --log-level warn report "$out/run" --units unit > "$out/report.txt" || fail "armour report failed: $(cat "$out/report.txt")"
# The storm line: a regular 1.5 m, 6 s wave gives its periods in seconds (the fit: H1/3 1.5 m, Tm and
# Tp within the record's resolution of 6 s); a period the record cannot give would read "unknown (--tm)".
grep -qE "storm Hs 1\.5 m \(H1/3 of eta at the gauge\), Tm [56]\.[0-9]+ s, Tp [56]\.[0-9]+ s, Ns " "$out/report.txt" \
  || fail "the storm line does not give Hs 1.5 m and both periods near 6 s: $(grep storm "$out/report.txt")"
! grep -qi "nan" "$out/report.txt" || fail "the printed report says nan: $(grep -i nan "$out/report.txt")"
for f in summary.json units.csv timeseries.csv storm.csv index.html plan.png elevation.png total_displacement.png \
         displacement_hist.png storm.png paraview_state.py; do
  [[ -s "$out/run/report/$f" ]] || fail "report/$f missing or empty"
done
/usr/bin/python3 - "$out/run/report" <<'PY' || fail "summary.json is inconsistent"
import csv, json, math, sys
folder = sys.argv[1]
s = json.load(open(f"{folder}/summary.json"))
units = list(csv.DictReader(open(f"{folder}/units.csv")))
series = list(csv.DictReader(open(f"{folder}/timeseries.csv")))
assert s["units"] == len(units) == 5, (s["units"], len(units))
# Free fall from rest for the run's last record time T: g T^2 / 2 (exact for constant acceleration
# up to the integrator's O(dt) error: 1e-3 relative covers it).
T = s["run_end_s"]
drop = next(u for u in units if u["unit"] == "unitdrop")
expected = 0.5 * 9.81 * T * T
assert abs(float(drop["displacement_m"]) - expected) < 1e-3 * expected, (drop["displacement_m"], expected)
assert abs(float(drop["dz"]) + expected) < 1e-3 * expected, drop["dz"]
assert s["damage"]["max_displacement_unit"] == "unitdrop", s["damage"]["max_displacement_unit"]
assert abs(s["damage"]["max_displacement_dn"] - expected) < 1e-3 * expected
# Counts: summary.json against units.csv.
dn = [float(u["displacement_dn"]) for u in units]
for k, v in s["damage"]["moved_more_than_dn"].items():
    assert v == sum(d > float(k) for d in dn), (k, v, dn)
assert s["damage"]["displaced_units"] == sum(int(u["displaced"]) for u in units)
assert s["damage"]["displaced_units"] >= 1                    # the falling unit
assert s["damage"]["rocking_units"] == sum(int(u["rocking"]) for u in units)
total = sum(float(u["displacement_m"]) for u in units)
assert abs(float(series[-1]["total_displacement_m"]) - total) < 1e-9 * max(total, 1.0), (series[-1], total)
assert abs(s["damage"]["total_displacement_m"] - total) < 1e-9 * max(total, 1.0)
assert math.isclose(s["damage"]["Nod"], s["damage"]["displaced_units"] * s["dn_mean_m"] / s["damage"]["trunk_width_m"])
# The storm at the gauge (the slope's toe, x = 8 m): the synthetic Airy wave, H = 1.5 m, T = 6 s;
# 5 % covers the ramp-up waves and the discrete sampling of the crests (0.05 s records).
st = s["storm"]
assert abs(st["H1_3_m"] - 1.5) < 0.075, st
assert abs(st["Tm_s"] - 6.0) < 0.3, st
assert abs(st["Tp_s"] - 6.0) < 0.6, st   # periodogram bins of 36 s padded to 51.2 s: 5.69 or 6.4 s
assert st["time_offset_s"] == 12.0
# Hudson applies to the cubes on the 1:1.5 slope (K_D 7.5 non-breaking): Ns_hudson = 2.24.
hudson = next(f for f in s["design"]["formulas"] if f["name"] == "Hudson")
assert hudson["applicable"], hudson
assert abs(hudson["values"]["Ns_hudson"] - (7.5 * 1.5) ** (1 / 3)) < 1e-9, hudson
# The storm CSV covers the run window (storm times 12 .. 13 s).
rows = list(csv.DictReader(open(f"{folder}/storm.csv")))
assert rows and float(rows[0]["storm_time_s"]) >= 12.0 - 1e-9 and float(rows[-1]["storm_time_s"]) <= 13.0 + 1e-9, rows[:1]
print("report numbers ok")
PY
grep -q "bodies.pvd" "$out/run/report/index.html" || fail "index.html does not link the run's bodies.pvd"

# A replay with `armour storm` and its command-line settings (a later storm time, the storm file's
# origin shifted by 1 m): the report takes them from bodies.nc (scene_file, scene_sets, storm_*),
# not from the scene file's hydro block (time offset 12 s, no offset).
"$armour" --log-level warn storm "$out/scene.yaml" --storm "$out/storm.nc" --time-offset 20 --duration 0.5 \
  --threads 1 --set 'hydro.storm.offset=[1, 0]' -o "$out/replay" >/dev/null
header=$(ncdump -h "$out/replay/bodies.nc")
grep -q ':history = ".*armour storm .*--time-offset 20 .*--set .*hydro.storm.offset=\[1, 0\]' <<< "$header" \
  || fail "bodies.nc's history does not give the armour storm command: $(grep history <<< "$header")"
grep -q ':storm_time_offset = 20\.' <<< "$header" || fail "bodies.nc does not record storm_time_offset = 20 s"
"$armour" --log-level warn report "$out/replay" --units unit > "$out/replay.txt" || fail "armour report failed: $(cat "$out/replay.txt")"
/usr/bin/python3 - "$out/run/report" "$out/replay/report" <<'PY' || fail "the report did not use the replay's settings"
import csv, json, sys
first = json.load(open(f"{sys.argv[1]}/summary.json"))["storm"]
s = json.load(open(f"{sys.argv[2]}/summary.json"))["storm"]
assert s["time_offset_s"] == 20.0, s["time_offset_s"]
# The gauge at the slope's toe (x = 8 m in the scene) lies 1 m further in the file's coordinates.
assert abs(s["gauge_x_m"] - (first["gauge_x_m"] + 1.0)) < 1e-9, (s["gauge_x_m"], first["gauge_x_m"])
rows = list(csv.DictReader(open(f"{sys.argv[2]}/storm.csv")))
assert rows and float(rows[0]["storm_time_s"]) >= 20.0 - 1e-9 and float(rows[-1]["storm_time_s"]) <= 20.5 + 1e-9, rows[:1]
print("replay settings ok")
PY

# Refusals.
expect_error() { # status 2 and the message pattern
  local pattern="$1"; shift
  set +e
  msg=$("$armour" --log-level warn report "$@" 2>&1); status=$?
  set -e
  [[ $status -eq 2 ]] || fail "armour report $* should exit 2, got $status: $msg"
  grep -q -- "$pattern" <<< "$msg" || fail "unclear message for armour report $*: $msg"
}
expect_error "not a folder; give the output folder of \`armour run\`" "$out/no-such-run"
mkdir -p "$out/empty"
expect_error "empty/bodies.nc: missing" "$out/empty" --scene "$out/scene.yaml"
mkdir -p "$out/damaged"
head -c 2000 "$out/run/bodies.nc" > "$out/damaged/bodies.nc"
expect_error "damaged/bodies.nc: open (not a readable netCDF file" "$out/damaged" --scene "$out/scene.yaml"
# A run attribute that is not a number (an edited file) is named.
mkdir -p "$out/edited"
cp "$out/replay/bodies.nc" "$out/edited/bodies.nc"
/usr/bin/python3 -c "
import netCDF4, sys
with netCDF4.Dataset(sys.argv[1], 'a') as d:
    d.storm_time_offset = 'twenty'
" "$out/edited/bodies.nc"
expect_error "edited/bodies.nc: global attribute 'storm_time_offset' is not one finite number" "$out/edited"
echo "report_cli: all checks passed"
