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
grep -Eq "update every 0.1 s \((exactly )?[0-9.]+ steps; records every 0.05 s on average, (exactly )?[0-9.]+ steps\): loads are evaluated at the exact update times" <<< "$checked" \
  || fail "check does not relate the time step to the storm's intervals: $checked"

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
# Records with a NaN (issue 23, item 11): `check` reads the records the run will read (storm times
# 12 .. 16 s plus one update interval) with the checks of `storm-file check`. A NaN in p at
# t = 15 s is refused, naming the file, the variable and the time; one at t = 17.5 s, which this
# run never reads, is not (`storm-file check` refuses both).
damage() { # source, target, record
  /usr/bin/python3 - "$1" "$2" "$3" <<'PY'
import shutil, sys, netCDF4, numpy
shutil.copy(sys.argv[1], sys.argv[2])
with netCDF4.Dataset(sys.argv[2], "a") as ds:
    iz, ix = [int(i[0]) for i in numpy.nonzero(numpy.asarray(ds["samples"][:]) > 0)]
    ds["p"][int(sys.argv[3]), iz, ix] = numpy.nan
PY
}
damage "$out/storm.nc" "$out/nan.nc" 300
damage "$out/storm.nc" "$out/nan-late.nc" 350
for f in nan nan-late; do sed "s/file: storm.nc/file: $f.nc/" "$out/scene.yaml" > "$out/$f.yaml"; done
set +e; msg=$("$armour" --log-level warn check "$out/nan.yaml" 2>&1); status=$?; set -e
[[ $status -eq 2 ]] || fail "check of a storm with a NaN in a record the run reads: expected exit 2, got $status: $msg"
grep -q "nan.nc: p = nan at t = 15 s (record 300)" <<< "$msg" || fail "the NaN is not located: $msg"
msg=$("$armour" --log-level warn check "$out/nan-late.yaml" 2>&1) || fail "check refused a NaN the run never reads: $msg"
grep -Eq "storm records: the [0-9]* records the run reads \\(storm times 12 \\.\\. 16\\.(1|0999)[0-9]* s\\) hold finite values" <<< "$msg" \
  || fail "check does not report the records it read: $msg"
set +e; msg=$("$armour" --log-level warn storm-file check "$out/nan-late.nc" 2>&1); status=$?; set -e
[[ $status -eq 2 ]] || fail "storm-file check should refuse the NaN at 17.5 s, got $status: $msg"
# The advice for a storm too short (issue 23, item 8): a file from 0.05 s and an offset of 0 s is
# an offset before the first record, not a duration too long (0.95 s is shorter than the file).
/usr/bin/python3 - "$out/storm.nc" "$out/late-start.nc" <<'PY'
import shutil, sys, netCDF4
shutil.copy(sys.argv[1], sys.argv[2])
with netCDF4.Dataset(sys.argv[2], "a") as ds:
    ds["time"][:] = ds["time"][:] + 0.05
PY
sed 's/file: storm.nc/file: late-start.nc/' "$out/scene.yaml" > "$out/late-start.yaml"
set +e
msg=$("$armour" --log-level warn check "$out/late-start.yaml" --set hydro.storm.time_offset=0 --set duration=0.95 2>&1); status=$?
set -e
[[ $status -eq 2 ]] || fail "an offset before the first record should exit 2, got $status: $msg"
grep -q "late-start.nc: holds storm times 0.05[0-9]* .. 18.0[45][0-9]* s, but the run needs 0 .. 0.95 s" <<< "$msg" || fail "unclear message: $msg"
grep -q "set the offset to at least 0.05 s (at most 17.1 s for this duration)" <<< "$msg" || fail "wrong advice: $msg"
! grep -q "shorten the duration" <<< "$msg" || fail "advises a shorter duration for a duration that fits: $msg"
set +e; msg=$("$armour" --log-level warn check "$out/late-start.yaml" --set duration=20 2>&1); set -e
grep -q "the file spans 18 s, less than the duration: shorten the duration to at most 18 s" <<< "$msg" \
  || fail "a duration longer than the file: wrong advice: $msg"
grep -q "shorten the duration to at most 2 s, set the offset to at most 10 s" <<< \
  "$("$armour" --log-level warn check "$out/short.yaml" 2>&1 || true)" || fail "a window past the end: wrong advice"

# Another storm in the same place: a restart must not mix two storms.
synth "$out/storm.nc" 19
set +e
msg=$(run -o "$out/halves" --restart --duration 5 2>&1); status=$?
set -e
[[ $status -eq 2 ]] || fail "a restart with another storm file should exit 2, got $status: $msg"
grep -q "the scene changed since the run started" <<< "$msg" || fail "unclear message: $msg"
echo "hydro_cli: all checks passed"
