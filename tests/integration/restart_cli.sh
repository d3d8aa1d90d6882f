#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `armour run --restart` end to end (tests/data/scenes/restart.yaml: sliding, tumbling and
# sleeping cubes, 2 s, checkpoints every 0.25 s). A run continued from its checkpoint must end
# exactly where an uninterrupted run ends: final_state.csv byte for byte, and the data of
# bodies.nc (every variable, every record) and the list of VTK frames identical. Cases: a run
# to T/2 (--duration) extended to T; a run stopped by SIGTERM (exit 130, checkpoint written,
# message) and restarted; a run killed by SIGKILL after a periodic checkpoint and restarted.
# Refusals: a changed scene (the changed line named), no checkpoint, the checkpoint of a
# guard-rail stop (checkpoint_at_error.nc is written and named, exit 3).
# Arguments: the armour binary, the scenes folder, a work folder.
set -euo pipefail
armour="$1"
scenes="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
scene="$scenes/restart.yaml"
run() { "$armour" --log-level warn run "$scene" --threads 1 "$@"; }

# The data of bodies.nc without the history attribute (which records each run's command line).
series() {
  if command -v ncdump > /dev/null; then
    ncdump "$1" | sed -n '/^data:/,$p'
  else
    /usr/bin/python3 - "$1" <<'EOF'
import sys, netCDF4, numpy
with netCDF4.Dataset(sys.argv[1]) as ds:
    for name, var in ds.variables.items():
        values = numpy.ma.getdata(var[:])
        print(name, values.dtype, values.shape, values.tobytes().hex())
EOF
  fi
}
# Same run: same final state (bytes), same series records, same VTK frame times.
same_as_reference() {
  local dir="$1" what="$2"
  cmp "$out/full/final_state.csv" "$dir/final_state.csv" || fail "$what: final_state.csv differs from the uninterrupted run"
  series "$out/full/bodies.nc" > "$out/full.series"
  series "$dir/bodies.nc" > "$dir.series"
  cmp "$out/full.series" "$dir.series" || fail "$what: bodies.nc data differs from the uninterrupted run"
  diff <(grep -o 'timestep="[^"]*"' "$out/full/bodies.pvd") <(grep -o 'timestep="[^"]*"' "$dir/bodies.pvd") \
    || fail "$what: bodies.pvd lists other frame times than the uninterrupted run"
  for f in $(grep -o 'file="[^"]*"' "$dir/bodies.pvd" | cut -d'"' -f2); do
    [ -f "$dir/$f" ] || fail "$what: bodies.pvd lists $f, which does not exist"
  done
  [ "$(ls "$dir/bodies" | wc -l)" -eq "$(grep -c '<DataSet' "$dir/bodies.pvd")" ] \
    || fail "$what: frame files not listed in bodies.pvd are left in $dir/bodies"
}
# Wait (at most 60 s) until the run writing into $1 has taken a periodic checkpoint.
wait_for_checkpoint() {
  for _ in $(seq 600); do
    [ -f "$1/checkpoint.nc" ] && return 0
    sleep 0.1
  done
  fail "no checkpoint.nc in $1 after 60 s"
}

# The reference: uninterrupted to T = 2 s. Periodic checkpoints do not perturb it (they only
# read the World): a run with checkpoints at the end only must end in the same bytes.
run -o "$out/full"
[ -f "$out/full/checkpoint.nc" ] || fail "no checkpoint.nc at the end of the run"
[ "$(wc -l < "$out/full/final_state.csv")" -eq 5 ] || fail "final_state.csv: expected a header and 4 rows"
sed 's/^  checkpoint_interval: .*/  checkpoint_interval: 0/' "$scene" > "$out/no-periodic.yaml"
"$armour" --log-level warn run "$out/no-periodic.yaml" --threads 1 -o "$out/no-periodic"
cmp "$out/full/final_state.csv" "$out/no-periodic/final_state.csv" \
  || fail "periodic checkpoints changed the run: final states differ"

# Extend: run to T/2, then restart to T (a longer duration than the checkpoint's run).
run -o "$out/half" --duration 1.0
log=$(run -o "$out/half" --restart 2>&1) || fail "restart to T failed: $log"
grep -q "restarted from t = [0-9.e-]* s (step [0-9]*)" "$out/half/run.log" \
  || fail "the run log does not say where the run restarted: $(grep -i restart "$out/half/run.log")"
[ -f "$out/half/run.1.log" ] || fail "the log of the first part was not kept as run.1.log"
# The first part ended off the output schedule (t = 1 s less round-off): its final frame and
# record are dropped, the uninterrupted run has neither.
grep -q "bodies.pvd: resuming at .*: keeping 4 of 5 frames" "$out/half/run.log" \
  || fail "extended run: the first part's final frame was not dropped: $(grep resuming "$out/half/run.log")"
