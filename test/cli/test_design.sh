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
summary test_design
