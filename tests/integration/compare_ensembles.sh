#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# utilities/compare_ensembles.py on two small tables whose statistics are known by hand:
#  - x: A = {1, 2, 3} (the failed member's 100 left out), B = {4, 6}: means 2 and 5, sd 1 and
#    sqrt(2), Welch's statistic (2 - 5) / sqrt(1/3 + 2/2) = -2.598;
#  - y: a NaN left out: A = {5, 7}, B = {5, 5}: (6 - 5) / sqrt(2/2 + 0) = +1.00;
#  - a file that is not an ensemble table is refused, naming it;
#  - --min-s 5 measures the storm damage again over the units placed 5 m or more up the slope,
#    from the members' analysis tables: A's one run has units at s 2, 6, 9 m displaced 3, 0.3 and
#    0.6 Dn (so 2 units kept: past 0.2 Dn 2, past 0.5 Dn 1, past 1 Dn 0, largest 0.6, mean 0.45).
# Arguments: the utilities folder, a work folder.
set -euo pipefail
utilities="$1"
out="$2"
rm -rf "$out" && mkdir -p "$out" && cd "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
printf 'member,packing,packing_seed,storm,storm_seed,x,y,status\n0,0,1,,,1,5,done\n1,1,2,,,2,nan,done\n2,2,3,,,3,7,done\n3,3,4,,,100,100,failed\n' > a.csv
printf 'member,packing,packing_seed,storm,storm_seed,x,y,status\n0,0,1,,,4,5,done\n1,1,2,,,6,5,done\n' > b.csv
table=$(/usr/bin/python3 "$utilities/compare_ensembles.py" a.csv b.csv --names A B)
grep -qF '| x | 2 +- 1 | 5 +- 1.4 | -2.60 |' <<< "$table" || fail "x: $table"
grep -qF '| y | 6 +- 1.4 | 5 +- 0 | +1.00 |' <<< "$table" || fail "y: $table"
grep -qF '| A (n = 3) | B (n = 2) |' <<< "$table" || fail "member counts: $table"
echo "not,a,table" > c.csv
set +e; msg=$(/usr/bin/python3 "$utilities/compare_ensembles.py" a.csv c.csv 2>&1); code=$?; set -e
[[ $code -ne 0 ]] || fail "a file that is not an ensemble table was read"
grep -q "c.csv: not an ensemble.csv" <<< "$msg" || fail "unclear message: $msg"
mkdir -p ra rb
for e in ra rb; do
  printf 'member,packing,packing_seed,storm,storm_seed,x,status\n0,0,1,s.nc,1,1,done\n' > $e/ensemble.csv
  mkdir -p $e/member-000/analysis $e/member-000/storm-0-seed-1/analysis
  printf 'unit,s\nu0,2\nu1,6\nu2,9\n' > $e/member-000/analysis/units.csv
done
printf 'unit,displacement_dn\nu0,3\nu1,0.3\nu2,0.6\n' > ra/member-000/storm-0-seed-1/analysis/units.csv
printf 'unit,displacement_dn\nu0,0\nu1,0.1\nu2,1.5\n' > rb/member-000/storm-0-seed-1/analysis/units.csv
table=$(/usr/bin/python3 "$utilities/compare_ensembles.py" ra/ensemble.csv rb/ensemble.csv --min-s 5)
for row in '| units | 2 +- 0 | 2 +- 0 |' '| moved_0.2dn | 2 +- 0 | 1 +- 0 |' '| moved_0.5dn | 1 +- 0 | 1 +- 0 |' \
           '| moved_1dn | 0 +- 0 | 1 +- 0 |' '| max_displacement_dn | 0.6 +- 0 | 1.5 +- 0 |' '| mean_displacement_dn | 0.45 +- 0 | 0.8 +- 0 |'; do
  grep -qF "$row" <<< "$table" || fail "--min-s: no row '$row' in: $table"
done
set +e; msg=$(/usr/bin/python3 "$utilities/compare_ensembles.py" ra/ensemble.csv rb/ensemble.csv --min-s 50 2>&1); code=$?; set -e
[[ $code -ne 0 ]] && grep -q "no unit placed 50.0 m or more up the slope" <<< "$msg" || fail "--min-s past every unit: $msg"
echo "compare_ensembles: OK"
