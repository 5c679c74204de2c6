#!/usr/bin/env bash
# CLI tests of WAV input to `firmness_model analyze` (src/core/io/wav.c through
# src/tools/recording.c): the real impact-hammer capture 5 of test/data
# (25.6 kHz float32) written as WAV by Debian's python3 (the wave module for
# integer PCM; IEEE float and WAVE_FORMAT_EXTENSIBLE headers packed by hand
# in wav_files.py) in every accepted form: 16-bit PCM, 32- and 64-bit float,
# stereo with the signal in channel 1, 24- and 32-bit PCM, extensible PCM
# (24 valid bits in 32, a LIST chunk before the data) and extensible float,
# 8-bit PCM, the 24 valid bits right-justified (against the spec: read x 256
# with a note), RIFF sizes of 0 and 0xFFFFFFFF (a stream never finalized:
# read to the end of the file, with a note). Each must give what the raw
# float32 files give: every figure of the strike within 0.1 % (8-bit: the
# peak within one step of 8 bits). Then
# every refusal: exit 2, one line naming the file.
# Usage: test_wav.sh /path/to/firmness_model
source "$(dirname "$0")/harness.sh" "$@"

data="$(cd "$(dirname "$0")/.." && pwd)/data"
force="$data/hammer_capture_5.force.f32"
resp="$data/hammer_capture_5.response.f32"
[ -s "$force" ] && [ -s "$resp" ] || { echo "test_wav: missing $force or $resp" >&2; exit 1; }
FS_N=100.0 # the force's full scale in the integer WAVs [N] (the capture peaks at 77 N)
FS_A=512.0 # the response's (it peaks at 496)

"$PY" - "$tmp" "$force" "$resp" "$(dirname "$0")" "$FS_N" "$FS_A" <<'EOF'
import struct, sys
out, force, resp, here, fs_n, fs_a = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], float(sys.argv[5]), float(sys.argv[6])
sys.path.insert(0, here)
import wav_files as W
f, a = W.read_f32(force), W.read_f32(resp)
rate = 25600
other = [0.25 * fs_n * ((k % 50) / 25.0 - 1.0) for k in range(len(f))]  # a sawtooth in channel 0
W.write_pcm(out + '/f16.wav', rate, [f], 16, fs_n)
W.write_pcm(out + '/f16s.wav', rate, [other, f], 16, fs_n)
W.write_pcm(out + '/f24.wav', rate, [f], 24, fs_n)
W.write_pcm(out + '/f32i.wav', rate, [other, f], 32, fs_n)
W.write_pcm(out + '/f8.wav', rate, [f], 8, fs_n)
W.write_float(out + '/ff32.wav', rate, [f], 32)
W.write_float(out + '/ff64s.wav', rate, [other, f, other], 64)
W.write_float(out + '/ffext.wav', rate, [f], 32, extensible=True)
W.write_extensible_pcm(out + '/fext24in32.wav', rate, [other, f], 32, fs_n, valid_bits=24)
# the same 24 valid bits right-justified, against the spec: the top byte only
# the sign's extension
ext = bytearray(open(out + '/fext24in32.wav', 'rb').read())
at = ext.find(b'data') + 8
for k in range(at, len(ext) - 3, 4):
    v = struct.unpack_from('<i', ext, k)[0] >> 8  # arithmetic: sign-extended
    struct.pack_into('<i', ext, k, v)
open(out + '/fext24right.wav', 'wb').write(ext)
W.write_float(out + '/a32.wav', rate, [a], 32)
W.write_pcm(out + '/a16s.wav', rate, [[0.0] * len(a), a], 16, fs_a)

