#!/usr/bin/env bash
# firmness_report on a microphone-only rig's bag (tap-only): strike_bag
# --tap-only writes no force topic; the report, with tap_only true, finds every
# strike in the audio (its stamp within 1 ms of the truth's contact start), its
# 0S2 within 0.5 % and its stiffness factor f^2 m^(2/3) within 1 % of the truth
# CSV, tap_only and judged_from_model set; without tap_only the bag is refused
# with the hint; a bag with a force topic under tap_only: the force not read,
# the strikes still the audio's.
#   test_tap_only.sh FIRMNESS_REPORT STRIKE_BAG
source "$(dirname "$0")/../cli/harness.sh" "$1"
SB=${2:?path to strike_bag}

"$SB" --strikes 40 --spacing 0.3 --seed 19 --tap-only --out "$tmp/tap.bag" >/dev/null 2>&1 ||
  bad "strike_bag --tap-only"
"$SB" --strikes 10 --spacing 0.3 --seed 5 --out "$tmp/full.bag" >/dev/null 2>&1 || bad "strike_bag"

# check CSV TRUTH N: every strike found and measured within the bounds.
check() {
  "$PY" - "$1" "$2" "$3" <<'PYEOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
truth = {int(r["apple_id"]): r for r in csv.DictReader(open(sys.argv[2]))}
n = int(sys.argv[3])
errs = []
if len(rows) != n:
    errs.append("%d strikes, expected %d" % (len(rows), n))
worst_f = worst_sf = worst_t = 0.0
for r in rows:
    t = truth[int(r["apple_id"])]
    f_true, m = float(t["resonance_hz"]), float(t["mass_kg"])
    sf_true = f_true ** 2 * m ** (2.0 / 3.0)
    f = float(r["resonance_hz"]) if r["resonance_hz"] else float("nan")
    sf = float(r["stiffness_factor_hz2_kg2_3"]) if r["stiffness_factor_hz2_kg2_3"] else float("nan")
    ef, es = abs(f / f_true - 1.0), abs(sf / sf_true - 1.0)
    dt = abs(int(r["stamp_ns"]) * 1e-9 - float(t["contact_start_s"]))
    worst_f, worst_sf, worst_t = max(worst_f, ef), max(worst_sf, es), max(worst_t, dt)
    if not (ef <= 0.005 and es <= 0.01):
        errs.append("apple %s: 0S2 %s Hz (true %.3f), S %s (true %.1f)" % (r["apple_id"], r["resonance_hz"], f_true, r["stiffness_factor_hz2_kg2_3"], sf_true))
    if r["tap_only"] != "1" or r["judged_from_model"] != "shear judged from the model only":
        errs.append("apple %s: tap_only %s, judged_from_model '%s'" % (r["apple_id"], r["tap_only"], r["judged_from_model"]))
    if r["fitted_modulus_pa"] != "" or r["peak_force_n"] != "":
        errs.append("apple %s: a pulse figure without a pulse" % r["apple_id"])
print("%d strikes: worst 0S2 %.3f %%, stiffness factor %.3f %%, onset %.3f ms"
      % (len(rows), 100 * worst_f, 100 * worst_sf, 1e3 * worst_t))
if worst_t > 0.001:
    errs.append("an onset %.3f ms from its contact start" % (1e3 * worst_t))
for e in errs:
    print("FAIL:", e, file=sys.stderr)
sys.exit(1 if errs else 0)
PYEOF
}

if "$FM" "$tmp/tap.bag" --set tap_only=true --csv "$tmp/tap.csv" >"$tmp/out" 2>"$tmp/err"; then
  check "$tmp/tap.csv" "$tmp/tap.truth.csv" 40 && ok || bad "tap-only bag"
else
  bad "firmness_report tap.bag --set tap_only=true exited $?: $(cat "$tmp/err")"
fi

# Without tap_only: refused, the hint given.
"$FM" "$tmp/tap.bag" >"$tmp/out" 2>"$tmp/err"
code=$?
[ "$code" -ne 0 ] && grep -q 'no message on /lane1/force.*--set tap_only=true' "$tmp/err" && ok ||
  bad "a bag without force and without tap_only: exit $code, $(cat "$tmp/err")"

# A bag with force under tap_only: the force not read (said), the strikes the audio's.
if "$FM" "$tmp/full.bag" --set tap_only=true --csv "$tmp/full.csv" >"$tmp/out" 2>"$tmp/err"; then
  grep -q 'tap_only is set: the .* messages on /lane1/force are not read' "$tmp/err" && ok ||
    bad "the unread force topic not said: $(cat "$tmp/err")"
  check "$tmp/full.csv" "$tmp/full.truth.csv" 10 && ok || bad "the force bag under tap_only"
else
  bad "firmness_report full.bag --set tap_only=true exited $?: $(cat "$tmp/err")"
fi

summary test_tap_only_report
