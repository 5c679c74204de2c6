#!/usr/bin/env bash
# Apples in flight and cameras that stamp late: no strike may be reliable
# under another apple's id, and a systematic lag is named.
#  - strike_bag --spacing 0.1: two apples between the camera (0.2 s
#    upstream) and the hammer at every strike; every strike on its own apple,
#    at least 95 % of them reliable.
#  - the same bag's estimates stamped 0.25 s late (50 ms after their own
#    strikes, a camera stamping at publish time), at 0.5 s spacing: no
#    strike on another apple, the 50 ms lag named.
#  - one estimate stamped 4294967295 s among estimates 0.3 s late: refused
#    and named; it changes no other strike's match.
# The bags are strike_bag's, edited through rosbag's Python API
# (edit_bag.py); attribution.py joins the report with strike_bag's truth.
set -uo pipefail
here=$(dirname "$0")
# shellcheck disable=SC1091
source "$here/rig_faults.sh"
counts() { /usr/bin/python3 "$here/attribution.py" "$1" "$2"; }
report() { "$rig_bin/firmness_report" "$1" --csv "$2" >"$3" 2>"$3.err"; }

"$rig_bin/strike_bag" --strikes 200 --spacing 0.1 --seed 11 --out "$tmp/line.bag" >/dev/null 2>&1
report "$tmp/line.bag" "$tmp/line.csv" "$tmp/line.txt"
c=$(counts "$tmp/line.truth.csv" "$tmp/line.csv")
check in_flight_own_apple "$c" 'strikes 200 found 200 reliable [0-9]+ wrong_reliable 0 wrong_unflagged 0 no_apple 0 doubtful 0$'
# At least 95 % of them reliable (190 of 200).
check in_flight_reliable "$c" 'reliable (19[0-9]|200) '

check in_flight_transit "$(grep 'apple transit' "$tmp/line.txt")" 'apple transit: 200\.[0-9] ms from estimate to strike'

"$rig_bin/strike_bag" --strikes 40 --seed 3 --out "$tmp/g40.bag" >/dev/null 2>&1
/usr/bin/python3 "$here/edit_bag.py" "$tmp/g40.bag" "$tmp/late.bag" apple_shift=0.25
report "$tmp/late.bag" "$tmp/late.csv" "$tmp/late.txt"
c=$(counts "$tmp/g40.truth.csv" "$tmp/late.csv")
check camera_late_no_wrong_apple "$c" 'found 40 reliable 0 wrong_reliable 0 wrong_unflagged 0 no_apple 40'
check camera_late_named "$(grep 'WARN apple estimates:' "$tmp/late.txt")" \
  'stamped 50 ms after their strikes: is the camera stamping at publish time\? \(apple_transit_s -0\.050 would match them\)'
check camera_late_reason "$(sed -n 2p "$tmp/late.csv")" \
  'no apple estimate stamped 0\.2 \+- 0\.04 s before the strike \(the nearest, apple 1, is stamped 0\.050 s after it\)'
# The lag, once set as the transit, matches every strike to its own apple.
"$rig_bin/firmness_report" "$tmp/late.bag" --set apple_transit_s=-0.05 --csv "$tmp/late2.csv" >/dev/null 2>&1
c=$(counts "$tmp/g40.truth.csv" "$tmp/late2.csv")
check camera_late_transit_set "$c" 'found 40 reliable [0-9]+ wrong_reliable 0 wrong_unflagged 0 no_apple 0 doubtful 0'

/usr/bin/python3 "$here/edit_bag.py" "$tmp/g40.bag" "$tmp/bogus.bag" apple_bogus=4294967295 apple_shift=0.3
report "$tmp/bogus.bag" "$tmp/bogus.csv" "$tmp/bogus.txt"
c=$(counts "$tmp/g40.truth.csv" "$tmp/bogus.csv")
check far_stamp_no_wrong_apple "$c" 'found 40 reliable 0 wrong_reliable 0 wrong_unflagged 0 no_apple 40'
check far_stamp_refused "$(grep 'WARN apple estimates refused' "$tmp/bogus.txt")" \
  'refused: 1 \(last: apple 9999 refused: stamped [0-9.]+ s after the newest force sample'
/usr/bin/python3 "$here/edit_bag.py" "$tmp/g40.bag" "$tmp/bogus_ok.bag" apple_bogus=4294967295
report "$tmp/bogus_ok.bag" "$tmp/bogus_ok.csv" "$tmp/bogus_ok.txt"
c=$(counts "$tmp/g40.truth.csv" "$tmp/bogus_ok.csv")
check far_stamp_others_matched "$c" 'found 40 reliable [0-9]+ wrong_reliable 0 wrong_unflagged 0 no_apple 0 doubtful 0'

rig_done "attribution"
