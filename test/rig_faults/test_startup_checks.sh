#!/usr/bin/env bash
# Settings each valid alone that cannot work together (af_lane_config_derive's
# start-up check, lane_config.h): firmness_report and `firmness_model analyze`
# refuse each with exit 2 and one line naming both parameters, their values
# and the bound; capture_to_bag refuses a --chunk longer than the station's
# ring. Before the check: an audio ring shorter than the apple wait made every
# strike "no audio", a noise band on the 0S2 took the 0S2 for noise, an
# impossible radius range refused every apple, force_buffer_s 0.0001 refused
# every force chunk in the node while firmness_report took them, and
# capture_to_bag --chunk 65536 at 25.6 kHz wrote a bag whose every force chunk
# was refused. Each bound here is worked out in test/core/test_lane_config_check.c.
set -uo pipefail
# shellcheck disable=SC1091
source "$(dirname "$0")/rig_faults.sh"
fm=$rig_bin/firmness_model
report=$rig_bin/firmness_report
data=$AF_ROOT/test/data # the package's own copies of the real captures (test/data/README.md)

# ---- the bad settings, each as the station's or the cultivar's YAML -----------
# audio_buffer_s 0.2 s < 0.025 s of noise reference + apple_wait_s 0.5 s +
# stream_stale_after_s 1 s = 1.525 s
printf 'audio_buffer_s: 0.2\n' >"$tmp/audio_ring.yaml"
audio_line='audio_buffer_s = 0.2 s is shorter than .* apple_wait_s 0.5 s .* stream_stale_after_s 1 s .*raise audio_buffer_s to at least 1.525 s'
# force_buffer_s 0.0001 s: a few samples, fewer than one strike's event of 0.032 s
printf 'force_buffer_s: 0.0001\n' >"$tmp/force_ring.yaml"
force_line='force_buffer_s = 0.0001 s holds [0-9]+ samples at force_sample_rate_hz = [0-9]+ Hz, fewer than one strike.s event .*strike_max_contact_s.* = 0.032 s'
# 500 .. 700 Hz lies inside Jonagold's 0S2 search range 257 .. 1157 Hz
printf 'measure_noise_band_low_hz: 500.0\nmeasure_noise_band_high_hz: 700.0\n' >"$tmp/noise_band.yaml"
band_line='measure_noise_band_low_hz = 500 \.\. measure_noise_band_high_hz = 700 Hz overlaps the 0S2.s search range 257 \.\. 1157 Hz .*modulus_min_pa.*mass_max_kg'
# 0.055 m is wider than the heaviest, flattest apple: 0.25 kg at 840 kg/m3, aspect 0.5: 0.05218 m
sed 's/^equatorial_radius_min_m: .*/equatorial_radius_min_m: 0.055/' "$AF_ROOT/config/jonagold.yaml" \
  >"$tmp/radius.yaml"
radius_line='equatorial_radius_min_m = 0.055 m is larger than any apple the cultivar accepts: mass_max_kg = 0.25 kg at density_kg_m3 = 840 kg/m3 and aspect_ratio_min = 0.5 .*0.05218 m'

"$rig_bin/strike_bag" --strikes 4 --seed 1 --out "$tmp/s.bag" >/dev/null 2>&1
analyze=("$fm" analyze --force "$data/hammer_capture_4.force.f32" --rate-force 25600
  --audio "$data/hammer_capture_4.response.f32" --rate-audio 48000 --mass 0.2 --R2 0.03)

# The shipped settings pass (the bag's 4 strikes reported; analyze's strike).
hostile_case report_shipped 0 'strikes 4: 4 on an apple' 20 256 -- "$report" "$tmp/s.bag"
hostile_case analyze_shipped 0 '"strikes": \[' 10 256 -- "${analyze[@]}"

for tool in report analyze; do
  if [ "$tool" = report ]; then cmd=("$report" "$tmp/s.bag"); else cmd=("${analyze[@]}"); fi
  hostile_case "${tool}_audio_ring" 2 "$audio_line" 10 256 -- "${cmd[@]}" --config "$tmp/audio_ring.yaml"
  hostile_case "${tool}_force_ring" 2 "$force_line" 10 256 -- "${cmd[@]}" --config "$tmp/force_ring.yaml"
  hostile_case "${tool}_noise_band" 2 "$band_line" 10 256 -- "${cmd[@]}" --config "$tmp/noise_band.yaml"
  hostile_case "${tool}_radius_range" 2 "$radius_line" 10 256 -- "${cmd[@]}" --cultivar "$tmp/radius.yaml"
done

# ---- capture_to_bag: a chunk longer than the station's ring -------------------
printf 'apple_id,stamp_s,mass_kg,equatorial_radius_m,strike_radius_m,stem_axis_x,stem_axis_y,stem_axis_z,confidence\n1,0.0100,0.175,0.037,0.04,1,0,0,0.9\n' \
  >"$tmp/apples.csv"
c2b=("$rig_bin/capture_to_bag" --force "$data/hammer_capture_4.force.f32" --rate-force 25600
  --audio "$data/hammer_capture_4.response.f32" --rate-audio 25600 --apples "$tmp/apples.csv")
# 65536 samples at 25.6 kHz = 2.56 s > force_buffer_s 2 s = 51200 samples
hostile_case c2b_chunk_65536 2 \
  '--chunk 65536: a force chunk of 2.56 s at 25600 Hz is longer than the station.s force ring \(force_buffer_s = 2 s, 51200 samples\).*--chunk at most 51200' \
  10 256 -- "${c2b[@]}" --chunk 65536 --out "$tmp/c65536.bag"
[ ! -e "$tmp/c65536.bag" ] || {
  echo "  FAIL c2b_chunk_65536: wrote $tmp/c65536.bag" >&2
  hostile_failed=$((hostile_failed + 1))
}
# The ring's length exactly: taken.
hostile_case c2b_chunk_51200 0 'chunks of 51200' 10 256 -- "${c2b[@]}" --chunk 51200 \
  --out "$tmp/c51200.bag"

# ---- the node and firmness_report take the same chunks ------------------------
# Each stream's own ring is its cap, as on the node's wire: with a force ring
# of 0.1 s (2560 samples at 25.6 kHz) the force chunks of 4096 are refused as
# oversized, the audio's (ring 51200) taken. firmness_report once capped both
# streams at the longer ring and took them.
"${c2b[@]}" --chunk 4096 --out "$tmp/c4096.bag" >/dev/null 2>&1
hostile_case report_force_chunk_cap 0 \
  '^  force +1 chunks, .* 6 refused \(rate 0, unit 0, index 0, malformed 0, oversized 6\)' 10 256 -- \
  "$report" "$tmp/c4096.bag" --set force_sample_rate_hz=25600 --set audio_sample_rate_hz=25600 \
  --set force_buffer_s=0.1

hostile_done
