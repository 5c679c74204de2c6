#!/usr/bin/env bash
# capture_to_bag end to end on a lab session made of the real captures of
# test/data (capture_files.py: 3.5 s at 25.6 kHz, three strikes; force
# as a 16-bit WAV of python's wave module, audio as a hand-packed float WAV;
# then raw float32 force and a stereo 16-bit audio WAV), with an apple CSV:
#  - --help: exit 0, every flag with its default (or "required");
#  - the bag, read back with rosbag's Python (not the package's reader):
#    the topics, types (md5) and frame ids of a strike_bag bag, chunks of
#    1024 samples (the last one the rest), header stamp = start + first
#    sample / rate, bag time = start + (first + n) / rate, the samples those
#    of the WAV as python decodes them, the AppleEstimates the CSV's rows;
#  - firmness_report on it: the three strikes on apples 11, 12, 13, contact
#    starts within one sample of the onsets found in python, peaks within
#    1.5 % (strike.h: the refined peak of these captures is 0.1 % and 0.8 %
#    above the largest sample);
#  - the same session as raw float32 + stereo WAV (other start, other lane):
#    the same strikes, every figure within 0.1 % (16-bit quantisation);
#  - the CSV as spreadsheets write it (a BOM, blanks around the fields): the
#    same AppleEstimates;
#  - refusals: exit 2, one line naming the flag, file, line, column and range.
# Usage: test_capture_to_bag.sh CAPTURE_TO_BAG FIRMNESS_REPORT STRIKE_BAG
#        (in the devel space's environment: rosbag's Python)
source "$(dirname "$0")/../cli/harness.sh" "$1"
REPORT=${2:?path to firmness_report}
SB=${3:?path to strike_bag}
here=$(cd "$(dirname "$0")" && pwd)
data="$here/../data"
[ -s "$data/hammer_capture_5.force.f32" ] || { echo "test_capture_to_bag: no captures in $data" >&2; exit 1; }
"$PY" "$here/capture_files.py" "$tmp" "$data" || { echo "test_capture_to_bag: capture_files.py failed" >&2; exit 1; }
RATES=(--set force_sample_rate_hz=25600 --set audio_sample_rate_hz=25600)

# --- --help ------------------------------------------------------------------------
if "$FM" --help >"$tmp/help" 2>&1; then ok; else bad "--help exited non-zero"; fi
for f in --force --audio --apples --out --rate-force --rate-audio --force-channel --audio-channel \
  --force-scale --audio-scale --audio-unit --audio-offset --start --chunk --ns; do
  if grep -E -- "^  $f [A-Z]+ .*\((default|required)" "$tmp/help" >/dev/null; then ok; else bad "--help: no line for $f with its default"; fi
done

# --- A: 16-bit force WAV, float audio WAV --------------------------------------------
"$FM" --force "$tmp/force16.wav" --force-scale 100 --audio "$tmp/audio32.wav" --apples "$tmp/apples.csv" \
  --out "$tmp/a.bag" >"$tmp/a.out" 2>"$tmp/a.err" || bad "conversion A exited $?: $(cat "$tmp/a.err")"
cat "$tmp/a.out"
if [ "$(cat "$tmp/a.err")" = "wrote $tmp/a.bag" ]; then ok; else bad "conversion A stderr: $(cat "$tmp/a.err")"; fi
if grep -q '^capture_to_bag: 3 apples; force 89600 samples at 25600 Hz' "$tmp/a.out" &&
  grep -q 'force_sample_rate_hz=25600 audio_sample_rate_hz=25600' "$tmp/a.out"; then ok; else bad "conversion A stdout"; fi
"$SB" --strikes 1 --out "$tmp/ref.bag" >/dev/null || bad "strike_bag failed"

if "$PY" - "$tmp" <<'EOF'; then ok; else bad "bag A is not what the WAVs and the CSV say"; fi
import csv, json, struct, sys, wave
import rosbag
d = sys.argv[1]
START_NS, RATE, FS = 1700000000 * 10**9, 25600, 100.0
def conns(path):
    b = rosbag.Bag(path)
    info = {c.topic: (c.datatype, c.md5sum) for c in b._connections.values()}
    frames = {}
    for topic, m, _ in b.read_messages():
        frames.setdefault(topic, m.header.frame_id)
    return b, info, frames
a, ainfo, aframes = conns(d + '/a.bag')
_, rinfo, rframes = conns(d + '/ref.bag')
assert ainfo == rinfo, (ainfo, rinfo)
assert aframes == rframes, (aframes, rframes)
with wave.open(d + '/force16.wav') as w:
    raw = w.readframes(w.getnframes())
