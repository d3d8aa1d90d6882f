#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `armour deform` end to end on cases/deformable/vcross-drop-smoke.yaml (seed 002's drop, coarse,
# 2 ms): the outputs exist (frames.pvd listing frames that exist, stress_history.csv,
# summary.json, checkpoint.bin, run.log); the Vcross's largest tension after 2 ms of impact is in
# the unit and of the order of seed 002's (1 to 6 MPa: the coarse smoke mesh, 2 of the impact's
# 4.7 ms); a run to 1 ms continued with --restart to 2 ms ends with the same checkpoint, stress
# history and frame list as the run that went through (byte for byte), and its first log is kept
# as run.1.log; bad input is refused naming the key; --restart without a checkpoint is refused;
# the rock dump's smoke variant runs and its rocks are stressed by their landing; stopped by SIGTERM
# and continued, it ends with the same bytes.
# Arguments: the armour binary, the cases folder, a work folder.
set -euo pipefail
armour="$1"
cases="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
scene="$cases/vcross-drop-smoke.yaml"
deform() { "$armour" --log-level warn deform "$scene" --threads 1 "$@"; }

deform -o "$out/full"
for f in frames.pvd stress_history.csv summary.json checkpoint.bin run.log; do
  [[ -s "$out/full/$f" ]] || fail "missing or empty output $f"
done
grep -o 'file="[^"]*"' "$out/full/frames.pvd" | sed 's/file="\(.*\)"/\1/' | while read -r frame; do
  [[ -s "$out/full/$frame" ]] || fail "frames.pvd lists $frame, which does not exist"
done
[[ $(grep -c '<DataSet' "$out/full/frames.pvd") == 3 ]] || fail "expected frames at 0, 1 and 2 ms"
/usr/bin/python3 - "$out/full/summary.json" <<'PY' || fail "the largest tension is not the expected order"
import json, sys
s = json.load(open(sys.argv[1]))
t = s["largest_tension"]
print("largest tension", t["value_Pa"] / 1e6, "MPa in", t["body"], "at", t["time_s"], "s")
assert t["body"] == "vcross", t
assert 1e6 < t["value_Pa"] < 6e6, t
assert abs(s["time_s"] - 0.002) < 1e-5, s["time_s"]
PY

# Half, then continued: the same bytes as the run that went through.
deform -o "$out/split" --duration 0.001
deform -o "$out/split" --restart
for f in checkpoint.bin stress_history.csv frames.pvd; do
  cmp "$out/full/$f" "$out/split/$f" || fail "restart: $f differs from the uninterrupted run"
done
[[ -s "$out/split/run.1.log" ]] || fail "restart: the first run's log was not kept as run.1.log"

# Refusals, each naming what to fix.
# A restart with another material (same mesh) is refused naming the change; the checkpoint stays.
sed 's/young_modulus: 26.6e9/young_modulus: 30e9/' "$cases/vcross-drop-smoke.yaml" > "$out/stiffer.yaml"
cp -r "$out/split" "$out/stiffer"
if "$armour" --log-level warn deform "$out/stiffer.yaml" -o "$out/stiffer" --restart 2> "$out/stiffer.err"; then
  fail "a restart with another material was accepted"
fi
grep -q "was written for another setup: 'material.young_modulus = 26600000000 Pa' then, 'material.young_modulus = 30000000000 Pa' now" "$out/stiffer.err" \
  || fail "changed material: $(cat "$out/stiffer.err")"
