#!/usr/bin/env bash
# The README's "Deploy on your rig" quick start, run as a lab would run it
# (the snippets and values are read from README.md itself, so a quick start
# that stops working fails here):
#  1. the remap launch file of "Launch arguments and remaps", written to a
#     file and launched on a master of our own (a free port): the node must
#     subscribe to the DAQ's and the vision system's topics it names;
#  2. calibration step 2: a session recorded with the README's
#     `roslaunch acoustic_firmness record.launch prefix:=/data/calib` (the
#     prefix moved to the scratch folder) while a strike_bag bag plays (the
#     rig), then `firmness_report calib_*.bag --config station.yaml
#     --cultivar cultivar.yaml` with copies of the shipped
#     files; the modulus_factor it advises, written into the cultivar copy,
#     must bring the median E(0S2) / fitted E2 to 1 (within 2e-4, the
#     printed digits);
#  3. step 3: the README's `yield_measured` example in the cultivar copy is
#     accepted by `firmness_model design --cultivar your.yaml` and by the
#     report;
#  4. step 4: the README's `grade_classes` example grades the strikes with
#     its class names.
# No process of ours may outlive the test. Registered as scripts_quick_start.
set -euo pipefail
source "$(dirname "$0")/harness.sh"
lib="$AF_DEVEL/lib/acoustic_firmness"
readme="$AF_ROOT/README.md"

# The README's snippets and example values.
/usr/bin/python3 - "$readme" "$tmp" <<'PY' || bad "README: a quick-start snippet is missing"
import re, sys
text = open(sys.argv[1]).read()
launch = re.search(r'```\n(<launch>\n.*?</launch>)\n```', text, re.S)
flat = ' '.join(text.split())
yield_measured = re.search(r'`yield_measured: ("[^"]*")`', flat)
grades = re.search(r'e\.g\. `("[^"|]*(?:\|[^"|]*)+")`', flat)
record = re.search(r'`(roslaunch acoustic_firmness record\.launch prefix:=/data/calib)`', flat)
report = re.search(r'`(firmness_report calib_\*\.bag --config station\.yaml --cultivar cultivar\.yaml)`', flat)
design = re.search(r'`(firmness_model design --cultivar your\.yaml)`', flat)
missing = [n for n, m in (('remap launch', launch), ('yield_measured', yield_measured),
                          ('grade_classes', grades), ('record.launch', record),
                          ('firmness_report', report), ('design', design)) if m is None]
if missing:
    print('README: not found: ' + ', '.join(missing))
    sys.exit(1)
open(sys.argv[2] + '/my_rig.launch', 'w').write(launch.group(1) + '\n')
open(sys.argv[2] + '/yield_measured', 'w').write(yield_measured.group(1))
open(sys.argv[2] + '/grade_classes', 'w').write(grades.group(1))
open(sys.argv[2] + '/record', 'w').write(record.group(1) + '\n')
PY
[ "$fail" -eq 0 ] || exit 1

port=$(af_free_port)
af_start_master "$port" "$tmp/master.log"

# 1. The remap launch file: the node listens where the lab's topics are.
roslaunch "$tmp/my_rig.launch" >"$tmp/launch.log" 2>&1 &
pids+=("$!")
af_wait_node /lane1/firmness_node || fail=1
remapped=$(sed -n 's|.*<remap from="[a-z]*" to="\([^"]*\)"/>.*|\1|p' "$tmp/my_rig.launch")
[ "$(wc -w <<<"$remapped")" -eq 3 ] || bad "my_rig.launch: expected three remaps, found '$remapped'"
for topic in $remapped; do
  for i in $(seq 50); do
    rostopic info "$topic" 2>/dev/null | sed -n '/Subscribers:/,$p' | grep -q /lane1/firmness_node && break
    [ "$i" = 50 ] && { bad "the remapped node does not subscribe to $topic"; break; }
    sleep 0.2
  done
done
af_stop_all
af_check_stopped "$port" || fail=1

# 2. Record a session as the README says, while a strike_bag bag plays the rig.
af_start_master "$port" "$tmp/master.log"
"$lib/strike_bag" --strikes 30 --seed 4 --out "$tmp/rig.bag" 2>/dev/null
read -r -a record <"$tmp/record"
(cd "$tmp" && exec "${record[@]/prefix:=\/data\/calib/prefix:=$tmp/calib}" >"$tmp/record.log" 2>&1) &
rec=$!
pids+=("$rec")
for topic in /lane1/force /lane1/audio /lane1/apple; do
  af_wait_subscriber "$topic" /record_lane1 30 || bad "record.launch never subscribed to $topic"
