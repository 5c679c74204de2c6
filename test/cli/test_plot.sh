#!/usr/bin/env bash
# firmness_model plot: a PNG and an SVG of the default strike, and bad input
# (exit 2, one line naming the flag).
source "$(dirname "$0")/harness.sh" "$@"

if "$FM" plot --out "$tmp/m.png" 2>"$tmp/err" && [ "$(head -c 8 "$tmp/m.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; then ok; else bad "plot PNG: $(cat "$tmp/err")"; fi
if "$FM" plot --E2 4e6 --profile paper --out "$tmp/m.svg" 2>"$tmp/err" && grep -q "<svg" "$tmp/m.svg"; then ok; else bad "plot SVG: $(cat "$tmp/err")"; fi
expect_usage "--out FILE.png|FILE.svg is required" plot
expect_usage "must end in .png or .svg" plot --out "$tmp/m.pdf"
expect_usage "cannot write" plot --out "$tmp/no/such/dir/m.png"
expect_usage "--modulus-min -1" plot --out "$tmp/m.png" --modulus-min -1
expect_usage "--modulus-max must be above --modulus-min" plot --out "$tmp/m.png" --modulus-max 1e6
expect_usage "--R2" plot --out "$tmp/m.png" --R2 -1
expect_usage "unknown flag '--frob'" plot --out "$tmp/m.png" --frob 1

summary test_plot
