#!/usr/bin/env bash
# Hostile data (findings 2, 3, 7, 9): non-finite samples, recordings
# and chunks beyond every ring, bags with duplicated chunks, two estimates at
# one stamp, another message type on the force topic, an index overflow, an
# empty chunk. Inputs are made here: the real capture test/data/hammer_capture_4
# with one sample replaced (Python's struct), sparse files (truncate), and
# bags from strike_bag edited through the rosbag API (bags.py). Each case: its
# exit code, one line, 2 s and 256 MiB.
set -uo pipefail
here=$(dirname "$0")
# shellcheck disable=SC1091
source "$here/hostile.sh"
fm=$hostile_bin/firmness_model
fr=$hostile_bin/firmness_report
data=$here/../data
/usr/bin/python3 - "$data" "$tmp" <<'PY'
import struct, sys
data, out = sys.argv[1], sys.argv[2]
def put(name, i, v, to):
    b = bytearray(open('%s/hammer_capture_4.%s.f32' % (data, name), 'rb').read())
    b[4 * i:4 * i + 4] = struct.pack('<f', v)
    open('%s/%s' % (out, to), 'wb').write(b)
put('force', 100, float('inf'), 'f_inf100.f32')
put('response', 300, float('nan'), 'a_nan300.f32')
put('force', 20000, float('nan'), 'f_nan20000.f32')
put('response', 20000, float('-inf'), 'a_inf20000.f32')
PY
f4=$data/hammer_capture_4.force.f32
a4=$data/hammer_capture_4.response.f32
cap=(--rate-force 25600 --rate-audio 25600 --mass 0.175 --R2 0.04)

# 2: one Inf at force sample 100 (inside the strike's span): the strike is
# kept and flagged; before, the whole chunk went and "strikes": [].
hostile_case inf_force_100 0 '"refused_samples"\]|1 refused \(non-finite\) force samples' 2 256 -- \
  "$fm" analyze --force "$tmp/f_inf100.f32" --audio "$a4" "${cap[@]}"
# 2: one NaN at audio sample 300 (inside the audio window): the right reason.
hostile_case nan_audio_300 0 'audio window \(samples [0-9]+\.\.[0-9]+\) holds 1 refused \(non-finite\) samples' \
  2 256 -- "$fm" analyze --force "$f4" --audio "$tmp/a_nan300.f32" "${cap[@]}"
# 2: a NaN and an -Inf far from the strike: counted, never silent.
hostile_case nan_elsewhere 0 '"force": \{"chunks": 25, "refused_samples": 1, "refused_spans": 1' 2 256 -- \
  "$fm" analyze --force "$tmp/f_nan20000.f32" --audio "$tmp/a_inf20000.f32" "${cap[@]}"
hostile_case nan_elsewhere_line 0 'a_inf20000.f32: 1 non-finite samples refused in 1 spans' 2 256 -- \
  "$fm" analyze --force "$tmp/f_nan20000.f32" --audio "$tmp/a_inf20000.f32" "${cap[@]}"

# 3: two recordings of 2^27 samples (512 MiB each, sparse): refused before
# they are read (1.06 GB before).
truncate -s $((4 << 27)) "$tmp/huge_f.f32" "$tmp/huge_a.f32"
hostile_case two_huge_recordings 2 'huge_f.f32: 134217728 samples, above --max-samples 16777216' 2 256 -- \
  "$fm" analyze --force "$tmp/huge_f.f32" --audio "$tmp/huge_a.f32" "${cap[@]}"
hostile_case max_samples_flag 2 "--max-samples 0 is outside the accepted range \[1, 134217728\] samples" 2 256 -- \
  "$fm" analyze --force "$f4" --audio "$a4" "${cap[@]}" --max-samples 0
hostile_case max_samples_small 2 'above --max-samples 1000 ' 2 256 -- \
  "$fm" analyze --force "$f4" --audio "$a4" "${cap[@]}" --max-samples 1000

# The bags: strike_bag's 4 strikes, edited.
"$hostile_bin/strike_bag" --strikes 4 --seed 11 --out "$tmp/good.bag" >/dev/null 2>&1
/usr/bin/python3 "$here/bags.py" "$tmp/good.bag" "$tmp" || exit 1
# 7: two estimates at one stamp: each strike a counted doubtful match.
hostile_case same_stamp 0 'strikes 4: 4 on an apple, 0 without apple, 0 without audio, 4 doubtful matches' \
  2 256 -- "$fr" "$tmp/same_stamp.bag"
