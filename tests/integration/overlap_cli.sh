#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Bodies that start inside each other (issue 23, item 9; simulation/Interpenetration.hpp). Each
# scene of tests/data/scenes/overlapping (two cubes at one pose, a duplicated Core-Loc, two
# Core-Locs at one centroid turned by 45 degrees) used to pass `armour check` ("0 engaged points")
# and run to the end with exit 0. Now `check` and `run` refuse each with exit 2, naming both
# bodies, their common volume as a share of the smaller one, and the fix; the run writes no
# final state. A scene whose bodies only touch passes and reports the largest share.
# Arguments: the armour binary, the scenes folder, a work folder.
set -euo pipefail
armour="$1"
scenes="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

refused() { # scene, first body, second body
  local scene="$scenes/overlapping/$1.yaml" name
  for command in check run; do
    set +e
    if [ $command = check ]; then
      msg=$("$armour" --log-level off check "$scene" 2>&1)
    else
      msg=$("$armour" --log-level off run "$scene" --threads 1 -o "$out/$1" 2>&1)
    fi
    code=$?
    set -e
    [ $code -eq 2 ] || fail "$command $1: expected exit 2, got $code: $msg"
    grep -q "error: .*$1.yaml: bodies '$2' and '$3' lie inside each other: they share [0-9.]* % of the smaller one's volume" <<< "$msg" \
      || fail "$command $1: both bodies and the share are not named: $msg"
    grep -q "move them apart, remove the duplicate, or check the placement file" <<< "$msg" \
      || fail "$command $1: no fix in: $msg"
  done
  [ ! -f "$out/$1/final_state.csv" ] || fail "run $1: a refused run wrote final_state.csv"
}
refused same-pose block_a block_b
refused duplicated-coreloc unit_0 unit_2
refused turned-45 upright turned
msg=$("$armour" --log-level off check "$scenes/overlapping/same-pose.yaml" 2>&1 || true)
grep -q "same position and orientation (a duplicated body)" <<< "$msg" || fail "same-pose: the duplicate is not called one: $msg"

# Touching bodies pass: the restart scene's stack (two cubes on each other, on the floor).
msg=$("$armour" --log-level warn check "$scenes/restart.yaml" 2>&1) || fail "restart.yaml refused: $msg"
grep -q "^interpenetration: [0-9]* pairs with overlapping boxes, .* largest share [0-9.e+-]* % .* lattice points in [0-9.]* s" <<< "$msg" \
  || fail "check does not report the interpenetration measure: $msg"
echo "overlap CLI: all checks passed"
