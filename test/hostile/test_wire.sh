#!/usr/bin/env bash
# Hostile bags for the wire and the bag reader (the bag reader's open
# items): force chunks that overlap (the head repeats what was sent:
# kept as a tail, not a restart; the head altered: a restart), bags whose
# header names an encryptor (refused as before, and the next bag in the same
# process read as sent: the reader reuses rosbag::Bag objects), and several
# bags on two workers. Bags from strike_bag, edited through the rosbag API
# (overlap_bag.py) or by the bag format's record layout (header_field.py).
# Each case: its exit code, one line, 2 s and 256 MiB.
set -uo pipefail
here=$(dirname "$0")
# shellcheck disable=SC1091
source "$here/hostile.sh"
fr=$hostile_bin/firmness_report

"$hostile_bin/strike_bag" --strikes 4 --seed 11 --out "$tmp/good.bag" >/dev/null 2>&1
/usr/bin/python3 "$here/overlap_bag.py" "$tmp/good.bag" "$tmp/overlap.bag" 40 >/dev/null || exit 1
/usr/bin/python3 "$here/overlap_bag.py" "$tmp/good.bag" "$tmp/overlap_changed.bag" 40 changed \
  >/dev/null || exit 1
/usr/bin/python3 "$here/header_field.py" "$tmp/good.bag" "$tmp/no_such_encryptor.bag" \
  encryptor=rosbag/NoSuchEncryptor || exit 1
/usr/bin/python3 "$here/header_field.py" "$tmp/good.bag" "$tmp/aes_no_key.bag" \
  encryptor=rosbag/AesCbcEncryptor || exit 1

# 169 of the 170 force chunks start 40 samples before the previous one's end,
# those 40 as sent: no restart (there were 169).
hostile_case overlap_no_restart 0 'force +170 chunks, 0 gaps \(0 samples lost\), 0 restarts, 0 duplicates, 169 overlaps \(6760 samples sent twice\)' \
  2 256 -- "$fr" "$tmp/overlap.bag"
# ... and its strikes are the good bag's: the detector takes only each
# chunk's new tail (lane.c), so the same 4 strikes, row for row.
hostile_case overlap_strikes 0 'strikes 4: 4 on an apple, 0 without apple, 0 without audio, 0 doubtful' \
  2 256 -- "$fr" "$tmp/overlap.bag" --csv "$tmp/overlap.csv"
"$fr" "$tmp/good.bag" --csv "$tmp/good.csv" >/dev/null 2>&1
hostile_count=$((hostile_count + 1))
if cmp -s "$tmp/good.csv" "$tmp/overlap.csv"; then
  echo "overlap_same_rows: the CSV of the overlapping bag is the good bag's, byte for byte"
else
  echo "  FAIL overlap_same_rows: the overlapping bag's CSV differs from the good bag's"
  diff "$tmp/good.csv" "$tmp/overlap.csv" | head -5
  hostile_failed=$((hostile_failed + 1))
fi
# The first repeated sample altered by 1 N: the head is not what was sent.
hostile_case overlap_changed_restarts 0 'force +170 chunks, 0 gaps \(0 samples lost\), 169 restarts' \
  2 256 -- "$fr" "$tmp/overlap_changed.bag"
# A bag naming an encryptor that does not exist, or AES without its key.
hostile_case encryptor_unknown 2 'no_such_encryptor.bag: not a readable bag: .*rosbag/NoSuchEncryptor .*does not exist' \
  2 256 -- "$fr" "$tmp/no_such_encryptor.bag"
hostile_case encryptor_aes_no_key 2 'aes_no_key.bag: not a readable bag: Encrypted symmetric key is not found' \
  2 256 -- "$fr" "$tmp/aes_no_key.bag"
# The good bag after the refused one, in the same process (the same reused
# rosbag::Bag): its 4 strikes.
hostile_case encryptor_then_good 2 'strikes 4: 4 on an apple, 0 without apple, 0 without audio, 0 doubtful' \
  2 256 -- "$fr" "$tmp/aes_no_key.bag" "$tmp/good.bag"
# Six bags on two workers: each reader its own Bag and its own errors.
mkdir -p "$tmp/six"
for k in 1 2 3 4 5 6; do cp "$tmp/good.bag" "$tmp/six/g$k.bag"; done
hostile_case six_bags_two_jobs 0 'strikes 24: 24 on an apple, 0 without apple, 0 without audio, 0 doubtful' \
  2 256 -- "$fr" "$tmp/six" --jobs 2
hostile_done
