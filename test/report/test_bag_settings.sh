#!/usr/bin/env bash
# firmness_report judges a bag with the node's settings recorded in it
# (/NS/settings, std_msgs/String, as the node publishes it latched and
# record.launch records it) when no file is given, and says so; --config or
# --cultivar set it aside, and says so; bags that disagree, or a snapshot
# that is not one, are refused with one line. The snapshots are written here
# from the shipped YAML files (comments dropped), with rosbag's Python, not
# by the node's writer.
#   test_bag_settings.sh FIRMNESS_REPORT STRIKE_BAG   (in the devel space's environment)
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}
root=$(cd "$(dirname "$0")/../.." && pwd)

"$SB" --strikes 6 --seed 9 --out "$tmp/plain.bag" >/dev/null 2>&1 || bad "strike_bag failed"

# with_settings IN OUT [KEY=VALUE...]: IN with a /lane1/settings message: the
# shipped files' rows, KEY's value replaced.
with_settings() {
  "$PY" - "$root/config" "$@" <<'EOF'
import re, sys, rosbag, rospy
from std_msgs.msg import String
config, src, dst, changes = sys.argv[1], sys.argv[2], sys.argv[3], dict(a.split('=', 1) for a in sys.argv[4:])
rows = []
for name in ('station.yaml', 'jonagold.yaml'):
    for line in open(config + '/' + name):
        line = re.sub(r'\s+#.*$', '', line.rstrip('\n'))
        if not line or line.startswith('#'):
            continue
        key, value = line.split(':', 1)
        rows.append('%s: %s' % (key, changes.pop(key, value.strip())))
rows += ['%s: %s' % kv for kv in changes.items()]   # a key the files do not have
with rosbag.Bag(src) as b_in, rosbag.Bag(dst, 'w') as b_out:
    t0 = b_in.get_start_time()
    b_out.write('/lane1/settings', String(data='\n'.join(rows) + '\n'), rospy.Time.from_sec(t0))
    for topic, msg, t in b_in.read_messages():
        b_out.write(topic, msg, t)
EOF
}
with_settings "$tmp/plain.bag" "$tmp/f11.bag" modulus_factor=1.1 || bad "writing f11.bag"
with_settings "$tmp/plain.bag" "$tmp/f11b.bag" modulus_factor=1.1 || bad "writing f11b.bag"
with_settings "$tmp/plain.bag" "$tmp/f12.bag" modulus_factor=1.2 || bad "writing f12.bag"
with_settings "$tmp/plain.bag" "$tmp/bogus.bag" no_such_row=3 || bad "writing bogus.bag"

factor_now() { "$PY" -c 'import json,sys; print(json.load(open(sys.argv[1]))["summary"]["modulus_factor_now"])' "$1"; }

# No snapshot: the files, nothing said.
"$FM" "$tmp/plain.bag" --json >"$tmp/plain.json" 2>"$tmp/err" || bad "plain bag: $(cat "$tmp/err")"
[ "$(factor_now "$tmp/plain.json")" = 1 ] && [ ! -s "$tmp/err" ] && ok || bad "plain bag: factor $(factor_now "$tmp/plain.json"), stderr $(cat "$tmp/err")"
# The snapshot: its modulus_factor, and one line saying where the settings came from.
"$FM" "$tmp/f11.bag" --json >"$tmp/f11.json" 2>"$tmp/err" || bad "f11 bag: $(cat "$tmp/err")"
[ "$(factor_now "$tmp/f11.json")" = 1.1 ] && ok || bad "f11 bag: factor $(factor_now "$tmp/f11.json"), not the recorded 1.1"
grep -q "settings from /lane1/settings of the bag (the node's, as recorded)" "$tmp/err" && [ "$(wc -l <"$tmp/err")" -eq 1 ] &&
  ok || bad "f11 bag does not say where its settings came from: $(cat "$tmp/err")"
# --set still applies after the snapshot.
"$FM" "$tmp/f11.bag" --json --set modulus_factor=1.3 >"$tmp/f13.json" 2>/dev/null
[ "$(factor_now "$tmp/f13.json")" = 1.3 ] && ok || bad "--set after the snapshot: factor $(factor_now "$tmp/f13.json")"
# A file given: the files, the snapshot set aside, said.
"$FM" "$tmp/f11.bag" --json --cultivar "$root/config/jonagold.yaml" >"$tmp/files.json" 2>"$tmp/err"
[ "$(factor_now "$tmp/files.json")" = 1 ] && grep -q "not used: --config or --cultivar given" "$tmp/err" &&
  ok || bad "--cultivar over a snapshot: factor $(factor_now "$tmp/files.json"), $(cat "$tmp/err")"
# Two bags with the same snapshot: used for both.
"$FM" "$tmp/f11.bag" "$tmp/f11b.bag" >/dev/null 2>"$tmp/err" && grep -q "of the bags" "$tmp/err" && ok ||
  bad "two bags, one snapshot: $(cat "$tmp/err")"

# A bag that cannot be read is left to the report (not read), the others judged with their settings.
head -c 40000 "$tmp/f11.bag" >"$tmp/cut.bag"
"$FM" "$tmp/f11.bag" "$tmp/cut.bag" >"$tmp/out" 2>"$tmp/err"
[ $? -eq 2 ] && grep -q "combined: 1 bags (1 more not read)" "$tmp/out" && grep -q "settings from /lane1/settings" "$tmp/err" &&
  ok || bad "a cut bag beside a recorded one: $(cat "$tmp/err")"

# Refusals: one line, exit 2.
expect_usage "other settings than .*modulus_factor: 1.2' against 'modulus_factor: 1.1'" "$tmp/f11.bag" "$tmp/f12.bag"
expect_usage "holds the node's settings (/lane1/settings) and .*plain.bag does not" "$tmp/f11.bag" "$tmp/plain.bag"
expect_usage "not a settings snapshot of this version: line .*: 'no_such_row' is not a parameter" "$tmp/bogus.bag"
# Files given: the disagreeing bags are judged alike with them.
"$FM" "$tmp/f11.bag" "$tmp/f12.bag" --config "$root/config/station.yaml" >/dev/null 2>&1 && ok ||
  bad "--config over disagreeing snapshots refused"

summary test_bag_settings
