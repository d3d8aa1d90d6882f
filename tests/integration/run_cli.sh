#!/usr/bin/env bash
# `armour check` and `armour run` end to end: check builds good scenes and prints the time step
# (exit 0); broken scenes exit 2 naming the file; a short run writes run.log (build line first,
# then the resolved settings, the summary) and final_state.csv with one row per body.
set -euo pipefail
armour="$1"
scenes="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

# The constraint solver's step is its own, not a fraction of the penalty solver's stable step.
msg=$("$armour" --log-level warn check "$scenes/block-on-slope.yaml" --set contact.solver=constraint 2>&1) \
  || fail "check with the constraint solver failed: $msg"
grep -q "^time step: 0.005 s (constraint solver, contact.constraint.time_step; 3 substeps" <<< "$msg" \
  || fail "constraint solver: no or wrong time step line in: $msg"

# Good scenes: exit 0, the resolved settings, the counts and the time step.
for scene in block-on-slope dolos-pile run-smoke; do
  set +e; msg=$("$armour" --log-level warn check "$scenes/$scene.yaml" 2>&1); code=$?; set -e
  [ $code -eq 0 ] || fail "check $scene.yaml exited $code: $msg"
  grep -q "^time step: [0-9.e+-]* s (auto: 0.2 x the stable step)" <<< "$msg" || fail "no time step in: $msg"
  grep -q "^stable time step: [0-9.e+-]* s" <<< "$msg" || fail "no stable time step in: $msg"
  grep -q "^check: .*$scene.yaml is valid" <<< "$msg" || fail "no verdict in: $msg"
done
msg=$("$armour" --log-level warn check "$scenes/dolos-pile.yaml" 2>&1)
grep -q "^bodies: 12 (12 dynamic, 0 fixed)" <<< "$msg" || fail "dolos-pile: expected 12 bodies in: $msg"
grep -q "^static pieces: 228 (4 half-spaces, 224 convex pieces, 0 fixed meshes)" <<< "$msg" \
  || fail "dolos-pile: expected 4 walls and 224 height-field pieces in: $msg"
grep -q "^  time_step = auto" <<< "$msg" || fail "dolos-pile: describeScene missing from: $msg"