hostile_case same_stamp_why 0 'apple 1, stamped 0\.200 s before the strike, fits apple_transit_s 0\.2 \+- 0\.04 s too; the strike may be either.s' 2 256 -- "$fr" "$tmp/same_stamp.bag"
# 7: a std_msgs/String on the force topic: named, counted, the bag goes on.
hostile_case string_on_force 0 '/lane1/force: a cut SignalChunk of 15 bytes .*wrong message type on this topic' \
  2 256 -- "$fr" "$tmp/string_on_force.bag"
hostile_case string_counted 0 'force +170 chunks.* 1 refused \(rate 0, unit 0, index 0, malformed 1' \
  2 256 -- "$fr" "$tmp/string_on_force.bag"
# A SignalChunk on the apple topic: refused per message (named, counted), the
# bag goes on with its 4 strikes (it once refused the whole bag).
hostile_case chunk_on_apple 0 'refused 1 message of another type on /lane1/apple, which carries acoustic_firmness/AppleEstimate \(the first: acoustic_firmness/SignalChunk\): counted, the rest of the bag read' \
  2 256 -- "$fr" "$tmp/chunk_on_apple.bag"
hostile_case chunk_on_apple_counted 0 'refused \(oversized or not their type; 1 of them apples\)' \
  2 256 -- "$fr" "$tmp/chunk_on_apple.bag"
hostile_case chunk_on_apple_strikes 0 'strikes 4: 4 on an apple' 2 256 -- "$fr" "$tmp/chunk_on_apple.bag"
# 7: every force chunk twice: duplicates, not restarts nor lost samples.
hostile_case duplicates 0 'force +170 chunks, 0 gaps \(0 samples lost\), 0 restarts, 170 duplicates' \
  2 256 -- "$fr" "$tmp/duplicates.bag"
hostile_case duplicates_not_doubtful 0 'strikes 4: 4 on an apple, 0 without apple, 0 without audio, 0 doubtful' \
  2 256 -- "$fr" "$tmp/duplicates.bag"
# 3: a 64 MiB SignalChunk in a bag: refused before it is copied (792 MB
# for 264 MB before).
hostile_case big_chunk 0 'a SignalChunk of 67108921 bytes .*above the cap of 100000 samples' \
  2 256 -- "$fr" "$tmp/big_chunk.bag"
# 9: a first_sample overflow is its own reason; an empty chunk is malformed.
hostile_case index_overflow 0 'force +170 chunks.* 1 refused \(rate 0, unit 0, index 1, malformed 0' \
  2 256 -- "$fr" "$tmp/overflow.bag"
hostile_case empty_chunk 0 'an empty SignalChunk \(0 bytes\)' 2 256 -- "$fr" "$tmp/empty_chunk.bag"
# 9: a unit "N\0x" is not the unit N (a NUL ended the C string in silence):
# the chunk refused for its unit, "N?x".
hostile_case nul_unit 0 'force +169 chunks.* 1 refused \(rate 0, unit 1, index 0, malformed 0' \
  2 256 -- "$fr" "$tmp/nul_unit.bag"
# A SignalChunk of another definition (its md5sum): the bag refused at open
# in one line naming topic, type and both md5sums, never deserialized as
# this build's.
hostile_case md5_mismatch 2 \
  'md5_mismatch.bag: topic /lane1/force has type acoustic_firmness/SignalChunk of md5sum 0123456789abcdef0123456789abcdef, not [0-9a-f]{32} as built here: recorded with another definition' \
  2 256 -- "$fr" "$tmp/md5_mismatch.bag"
# 3: a bag chunk of 2^26 samples (256 MiB): rosbag would hold it whole; the
# bag is refused in one line.
/usr/bin/python3 "$here/bags.py" "$tmp/good.bag" "$tmp" $((1 << 26)) big || exit 1
hostile_case bag_chunk_256mib 2 'claims [0-9]+ bytes uncompressed, above the 128 MiB accepted' \
  2 256 -- "$fr" "$tmp/big_chunk.bag"
hostile_done
