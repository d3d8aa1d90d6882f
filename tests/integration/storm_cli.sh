#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# armour storm-file synth | check | info, as a user runs them: small still-water, Airy and JONSWAP
# files are written (atomically: no .partial left), pass `check` and show their grid in `info`;
# a truncated copy fails `check` with exit 2 naming the file; bad options exit 2 naming the option.
set -euo pipefail
armour="$1"
out="$2"
rm -rf "$out" && mkdir -p "$out"
cd "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

# Still water on a 4 m x 3 m grid of 0.5 m voxels, seabed at z = 0.5 (one row without data).
set +e; msg=$("$armour" --log-level warn storm-file synth still --out still.nc --x-max 4 --z-max 3 --voxel 0.5 \
  --swl 2 --depth 1.5 --duration 1 --dt 0.5 2>&1); code=$?; set -e
[ $code -eq 0 ] || fail "synth still exited $code: $msg"
grep -q "^still.nc: 3 records" <<< "$msg" || fail "synth still: no record count in: $msg"
[ -f still.nc ] || fail "no still.nc"
[ ! -e still.nc.partial ] || fail "still.nc.partial left behind"

# An Airy wave, H = 0.3 m, T = 4 s on 2 m of water.
set +e; msg=$("$armour" --log-level warn storm-file synth airy --out airy.nc --x-max 10 --z-max 3 --swl 2 \
  --depth 2 --height 0.3 --period 4 --duration 8 --dt 0.1 2>&1); code=$?; set -e
[ $code -eq 0 ] || fail "synth airy exited $code: $msg"

# check: exit 0 and the summary line.
msg=$("$armour" --log-level warn storm-file check still.nc 2>&1)
grep -q "^still.nc: valid storm file (3 records, t = 0..1 s, dt = 0.5 s, 8 x 6 voxels of 0.5 x 0.5 m, 40 with data, variability: none)" \
  <<< "$msg" || fail "check still.nc: unexpected summary: $msg"
msg=$("$armour" --log-level warn storm-file check airy.nc 2>&1)
grep -q "^airy.nc: valid storm file (81 records, t = 0..8 s, dt = 0.1 s, 40 x 12 voxels" <<< "$msg" \
  || fail "check airy.nc: unexpected summary: $msg"

# info: grid, time axis, water, variability, provenance (with the command line), eta range.
msg=$("$armour" --log-level warn storm-file info still.nc 2>&1)
grep -q "^grid: *8 x 6 voxels (nx x nz) of 0.5 x 0.5 m, 40 with data" <<< "$msg" || fail "info: no grid in: $msg"
grep -q "^still water: *z = 2 m" <<< "$msg" || fail "info: no still water level in: $msg"
grep -q "^variability: *none" <<< "$msg" || fail "info: no variability line in: $msg"
grep -q "^source: *synthetic: still" <<< "$msg" || fail "info: no provenance in: $msg"
grep -q "^command: *armour storm-file synth still --out still.nc" <<< "$msg" || fail "info: no command in: $msg"
grep -q "^software: *armour [0-9.]* (git " <<< "$msg" || fail "info: no software in: $msg"
msg=$("$armour" --log-level warn storm-file info airy.nc 2>&1)
grep -q "^records: *81, t = 0 .. 8 s, dt = 0.1 s" <<< "$msg" || fail "info airy: no time axis in: $msg"
# The wave ramps up over 2 periods (8 s): eta stays within +-H/2 and reaches nearly H/2.
grep -Eq "^eta: *-0\.1[0-9]* \.\. 0\.1[0-9]* m" <<< "$msg" || fail "info airy: eta range not within 0.1..0.15 m: $msg"
json=$("$armour" --log-level warn storm-file info airy.nc --json 2>&1)
grep -q '"nx": 40, "nz": 12' <<< "$json" || fail "info --json: no grid in: $json"
grep -q '"variability": null' <<< "$json" || fail "info --json: no variability in: $json"

# JONSWAP with a variability model given on the command line: written to the header, a_n = Hs/2.
set +e; msg=$("$armour" --log-level warn storm-file synth jonswap --out sea.nc --x-max 5 --z-max 4 --voxel 0.5 \
  --swl 3 --depth 3 --hs 0.5 --tp 3 --components 32 --seed 7 --duration 3 --dt 0.5 \
  --variability 1.2,0.3,1.1,0.25,1.3,0.2,0.9,0.15 --prob-above 0.45,0.55 2>&1); code=$?; set -e
[ $code -eq 0 ] || fail "synth jonswap exited $code: $msg"
msg=$("$armour" --log-level warn storm-file check sea.nc 2>&1)
grep -q "variability: Weibull)" <<< "$msg" || fail "check sea.nc: no variability in: $msg"
msg=$("$armour" --log-level warn storm-file info sea.nc 2>&1)
grep -q "trough_below *shape 0.9, scale 0.15" <<< "$msg" || fail "info sea.nc: class fits missing: $msg"
grep -q "P(above the mean): crests 0.45, troughs 0.55" <<< "$msg" || fail "info sea.nc: probabilities missing: $msg"
grep -q "normalisation: P_n = 2513.81 Pa at a_n = 0.25 m" <<< "$msg" || fail "info sea.nc: normalisation: $msg"

# A truncated copy: exit 2, the file named.
head -c 3000 airy.nc > truncated.nc
set +e; msg=$("$armour" --log-level off storm-file check truncated.nc 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "check truncated.nc: expected exit 2, got $code: $msg"
grep -q "error: truncated.nc" <<< "$msg" || fail "check truncated.nc: the file is not named in: $msg"
set +e; msg=$("$armour" --log-level off storm-file info missing.nc 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "info missing.nc: expected exit 2, got $code: $msg"
grep -q "error: missing.nc" <<< "$msg" || fail "info missing.nc: the file is not named in: $msg"

# Refused settings: exit 2, the option named, no file left behind.
expect_refusal() { # expect_refusal <option named in the message> <synth arguments...>
  local option="$1"; shift
  set +e; msg=$("$armour" --log-level off storm-file synth "$@" --out refused.nc 2>&1); code=$?; set -e
  [ $code -eq 2 ] || fail "synth $*: expected exit 2, got $code: $msg"
  grep -q "error: $option" <<< "$msg" || fail "synth $*: $option not named in: $msg"
  [ ! -e refused.nc ] && [ ! -e refused.nc.partial ] || fail "synth $*: a file was left behind"
}
expect_refusal --height airy --height 2 --depth 2 --swl 2            # H/h = 1 > 0.78: breaks
expect_refusal --height airy --height 3 --period 3                    # H/L = 0.21 > 1/7
expect_refusal --height stokes2 --height 2 --period 14 --depth 6 --swl 6 # second harmonic > 1/4
expect_refusal --dt still --dt 0
expect_refusal --x-min still --x-min 25
expect_refusal --variability airy --variability 1,2,3
expect_refusal --height jonswap --height 2                            # jonswap takes --hs
msg=$("$armour" --log-level off storm-file synth airy --height 2 --depth 2 --swl 2 --out refused.nc 2>&1 || true)
grep -q "0.78" <<< "$msg" || fail "the breaking limit is not given in: $msg"
echo "storm_cli: all checks passed"