grep -q "bodies.nc: resuming at .*: keeping 100 of 101 records" "$out/half/run.log" \
  || fail "extended run: the first part's final record was not dropped: $(grep resuming "$out/half/run.log")"
same_as_reference "$out/half" "extended run"

# SIGTERM: the run finishes the step, writes a checkpoint, says so and exits 130.
# (armour itself in the background, not the shell function, so that the signals reach it)
"$armour" --log-level warn run "$scene" --threads 1 -o "$out/term" 2> "$out/term.err" &
pid=$!
wait_for_checkpoint "$out/term"
sleep 0.3
kill -TERM $pid
set +e; wait $pid; code=$?; set -e
[ $code -eq 130 ] || fail "SIGTERM: expected exit 130, got $code (a run that ended first makes this test void): $(cat "$out/term.err")"
grep -q "stopped by SIGTERM at t = .*checkpoint written to .*checkpoint.nc" "$out/term.err" \
  || fail "SIGTERM: unclear message: $(cat "$out/term.err")"
grep -q "continue with: armour run .* --restart" "$out/term.err" || fail "SIGTERM: no restart hint: $(cat "$out/term.err")"
[ ! -f "$out/term/final_state.csv" ] || fail "SIGTERM: a stopped run must not write final_state.csv"
log=$(run -o "$out/term" --restart 2>&1) || fail "restart after SIGTERM failed: $log"
same_as_reference "$out/term" "run stopped by SIGTERM"

# SIGKILL after a periodic checkpoint: no chance to clean up; the restart drops what the killed
# run wrote after its last checkpoint and recomputes it. Checkpoints every 0.5 s here (an output
# setting, which a restart may change): the first is taken by t = 0.65 s and the next after
# 1 s, so a kill right after the 0.75 s frame leaves a frame newer than the checkpoint.
sed 's/^  checkpoint_interval: .*/  checkpoint_interval: 0.5/' "$scene" > "$out/kill.yaml"
"$armour" --log-level warn run "$out/kill.yaml" --threads 1 -o "$out/kill" 2> /dev/null &
pid=$!
for _ in $(seq 600); do
  grep -qs 'timestep="0.75' "$out/kill/bodies.pvd" && break
  sleep 0.05
done
kill -KILL $pid
set +e; wait $pid 2> /dev/null; code=$?; set -e
[ $code -eq 137 ] || fail "SIGKILL: expected exit 137, got $code (a run that ended first makes this test void)"
[ -f "$out/kill/checkpoint.nc" ] || fail "SIGKILL: no periodic checkpoint before the kill"
log=$(run -o "$out/kill" --restart 2>&1) || fail "restart after SIGKILL failed: $log"
grep -q "bodies.pvd: resuming at .*: keeping [0-9]* of [0-9]* frames" "$out/kill/run.log" || fail "SIGKILL: no resume in the log"
kept=$(grep -o "bodies.pvd: resuming at .*: keeping [0-9]* of [0-9]* frames" "$out/kill/run.log" | awk '{print $(NF-3), $(NF-1)}')
[ "${kept% *}" -lt "${kept#* }" ] || echo "note: SIGKILL came before a frame newer than the checkpoint (kept $kept)"
same_as_reference "$out/kill" "run killed by SIGKILL"
! ls "$out/kill" | grep -q '\.tmp\.' || fail "temporary files left: $(ls "$out/kill")"

# The constraint solver (issue 22): a run to T/2 extended to T ends in the bytes of the
# uninterrupted run too (the warm-start impulses and friction stretches are in the checkpoint).
crun() { run --set contact.solver=constraint "$@"; }
crun -o "$out/c-full"
crun -o "$out/c-half" --duration 1.0
log=$(crun -o "$out/c-half" --restart 2>&1) || fail "constraint solver: restart to T failed: $log"
grep -q "time step by stage (constraint solver" "$out/c-half/run.log" || fail "constraint solver: not used in $out/c-half"
cmp "$out/c-full/final_state.csv" "$out/c-half/final_state.csv" \
  || fail "constraint solver: the extended run's final_state.csv differs from the uninterrupted run's"
series "$out/c-full/bodies.nc" > "$out/c-full.series"
series "$out/c-half/bodies.nc" > "$out/c-half.series"
cmp "$out/c-full.series" "$out/c-half.series" || fail "constraint solver: bodies.nc data differs after the restart"
cmp -s "$out/full/final_state.csv" "$out/c-full/final_state.csv" && fail "constraint solver: same bytes as penalty (not used?)"