# --- refused files
good = open(out + '/f16.wav', 'rb').read()
open(out + '/truncated.wav', 'wb').write(good[:len(good) // 2])  # sizes past the end
riff_lies = bytearray(good); struct.pack_into('<I', riff_lies, 4, len(good) + 100)
open(out + '/riff_lies.wav', 'wb').write(riff_lies)
st = W.fmt_chunk(1, 2, rate, 16)  # stereo 16-bit: 4-byte frames, 6 bytes of data
open(out + '/part_frame.wav', 'wb').write(W.riff([st, W.data_chunk(b'\1\0\2\0\3\0')]))
open(out + '/mp3tag.wav', 'wb').write(W.riff([W.fmt_chunk(0x55, 1, rate, 16), W.data_chunk(b'\0' * 8)]))
open(out + '/bits12.wav', 'wb').write(W.riff([W.fmt_chunk(1, 1, rate, 12)[:-2] + b'\x0c\x00', W.data_chunk(b'\0' * 8)]))
open(out + '/float16.wav', 'wb').write(W.riff([W.fmt_chunk(3, 1, rate, 16), W.data_chunk(b'\0' * 8)]))
open(out + '/nodata.wav', 'wb').write(W.riff([W.fmt_chunk(1, 1, rate, 16)]))
# a stream never finalized: RIFF size 0; RIFF and 'data' sizes 0xFFFFFFFF and
# half a frame at the end
riff0 = bytearray(good); struct.pack_into('<I', riff0, 4, 0)
open(out + '/riff0.wav', 'wb').write(riff0)
riffff = bytearray(good) + b'\x01'; struct.pack_into('<I', riffff, 4, 0xFFFFFFFF)
struct.pack_into('<I', riffff, riffff.find(b'data') + 4, 0xFFFFFFFF)
open(out + '/riffff.wav', 'wb').write(riffff)
# a RIFF size that holds 'WAVE' alone
riff4 = bytearray(good); struct.pack_into('<I', riff4, 4, 4)
open(out + '/riff4.wav', 'wb').write(riff4)
# an MP3: an ID3v2 tag, then MPEG-1 layer III frames (128 kbit/s, 44.1 kHz: 417 bytes each)
frame = b'\xff\xfb\x90\x64' + b'\0' * 413
open(out + '/tagged.bin', 'wb').write(b'ID3\x04\x00\x00\x00\x00\x00\x00' + frame * 3)
# the same frames without a tag: 1668 bytes, whole float32 samples as raw
open(out + '/sync.f32', 'wb').write(frame * 4)
open(out + '/odd.f32', 'wb').write(open(force, 'rb').read()[:4 * 100 + 3])
open(out + '/song.mp3', 'wb').write(b'\0' * 16)
EOF
[ -s "$tmp/f16.wav" ] || { echo "test_wav: writing the WAVs failed" >&2; exit 1; }

apple=(--mass 0.175 --R2 0.04)
"$FM" analyze --force "$force" --audio "$resp" --rate-force 25600 --rate-audio 25600 "${apple[@]}" \
  >"$tmp/ref.json" 2>"$tmp/err" || bad "analyze on the raw capture: $(cat "$tmp/err")"

# same_as_raw tolerance args...: analyze args finds the one strike of the raw
# files with every number within tolerance (relative), every flag the same.
same_as_raw() {
  local tol=$1
  shift
  if ! "$FM" analyze "$@" "${apple[@]}" >"$tmp/json" 2>"$tmp/err"; then
    bad "'$*' exited non-zero: $(cat "$tmp/err")"
    return
  fi
  if "$PY" - "$tmp/ref.json" "$tmp/json" "$tol" "$*" <<'EOF'; then ok; else bad "'$*' differs from the raw files"; fi
import json, sys
ref, got, tol = json.load(open(sys.argv[1]))['strikes'], json.load(open(sys.argv[2]))['strikes'], float(sys.argv[3])
if len(ref) != 1 or len(got) != 1:
    print('strikes: raw %d, WAV %d' % (len(ref), len(got)), file=sys.stderr); sys.exit(1)
worst, bad = 0.0, []
for key, r in ref[0].items():
    g = got[0][key]
    if key.startswith('mode_'):  # how the 0S2 was picked: its words carry rounded figures
        continue
    if isinstance(r, float) or (isinstance(r, int) and not isinstance(r, bool)):
        if not isinstance(g, (int, float)) or isinstance(g, bool):
            bad.append(key); continue
        d = abs(g - r) / abs(r) if r else abs(g)
        worst = max(worst, d)
        if d > tol:
            bad.append('%s %r vs raw %r' % (key, g, r))
    elif g != r:
        bad.append('%s %r vs raw %r' % (key, g, r))
print('  %-70s worst relative difference %.2e' % (sys.argv[4][:70], worst))
if bad:
    print('  differ: ' + '; '.join(bad), file=sys.stderr)
sys.exit(1 if bad else 0)
EOF
}

A=(--audio "$resp" --rate-audio 25600)
echo "analyze on WAVs of capture 5 against the raw float32 files:"
same_as_raw 1e-3 --force "$tmp/f16.wav" --force-scale "$FS_N" "${A[@]}"
same_as_raw 1e-3 --force "$tmp/ff32.wav" --audio "$tmp/a32.wav"
same_as_raw 1e-3 --force "$tmp/f16s.wav" --force-channel 1 --force-scale "$FS_N" --audio "$tmp/a32.wav"
same_as_raw 1e-3 --force "$tmp/f16.wav" --force-scale "$FS_N" --rate-force 25600 \
  --audio "$tmp/a16s.wav" --audio-channel 1 --audio-scale "$FS_A"
same_as_raw 1e-3 --force "$tmp/f24.wav" --force-scale "$FS_N" "${A[@]}"
same_as_raw 1e-3 --force "$tmp/f32i.wav" --force-channel 1 --force-scale "$FS_N" "${A[@]}"
same_as_raw 1e-3 --force "$tmp/ff64s.wav" --force-channel 1 "${A[@]}"
same_as_raw 1e-3 --force "$tmp/ffext.wav" "${A[@]}"
same_as_raw 1e-3 --force "$tmp/fext24in32.wav" --force-channel 1 --force-scale "$FS_N" "${A[@]}"
same_as_raw 1e-3 --force "$tmp/fext24right.wav" --force-channel 1 --force-scale "$FS_N" "${A[@]}"
same_as_raw 1e-3 --force "$tmp/riff0.wav" --force-scale "$FS_N" "${A[@]}"
same_as_raw 1e-3 --force "$tmp/riffff.wav" --force-scale "$FS_N" "${A[@]}"
# each said in one line
note_says() {
  if "$FM" analyze "$@" "${A[@]}" "${apple[@]}" >/dev/null 2>"$tmp/err" && grep -q -- "$line" "$tmp/err"; then
    ok
  else
    bad "'$*' does not say '$line': $(head -c 300 "$tmp/err")"
  fi
}
line="fext24right.wav: note: its 24 valid bits sit right-justified in 32-bit samples (the top bits only the sign's extension, against the WAV spec): read as 24-bit samples (x 256)"
note_says --force "$tmp/fext24right.wav" --force-channel 1 --force-scale "$FS_N"
line="riff0.wav: note: its RIFF size is 0, as a recorder leaves a stream it never finalized: read to the end of the file, 25600 frames"
note_says --force "$tmp/riff0.wav" --force-scale "$FS_N"
line="riffff.wav: note: its RIFF size is 0xFFFFFFFF, as a recorder leaves a stream it never finalized: read to the end of the file, 25600 frames"
note_says --force "$tmp/riffff.wav" --force-scale "$FS_N"
# left-justified as the spec says: no note
if "$FM" analyze --force "$tmp/fext24in32.wav" --force-channel 1 --force-scale "$FS_N" "${A[@]}" "${apple[@]}" \
  >/dev/null 2>"$tmp/err" && ! grep -q "note:" "$tmp/err"; then ok; else bad "fext24in32.wav: $(head -c 300 "$tmp/err")"; fi
# float32 in, float32 out: the very same figures
same_as_raw 0 --force "$tmp/ff32.wav" "${A[@]}"

# 8 bits: one strike, its peak within one step (FS/128) of the raw one's
if "$FM" analyze --force "$tmp/f8.wav" --force-scale "$FS_N" "${A[@]}" "${apple[@]}" >"$tmp/json" 2>"$tmp/err" &&
  "$PY" -c "
import json, sys
r, g = json.load(open('$tmp/ref.json'))['strikes'], json.load(open('$tmp/json'))['strikes']
print('  8-bit PCM: %d strike, peak %.3f N (raw %.3f N, step %.3f N)' % (len(g), g[0]['peak_force_n'], r[0]['peak_force_n'], $FS_N / 128) if g else '  8-bit: no strike')
sys.exit(0 if len(g) == 1 and abs(g[0]['peak_force_n'] - r[0]['peak_force_n']) <= $FS_N / 128 else 1)"; then
  ok
else
  bad "8-bit WAV: $(cat "$tmp/err")"
fi

# without --force-scale an integer WAV reads +-1 at full scale: the peak is
# the raw one over FS_N (the default is documented, never a guess)
if "$FM" analyze --force "$tmp/f16.wav" "${A[@]}" "${apple[@]}" --set strike_threshold_min_n=0.001 \
  >"$tmp/json" 2>"$tmp/err" && "$PY" -c "
import json, sys
r, g = json.load(open('$tmp/ref.json'))['strikes'], json.load(open('$tmp/json'))['strikes']
sys.exit(0 if len(g) == 1 and abs(g[0]['peak_force_n'] * $FS_N / r[0]['peak_force_n'] - 1) < 1e-3 else 1)"; then
  ok
else
  bad "16-bit WAV without --force-scale: $(head -c 300 "$tmp/err") $(head -c 300 "$tmp/json")"
fi

# --- refusals: exit 2, one line naming the file and what is wrong
R=(--mass 0.175 --R2 0.04)
expect_usage "tagged.bin: is MP3 (ID3 tag)" analyze --force "$tmp/tagged.bin" "${A[@]}" "${R[@]}"
expect_usage "sync.f32: is MP3/MPEG audio (frame sync)" analyze --force "$tmp/sync.f32" --rate-force 25600 "${A[@]}" "${R[@]}"
expect_usage "song.mp3: named .mp3 but not a RIFF/WAVE file" analyze --force "$tmp/song.mp3" --rate-force 25600 "${A[@]}" "${R[@]}"
expect_usage "truncated.wav: WAV RIFF size says" analyze --force "$tmp/truncated.wav" "${A[@]}" "${R[@]}"
expect_usage "riff_lies.wav: WAV RIFF size says" analyze --force "$tmp/riff_lies.wav" "${A[@]}" "${R[@]}"
expect_usage "part_frame.wav: WAV 'data' chunk of 6 bytes is not a whole number of 4-byte frames" analyze --force "$tmp/part_frame.wav" "${A[@]}" "${R[@]}"
expect_usage "mp3tag.wav: WAV format tag 0x0055 (MPEG layer 3)" analyze --force "$tmp/mp3tag.wav" "${A[@]}" "${R[@]}"
expect_usage "bits12.wav: WAV PCM of 12 bits" analyze --force "$tmp/bits12.wav" "${A[@]}" "${R[@]}"
expect_usage "float16.wav: WAV IEEE float of 16 bits" analyze --force "$tmp/float16.wav" "${A[@]}" "${R[@]}"
expect_usage "riff4.wav: WAV has no 'fmt ' chunk within the 12 bytes its RIFF size (4) says; the file has" analyze --force "$tmp/riff4.wav" "${A[@]}" "${R[@]}"
expect_usage "nodata.wav: WAV has no 'data' chunk" analyze --force "$tmp/nodata.wav" "${A[@]}" "${R[@]}"
expect_usage "odd.f32: 403 bytes is not a whole number of float32 samples" analyze --force "$tmp/odd.f32" --rate-force 25600 "${A[@]}" "${R[@]}"
expect_usage "f16.wav: --rate-force 25000 disagrees with the WAV header's 25600 Hz" analyze --force "$tmp/f16.wav" --rate-force 25000 "${A[@]}" "${R[@]}"
expect_usage "a32.wav: --rate-audio 48000 disagrees with the WAV header's 25600 Hz" analyze --force "$force" --rate-force 25600 --audio "$tmp/a32.wav" --rate-audio 48000 "${R[@]}"
expect_usage "f16s.wav: --force-channel 2 is beyond the WAV's 2 channels (0 to 1)" analyze --force "$tmp/f16s.wav" --force-channel 2 "${A[@]}" "${R[@]}"
expect_usage "a32.wav: --audio-channel 1 is beyond the WAV's 1 channel (0 to 0)" analyze --force "$force" --rate-force 25600 --audio "$tmp/a32.wav" --audio-channel 1 "${R[@]}"
expect_usage "hammer_capture_5.force.f32: --force-channel 1 is beyond raw float32's one channel" analyze --force "$force" --rate-force 25600 --force-channel 1 "${A[@]}" "${R[@]}"
expect_usage "hammer_capture_5.force.f32: raw float32 needs --rate-force HZ" analyze --force "$force" "${A[@]}" "${R[@]}"
expect_usage "--force-scale 0 is outside the accepted range (0, 1e6\] N" analyze --force "$tmp/f16.wav" --force-scale 0 "${A[@]}" "${R[@]}"
expect_usage "--audio-channel -1 is outside the accepted range \[0, 65535\]" analyze --force "$tmp/f16.wav" --audio-channel -1 "${A[@]}" "${R[@]}"

summary test_wav
