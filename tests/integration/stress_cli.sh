#!/usr/bin/env bash
# `output.unit_loads` and `armour stress` end to end (issue 26) on the Dolos pile
# (tests/data/scenes/dolos-pile.yaml): a run that records the loads of some units; the same run
# stopped between two records and continued, whose files must be the same bytes; the stress of
# every recorded unit, the same on 1 and 2 threads; and the refusals, each naming what to fix.
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"
cli_setup "$@"
scene="$data/dolos-pile.yaml"
sets=(--set "output.unit_loads=[dolos_0_0_0, 'dolos_1_*']" --set output.vtk_interval=0 --set output.unit_loads_interval=0.02)

# The whole run, and the same run stopped at 0.71 s (mid-window: the held peaks go into the
# checkpoint) and continued to 1.5 s.
"$armour" --log-level warn run "$scene" -o "$out/whole" --duration 1.5 "${sets[@]}" --threads 1
"$armour" --log-level warn run "$scene" -o "$out/split" --duration 0.71 "${sets[@]}" --threads 1
"$armour" --log-level warn run "$scene" -o "$out/split" --duration 1.5 "${sets[@]}" --threads 1 --restart
for f in units.csv records.csv loads.csv; do
  cmp -s "$out/whole/unit_loads/$f" "$out/split/unit_loads/$f" || fail "$f differs after a restart mid-window"
done
rows=$(($(wc -l < "$out/whole/unit_loads/records.csv") - 1))
[ "$rows" -eq $((5 * 76)) ] || fail "expected 5 units x 76 records (t = 0, then every 0.02 s to 1.5 s), got $rows rows"
head -1 "$out/whole/unit_loads/units.csv" | grep -q "^unit,name,scene_body,mass_kg,volume_m3,dn_m,surface$" \
  || fail "units.csv header: $(head -1 "$out/whole/unit_loads/units.csv")"
[ -s "$out/whole/unit_loads/0-dolos_0_0_0.vtp" ] || fail "no surface file for dolos_0_0_0"

# The stress of the recorded units: outputs, a verdict per unit, the same on 1 and 2 threads.
msg=$("$armour" --log-level warn stress "$out/whole" --tets 800 --every 3 --threads 1) || fail "stress failed: $msg"
grep -q "of 5 units above the tensile strength 3.5 MPa" <<< "$msg" || fail "no verdict line in: $msg"
for f in units.csv series.csv events.csv summary.json stress_map.vtp stress.log dolos_1_0_1-peak.vtu; do
  [ -s "$out/whole/stress/$f" ] || fail "stress: no $f"
done
[ "$(($(wc -l < "$out/whole/stress/units.csv") - 1))" -eq 5 ] || fail "units.csv should have 5 rows"
/usr/bin/python3 - "$out/whole/stress" <<'PY' || fail "stress outputs do not read back"
import csv, json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["units"] == 5 and s["model"]["every"] == 3, s
rows = list(csv.DictReader(open(f"{d}/units.csv")))
for r in rows:
    assert float(r["max_sigma1_pa"]) >= float(r["max_body_sigma1_pa"]) > 0.0, r
    assert r["over_strength"] in ("0", "1"), r
ev = list(csv.DictReader(open(f"{d}/events.csv")))
assert all(e["kind"] in ("impact", "rocking", "sustained") for e in ev), ev
# The units fall about 1.6 m and land at about 0.52 s: the peaks of that landing come from contact
# forces that rose from nothing, which makes them impacts (a real run's classification, not only
# the synthetic series of test_stress_events).
landing = [e for e in ev if abs(float(e["time_s"]) - 0.52) < 0.03]
assert len(landing) >= 3 and all(e["kind"] == "impact" for e in landing), landing
PY
"$armour" --log-level warn stress "$out/whole" --tets 800 --every 3 --threads 2 -o "$out/whole/stress2" > /dev/null
cmp -s "$out/whole/stress/series.csv" "$out/whole/stress2/series.csv" || fail "series.csv differs between 1 and 2 threads"

# Refusals: exit 2 and the fix named.
"$armour" --log-level warn run "$scene" -o "$out/plain" --duration 0.05 --set output.vtk_interval=0
expect_refusal "unit_loads/units.csv: missing: run the rigid replay with output.unit_loads" \
  "$armour" --log-level warn stress "$out/plain"
expect_refusal "'dolos_9' was not recorded by the run; it recorded: dolos_0_0_0, dolos_1_0_0" \
  "$armour" --log-level warn stress "$out/whole" --units dolos_9
expect_refusal "output.unit_loads = \[nothing\]: 'nothing' names no body of the scene" \
  "$armour" --log-level warn check "$scene" --set "output.unit_loads=[nothing]"
expect_refusal "--radius" "$armour" --log-level warn stress "$out/whole" --radius 0
# A records file cut short behind the checkpoint's back: the restart refuses it (the checkpoint at the
# end counts 375 rows: the last 5, of the window the run ended in, are the final off-schedule ones).
head -n 20 "$out/split/unit_loads/records.csv" > "$out/cut.csv" && mv "$out/cut.csv" "$out/split/unit_loads/records.csv"
expect_refusal "records.csv: holds 19 complete rows, but the checkpoint was taken after 375" \
  "$armour" --log-level warn run "$scene" -o "$out/split" --duration 1.6 "${sets[@]}" --restart
# Another record interval at a restart: refused, naming the key and the checkpoint's value.
expect_refusal "output.unit_loads_interval = 0.05 s, but the checkpoint's run recorded every 0.02 s" \
  "$armour" --log-level warn run "$scene" -o "$out/whole" --duration 1.6 "${sets[@]}" --set output.unit_loads_interval=0.05 --restart
# Unit loads turned on at a restart: refused (the sleeping units' loads are not in the checkpoint).
expect_refusal "did not record unit loads" \
  "$armour" --log-level warn run "$scene" -o "$out/plain" --duration 0.1 "${sets[@]}" --restart
echo "stress_cli: all checks passed"
