#!/usr/bin/env bash
# Clocks that disagree, a saturated microphone and a hammer that bounces,
# written into strike_bag's bags through rosbag's Python API (edit_bag.py,
# bounce_bag.py): each named where it happens, no strike reliable and wrong.
#  - audio stamped 50 ms, 200 ms late and 30 ms early: the lag learned and
#    shown, the strikes measured as with no offset (same reliable strikes and
#    grades, 0S2 within 1e-4 relative of the clean bag's);
#  - a 0.3 s step in the force clock, frozen force stamps, audio stamped as
#    if 44.1 kHz while labelled 48 kHz: each named (WARN), the strikes near
#    it flagged clock_fault, none on another apple;
#  - the audio clipped at 0.3 Pa: every strike flagged audio_clipped, the
#    WARN "lower the microphone gain"; the clean bag: none;
#  - the sample counters beyond 2^53, 2^60, 2^63: the same strikes, to the
#    nanosecond;
#  - a second impact of the first one's shape 0.2 and 0.3 ms into the
#    contact at 15 and 20 %: every one flagged double_hit, never reliable;
#    the clean bag: none.
set -uo pipefail
here=$(dirname "$0")
# shellcheck disable=SC1091
source "$here/rig_faults.sh"
edit() { /usr/bin/python3 "$here/edit_bag.py" "$@"; }
report() { "$rig_bin/firmness_report" "$1" --csv "$1.csv" >"$1.txt" 2>"$1.err"; }
# Compares two reports strike by strike: reliable and grade equal, 0S2 within 1e-4.
same() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import csv, sys
a, b = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
ok = len(a) == len(b) and all(x['reliable'] == y['reliable'] and x['grade'] == y['grade'] for x, y in zip(a, b))
d = max(abs(float(x['resonance_hz']) / float(y['resonance_hz']) - 1) for x, y in zip(a, b)
        if x['resonance_hz'] and y['resonance_hz'])
print('strikes %d %d same_verdicts %s max_0s2_rel %.2e' % (len(a), len(b), ok, d))
PY
}
flagged() { # CSV COLUMN: strikes with it 1
  /usr/bin/python3 -c "import csv,sys; r=list(csv.DictReader(open(sys.argv[1]))); print('%d of %d' % (sum(x[sys.argv[2]] == '1' for x in r), len(r)))" "$1" "$2"
}

g=$tmp/g40.bag
"$rig_bin/strike_bag" --strikes 40 --seed 3 --out "$g" >/dev/null 2>&1
report "$g"
check clean_lag "$(grep 'audio lag:' "$g.txt")" 'audio lag: [0-9.]+ ms median .* windows moved 0\.00 ms'
check clean_no_clip "$(flagged "$g.csv" audio_clipped)" '^0 of 40$'
check clean_no_bounce "$(flagged "$g.csv" double_hit)" '^0 of 40$'
check clean_no_clock "$(grep -c 'WARN' "$g.txt")" '^0$'

for shift in 0.05 0.2 -0.03; do
  b=$tmp/shift$shift.bag
  edit "$g" "$b" audio_shift=$shift
  report "$b"
  ms=$(/usr/bin/python3 -c "print('%.0f' % (1e3 * $shift))")
  # The median lag and the windows' shift within 1 ms of the offset.
  got=$(sed -nE 's/.*audio lag: (-?[0-9.]+) ms median .*windows moved (-?[0-9.]+) ms.*/\1 \2/p' "$b.txt")
  check "audio_${ms}ms_learned" "$(/usr/bin/python3 -c "import sys; a, w = map(float, sys.argv[1].split()); print('lag %.2f ms, window %.2f ms: %s' % (a, w, abs(a - $ms) < 1 and abs(w - $ms) < 1))" "$got")" 'True$'

  check "audio_${ms}ms_as_clean" "$(same "$g.csv" "$b.csv")" 'strikes 40 40 same_verdicts True max_0s2_rel [0-9.]+e-(0[5-9]|[1-9][0-9])$'
done
# With learning off, a 50 ms offset is a clock fault, never the fruit's silence.
b=$tmp/shift0.05.bag
"$rig_bin/firmness_report" "$b" --set audio_lag_learn=false --csv "$b.off.csv" >"$b.off.txt" 2>&1
check audio_lag_off_flagged "$(flagged "$b.off.csv" reliable)" '^0 of 40$'
check audio_lag_off_named "$(sed -n 2p "$b.off.csv")" 'judged across a clock fault, not the fruit.s: its sound.s onset lies 50\.0 ms after the contact by the audio.s stamps, its audio window was taken 0\.0 ms after \(audio_lag_learn false\)'

