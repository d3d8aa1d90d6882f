#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Issue 9's ensembles: `armour ensemble --storm` places packings and replays storm realisations
# (variability seeds) on each, in one process and under `mpirun -np 2`. Checked:
#  - the members do not depend on the rank that ran them: the two ensemble.csv are identical to the
#    last bit (each member is a deterministic function of its seeds);
#  - ensemble.json's mean and standard deviation are those of the rows (1e-12 relative);
#  - the storm's variability is live: two seeds on the same packing give different damage, while the
#    packing measures of the same packing are identical;
#  - the damage counts are ordered (moved > 1 Dn <= moved > 0.5 Dn <= moved > 0.2 Dn);
#  - --realisations on a storm without a variability model is refused, naming the file;
#  - stopped by SIGINT in a placement, it exits 130 with the command that continues; continued with
#    --restart it reads the finished members back (not run again), continues the placement from
#    its checkpoint, and ends with the uninterrupted ensemble's tables to the last bit; a restart
#    with other inputs is refused, naming the member's record.
# Arguments: the armour binary, the placement cases folder, a work folder.
set -euo pipefail
armour="$1"
cases="$2"
out="$3"
rm -rf "$out" && mkdir -p "$out"
cd "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
cp "$cases/dolos-smoke.yaml" dolos.yaml
# A 7 m, 10 s Airy wave over the pack (SWL z = 8 m) with a Weibull variability model: 2 s of it.
"$armour" --log-level warn storm-file synth airy --out airy.nc --x-min -6 --x-max 16 --z-min -2 --z-max 14 \
  --voxel 0.5 --swl 8 --depth 10 --trunk-origin -4 --trunk-length 8 --height 7 --period 10 --duration 4 \
  --dt 0.05 --ramp 1 --variability 1.5,0.3,1.5,0.3,1.5,0.3,1.5,0.3 > synth.txt
"$armour" --log-level warn storm-file synth still --out still.nc --x-min -6 --x-max 16 --z-min -2 --z-max 14 \
  --voxel 0.5 --swl 8 --depth 10 --trunk-origin -4 --trunk-length 8 --duration 4 --dt 0.5 > synth-still.txt
set +e; msg=$("$armour" --log-level off ensemble dolos.yaml --runs 1 --storm still.nc --realisations 2 2>&1); code=$?; set -e
[ $code -eq 2 ] || fail "--realisations 2 on a storm without variability: expected exit 2, got $code: $msg"
grep -q "still.nc: carries no variability model" <<< "$msg" || fail "refusal does not name the file: $msg"

common=(ensemble dolos.yaml --runs 2 --storm airy.nc --realisations 2 --duration 2)
"$armour" --log-level warn "${common[@]}" --threads 1 --output serial > serial.txt 2>&1 \
  || fail "serial ensemble failed: $(tail -20 serial.txt)"
command -v mpirun > /dev/null || fail "mpirun not found: install openmpi-bin (scripts/install-deps)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mpirun -np 2 "$armour" --log-level warn "${common[@]}" --threads 1 --output mpi > mpi.txt 2>&1 \
  || fail "mpirun -np 2 ensemble failed: $(tail -20 mpi.txt)"
grep -q "on 2 ranks" mpi.txt || fail "the MPI run did not run on 2 ranks (armour built without MPI?): $(head -3 mpi.txt)"
cmp serial/ensemble.csv mpi/ensemble.csv || fail "the members differ between 1 and 2 ranks"
/usr/bin/python3 - serial/ensemble.csv serial/ensemble.json <<'PY' || fail "ensemble tables inconsistent"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
stats = json.load(open(sys.argv[2]))
assert len(rows) == 4 and stats["members"] == 4 and stats["failed"] == 0, (len(rows), stats)
assert all(r["status"] == "done" for r in rows)
for name, s in stats.items():
    if not isinstance(s, dict):
        continue
    v = [float(r[name]) for r in rows]
    m = sum(v) / len(v)
    sd = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1))
    assert abs(m - s["mean"]) <= 1e-12 * max(1.0, abs(m)), (name, m, s)
    assert abs(sd - s["std"]) <= 1e-12 * max(1.0, abs(sd)), (name, sd, s)
