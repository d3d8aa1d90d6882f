#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The smoke variant of a shipped placement case (cases/placement/*-smoke.yaml): `armour place`
# places every unit of its grid, no unit is left moving or moved more than 1 Dn, the placed scene passes `armour check`
# (nothing starts overlapping deeper than the guard rail) and placement.json holds the expected
# unit and rock counts.
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
/usr/bin/python3 - "$out/$name-out/placement.json" "$units" "$rocks" <<'PY' || fail "placement.json: $(cat "$out/$name-out/placement.json")"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["units"] == int(sys.argv[2]) and s["rocks"] == int(sys.argv[3]), s
assert s["still_moving"] == [], s
# The pack holds its grid: no unit ends more than 1 Dn from where it was released.
assert s["moved_more_than_1dn"] == [], s["moved_more_than_1dn"]
PY
echo "$name: OK"; cat "$out/$name-out/placement.txt"