force = [v * FS / 32768.0 for v in struct.unpack('<%dh' % (len(raw) // 2), raw)]
with open(d + '/audio32.wav', 'rb') as fh:
    blob = fh.read()
k = blob.index(b'data')
n = struct.unpack('<I', blob[k + 4:k + 8])[0] // 4
audio = list(struct.unpack('<%df' % n, blob[k + 8:k + 8 + 4 * n]))
got = {'/lane1/force': [], '/lane1/audio': []}
apples, last_t = [], 0
for topic, m, t in a.read_messages():
    assert t.to_nsec() >= last_t, 'bag time goes back at %s' % topic
    last_t = t.to_nsec()
    if topic == '/lane1/apple':
        apples.append(m)
        assert t == m.header.stamp
        continue
    x = got[topic]
    assert m.first_sample == len(x), (topic, m.first_sample, len(x))
    assert len(m.data) == 1024 or len(x) + len(m.data) == 89600, (topic, len(m.data))
    assert abs(m.header.stamp.to_nsec() - START_NS - m.first_sample * 1e9 / RATE) <= 1
    assert abs(t.to_nsec() - START_NS - (m.first_sample + len(m.data)) * 1e9 / RATE) <= 1
    assert m.sample_rate == RATE and m.unit == ('N' if topic.endswith('force') else 'Pa')
    x.extend(m.data)
assert len(got['/lane1/force']) == len(force) == 89600 and len(got['/lane1/audio']) == len(audio)
assert max(abs(p - q) for p, q in zip(got['/lane1/force'], force)) <= 1e-5
assert got['/lane1/audio'] == [struct.unpack('<f', struct.pack('<f', v))[0] for v in audio]
rows = list(csv.DictReader(open(d + '/apples.csv')))
assert len(apples) == len(rows) == 3
for m, r in zip(apples, rows):
    assert m.apple_id == int(r['apple_id']) and m.mass == float(r['mass_kg'])
    assert m.equatorial_radius == float(r['equatorial_radius_m']) and m.strike_radius == 0.04
    assert (m.stem_axis.x, m.stem_axis.y, m.stem_axis.z) == (1, 0, 0) and m.confidence == 0.9
    assert m.header.stamp.to_nsec() == START_NS + round(float(r['stamp_s']) * 1e9)
print('  bag A: topics, types, frames as strike_bag; 88 + 88 chunks, samples and apples as written')
EOF

# --- firmness_report on A against the captures -----------------------------------------
"$REPORT" "$tmp/a.bag" --json "${RATES[@]}" >"$tmp/a.json" 2>"$tmp/err" || bad "report on A exited $?: $(cat "$tmp/err")"
if "$PY" - "$tmp/a.json" "$tmp/expect.json" <<'EOF'; then ok; else bad "report on A vs the captures"; fi
import json, sys
rep, exp = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
s, strikes = rep['summary'], rep['strikes']
assert s['strikes'] == 3 and s['with_apple'] == 3 and s['without_audio'] == 0, s
assert s['force']['gaps'] == 0 and s['audio']['gaps'] == 0, s
for o, e in zip(strikes, exp['strikes']):
    start_s = o['stamp_ns'] * 1e-9 - 1700000000
    d_start, d_peak = start_s - e['onset_s'], o['peak_force_n'] / e['peak_n'] - 1
    print('  apple %d (capture %d): start %+.1f samples, peak %.3f N vs %.3f N (%+.2f %%)'
          % (o['apple_id'], e['capture'], d_start * exp['rate_hz'], o['peak_force_n'], e['peak_n'],
             100 * d_peak))
    assert o['apple_id'] == e['apple_id'], (o['apple_id'], e)
    assert abs(d_start) <= 1.0 / exp['rate_hz'], d_start
    assert abs(d_peak) < 0.015, d_peak
assert len(strikes) == 3
EOF

# --- B: raw float32 force, stereo 16-bit audio, another start and lane ------------------
"$FM" --force "$tmp/force.f32" --rate-force 25600 --audio "$tmp/audio16s.wav" --audio-channel 1 \
  --audio-scale 512 --apples "$tmp/apples.csv" --start 1800000000 --ns lab/two --out "$tmp/b.bag" \
  >/dev/null 2>"$tmp/b.err" || bad "conversion B exited $?: $(cat "$tmp/b.err")"
"$REPORT" "$tmp/b.bag" --ns lab/two --json "${RATES[@]}" >"$tmp/b.json" 2>"$tmp/err" || bad "report on B exited $?: $(cat "$tmp/err")"
if "$PY" - "$tmp/a.json" "$tmp/b.json" <<'EOF'; then ok; else bad "report on B differs from A"; fi
import json, sys
a, b = json.load(open(sys.argv[1]))['strikes'], json.load(open(sys.argv[2]))['strikes']
assert len(a) == len(b) == 3
worst = 0.0
for p, q in zip(a, b):
    assert p['apple_id'] == q['apple_id'] and p['flags'] == q['flags'], (p, q)
    assert abs(q['stamp_ns'] - p['stamp_ns'] - 10**17) < 1000, (p['stamp_ns'], q['stamp_ns'])
    for key in ('contact_time_s', 'peak_force_n', 'impulse_n_s', 'resonance_hz', 'snr_db',
                'stiffness_factor_hz2_kg2_3', 'modulus_from_resonance_pa', 'band_high_hz'):
        d = abs(q[key] / p[key] - 1)
        worst = max(worst, d)
        assert d < 1e-3, (key, p[key], q[key])
print('  bag B (raw float32 + stereo WAV) vs A: worst relative difference %.2e' % worst)
EOF

# --- the CSV as spreadsheets write it: a UTF-8 BOM before the header, blanks
# around every field (before the commas too), blank lines at the end: the
# same AppleEstimates as the plain CSV's
"$PY" - "$tmp/apples.csv" "$tmp/sheet.csv" <<'EOF'
import sys
lines = open(sys.argv[1]).read().splitlines()
out = ['\ufeff' + lines[0].replace(',', ' ,\t')] + [' ' + l.replace(',', '\t , ') + ' \t' for l in lines[1:]]
open(sys.argv[2], 'w', encoding='utf-8').write('\n'.join(out) + '\n \n\t\n')
EOF
"$FM" --force "$tmp/force16.wav" --force-scale 100 --audio "$tmp/audio32.wav" --apples "$tmp/sheet.csv" \
  --out "$tmp/sheet.bag" >/dev/null 2>"$tmp/sheet.err" || bad "the spreadsheet's CSV: $(cat "$tmp/sheet.err")"
if "$PY" - "$tmp/a.bag" "$tmp/sheet.bag" <<'EOF'; then ok; else bad "the spreadsheet's CSV gave other apples"; fi
import sys, rosbag
def apples(path):
    with rosbag.Bag(path) as b:
        return [(t, m.apple_id, m.header.stamp.to_nsec(), m.mass, m.equatorial_radius, m.confidence)
                for t, m, _ in b.read_messages() if m._type.endswith('AppleEstimate')]
a, s = apples(sys.argv[1]), apples(sys.argv[2])
print('  spreadsheet CSV: %d apples, the same as the plain CSV\'s: %s' % (len(s), a == s))
sys.exit(0 if a == s and len(a) == 3 else 1)
EOF

# --- refusals ---------------------------------------------------------------------------
G=(--force "$tmp/force16.wav" --audio "$tmp/audio32.wav" --out "$tmp/x.bag")
csv_case() { # name sed-expression: a CSV made from apples.csv
  sed "$2" "$tmp/apples.csv" >"$tmp/$1.csv"
}
csv_case mass 's/^12,1.3007,0.175/12,1.3007,0/'
expect_usage "mass.csv:3: column mass_kg: '0' is not a number in \[0.001, 10\] kg" "${G[@]}" --apples "$tmp/mass.csv"
csv_case late 's/^13,2.3007/13,3.6/'
expect_usage "late.csv:4: column stamp_s: '3.6' is not a number in \[0, 3.5\] s" "${G[@]}" --apples "$tmp/late.csv"
csv_case order 's/^13,2.3007/13,1.0/'
expect_usage "order.csv:4: stamp_s '1' is before the previous row's 1.3007 s" "${G[@]}" --apples "$tmp/order.csv"
csv_case dup 's/^13,/12,/'
expect_usage "dup.csv:4: apple_id '12' is given twice" "${G[@]}" --apples "$tmp/dup.csv"
csv_case nocol '1s/,confidence//'
expect_usage "nocol.csv:1: the header has no column 'confidence'" "${G[@]}" --apples "$tmp/nocol.csv"
csv_case unknown '1s/confidence/conf/'
expect_usage "unknown.csv:1: header column 9 'conf' is not a known column" "${G[@]}" --apples "$tmp/unknown.csv"
csv_case conf 's/0.9$/1.5/'
expect_usage "conf.csv:2: column confidence: '1.5' is not a number in \[0, 1\]" "${G[@]}" --apples "$tmp/conf.csv"
csv_case radius 's/,0.04,/,0.0001,/'
expect_usage "radius.csv:2: column strike_radius_m: '0.0001' is not 0 (unknown) or a number in \[0.0005, 1\] m" "${G[@]}" --apples "$tmp/radius.csv"
csv_case id0 's/^11,/0,/'
expect_usage "id0.csv:2: column apple_id: '0' is not a whole number in \[1, 4294967295\] (0 is StrikeReport's \"no apple\")" "${G[@]}" --apples "$tmp/id0.csv"
csv_case id 's/^11,/11.5,/'
expect_usage "id.csv:2: column apple_id: '11.5' is not a whole number" "${G[@]}" --apples "$tmp/id.csv"
csv_case axis 's/,1,0,0,/,1,nan,0,/'
expect_usage "axis.csv:2: column stem_axis_y: 'nan' is not a finite number" "${G[@]}" --apples "$tmp/axis.csv"
csv_case short 's/,0.9$//'
expect_usage "short.csv:2: 8 fields, the header has 9" "${G[@]}" --apples "$tmp/short.csv"
head -1 "$tmp/apples.csv" >"$tmp/header_only.csv"
expect_usage "header_only.csv: no apple rows after the header" "${G[@]}" --apples "$tmp/header_only.csv"
expect_usage "--apples $tmp/none.csv: cannot read: No such file" "${G[@]}" --apples "$tmp/none.csv"
A=(--apples "$tmp/apples.csv" --out "$tmp/x.bag")
expect_usage "--force $tmp/none.wav: cannot read: No such file" --force "$tmp/none.wav" --audio "$tmp/audio32.wav" "${A[@]}"
expect_usage "audio16s.wav: --audio-channel 2 is beyond the WAV's 2 channels (0 to 1)" --force "$tmp/force16.wav" --audio "$tmp/audio16s.wav" --audio-channel 2 "${A[@]}"
expect_usage "force.f32: --force-channel 1 is beyond raw float32's one channel" --force "$tmp/force.f32" --rate-force 25600 --force-channel 1 --audio "$tmp/audio32.wav" "${A[@]}"
expect_usage "force.f32: raw float32 needs --rate-force HZ" --force "$tmp/force.f32" --audio "$tmp/audio32.wav" "${A[@]}"
expect_usage "force16.wav: --rate-force 25000 disagrees with the WAV header's 25600 Hz" --force "$tmp/force16.wav" --rate-force 25000 --audio "$tmp/audio32.wav" "${A[@]}"
printf 'ID3\004\000\000\000\000\000\000' >"$tmp/song.mp3"
expect_usage "song.mp3: is MP3 (ID3 tag)" --force "$tmp/force16.wav" --audio "$tmp/song.mp3" "${A[@]}"
expect_usage "--rate-audio 500 is outside the accepted range \[1000, 1e6\] Hz" "${G[@]}" --apples "$tmp/apples.csv" --rate-audio 500
expect_usage "--force-scale 0 is outside the accepted range (0, 1e6\] N" "${G[@]}" --apples "$tmp/apples.csv" --force-scale 0
expect_usage "--audio-unit: audio_unit = 'dB' is not one of: Pa, V" "${G[@]}" --apples "$tmp/apples.csv" --audio-unit dB
expect_usage "--chunk 8 is outside the accepted range \[16, 65536\] samples" "${G[@]}" --apples "$tmp/apples.csv" --chunk 8
expect_usage "--start 0 is outside the accepted range \[1, 4e9) s" "${G[@]}" --apples "$tmp/apples.csv" --start 0
expect_usage "--audio-offset 4000 is outside the accepted range \[-3600, 3600\] s" "${G[@]}" --apples "$tmp/apples.csv" --audio-offset 4000
expect_usage "--ns 'lane 1' must be a namespace" "${G[@]}" --apples "$tmp/apples.csv" --ns "lane 1"
expect_usage "--apples is required" --force "$tmp/force16.wav" --audio "$tmp/audio32.wav" --out "$tmp/x.bag"
expect_usage "unknown flag '--bogus'" "${G[@]}" --apples "$tmp/apples.csv" --bogus 1
expect_usage "--out needs a value" --force "$tmp/force16.wav" --out
expect_usage "--out $tmp/no/dir/x.bag: input/output error" --force "$tmp/force16.wav" --audio "$tmp/audio32.wav" --apples "$tmp/apples.csv" --out "$tmp/no/dir/x.bag"
[ ! -e "$tmp/x.bag" ] && ok || bad "a refused conversion left $tmp/x.bag"

summary test_capture_to_bag
