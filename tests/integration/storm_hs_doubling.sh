#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Issue 9: doubling Hs increases damage. The crane-placed dolos pack (cases/placement/dolos-smoke.yaml:
# four 17 t dolosse on a rough 1:2 slope, z 1.4-3.2 m) under two regular seas that differ only in
# the wave height, H = 3.5 m and 7 m (Hs = H for a regular sea; Airy, T = 10 s, 10 m of water,
# SWL z = 8 m, with seed 000's Weibull variability model normalised by rho g H / 2), 6 s each
# through `armour storm`. Required: the total displacement (sum over units, from the placed pack)
# and the largest unit displacement both grow by more than half when H doubles (Froude-Krylov
# forces and the variability scale with H, drag with H^2, and a pack resting on friction responds
# more than proportionally: 0.54 m and 0.27 Dn against 8.1 m and 3.7 Dn when written), and no count
# of moved units falls.
# Why regular waves: a JONSWAP sea of Hs 6 m (the most a linear sea allows on 10 m of water) gives
# these 17 t units horizontal loads below 15 kN against 167 kN of weight in its first 14 s, so
# neither sea moves them and the comparison would test nothing; the regular wave's every crest is
# its largest.
# Arguments: the armour binary, the placement cases folder, a work folder.
set -euo pipefail
armour="$1"
cases="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
cd "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
cp "$cases/dolos-smoke.yaml" dolos.yaml
"$armour" --log-level warn place dolos.yaml --threads 1 > place.txt || fail "place failed: $(cat place.txt)"
for hs in 3.5 7; do
  "$armour" --log-level warn storm-file synth airy --out "hs$hs.nc" --x-min -6 --x-max 16 --z-min -2 --z-max 14 \
    --voxel 0.5 --swl 8 --depth 10 --trunk-origin -4 --trunk-length 8 --height "$hs" --period 10 --duration 6 \
    --dt 0.05 --ramp 1 --variability 1.5,0.3,1.5,0.3,1.5,0.3,1.5,0.3 > "synth$hs.txt"
  "$armour" --log-level warn storm dolos-placed.yaml --storm "hs$hs.nc" --threads 1 -o "run$hs" > "storm$hs.txt" 2>&1 \
    || fail "armour storm (Hs $hs m) failed: $(tail -5 "storm$hs.txt")"
  "$armour" --log-level warn analyse dolos-placed.yaml --state "run$hs/final_state.csv" --reference dolos-placed.yaml \
    --units unit_ --output "damage$hs" > "analyse$hs.txt" || fail "analyse failed: $(cat "analyse$hs.txt")"
done
/usr/bin/python3 - damage3.5/pack.json damage7/pack.json <<'PY' || fail "doubling Hs did not increase the damage"
import json, sys
small, large = (json.load(open(p)) for p in sys.argv[1:3])
print(f"H 3.5 m: total {small['total_displacement_m']:.4f} m, max {small['max_displacement_dn']:.4f} Dn, moved {small['moved_more_than_dn']}")
print(f"H 7 m: total {large['total_displacement_m']:.4f} m, max {large['max_displacement_dn']:.4f} Dn, moved {large['moved_more_than_dn']}")
assert large["total_displacement_m"] > 1.5 * small["total_displacement_m"], "total displacement"
assert large["max_displacement_dn"] > 1.5 * small["max_displacement_dn"], "largest displacement"
for k, n in small["moved_more_than_dn"].items():
    assert large["moved_more_than_dn"][k] >= n, ("moved count fell", k)
PY
echo "storm_hs_doubling: OK"
