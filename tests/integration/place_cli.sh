#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Placement end to end with the smoke variant of seed 001's dolos set-up
# (cases/placement/dolos-smoke.yaml):
#  - `armour place` writes the placed scene beside the file and units.csv / placement.json /
#    placement.txt in its output folder (with --output, the folder beside the placed scene); every unit is placed and none is still moving;
#  - `armour analyse` of the placed scene against itself finds no displacement, every unit
#    touches something (contact number >= 1) and the P2 values lie in [-1/2, 1];
#  - `armour ensemble --runs 2` places two members with different seeds and reports mean +- std;
#  - stopped by SIGINT, `armour place` exits 130 with a checkpoint and the command that continues
#    it; continued with --restart it writes the same placed scene, byte for byte, as the run that
#    was not stopped, and removes its checkpoint; --restart with another --set or without a
#    checkpoint is refused;
#  - a scene without a placement block and a missing grid file are refused (exit 2) with
#    messages that name the file and the fix.
# Arguments: the armour binary, the cases/placement folder, a work folder.
set -euo pipefail
armour="$1"
cases="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
cp "$cases/dolos-smoke.yaml" "$out/dolos.yaml"

"$armour" --log-level warn place "$out/dolos.yaml" --threads 1 > "$out/place.txt" || fail "place failed: $(cat "$out/place.txt")"
[[ -f "$out/dolos-placed.yaml" ]] || fail "no placed scene"
for f in units.csv placement.json placement.txt; do [[ -f "$out/dolos-out/$f" ]] || fail "no $f"; done
/usr/bin/python3 - "$out/dolos-out/placement.json" <<'PY' || fail "placement.json is wrong"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["units"] == 4, s
assert s["still_moving"] == [], s
PY

"$armour" --log-level warn analyse "$out/dolos-placed.yaml" --reference "$out/dolos-placed.yaml" --axis upper-fluke \
  --output "$out/analysis" > "$out/analyse.txt" || fail "analyse failed: $(cat "$out/analyse.txt")"
/usr/bin/python3 - "$out/analysis" <<'PY' || fail "the analysis is wrong"
import csv, json, sys
folder = sys.argv[1]
p = json.load(open(folder + "/pack.json"))
assert p["units"] == 4, p
assert p["delta_rms_m"] == 0.0 and p["max_displacement_dn"] == 0.0, p   # against itself
assert -0.5 <= p["p2_q_tensor"] <= 1.0 and -0.5 <= p["p2_mean_director"] <= 1.0, p
rows = list(csv.DictReader(open(folder + "/units.csv")))
assert len(rows) == 4
for r in rows:
    assert int(r["contact_number"]) >= 1, r       # at rest: it rests on something
    assert 0.0 <= float(r["dip_deg"]) <= 90.0, r
PY

"$armour" --log-level warn ensemble "$out/dolos.yaml" --runs 2 --axis upper-fluke --output "$out/ensemble" \
  > "$out/ensemble.txt" || fail "ensemble failed: $(cat "$out/ensemble.txt")"
/usr/bin/python3 - "$out/ensemble" <<'PY' || fail "the ensemble tables are wrong"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/ensemble.csv")))
assert [r["packing_seed"] for r in rows] == ["1", "2"] and all(r["status"] == "done" for r in rows), rows
e = json.load(open(sys.argv[1] + "/ensemble.json"))
assert e["delta_rms_m"]["mean"] > 0.0 and e["delta_rms_m"]["std"] >= 0.0, e
PY

# Stopped and continued: a checkpoint at every safe point (--checkpoint-minutes 1e-9), SIGINT as
# soon as the first one is there.
[[ ! -e "$out/dolos-out/place-checkpoint.nc" ]] || fail "a finished placement left its checkpoint"
mkdir -p "$out/stop" && cp "$out/dolos.yaml" "$out/stop/dolos.yaml"
"$armour" --log-level warn place "$out/stop/dolos.yaml" --threads 1 --checkpoint-minutes 1e-9 \
  > "$out/stop/place.txt" 2> "$out/stop/stderr.txt" &
pid=$!
for _ in $(seq 1 600); do [[ -e "$out/stop/dolos-out/place-checkpoint.nc" ]] && break; sleep 0.05; done
kill -INT "$pid"
set +e
wait "$pid"; code=$?
set -e
[[ $code -eq 130 ]] || fail "stopped by SIGINT: exit $code ($(cat "$out/stop/stderr.txt"))"
grep -q "continue with: armour place $out/stop/dolos.yaml --restart" "$out/stop/stderr.txt" ||
  fail "no restart command: $(cat "$out/stop/stderr.txt")"