# Broken scenes: exit 2, the file named in the message.
for scene in "$scenes"/broken/*.yaml; do
  name=$(basename "$scene")
  set +e; msg=$("$armour" --log-level off check "$scene" 2>&1); code=$?; set -e
  [ $code -eq 2 ] || fail "check $name: expected exit 2, got $code: $msg"
  grep -q "error: .*$name" <<< "$msg" || fail "check $name: the file is not named in: $msg"
done
# Initial positions the guard rails would stop: check evaluates the first contact forces.
msg=$("$armour" --log-level off check "$scenes/unrunnable/deep-overlap.yaml" 2>&1 || true)
grep -q "initial positions cannot be run: .*body 'first' and body 'second' overlap by 0.006 m" <<< "$msg" \
  || fail "deep initial overlap not explained: $msg"
msg=$("$armour" --log-level warn check "$scenes/run-smoke.yaml" 2>&1)
grep -q "^initial contacts: [0-9]* candidate pairs, 0 engaged points, deepest overlap 0 m" <<< "$msg" \
  || fail "run-smoke: no initial contact summary in: $msg"
# A fixed time step above the stability limit is a user error too.
sed 's/^time_step: auto .*/time_step: 0.01/' "$scenes/block-on-slope.yaml" > "$out/long-step.yaml"
set +e; msg=$("$armour" --log-level off check "$out/long-step.yaml" 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "a 10 ms time step was accepted (exit $code): $msg"
grep -q "long-step.yaml: time_step: .*stability limit" <<< "$msg" || fail "time-step error unclear: $msg"

# --set KEY=VALUE changes a setting for one command; a misspelt key is refused like one in the file.
msg=$("$armour" --log-level warn check "$scenes/run-smoke.yaml" --set duration=7 2>&1)
grep -q "^  duration = 7 s" <<< "$msg" || fail "--set duration=7 not applied: $msg"
set +e; msg=$("$armour" --log-level off check "$scenes/run-smoke.yaml" --set contact.modle=fdem 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "--set contact.modle: expected exit 2, got $code: $msg"
grep -q "run-smoke.yaml: contact.modle: unknown key (did you mean 'model'?)" <<< "$msg" || fail "--set typo unclear: $msg"

# A run: the smoke scene (two cubes dropped on a floor, 0.3 s), written to --output.
set +e; log=$("$armour" run "$scenes/run-smoke.yaml" --threads 1 -o "$out/smoke" 2>&1); code=$?; set -e
[ $code -eq 0 ] || fail "run exited $code: $log"
[ -f "$out/smoke/run.log" ] || fail "no run.log"
head -n 1 "$out/smoke/run.log" | grep -q "armour [0-9.]* (git .*, 1 threads)" \
  || fail "run.log does not start with the build line (1 thread): $(head -n 1 "$out/smoke/run.log")"
grep -q "  duration = 0.3 s" "$out/smoke/run.log" || fail "resolved settings missing from run.log"
grep -Eq "finished: t = 0\.(3|2999[0-9]*) s" "$out/smoke/run.log" || fail "no summary in run.log"
grep -q "final kinetic energy" "$out/smoke/run.log" || fail "no final kinetic energy in run.log"
# The automatic step need not divide the output intervals; the log says how they relate (issue 23, item 8).
grep -Eq "time step [0-9.e-]+ s; series every 0.01 s \((exactly )?[0-9.]+ steps\), VTK every 0.1 s \((exactly )?[0-9.]+ steps\): each output is written at the first step at or after its time" \
  "$out/smoke/run.log" || fail "run.log does not relate the time step to the output intervals"
[ -f "$out/smoke/final_state.csv" ] || fail "no final_state.csv"
# ParaView series: frames at 0, 0.1, 0.2 and 0.3 s (vtk_interval 0.1 s), all listed in bodies.pvd.
[ "$(grep -c '<DataSet' "$out/smoke/bodies.pvd")" -eq 4 ] || fail "bodies.pvd should list 4 frames: $(cat "$out/smoke/bodies.pvd")"
for f in $(grep -o 'file="[^"]*"' "$out/smoke/bodies.pvd" | cut -d'"' -f2); do
  [ -f "$out/smoke/$f" ] || fail "bodies.pvd lists $f, which does not exist"
done
# netCDF series: HDF5 signature, and 31 records at 0.01 s over 0.3 s (checked in the run log).
head -c 4 "$out/smoke/bodies.nc" | grep -q "HDF" || fail "bodies.nc is not a netCDF-4 (HDF5) file"
grep -q "wrote 4 VTK frames, 31 series records" "$out/smoke/run.log" || fail "output counts missing from run.log"
[ "$(head -n 1 "$out/smoke/final_state.csv")" = "body,name,x,y,z,qw,qx,qy,qz,vx,vy,vz" ] || fail "bad CSV header"
[ "$(wc -l < "$out/smoke/final_state.csv")" -eq 3 ] || fail "final_state.csv: expected a header and 2 rows"
# At 0.3 s both cubes have landed: centroids within 1 cm of z = 0.5 m.
awk -F, 'NR > 1 { d = $5 - 0.5; if (d < 0) d = -d; if (d > 0.01) exit 1 }' "$out/smoke/final_state.csv" \
  || fail "cubes not on the floor at 0.3 s: $(cat "$out/smoke/final_state.csv")"

# --duration overrides the scene's.
"$armour" --log-level warn run "$scenes/run-smoke.yaml" --duration 0.05 -o "$out/short" 2>/dev/null
# Free fall for 0.05 s: the low cube (from z = 0.6 m) is at 0.6 - g t^2 / 2 = 0.5877 m.
awk -F, 'NR == 2 { d = $5 - 0.58774; if (d < 0) d = -d; if (d > 1e-3) exit 1 }' "$out/short/final_state.csv" \
  || fail "--duration 0.05: the low cube should be in free fall at z = 0.5877 m: $(cat "$out/short/final_state.csv")"
set +e; msg=$("$armour" --log-level off run "$scenes/run-smoke.yaml" --duration -1 -o "$out/x" 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "--duration -1 accepted (exit $code): $msg"
set +e; msg=$("$armour" --log-level off run "$scenes/run-smoke.yaml" --duration 0 -o "$out/x" 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "--duration 0 accepted (exit $code): $msg"
# A number beyond a double (issue 23, item 13): out of range, as typed, on the command line and in --set.
set +e; msg=$("$armour" --log-level off run "$scenes/run-smoke.yaml" --duration 1e999 -o "$out/x" 2>&1); code=$?; set -e
[ $code -ne 0 ] || fail "--duration 1e999 accepted: $msg"
grep -q -- "--duration: 1e999 is out of range: beyond 1.79769e+308, the largest number a double holds" <<< "$msg" \
  || fail "--duration 1e999: not called out of range: $msg"
set +e; msg=$("$armour" --log-level off check "$scenes/run-smoke.yaml" --set duration=1e999 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "--set duration=1e999: expected exit 2, got $code: $msg"
grep -q "run-smoke.yaml: duration = 1e999: out of range" <<< "$msg" || fail "--set duration=1e999: not called out of range: $msg"

# Bodies that start inside each other trip the overlap guard rail: exit 3, the bodies named, the
# state at the stop written.
set +e; msg=$("$armour" --log-level off run "$scenes/unrunnable/deep-overlap.yaml" -o "$out/overlap" 2>&1); code=$?; set -e
[ $code -eq 3 ] || fail "overlapping start: expected exit 3, got $code: $msg"
grep -q "deep-overlap.yaml: the simulation stopped: .*body 'first' and body 'second' overlap" <<< "$msg" \
  || fail "overlapping start: unclear message: $msg"
[ "$(wc -l < "$out/overlap/state_at_error.csv")" -eq 3 ] || fail "no state_at_error.csv with 2 rows"
# A body that slides off a slope's crest leaves the static domain (where the crest is cut): the
# run says so once, with the time and the bounds, and counts it at the end; `armour analyse` of
# the final state counts it off the model (crest-slide.yaml: a frictionless cube at 4 m/s).
"$armour" --log-level warn run "$scenes/crest-slide.yaml" --threads 1 -o "$out/crest" 2>/dev/null || fail "the crest run failed"
[ "$(grep -c "body 'cube' left the static domain" "$out/crest/run.log")" -eq 1 ] \
  || fail "no single exit warning in: $(grep -i domain "$out/crest/run.log")"
grep -q "1 bodies left the static domain in this run (1 outside it at the end)" "$out/crest/run.log" \
  || fail "no exit count in: $(grep -i domain "$out/crest/run.log")"
msg=$("$armour" --log-level warn analyse "$scenes/crest-slide.yaml" --state "$out/crest/final_state.csv" --output "$out/crest-analysis" 2>&1) \
  || fail "analyse of the crest run failed: $msg"
grep -q "^off the model       1 units beyond the static domain" <<< "$msg" || fail "not counted off the model: $msg"
echo "run CLI: all checks passed"