# The log of a killed run keeps every line logged before the kill (issue 23, item 12): run.log is
# flushed line by line, not in 8 KiB blocks. A long run is killed as soon as its first progress
# line (every 5 s of wall time) is in run.log, then restarted and killed as soon as the
# "restarted from" line is there; with a block-buffered log neither line reaches the file and the
# waits run out (20 s each).
wait_for_line() { # file, pattern
  for _ in $(seq 400); do
    grep -qs "$2" "$1" && return 0
    sleep 0.05
  done
  return 1
}
"$armour" --log-level warn run "$scene" --threads 1 --duration 600 -o "$out/killlog" 2> /dev/null &
pid=$!
wait_for_line "$out/killlog/run.log" "steps/s, ETA" || true
kill -KILL $pid 2> /dev/null || true
set +e; wait $pid 2> /dev/null; code=$?; set -e
[ $code -eq 137 ] || fail "log of a killed run: expected exit 137, got $code"
grep -q "steps/s, ETA" "$out/killlog/run.log" || fail "a run killed by SIGKILL lost its progress lines: $(tail -n 3 "$out/killlog/run.log")"
grep -q "checkpoints to .*checkpoint.nc" "$out/killlog/run.log" || fail "a run killed by SIGKILL lost its start-up lines"
"$armour" --log-level warn run "$scene" --threads 1 --duration 600 -o "$out/killlog" --restart 2> "$out/killlog.err" &
pid=$!
wait_for_line "$out/killlog/run.log" "restarted from t = " || true
kill -KILL $pid 2> /dev/null || true # (a restart that failed is gone; its message is in killlog.err)
set +e; wait $pid 2> /dev/null; code=$?; set -e
[ $code -eq 137 ] || fail "log of a killed restart: expected exit 137, got $code: $(cat "$out/killlog.err")"
grep -q "restarted from t = [0-9.e-]* s (step [0-9]*)" "$out/killlog/run.log" \
  || fail "a restarted run killed by SIGKILL lost its 'restarted from' line: $(tail -n 3 "$out/killlog/run.log")"
grep -q "steps/s, ETA" "$out/killlog/run.1.log" || fail "the killed first part's log was not kept as run.1.log"

# Refused: a changed material (the change named, exit 2, the run left as it was).
sed 's/friction: 0.5,/friction: 0.6,/' "$scene" > "$out/changed.yaml"
cp -r "$out/full" "$out/changed"
set +e; msg=$("$armour" --log-level off run "$out/changed.yaml" -o "$out/changed" --restart 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "changed scene: expected exit 2, got $code: $msg"
grep -q "checkpoint.nc: scene_fingerprint .* the scene changed .*friction static = 0.5.*friction static = 0.6" <<< "$msg" \
  || fail "changed scene: the message does not name the change: $msg"
cmp "$out/full/final_state.csv" "$out/changed/final_state.csv" || fail "a refused restart changed the folder"
[ ! -f "$out/changed/run.1.log" ] || fail "a refused restart moved the run log"

# Refused: nothing to restart from.
set +e; msg=$(run -o "$out/empty" --restart 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "no checkpoint: expected exit 2, got $code: $msg"
grep -q "empty/checkpoint.nc: no checkpoint here" <<< "$msg" || fail "no checkpoint: unclear message: $msg"

# A guard-rail stop writes checkpoint_at_error.nc beside state_at_error.csv and names both; a
# restart from the state of a failed step is refused.
set +e; msg=$("$armour" --log-level off run "$scenes/unrunnable/deep-overlap.yaml" --threads 1 -o "$out/overlap" 2>&1); code=$?; set -e
[ $code -eq 3 ] || fail "overlapping start: expected exit 3, got $code: $msg"
grep -q "state_at_error.csv, .*checkpoint_at_error.nc" <<< "$msg" || fail "the error checkpoint is not named: $msg"
[ -f "$out/overlap/checkpoint_at_error.nc" ] || fail "no checkpoint_at_error.nc"
if command -v ncdump > /dev/null; then
  header=$(ncdump -h "$out/overlap/checkpoint_at_error.nc") # (grep -q in a pipe would cut ncdump short: pipefail)
  grep -q ":stop_reason = .*body .*first.* and body .*second.* overlap" <<< "$header" \
    || fail "checkpoint_at_error.nc has no stop_reason naming the bodies"
fi
cp "$out/overlap/checkpoint_at_error.nc" "$out/overlap/checkpoint.nc"
set +e; msg=$("$armour" --log-level off run "$scenes/unrunnable/deep-overlap.yaml" -o "$out/overlap" --restart 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "restart from an error checkpoint: expected exit 2, got $code: $msg"
grep -q "stopped on an error" <<< "$msg" || fail "restart from an error checkpoint: unclear message: $msg"

echo "restart CLI: all checks passed"
