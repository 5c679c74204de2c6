#!/usr/bin/env bash
# Regenerates the figures in doc/: the model's default strike
# (firmness_model plot) and firmness_report --plots of a 100-strike synthetic
# bag (strike_bag, seed 7): one strike's figure and the three session figures;
# over a shift (doc/shift.md): the hammer's velocity on a +5 % drift (seed 3)
# and the learned modulus factor (true factor 0.85, 5 % spread, 20 %
# unreliable strikes, seed 1).
# Builds first if needed (AF_BUILD_DIR as for scripts/build.sh).
set -euo pipefail
source "$(dirname "$0")/env.sh"
af_ensure_station_built
lib="$AF_DEVEL/lib/acoustic_firmness"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$AF_ROOT/doc"
"$lib/firmness_model" plot --out "$AF_ROOT/doc/model_default.png"
"$lib/strike_bag" --strikes 100 --seed 7 --out "$tmp/s.bag" >/dev/null
"$lib/firmness_report" "$tmp/s.bag" --plots "$tmp/plots" >/dev/null
cp "$tmp/plots/strike_0001_apple_1.png" "$AF_ROOT/doc/report_strike.png"
for f in firmness_histogram stiffness_vs_mass resonance_vs_band; do
  cp "$tmp/plots/$f.png" "$AF_ROOT/doc/report_$f.png"
done
"$lib/strike_bag" --strikes 100 --seed 3 --velocity-drift 0.05 --out "$tmp/d.bag" >/dev/null
"$lib/firmness_report" "$tmp/d.bag" --plots "$tmp/drift" >/dev/null
cp "$tmp/drift/hammer_velocity.png" "$AF_ROOT/doc/shift_hammer_velocity.png"
"$lib/strike_bag" --strikes 120 --seed 1 --modulus-factor 0.85 --modulus-factor-spread 0.05 \
  --unreliable-fraction 0.2 --out "$tmp/f.bag" >/dev/null
"$lib/firmness_report" "$tmp/f.bag" --plots "$tmp/factor" >/dev/null
cp "$tmp/factor/modulus_factor.png" "$AF_ROOT/doc/shift_modulus_factor.png"
echo "plots: doc/model_default.png doc/report_strike.png doc/report_firmness_histogram.png" \
  "doc/report_stiffness_vs_mass.png doc/report_resonance_vs_band.png" \
  "doc/shift_hammer_velocity.png doc/shift_modulus_factor.png"