b=$tmp/step.bag
edit "$g" "$b" force_step=10,0.3
report "$b"
check force_step_warn "$(grep 'WARN force clock' "$b.txt")" 'force clock stepped \+0\.300000 s at sample'
check force_step_flagged "$(grep -c 'clock_fault' "$b.csv")" '^[1-9]'
check force_step_no_wrong "$(/usr/bin/python3 "$here/attribution.py" "${g%.bag}.truth.csv" "$b.csv")" 'wrong_reliable 0 wrong_unflagged 0'

b=$tmp/frozen.bag
edit "$g" "$b" force_frozen=10
report "$b"
check force_frozen_warn "$(grep 'WARN force clock' "$b.txt")" 'force stamps frozen'
check force_frozen_no_wrong "$(/usr/bin/python3 "$here/attribution.py" "${g%.bag}.truth.csv" "$b.csv")" 'wrong_reliable 0 wrong_unflagged 0'

b=$tmp/rate.bag
edit "$g" "$b" audio_stamp_rate=44100
report "$b"
check audio_rate_warn "$(grep 'WARN audio clock' "$b.txt")" 'audio stamps advance at 44100 Hz of samples while the chunks say 48000 Hz'
# The rate is judged over 2 s of stamps: the strikes after that are flagged
# (the two before were aligned by their own sound's onset).
check audio_rate_flagged "$(grep -c 'clock_fault' "$b.csv")" '^(3[8-9]|40)$'
check audio_rate_none_reliable_after "$(flagged "$b.csv" reliable)" '^[0-2] of 40$'

b=$tmp/clip.bag
edit "$g" "$b" audio_clip=0.3
report "$b"
check clip_flagged "$(flagged "$b.csv" audio_clipped)" '^40 of 40$'
check clip_none_reliable "$(flagged "$b.csv" reliable)" '^0 of 40$'
check clip_warn "$(grep 'WARN microphone' "$b.txt")" 'microphone clipped on 40 strikes: lower the microphone gain'
check clip_reason "$(sed -n 2p "$b.csv")" 'microphone clipped \([0-9]+ samples at its extremes 0\.3 and -0\.3, [0-9]+ flat tops\): lower the microphone gain'

for d in 0.0002 0.0003; do
  for f in 0.15 0.2; do
    b=$tmp/bounce_${d}_$f.bag
    /usr/bin/python3 "$here/bounce_bag.py" "$g" "${g%.bag}.truth.csv" "$b" "$d" "$f" >/dev/null
    report "$b"
    # 32 strikes bounce (the 9th on); the 8 before, clean, set the reference.
    check "bounce_${d}_${f}_flagged" "$(flagged "$b.csv" double_hit)" '^32 of 40$'
    check "bounce_${d}_${f}_unreliable" "$(/usr/bin/python3 -c "import csv,sys; r=list(csv.DictReader(open(sys.argv[1]))); print(sum(x['double_hit']=='1' and x['reliable']=='1' for x in r))" "$b.csv")" '^0$'
  done
done
check bounce_reason "$(sed -n 10p "$tmp/bounce_0.0002_0.2.bag.csv")" 'double hit \(a second impact inside the contact'

# A sample counter that has run long: 2^53, 2^60, 2^63 added to both streams'
# first_sample. The same strikes at the same nanosecond, the same 0S2.
for o in 9007199254740992 1152921504606846976 9223372036854775808; do
  b=$tmp/index$o.bag
  edit "$g" "$b" index_offset=$o
  report "$b"
  check "index_offset_$o" "$(/usr/bin/python3 -c "
import csv, sys
a, b = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
print('strikes %d, stamps off %d ns, 0S2 equal %d' % (len(b), max([abs(int(x['stamp_ns']) - int(y['stamp_ns'])) for x, y in zip(a, b)] or [-1]), sum(x['resonance_hz'] == y['resonance_hz'] for x, y in zip(a, b))))" "$g.csv" "$b.csv")" '^strikes 40, stamps off 0 ns, 0S2 equal 40$'
done

rig_done "clocks, clipping, bounces"