done
# played once the recorder is connected on each topic (not only registered)
/usr/bin/python3 "$AF_ROOT/scripts/play_connected.py" --wait /record_lane1 -- -q "$tmp/rig.bag" \
  >/dev/null || bad "the rig's bag was not played to the recorder"
sleep 1
kill -INT "$rec" 2>/dev/null || true
wait "$rec" 2>/dev/null || true
for _ in $(seq 150); do ls "$tmp"/calib_*.bag >/dev/null 2>&1 && break; sleep 0.2; done
af_stop_all
af_check_stopped "$port" || fail=1
ls "$tmp"/calib_*.bag >/dev/null 2>&1 || { bad "record.launch wrote no calib_*.bag"; cat "$tmp/record.log" >&2; exit 1; }
mv "$tmp"/calib_*.bag "$tmp/run.bag"

cp "$AF_ROOT/config/station.yaml" "$tmp/station.yaml"
cp "$AF_ROOT/config/jonagold.yaml" "$tmp/cultivar.yaml"
report() { (cd "$tmp" && "$lib/firmness_report" run.bag --config station.yaml --cultivar cultivar.yaml "$@"); }
report >"$tmp/report1.txt" 2>&1 || bad "firmness_report run.bag exited $?"
grep -q '^  strikes 30: 30 on an apple' "$tmp/report1.txt" || bad "the recorded session does not hold the 30 strikes: $(grep 'strikes' "$tmp/report1.txt" | head -1)"
factor=$(sed -n 's/.*modulus_factor should be \([0-9.]*\) (run with 1.0000)/\1/p' "$tmp/report1.txt")
[ -n "$factor" ] || bad "firmness_report advises no modulus_factor"
sed -i "s/^modulus_factor: [^ ]*/modulus_factor: $factor/" "$tmp/cultivar.yaml"
grep -q "^modulus_factor: $factor " "$tmp/cultivar.yaml" || bad "cultivar.yaml: modulus_factor not set"
report >"$tmp/report2.txt" 2>&1 || bad "firmness_report with modulus_factor $factor exited $?"
median=$(sed -n 's/.*E(0S2) \/ fitted E2 median \([0-9.]*\),.*/\1/p' "$tmp/report2.txt")
/usr/bin/python3 -c "import sys; sys.exit(abs(float('$median') - 1.0) > 2e-4)" 2>/dev/null \
  || bad "with modulus_factor $factor the median E(0S2) / fitted E2 is '$median', not 1"
echo "quick start: modulus_factor $factor advised; median ratio with it $median"

# 3. The README's measured yield stresses.
yield=$(cat "$tmp/yield_measured")
sed -i "s/^yield_measured: \"\"/yield_measured: $yield/" "$tmp/cultivar.yaml"
grep -qF "yield_measured: $yield" "$tmp/cultivar.yaml" || bad "cultivar.yaml: yield_measured not set"
(cd "$tmp" && "$lib/firmness_model" design --cultivar cultivar.yaml) >"$tmp/design.txt" 2>&1 \
  || bad "firmness_model design --cultivar with yield_measured $yield exited $?: $(tail -2 "$tmp/design.txt")"
report >"$tmp/report3.txt" 2>&1 || bad "firmness_report with yield_measured $yield exited $?"

# 4. The README's grade classes: every class name is given to some strike.
classes=$(cat "$tmp/grade_classes")
sed -i "s/^grade_classes: .*/grade_classes: $classes/" "$tmp/cultivar.yaml"
report --csv "$tmp/strikes.csv" >"$tmp/report4.txt" 2>&1 || bad "firmness_report with grade_classes $classes exited $?"
/usr/bin/python3 - "$tmp/strikes.csv" "$classes" <<'PY' || bad "the README's grade classes are not all given"
import csv, sys
names = [p.strip() for p in sys.argv[2].strip('"').split('|')][0::2]
given = {row['grade'] for row in csv.DictReader(open(sys.argv[1]))}
print('quick start: classes %s; given %s' % (names, sorted(given)))
sys.exit(0 if set(names) <= given else 1)
PY
exit "$fail"
