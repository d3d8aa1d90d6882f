#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Issue 23: storm files with damaged HDF5 metadata (tests/fuzz/regressions/storm/*.nc, bits flipped in
# a valid storm file) crash libhdf5 1.10 inside nc_open (a double free or a wild pointer in
# H5G__link_release_table). armour reads a storm file in a child process first
# (core/ProbeInChild.hpp): the command must end normally with exit 2 and an error naming the file,
# the signal and the fix, never die by a signal.
#
# Whether the library crashes depends on what the freed memory held: in a fresh process it is often
# zero and the library only returns an error. MALLOC_PERTURB_ (glibc) fills allocations with a
# pattern, which makes the crash happen on every run. The control run (the child probe switched
# off, ARMOUR_PROBE_IN_CHILD=0) shows that each file does crash the library; if a later libhdf5
# no longer crashes on it, the test says so and checks the ordinary error instead.
set -euo pipefail
armour="$1"
reproducers="$2"
scenes="$3"
out="$4"
rm -rf "$out" && mkdir -p "$out"
cd "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
export MALLOC_PERTURB_=165

count=0
for file in "$reproducers"/*.nc; do
  name=$(basename "$file")
  cp "$file" "$name"
  # Control: without the child, the library crashes (exit 128 + signal).
  set +e; ARMOUR_PROBE_IN_CHILD=0 "$armour" --log-level off storm-file check "$name" > control.log 2>&1; control=$?; set -e
  # With it (the default): exit 2 and the error.
  set +e; msg=$("$armour" --log-level off storm-file check "$name" 2>&1); code=$?; set -e
  [ $code -eq 2 ] || fail "$name: expected exit 2, got $code: $msg"
  grep -q "error: $name: " <<< "$msg" || fail "$name: the file is not named in: $msg"
  if [ $control -gt 128 ]; then
    grep -q "crashed the netCDF/HDF5 library with signal $((control - 128)) " <<< "$msg" \
      || fail "$name: the library died by signal $((control - 128)) without the child, but the error does not say so: $msg"
    grep -q "the file's HDF5 structure is damaged" <<< "$msg" || fail "$name: no diagnosis in: $msg"
    grep -q "regenerate it (foam-proxy sample, or armour storm-file synth) or copy it again" <<< "$msg" \
      || fail "$name: no fix in: $msg"
    echo "$name: without the child the library dies by signal $((control - 128)); with it: exit 2"
  else
    echo "NOTE: $name no longer crashes this libhdf5 (exit $control without the child): the ordinary error is checked"
  fi
  count=$((count + 1))
done
[ $count -ge 1 ] || fail "no reproducer in $reproducers"

# The same through a scene: armour check opens the storm file of the hydro block after building the
# scene (its allocations leave the memory that the library then misreads: no MALLOC_PERTURB_ needed).
unset MALLOC_PERTURB_
cp "$scenes/wave-slope.yaml" .
first=$(ls "$reproducers"/*.nc | head -n 1)
cp "$first" storm.nc
set +e; msg=$("$armour" --log-level off check wave-slope.yaml 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "check wave-slope.yaml with a damaged storm.nc: expected exit 2, got $code: $msg"
grep -q "error: .*storm.nc: reading this storm file" <<< "$msg" || fail "check wave-slope.yaml: no storm-file error in: $msg"

echo "storm_damaged_cli: all checks passed ($count reproducers)"
