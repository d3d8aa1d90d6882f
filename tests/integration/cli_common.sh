#!/usr/bin/env bash
# Sourced by the command-line tests: `cli_setup "$@"` takes the armour program, the data folder and
# a fresh output folder from the test's arguments (armour, data, out); `fail` stops the test with
# a message; `expect_refusal TEXT COMMAND...` runs a command that must exit 2 with TEXT in its
# output (an input error that names what to fix).
set -euo pipefail
cli_setup() {
  armour="$1"
  data="$2"
  out="$3"
  rm -rf "$out" && mkdir -p "$out"
}
fail() { echo "FAIL: $*" >&2; exit 1; }
expect_refusal() {
  local want="$1"; shift
  set +e; local msg; msg=$("$@" 2>&1); local code=$?; set -e
  [ $code -eq 2 ] || fail "expected exit 2 from '$*', got $code: $msg"
  grep -q -- "$want" <<< "$msg" || fail "expected '$want' in: $msg"
}
