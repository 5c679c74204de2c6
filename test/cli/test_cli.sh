#!/usr/bin/env bash
# CLI tests of firmness_model: JSON keys, bad input (exit 2, flag named),
# sweep CSV, profiles, bench. Usage: test_cli.sh /path/to/firmness_model
source "$(dirname "$0")/harness.sh" "$@"

# json_check 'python expression on d' args...
json_check() {
  local expr=$1
  shift
  if "$FM" "$@" --json >"$tmp/json" 2>"$tmp/err" &&
    "$PY" -c "import json,sys,math; d=json.load(open('$tmp/json')); sys.exit(0 if ($expr) else 1)"; then
    ok
  else
    bad "'$* --json' does not satisfy: $expr ($(cat "$tmp/err"))"
  fi
}

keys="contact_time_s peak_force_n max_deformation_m delivered_restitution lobes band_low_hz band_high_hz resonance_hz excitation_at_resonance_db max_contact_pressure_pa max_shear_stress_pa yield_shear_stress_pa min_strike_radius_m excites_mode no_damage reliable delivered_energy_j absorbed_energy_j bruise_energy_j below_bruise_energy"
pykeys=$(printf "'%s'," $keys)
json_check "all(k in d for k in [$pykeys])"
json_check "all(set(l) == {'index','start_hz','end_hz','peak_hz','band_low_hz','band_high_hz'} for l in d['lobes']) and [l['index'] for l in d['lobes']] == list(range(1, len(d['lobes']) + 1))"
# The paper's optimal strike on the average apple, default profile: a ~1.3 ms,
# ~35-40 N pulse, the 0S2 near 682 Hz (PHYSICS.md 5), reliable.
json_check "1.2e-3 < d['contact_time_s'] < 1.5e-3 and 30 < d['peak_force_n'] < 40 and abs(d['resonance_hz'] - 682) < 3 and d['reliable'] is True"
# The flags land: a harder apple gives a shorter pulse.
json_check "d['contact_time_s'] < 1.25e-3 and d['peak_force_n'] > 40" --E2 12e6
# Paper profile: lobe 2 at power-half never holds the 0S2 (PHYSICS.md 7).
json_check "d['excites_mode'] is False and d['reliable'] is False" --profile paper
# The paper's strike's energy (PHYSICS.md 1): 10 g at 1.4 m/s delivers 0.5 x 0.010 x 1.4^2
# = 9.8 mJ; the fruit keeps (1 - e^2) of it at the delivered e.
json_check "abs(d['delivered_energy_j'] - 0.0098) < 1e-12 and abs(d['absorbed_energy_j'] - (1 - d['delivered_restitution']**2) * 0.0098) < 1e-12 and d['below_bruise_energy'] is (d['absorbed_energy_j'] < d['bruise_energy_j'])"
json_check "d['excites_mode'] is True" --profile paper --lobe 1 --band-level amplitude-half
# A sharp bump: bruise risk.
json_check "d['no_damage'] is False and d['reliable'] is False" --R2 0.005

expect_usage "--R2" --R2 -0.01
expect_usage "--R2" --R2 0
expect_usage "--mass" --mass 0
expect_usage "--E2" --E2 -8e6
expect_usage "--E2" --E2 nan
expect_usage "--e" --e 1.5
expect_usage "--e" --e 0
expect_usage "--nu2" --nu2 0.5
expect_usage "--nu2" --nu2 -0.1
expect_usage "--hammer-mass" --hammer-mass abc
expect_usage "--v0" --v0
expect_usage "--damping" --damping linear
expect_usage "--band-level" --band-level half
expect_usage "--shear-ratio" --shear-ratio 0.3
expect_usage "--lobe" --lobe 0
expect_usage "--profile" --profile fancy
expect_usage "--frobnicate" --frobnicate 3
expect_usage "--steps" sweep --param E2 --from 2e6 --to 12e6 --steps 0
expect_usage "--param" sweep --param colour --from 1 --to 2 --steps 2
expect_usage "--E2" sweep --param E2 --from -1 --to 12e6 --steps 3