cmp "$out/split/checkpoint.bin" "$out/stiffer/checkpoint.bin" || fail "a refused restart changed the checkpoint"
if deform -o "$out/none" --restart 2> "$out/none.err"; then fail "--restart without a checkpoint was accepted"; fi
grep -q "no checkpoint to continue from" "$out/none.err" || fail "--restart without a checkpoint: $(cat "$out/none.err")"
sed 's/poisson_ratio: 0.205/poisson_ratio: 0.5/' "$scene" > "$out/bad.yaml"
if "$armour" --log-level warn deform "$out/bad.yaml" -o "$out/bad" 2> "$out/bad.err"; then fail "poisson_ratio 0.5 accepted"; fi
grep -q "material.poisson_ratio = 0.5: must be in (-1, 0.5)" "$out/bad.err" || fail "bad poisson_ratio: $(cat "$out/bad.err")"
sed 's/shape: vcross/shape: vcros/' "$scene" > "$out/bad2.yaml"
if "$armour" --log-level warn deform "$out/bad2.yaml" -o "$out/bad2" 2> "$out/bad2.err"; then fail "unknown shape accepted"; fi
grep -q "did you mean 'vcross'" "$out/bad2.err" || fail "unknown shape: $(cat "$out/bad2.err")"
# Seed 002's rock dump, smoke: 8 angular rocks (one shape, random orientations, a grid of copies)
# thrown onto the floor of the bin land and are stressed by the impacts (von Mises above 1 MPa in
# a rock).
"$armour" --log-level warn deform "$cases/rock-dump-smoke.yaml" -o "$out/rocks" --threads 1
/usr/bin/python3 - "$out/rocks/summary.json" <<'PY' || fail "rock dump smoke: no impact stresses"
import json, sys
s = json.load(open(sys.argv[1]))
v = s["largest_von_mises"]
print("rock dump smoke: largest von Mises", v["value_Pa"] / 1e6, "MPa in", v["body"], "at", v["time_s"], "s")
assert v["body"].startswith("rock_"), v
assert v["value_Pa"] > 1e6, v
assert s["elements"] == 8 * 56, s["elements"]
PY
# Stopped by SIGTERM (exit 130, checkpoint written) and continued: the same bytes as the run that
# went through.
"$armour" --log-level warn deform "$cases/rock-dump-smoke.yaml" -o "$out/rocks-stopped" --threads 1 &
pid=$!
sleep 1.5
kill -TERM "$pid"
status=0
wait "$pid" || status=$?
[[ $status == 130 ]] || fail "SIGTERM: exit status $status, expected 130 (did the run end before the signal?)"
[[ -s "$out/rocks-stopped/checkpoint.bin" ]] || fail "SIGTERM: no checkpoint written"
"$armour" --log-level warn deform "$cases/rock-dump-smoke.yaml" -o "$out/rocks-stopped" --threads 1 --restart
for f in checkpoint.bin stress_history.csv; do
  cmp "$out/rocks/$f" "$out/rocks-stopped/$f" || fail "SIGTERM and restart: $f differs from the uninterrupted run"
done

# A deformable beam on two fixed rigid supports (rigid_bodies:, cases/deformable/beam-on-rigid-
# supports.yaml, coarse: 500 tets, 5 % mass scaling): damped to rest, the supports carry the
# weight, the added mass's included (it is real mass to gravity), half each within 1 %.
sed 's/    tets: 3000/    tets: 500/; s/^  duration: 0.04 .*/  duration: 0.04\n  mass_scaling: 0.05/' \
  "$cases/beam-on-rigid-supports.yaml" > "$out/beam.yaml"
"$armour" --log-level info deform "$out/beam.yaml" -o "$out/beam" --threads 1 > "$out/beam.log" 2>&1 \
  || fail "the beam on rigid supports failed: $(tail -n 3 "$out/beam.log")"
/usr/bin/python3 - "$out/beam.log" <<'PY' || fail "the rigid supports do not carry the beam's weight"
import re, sys
log = open(sys.argv[1]).read()
added = float(re.search(r"([0-9.e+-]+) kg added", log).group(1))
loads = {m.group(1): float(m.group(2)) for m in re.finditer(r"rigid body '(\w+)' carries \[[^,]+, [^,]+, ([^\]]+)\] N", log)}
weight = (2340.0 + added) * 9.81
assert set(loads) == {"left", "right"}, loads
assert abs(-(loads["left"] + loads["right"]) - weight) < 1e-3 * weight, (loads, weight)
for k, v in loads.items():
    assert abs(-v - weight / 2) < 0.01 * weight / 2, (k, v, weight / 2)