set +e
msg=$("$armour" place "$out/stop/dolos.yaml" --restart --set seed=9 2>&1); code=$?
set -e
[[ $code -eq 2 ]] || fail "restart with another --set: exit $code"
grep -q "place-checkpoint.nc.*the scene changed since the run started" <<< "$msg" || fail "unclear message: $msg"
"$armour" --log-level warn place "$out/stop/dolos.yaml" --threads 1 --restart > "$out/stop/restart.txt" ||
  fail "restart failed: $(cat "$out/stop/restart.txt")"
# (line 1 names the placement file, which is in another folder)
cmp <(tail -n +2 "$out/dolos-placed.yaml") <(tail -n +2 "$out/stop/dolos-placed.yaml") ||
  fail "the continued placement differs from the uninterrupted one"
cmp "$out/dolos-out/units.csv" "$out/stop/dolos-out/units.csv" || fail "units.csv differs after the restart"
[[ ! -e "$out/stop/dolos-out/place-checkpoint.nc" ]] || fail "the continued placement left its checkpoint"
set +e
msg=$("$armour" place "$out/stop/dolos.yaml" --restart 2>&1); code=$?
set -e
[[ $code -eq 2 ]] || fail "restart without a checkpoint: exit $code"
grep -q "place-checkpoint.nc" <<< "$msg" || fail "unclear message: $msg"

# Refusals.
set +e
msg=$("$armour" place "$out/dolos.yaml" --checkpoint-minutes -1 2>&1); code=$?
set -e
[[ $code -eq 2 ]] || fail "--checkpoint-minutes -1: exit $code"
grep -q -- "--checkpoint-minutes.*-1: give the wall time between checkpoints in minutes" <<< "$msg" || fail "unclear message: $msg"
set +e
msg=$("$armour" place "$cases/../../tests/data/scenes/block-on-slope.yaml" 2>&1); code=$?
set -e
[[ $code -eq 2 ]] || fail "a scene without placement: exit $code"
grep -q "no \`placement:\` block" <<< "$msg" || fail "unclear message: $msg"
sed -e 's/grid: {rows: 2, units_per_row: 2, dx: 1.94, dy: 1.3, stagger: 0.5, first_row: 0.7}/grid: {file: nowhere.csv}/' \
  "$out/dolos.yaml" > "$out/nogrid.yaml"
grep -q "nowhere.csv" "$out/nogrid.yaml" || fail "test set-up: the grid line was not replaced"
set +e
msg=$("$armour" place "$out/nogrid.yaml" 2>&1); code=$?
set -e
[[ $code -eq 2 ]] || fail "a missing grid file: exit $code"
grep -q "nowhere.csv: cannot open the grid file" <<< "$msg" || fail "unclear message: $msg"
mkdir -p "$out/a-folder"
set +e
msg=$("$armour" place "$out/dolos.yaml" --output "$out/a-folder" 2>&1); code=$?
set -e
[[ $code -eq 2 ]] || fail "--output naming a folder: exit $code"
grep -q "a-folder is a folder; give the path of the placed scene file" <<< "$msg" || fail "unclear message: $msg"
# --output in a folder that does not exist yet: made at the start (it was found missing only when
# the placed scene was written, after the whole placement); one that cannot be made is refused at
# once, naming --output.
"$armour" --log-level warn place "$out/dolos.yaml" --threads 1 --output "$out/new/deeper/placed.yaml" > "$out/place-new.txt" \
  || fail "place into a new folder failed: $(cat "$out/place-new.txt")"
[[ -f "$out/new/deeper/placed.yaml" ]] || fail "no placed scene in the new folder"
# Its tables go beside it (the default folder dolos-out taken there), not beside the file, where
# another placement of the same file would overwrite them (and share its checkpoint).
for f in units.csv placement.json placement.txt; do
  [[ -f "$out/new/deeper/dolos-out/$f" ]] || fail "--output: no $f beside the placed scene"
done
set +e
msg=$("$armour" place "$out/dolos.yaml" --output "$out/dolos.yaml/inside/placed.yaml" 2>&1); code=$?
set -e
[[ $code -eq 2 ]] || fail "--output under a file: exit $code"
grep -q -- "--output: cannot create the folder" <<< "$msg" || fail "unclear message: $msg"
echo "place_cli: OK"
