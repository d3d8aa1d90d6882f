#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The smoke variant of a shipped placement case (cases/placement/*-smoke.yaml): `armour place`
# places every unit of its grid, no unit is left moving or moved more than 1 Dn, the placed scene passes `armour check`
# (nothing starts overlapping deeper than the guard rail) and placement.json holds the expected
# unit and rock counts. The placed scene names its state (<name>-placed-state.nc, initial_state:);
# run from it for 1 s the pack stays where the placement left it (no unit moves 1 mm): the
# contacts keep their friction springs. The same scene without its state (positions only) is run
# too and its largest move printed, for comparison; under other contact settings only the bodies'
# state is used; a scene edited after the placement is refused (exit 2, the body named), and so is
# a missing state file (named).
# Arguments: the armour binary, the case file, a work folder, expected units, expected rocks.
set -euo pipefail
armour="$1"
case_file="$2"
out="$3"
units="$4"
rocks="$5"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
name=$(basename "$case_file" .yaml)
cp "$case_file" "$out/$name.yaml"
"$armour" --log-level warn place "$out/$name.yaml" --threads 1 > "$out/place.txt" || fail "place failed: $(cat "$out/place.txt")"
"$armour" --log-level warn check "$out/$name-placed.yaml" > "$out/check.txt" || fail "the placed scene does not pass check: $(cat "$out/check.txt")"
# A settled pack is not taken for bodies inside each other (issue 23, item 9): its largest shared
# volume is printed for the record (refused above 1 % of a unit).
grep "^interpenetration: .* largest share" "$out/check.txt" || fail "check does not measure the interpenetration: $(cat "$out/check.txt")"
/usr/bin/python3 - "$out/$name-out/placement.json" "$units" "$rocks" <<'PY' || fail "placement.json: $(cat "$out/$name-out/placement.json")"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["units"] == int(sys.argv[2]) and s["rocks"] == int(sys.argv[3]), s
assert s["still_moving"] == [], s
# The pack holds its grid: no unit ends more than 1 Dn from where it was released.
assert s["moved_more_than_1dn"] == [], s["moved_more_than_1dn"]
PY
placed="$out/$name-placed.yaml"
[[ -f "$out/$name-placed-state.nc" ]] || fail "no placed state $name-placed-state.nc beside the placed scene"
grep -q "^initial_state: $name-placed-state.nc" "$placed" || fail "the placed scene does not name its state"
printf 'output: {series_interval: 0.1, vtk_interval: 10}\n' >> "$placed"
"$armour" --log-level warn run "$placed" --duration 1 --threads 1 -o "$out/from-state" > "$out/from-state.txt" \
  || fail "run from the placed state failed: $(cat "$out/from-state.txt")"
grep -q "started from the placed state .* (positions, contacts and their friction springs" "$out/from-state/run.log" \
  || fail "the run did not start from the placed state"
# Under other contact settings the state's contacts do not fit: the bodies' state only, with a warning.
"$armour" --log-level warn run "$placed" --duration 0.01 --threads 1 -o "$out/other-contacts" \
  --set contact.sample_spacing=0.08 > "$out/other-contacts.txt" 2>&1 || fail "run under other contact settings failed"
grep -q "positions and velocities as the placement left them" "$out/other-contacts/run.log" \
  || fail "the state's contacts were carried over to other contact settings"
grep -v "^initial_state:" "$placed" > "$out/$name-positions.yaml"
"$armour" --log-level warn run "$out/$name-positions.yaml" --duration 1 --threads 1 -o "$out/from-positions" \
  > "$out/from-positions.txt" || fail "run from the positions failed: $(cat "$out/from-positions.txt")"
/usr/bin/python3 - "$out/from-state/bodies.nc" "$out/from-positions/bodies.nc" <<'PY' || fail "the pack moved when run from its placed state"
import sys, netCDF4, numpy
def largest(path):
    with netCDF4.Dataset(path) as ds:
        names = [n.strip() for n in netCDF4.chartostring(ds["body_name"][:])]
        x = numpy.asarray(ds["position"][:])
    units = [i for i, n in enumerate(names) if n.startswith("unit_")]
    return max(numpy.linalg.norm(x[-1, i] - x[0, i]) for i in units)
state, positions = largest(sys.argv[1]), largest(sys.argv[2])
print(f"largest unit move in 1 s: {state * 1e3:.4f} mm from the placed state, {positions * 1e3:.4f} mm from the positions alone")
assert state < 1e-3, state
PY
/usr/bin/python3 - "$placed" "$out/$name-edited.yaml" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
# Move the first unit by 1 cm along x.
m = re.search(r"(- name: unit_\w+\n(?:  .*\n)*?    position: \[)([^,]+)", text)
text = text[:m.start(2)] + repr(float(m.group(2)) + 0.01) + text[m.end(2):]
open(sys.argv[2], "w").write(text)
PY
set +e; msg=$("$armour" --log-level off run "$out/$name-edited.yaml" --duration 0.01 --threads 1 -o "$out/edited" 2>&1); code=$?; set -e
[[ $code -eq 2 ]] || fail "a scene edited after the placement should be refused (exit 2), got $code: $msg"
grep -q "was edited after the placement" <<< "$msg" || fail "unclear refusal of the edited scene: $msg"
sed "s/^initial_state: .*/initial_state: missing-state.nc/" "$placed" > "$out/$name-missing.yaml"
set +e; msg=$("$armour" --log-level off run "$out/$name-missing.yaml" --duration 0.01 --threads 1 -o "$out/missing" 2>&1)
code=$?; set -e
[[ $code -eq 2 ]] || fail "a missing placed state should be refused (exit 2), got $code: $msg"
grep -q "missing-state.nc: no placed state here" <<< "$msg" || fail "the missing state file is not named: $msg"
echo "$name: OK"; cat "$out/$name-out/placement.txt"