# The four commands that once hung, and extremes of every flag: exit 2
# with one line naming the flag, never a hang (the table's physical
# ranges), or exit 1 with one line naming the exhausted budget.
expect_bounded 2 "--E2 1e-30 is outside the accepted range \[1e5, 1e9\] Pa" --E2 1e-30 --json
expect_bounded 2 "--R2 1e-300 is outside the accepted range \[0.0005, 1\] m" --R2 1e-300 --json
expect_bounded 2 "--R2 2.2250738585072014e-308 is outside" --R2 2.2250738585072014e-308 --json
expect_bounded 2 "--hammer-mass 1e+30 is outside the accepted range \[0.0005, 1\] kg" --hammer-mass 1e30 --json
expect_bounded 2 "--v0 1e-09 is outside the accepted range \[0.05, 10\] m/s" --v0 1e-9
expect_bounded 2 "--hammer-E 1e-300 is outside the accepted range 0 or \[1e5, 1e12\] Pa" --hammer-E 1e-300
expect_bounded 2 "--hammer-radius 1e-300 is outside" --hammer-radius 1e-300
expect_bounded 2 "--e 1e-300" --damping hu-guo --e 1e-300
expect_bounded 2 "--density 1e+300" --density 1e300
expect_bounded 2 "--modulus-factor 0.001" --modulus-factor 1e-3
expect_bounded 2 "--gravity 1000000 is outside the accepted range \\[0, 20\\] m/s2" --gravity 1e6
expect_bounded 2 "--mass 1e-300" --mass 1e-300
expect_bounded 2 "--E2" --E2 1e400
expect_bounded 2 "--lobe" --lobe 1e300
expect_bounded 2 "--seconds" bench --seconds 1e300
expect_bounded 2 "--steps" sweep --param E2 --from 2e6 --to 12e6 --steps 1e300
expect_bounded 2 "--E2" sweep --param E2 --from 1e-30 --to 2e6 --steps 2
# Inside every range, the worst corner found (a 1 kg hammer at 5 cm/s on a
# 0.1 MPa fruit under 20 m/s2: it rests on the fruit): the ODE budget.
expect_bounded 1 "impact ODE budget exhausted" --E2 1e5 --R2 0.0005 --v0 0.05 --hammer-mass 1 --gravity 20
# Each value alone at both ends of its range answers, never a hang.
for flag in "E2 1e5 1e9" "R2 0.0005 1" "v0 0.05 10" "hammer-mass 0.0005 1" "gravity 0 20" "e 0.05 1" \
  "hammer-E 1e5 1e12" "hammer-radius 0.0005 0.1" "mass 0.001 10" "density 100 3000" \
  "modulus-factor 0.1 10" "yield-ratio 0.001 1" "nu2 0 0.49" "hammer-nu 0 0.49"; do
  set -- $flag
  for v in "$2" "$3"; do
    t0=$(date +%s%N)
    timeout 10 "$FM" "--$1" "$v" --json >/dev/null 2>"$tmp/err"
    code=$?
    ms=$((($(date +%s%N) - t0) / 1000000))
    if [ "$ms" -le 1000 ] && { [ "$code" -eq 0 ] || { [ "$code" -eq 1 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ]; }; }; then
      ok
    else
      bad "--$1 $v: exit $code after $ms ms: $(cat "$tmp/err")"
    fi
  done
done

if "$FM" sweep --param E2 --from 2e6 --to 12e6 --steps 6 >"$tmp/sweep.csv" 2>"$tmp/err" &&
  [ "$(wc -l <"$tmp/sweep.csv")" -eq 7 ] && head -1 "$tmp/sweep.csv" | grep -q '^E2,contact_time_s,'; then
  ok
else
  bad "sweep to stdout: $(cat "$tmp/err")"
fi
# Contact time falls as E2 rises (PHYSICS.md 7: 2.41 -> 1.17 ms over 2 -> 12 MPa).
if "$PY" -c "
import csv,sys
rows=list(csv.DictReader(open('$tmp/sweep.csv')))
t=[float(r['contact_time_s']) for r in rows]
sys.exit(0 if all(a > b for a, b in zip(t, t[1:])) else 1)"; then ok; else bad "contact time not falling with E2"; fi
if "$FM" sweep --param R2 --from 0.01 --to 0.05 --steps 3 --csv "$tmp/r2.csv" >/dev/null 2>&1 &&
  [ "$(wc -l <"$tmp/r2.csv")" -eq 4 ]; then ok; else bad "sweep --csv"; fi

bench_out=$("$FM" bench --seconds 0.2)
if grep -q "^ODE path, this strike" <<<"$bench_out" && grep -q "^fast path, 1000 random strikes" <<<"$bench_out"; then ok; else bad "bench"; fi
# sweep: the fast path by default, the ODE path with --ode; the same rows to 0.1 %
"$FM" sweep --param E2 --from 2e6 --to 12e6 --steps 4 >"$tmp/fast.csv" &&
  "$FM" sweep --param E2 --from 2e6 --to 12e6 --steps 4 --ode >"$tmp/ode.csv" || bad "sweep --ode"
if /usr/bin/python3 - "$tmp/fast.csv" "$tmp/ode.csv" <<'PY'
import csv, sys
a, b = (list(csv.DictReader(open(f))) for f in sys.argv[1:3])
assert len(a) == len(b) == 4
for x, y in zip(a, b):
    for k in ("contact_time_s", "peak_force_n", "band_high_hz", "max_shear_stress_pa"):
        assert abs(float(x[k]) / float(y[k]) - 1) < 1e-3, (k, x[k], y[k])
    assert x["reliable"] == y["reliable"]
PY
then ok; else bad "sweep fast vs --ode"; fi
if "$FM" --help | grep -q -- "--hammer-radius"; then ok; else bad "--help lists flags"; fi

summary test_cli
