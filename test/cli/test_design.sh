#!/bin/bash
# firmness_model design: the recommended strike on the shipped cultivar (fast
# and --ode agree), the paper's optimum, the feasibility map, bad flags.
# Usage: test_design.sh /path/to/firmness_model
source "$(dirname "$0")/harness.sh" "$@"
out=$("$FM" design --cultivar "$(dirname "$0")/../../config/jonagold.yaml" --plot "$tmp/map.png") || bad "design exit"
grep -q "^recommended strike: hammer" <<<"$out" && ok || bad "no recommended strike: $out"
grep -q "^the paper's optimum: hammer 10.0 g at 1.40 m/s" <<<"$out" && ok || bad "paper's optimum"
[ -s "$tmp/map.png" ] && ok || bad "no feasibility map"
ode=$("$FM" design --cultivar "$(dirname "$0")/../../config/jonagold.yaml" --ode --hammer-mass-range 0.002:0.004 --v0-range 0.5:1.5)
fast=$("$FM" design --cultivar "$(dirname "$0")/../../config/jonagold.yaml" --hammer-mass-range 0.002:0.004 --v0-range 0.5:1.5)
[ "$(grep '^recommended' <<<"$ode")" = "$(grep '^recommended' <<<"$fast")" ] && ok || bad "fast and ODE differ"
"$FM" design --hammer-mass-range 5:1 2>/dev/null; [ $? -eq 2 ] && ok || bad "bad range exit"
"$FM" design --bogus 1 2>/dev/null; [ $? -eq 2 ] && ok || bad "unknown flag exit"
# A measured yield in the cultivar YAML overrides the law (a lower yield gives
# up more apples at the paper's optimum); a malformed one exits 2 naming it.
yaml="$(dirname "$0")/../../config/jonagold.yaml"
sed 's/^yield_measured: ""/yield_measured: "2e6:0.12e6, 8e6:0.2e6, 12e6:0.25e6"/' "$yaml" >"$tmp/measured.yaml"
measured=$("$FM" design --cultivar "$tmp/measured.yaml" --hammer-mass-range 0.002:0.004 --v0-range 0.5:1.5)
law=$("$FM" design --cultivar "$yaml" --hammer-mass-range 0.002:0.004 --v0-range 0.5:1.5)
[ "$(grep -A1 "^the paper's optimum" <<<"$measured" | grep -o '[0-9]* of 72')" != "$(grep -A1 "^the paper's optimum" <<<"$law" | grep -o '[0-9]* of 72')" ] && ok || bad "yield_measured ignored"
sed 's/^yield_measured: ""/yield_measured: "8e6:0.3e6, 2e6:0.1e6"/' "$yaml" >"$tmp/bad.yaml"
"$FM" design --cultivar "$tmp/bad.yaml" 2>"$tmp/err" >/dev/null; [ $? -eq 2 ] && grep -q "yield_measured" "$tmp/err" && ok || bad "bad yield_measured: $(cat "$tmp/err")"
summary test_design
