#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Storm replay end to end (tests/data/scenes/wave-slope.yaml): synthesise an Airy storm file next
# to a copy of the scene, `armour check` it (the storm file is opened and must cover the run),
# `armour run` it, and check that
#  - the loaded units feel hydrodynamic forces in bodies.nc (hydro_force), the dry unit and the
#    fixed rock none;
#  - a run stopped at half time and continued with --restart ends bit for bit where the
#    uninterrupted run ends (the hydro stage's held loads are in the checkpoint);
#  - `armour storm` with the storm on the command line replays the same run bit for bit, and
#    runs to the storm's end without --duration;
#  - a storm file too short for the run, a missing storm file, and a changed storm file on
#    restart are refused with messages that name the file and the fix.
# Arguments: the armour binary, the scenes folder, a work folder.
set -euo pipefail
armour="$1"
scenes="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
cp "$scenes/wave-slope.yaml" "$out/scene.yaml"
synth() {
  "$armour" --log-level warn storm-file synth airy --out "$1" --x-min 0 --x-max 24 --z-min 0 --z-max 10 \
    --voxel 0.25 --swl 6 --depth 4 --height 1.5 --period 6 --duration "$2"
}
synth "$out/storm.nc" 18
run() { "$armour" --log-level warn run "$out/scene.yaml" --threads 1 "$@"; }

# check: the storm file is read and covers storm times 12 .. 16 s.
checked=$("$armour" --log-level warn check "$out/scene.yaml")
grep -q "hydro: storm .*storm.nc (361 records" <<< "$checked" || fail "check does not report the storm file: $checked"
grep -q "4 loaded bodies" <<< "$checked" || fail "check should count 4 loaded units: $checked"

# The run, and the hydrodynamic forces it recorded.
run -o "$out/full"
[[ -f "$out/full/bodies.nc" ]] || fail "no bodies.nc"
/usr/bin/python3 - "$out/full/bodies.nc" <<'PY' || fail "hydro_force in bodies.nc is wrong"
import sys, netCDF4, numpy
with netCDF4.Dataset(sys.argv[1]) as ds:
    names = [n.strip() for n in netCDF4.chartostring(ds["body_name"][:])]
    f = numpy.asarray(ds["hydro_force"][:])            # (time, body, 3)
    mass = 2400.0                                       # cube of 1 m^3
    g = 9.81
    mean = {n: f[:, i, :].mean(axis=0) for i, n in enumerate(names)}
    peak = {n: numpy.abs(f[:, i, :]).max() for i, n in enumerate(names)}
    # The submerged cube: buoyancy about rho g V = 1025 x 9.81 x 1 N upward on average (waves add
    # and take away; 20 % covers them), horizontal loads from the wave's pressure gradient and drag.
    assert 0.8 * 1025 * g < mean["unit_deep"][2] < 1.2 * 1025 * g, mean["unit_deep"]
    assert peak["unit_deep"] > 0, peak
    assert numpy.abs(f[:, names.index("unit_deep"), 0]).max() > 100.0, "no horizontal wave load on unit_deep"
    assert peak["unit_swl"] > 100.0, peak           # in and out of the water
    assert peak["unit_coreloc"] > 100.0, peak
    assert peak["unit_dry"] == 0.0, peak             # above every crest: no load, no cost
    assert peak["rock"] == 0.0, peak                 # fixed bodies never take loads
print("hydro forces ok")
PY

# Stop at half time, continue: bit for bit.
run -o "$out/halves" --duration 2
run -o "$out/halves" --restart
cmp "$out/full/final_state.csv" "$out/halves/final_state.csv" || fail "the restarted storm replay differs from the uninterrupted one"

# armour storm: the same storm given on the command line replays the same run, bit for bit;
# without --duration it runs to the storm's end (offset 16 s of an 18 s storm: 2 s).
"$armour" --log-level warn storm "$out/scene.yaml" --storm "$out/storm.nc" --duration 4 --threads 1 -o "$out/storm-cmd"
cmp "$out/full/final_state.csv" "$out/storm-cmd/final_state.csv" || fail "armour storm differs from armour run of the same storm"
"$armour" --log-level warn storm "$out/scene.yaml" --storm "$out/storm.nc" --time-offset 16 --threads 1 -o "$out/storm-end"
/usr/bin/python3 - "$out/storm-end/bodies.nc" <<'PY' || fail "armour storm without --duration should run to the storm's end (2 s)"
import sys, netCDF4
with netCDF4.Dataset(sys.argv[1]) as ds:
    t = float(ds["time"][-1])
    assert abs(t - 2.0) < 1e-2, t
PY
set +e
msg=$("$armour" --log-level warn storm "$out/scene.yaml" --storm "$out/storm.nc" --time-offset 20 2>&1); status=$?
set -e
[[ $status -eq 2 ]] || fail "an offset past the storm's end should exit 2, got $status: $msg"
grep -q "is at or after the end of the storm file" <<< "$msg" || fail "unclear message: $msg"

# Refusals.
synth "$out/short.nc" 14
sed 's/file: storm.nc/file: short.nc/' "$out/scene.yaml" > "$out/short.yaml"
set +e
msg=$("$armour" --log-level warn check "$out/short.yaml" 2>&1); status=$?
set -e
[[ $status -eq 2 ]] || fail "a storm file too short should exit 2, got $status: $msg"
grep -q "short.nc: holds storm times 0 .. 14 s, but the run needs 12 .. 16 s" <<< "$msg" || fail "unclear message: $msg"
sed 's/file: storm.nc/file: missing.nc/' "$out/scene.yaml" > "$out/missing.yaml"
set +e
msg=$("$armour" --log-level warn check "$out/missing.yaml" 2>&1); status=$?
set -e
[[ $status -eq 2 ]] || fail "a missing storm file should exit 2, got $status: $msg"
grep -q "missing.nc" <<< "$msg" || fail "the message should name the missing file: $msg"
# Another storm in the same place: a restart must not mix two storms.
synth "$out/storm.nc" 19
set +e
msg=$(run -o "$out/halves" --restart --duration 5 2>&1); status=$?
set -e
[[ $status -eq 2 ]] || fail "a restart with another storm file should exit 2, got $status: $msg"
grep -q "the scene changed since the run started" <<< "$msg" || fail "unclear message: $msg"
echo "hydro_cli: all checks passed"