by_packing = {}
for r in rows:
    by_packing.setdefault(r["packing"], []).append(r)
    assert int(float(r["storm_moved_1dn"])) <= int(float(r["storm_moved_0.5dn"])) <= int(float(r["storm_moved_0.2dn"]))
for packing, members in by_packing.items():
    a, b = members
    assert a["storm_seed"] != b["storm_seed"]
    assert a["packing_density"] == b["packing_density"] and a["p2_q_tensor"] == b["p2_q_tensor"], packing
    da, db = float(a["storm_total_displacement_m"]), float(b["storm_total_displacement_m"])
    assert abs(da - db) > 1e-9 * max(da, db), ("variability seeds gave the same storm", packing, da, db)
    print(f"packing {packing}: total displacement {da:.4f} m (seed {a['storm_seed']}) vs {db:.4f} m (seed {b['storm_seed']})")
PY
for f in serial/member-000/placed.yaml serial/member-001/storm-0-seed-2/final_state.csv serial/member-001/storm-0-seed-2/run.log; do
  [ -s "$f" ] || fail "missing $f"
done
# Stopped and continued: checkpoints at every safe point of a placement, SIGINT as soon as the
# second packing's placement has one (the first packing and its two storm runs are done by then).
"$armour" --log-level warn "${common[@]}" --threads 1 --output stop --checkpoint-minutes 1e-9 > stop.txt 2> stop.err &
pid=$!
# (up to 10 min: a loaded CI machine; the ensemble alone takes about 30 s)
for _ in $(seq 1 12000); do [[ -e stop/member-001/place-checkpoint.nc ]] && break; sleep 0.05; done
[[ -e stop/member-001/place-checkpoint.nc ]] || { kill -INT "$pid"; fail "the second packing's placement never checkpointed"; }
kill -INT "$pid"
set +e; wait "$pid"; code=$?; set -e
[[ $code -eq 130 ]] || fail "stopped by SIGINT: exit $code ($(cat stop.err))"
grep -q "stopped by SIGINT while placing packing seed 2" stop.err || fail "the stop does not say where: $(cat stop.err)"
grep -q "continue with: armour ensemble dolos.yaml --restart --runs 2 " stop.err || fail "no restart command: $(cat stop.err)"
[[ -s stop/member-000/storm-0-seed-2/measures.csv ]] || fail "the finished members are not recorded"
set +e; msg=$("$armour" "${common[@]}" --threads 1 --output stop --restart --set placement.crane.speed=0.4 2>&1); code=$?; set -e
[[ $code -eq 2 ]] || fail "restart with another --set: exit $code: $msg"
grep -q "member-000/measures.csv: was written by an ensemble of other inputs" <<< "$msg" || fail "unclear message: $msg"
"$armour" --log-level warn "${common[@]}" --threads 1 --output stop --restart > restart.txt 2>&1 ||
  fail "restart failed: $(tail -20 restart.txt)"
[[ $(grep -c "placed before\|stormed before" restart.txt) -eq 3 ]] || fail "the finished members ran again: $(cat restart.txt)"
grep -q "continuing its placement from .*member-001/place-checkpoint.nc" restart.txt || fail "the placement started anew"
cmp serial/ensemble.csv stop/ensemble.csv || fail "the continued ensemble's members differ from the uninterrupted one's"
cmp serial/ensemble.json stop/ensemble.json || fail "the continued ensemble's statistics differ"
[[ ! -e stop/member-001/place-checkpoint.nc ]] || fail "the finished placement left its checkpoint"
set +e; msg=$("$armour" "${common[@]}" --output nowhere --restart 2>&1); code=$?; set -e
[[ $code -eq 2 ]] || fail "restart of an ensemble that never ran: exit $code"
grep -q "nowhere: does not exist, so there is no ensemble to continue" <<< "$msg" || fail "unclear message: $msg"
echo "ensemble_cli: OK"
