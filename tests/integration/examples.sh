#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The numbered examples (examples/README.md), each run by its own run.sh, which checks its outcome
# against the physics (01: Coulomb's slide to 1 %; 02: a pile at rest; 03: the dry unit still,
# the wet ones moved; 04: a placed pack at rest for 2 s).
# Arguments: the armour binary, the examples folder, a work folder.
set -euo pipefail
armour="$1"
examples="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
count=0
for run in "$examples"/0*/run.sh; do
  name="$(basename "$(dirname "$run")")"
  bash "$run" "$armour" "$out/$name" > "$out/$name.log" 2>&1 || { tail -30 "$out/$name.log" >&2; echo "FAIL: $name" >&2; exit 1; }
  tail -1 "$out/$name.log"
  count=$((count + 1))
done
[[ $count -ge 4 ]] || { echo "FAIL: found $count examples, expected 4 or more" >&2; exit 1; }
echo "examples: OK ($count)"
