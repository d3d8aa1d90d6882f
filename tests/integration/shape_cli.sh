#!/usr/bin/env bash
# The shape commands end to end: export every shape at a given Dn in every format, read it back
# with `shape info`, and check the volume (1e-6 relative: binary STL stores float32), the
# watertightness and the error messages for bad input.
set -euo pipefail
armour="$1"
out="$2"
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

dn=1.71
expected=$(awk -v d=$dn 'BEGIN { printf "%.9g", d*d*d }')
shapes=$("$armour" --log-level off shape list | awk '/^[a-z]/ {print $1}')
[ "$(echo "$shapes" | wc -l)" -ge 12 ] || fail "shape list shows fewer than 12 shapes: $shapes"
for shape in $shapes; do
  for ext in stl obj vtp; do
    "$armour" --log-level off shape export "$shape" --dn $dn -o "$out/$shape.$ext" >/dev/null
    info=$("$armour" --log-level off shape info "$out/$shape.$ext")
    grep -q "^watertight:    yes" <<< "$info" || fail "$shape.$ext not watertight: $info"
    grep -q "^valid solid:   yes" <<< "$info" || fail "$shape.$ext not valid: $info"
    v=$(echo "$info" | awk '/^volume:/ {print $2}')
    awk -v v="$v" -v e="$expected" 'BEGIN { r = (v - e) / e; if (r < 0) r = -r; exit !(r < 1e-6) }' \
      || fail "$shape.$ext volume $v, expected $expected"
  done
done

# ASCII STL and an explicit format.
"$armour" --log-level off shape export cube --volume 2 --format stl-ascii -o "$out/a.stl" >/dev/null
head -c 5 "$out/a.stl" | grep -q solid || fail "stl-ascii did not write ASCII"

# Bad input: exit code 2 and a message that names the problem and the fix.
expect_error() { # expect_error "fragment" command...
  local fragment="$1"; shift
  set +e; msg=$("$@" 2>&1); code=$?; set -e
  [ $code -eq 2 ] || fail "expected exit 2 from '$*', got $code: $msg"
  grep -q -- "$fragment" <<< "$msg" || fail "expected '$fragment' in: $msg"
}
expect_error "valid shapes are" "$armour" shape export blob --dn 1 -o "$out/x.stl"
expect_error "exactly one of --volume" "$armour" shape export cube -o "$out/x.stl"
expect_error "exactly one of --volume" "$armour" shape export cube --dn 1 --volume 1 -o "$out/x.stl"
expect_error "name=value" "$armour" shape export cube --dn 1 --param aspect_y -o "$out/x.stl"
expect_error "unknown mesh file extension" "$armour" shape export cube --dn 1 -o "$out/x.ply"
expect_error "cannot open" "$armour" shape info "$out/missing.stl"
# A cube with one face removed: not watertight, and `info` says so.
grep "^v" "$out/cube.obj" > "$out/open.obj"
grep '^f' "$out/cube.obj" | head -n 11 >> "$out/open.obj"
expect_error "open edges" "$armour" shape info "$out/open.obj"
echo "shape CLI: all checks passed"