PY
# A rigid body given twice the keys of a deformable one is refused, naming the key.
printf 'bodies: [{shape: cube, volume: 1, position: [0, 0, 1]}]\nrigid_bodies: [{shape: cube, volume: 1, position: [0, 0, -1], tets: 10}]\nrun: {duration: 0.001}\n' > "$out/bad-rigid.yaml"
set +e; msg=$("$armour" --log-level warn deform "$out/bad-rigid.yaml" -o "$out/bad-rigid" 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "a rigid body with tets: expected exit 2, got $code: $msg"
grep -q "rigid_bodies\[0\].tets" <<< "$msg" || fail "a rigid body with tets: the key is not named in: $msg"

# A body from a mesh file: a Dolos exported at 2 m^3, scaled back to 1 m^3 by volume:, centred on
# its centroid at position:, on the floor; a missing file is refused naming the key.
"$armour" --log-level warn shape export dolos --volume 2 -o "$out/dolos.stl" > /dev/null
printf 'bodies: [{name: d, mesh: dolos.stl, volume: 1, tets: 300, position: [0, 0, 1]}]\nhalf_spaces: [{point: [0, 0, 0], normal: [0, 0, 1]}]\nrun: {duration: 0.0005}\n' > "$out/from-mesh.yaml"
"$armour" --log-level info deform "$out/from-mesh.yaml" -o "$out/from-mesh" --threads 1 > "$out/from-mesh.log" 2>&1 \
  || fail "a body from a mesh file failed: $(tail -n 3 "$out/from-mesh.log")"
vol=$(grep -o "body 'd': [0-9]* tetrahedra, [0-9.e+-]* m^3" "$out/from-mesh.log" | awk '{print $5}')
/usr/bin/python3 -c "import sys; v = float('$vol'); sys.exit(0 if abs(v - 1.0) < 1e-6 else 1)" \
  || fail "the mesh file's body should be scaled to 1 m^3, got '$vol'"
sed 's/dolos.stl/missing.stl/' "$out/from-mesh.yaml" > "$out/missing-mesh.yaml"
set +e; msg=$("$armour" --log-level warn deform "$out/missing-mesh.yaml" -o "$out/missing" 2>&1); code=$?; set -e
[ $code -eq 2 ] && grep -q "bodies\[0\].mesh = missing.stl: no such file" <<< "$msg" \
  || fail "a missing mesh file: expected exit 2 naming bodies[0].mesh, got $code: $msg"
# Moving rigid bodies (rigid_bodies[i].fixed: false; app/DeformRigidPack): a deformable cube
# (tet4) set on a free rigid block that stands on the floor, damped to rest: the block carries the
# cube's weight within 0.5 % and hardly moves. Continued from a stop at a frame time, the
# run ends with the same bytes in checkpoint.bin, stress_history.csv, the World's state
# (rigid_checkpoint.nc, build line aside) and the rigid frames; on 2 threads with the same bytes as
# on 1. A restart with the block made fixed, or with another density, is refused naming why; so is
# one whose rigid checkpoint is gone.
cat > "$out/stack.yaml" <<'YAML'
material: {mass_damping: 200}
element: tet4
bodies:
  - {name: cube, box: [0.5, 0.5, 0.5], cells: [2, 2, 2], position: [0.1, 0, 1.2505]}
rigid_bodies:
  - {name: block, shape: cube, volume: 1, position: [0, 0, 0.5], fixed: false}
half_spaces:
  - {point: [0, 0, 0], normal: [0, 0, 1]}
contact: {friction: 0.6}
run: {duration: 0.2, frames_every: 0.05}
YAML
stack() { "$armour" --log-level info deform "$out/stack.yaml" "$@"; }
stack -o "$out/stack" --threads 1 > "$out/stack.log" 2>&1 || fail "the stack on a moving block failed: $(tail -n 3 "$out/stack.log")"
/usr/bin/python3 - "$out/stack.log" <<'PY' || fail "the moving block does not carry the cube"
import re, sys
log = open(sys.argv[1]).read()
m = re.search(r"rigid body 'block' moved \[([^,]+), ([^,]+), ([^\]]+)\] m, speed ([0-9.e+-]+) m/s; it carries \[[^,]+, [^,]+, ([^\]]+)\] N", log)
assert m, "no closing line for the block"
moved = [float(m.group(k)) for k in (1, 2, 3)]
speed, carried = float(m.group(4)), float(m.group(5))
weight = 0.125 * 2340 * 9.81
print("block moved", moved, "m, speed", speed, "m/s, carries", carried, "N of the cube's weight", weight, "N")
assert abs(-carried - weight) < 0.005 * weight, (carried, weight)
assert max(abs(u) for u in moved) < 1e-3 and speed < 1e-3, (moved, speed)
PY
grep -o 'file="[^"]*"' "$out/stack/rigid/bodies.pvd" | sed 's/file="\(.*\)"/\1/' | while read -r frame; do
  [[ -s "$out/stack/rigid/$frame" ]] || fail "rigid/bodies.pvd lists $frame, which does not exist"
done
[[ $(grep -c '<DataSet' "$out/stack/rigid/bodies.pvd") == 5 ]] || fail "expected rigid frames at 0, 0.05, ..., 0.2 s"
stack -o "$out/stack-split" --threads 1 --duration 0.1 > /dev/null 2>&1
stack -o "$out/stack-split" --threads 1 --restart > /dev/null 2>&1 || fail "the moving block's restart failed"
for f in checkpoint.bin stress_history.csv rigid/bodies.pvd rigid/bodies/frame_000004.vtp; do
  cmp "$out/stack/$f" "$out/stack-split/$f" || fail "moving rigid bodies, restart: $f differs from the uninterrupted run"
done
rigid_state() { ncdump "$1" | grep -v armour_build; }
diff <(rigid_state "$out/stack/rigid_checkpoint.nc") <(rigid_state "$out/stack-split/rigid_checkpoint.nc") > /dev/null \
  || fail "moving rigid bodies, restart: rigid_checkpoint.nc differs from the uninterrupted run"
stack -o "$out/stack-2" --threads 2 > /dev/null 2>&1
cmp "$out/stack/checkpoint.bin" "$out/stack-2/checkpoint.bin" || fail "moving rigid bodies: 2 threads differ from 1"
sed 's/, fixed: false}/}/' "$out/stack.yaml" > "$out/stack-fixed.yaml"
set +e; msg=$("$armour" --log-level warn deform "$out/stack-fixed.yaml" -o "$out/stack-split" --restart 2>&1); code=$?; set -e
[ $code -eq 2 ] && grep -q "'rigid\[0\] = moving, .*' then, 'rigid\[0\] = position \[0, 0, 0.5\] m" <<< "$msg" || fail "restart with the block fixed: $code: $msg"
sed 's/fixed: false}/fixed: false, density: 2500}/' "$out/stack.yaml" > "$out/stack-dense.yaml"
set +e; msg=$("$armour" --log-level warn deform "$out/stack-dense.yaml" -o "$out/stack-split" --restart 2>&1); code=$?; set -e
[ $code -eq 2 ] && grep -q "does not match the scene.*density 2500" <<< "$msg" || fail "restart with another density: $code: $msg"
sed 's/contact: {friction: 0.6}/contact: {friction: 0.6, rigid_penalty_modulus: 1e14}/' "$out/stack.yaml" > "$out/stack-stiff.yaml"
set +e; msg=$("$armour" --log-level warn deform "$out/stack-stiff.yaml" -o "$out/stack-stiff" 2>&1); code=$?; set -e
[ $code -eq 2 ] && grep -q "contact.rigid_penalty_modulus: 1e+14 Pa: the rigid bodies' contact is stable for steps up to" <<< "$msg" \
  || fail "a rigid contact too stiff for the deformable step: $code: $msg"
rm "$out/stack-split/rigid_checkpoint.nc"
set +e; msg=$("$armour" --log-level warn deform "$out/stack.yaml" -o "$out/stack-split" --restart 2>&1); code=$?; set -e
[ $code -eq 2 ] && grep -q "the rigid bodies' state of step [0-9]* (that of checkpoint.bin) is not there" <<< "$msg" \
  || fail "restart without the rigid checkpoint: $code: $msg"
echo "deform CLI: outputs, tension, restart, refusals, the rock dump, the beam on rigid supports, a mesh file and moving rigid bodies as expected"
