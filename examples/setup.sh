# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by each example's run.sh with its arguments, [ARMOUR] [OUT]: sets $armour (the binary;
# a path is made absolute; default: armour on the PATH) and makes and enters $out (default ./out).
armour="${1:-armour}"
[[ "$armour" == */* ]] && armour="$(cd "$(dirname "$armour")" && pwd)/$(basename "$armour")"
out="${2:-$PWD/out}"
mkdir -p "$out" && cd "$out"
