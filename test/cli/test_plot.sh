#!/usr/bin/env bash
# firmness_model plot: a PNG and an SVG of a strike, their content read back
# by plot_content.py (size, three framed panels not blank, the series, the
# rules where the physics puts them, the labels' glyphs), and bad input (exit
# 2, one line naming the flag).
source "$(dirname "$0")/harness.sh" "$@"
# The figure's size: plot_cmd.c's 1500 x 620 px (pt in the SVG).
W=1500 H=620
content() { "$PY" "$(dirname "$0")/plot_content.py" "$@"; }

# The default strike (8 MPa, 175 g, R2 40 mm): its 0S2 (682 Hz, PHYSICS.md §5)
# inside the main lobe's -6 dB band and the shear below the yield (§7: the
# shipped profile reproduces the paper's 31 mm threshold, so 40 mm is safe).
if "$FM" plot --out "$tmp/m.png" 2>"$tmp/err" && content png "$tmp/m.png" $W $H safe; then ok; else bad "plot PNG, R2 40 mm: $(cat "$tmp/err")"; fi
# R2 10 mm: t_c ∝ R^-1/5 (§3) lowers the band's edge by 4^0.2 (722 -> 547 Hz),
# below the 0S2, and the shear rises past the yield (§7): both rules move.
if "$FM" plot --R2 0.01 --out "$tmp/r10.png" 2>"$tmp/err" && content png "$tmp/r10.png" $W $H bruise; then ok; else bad "plot PNG, R2 10 mm: $(cat "$tmp/err")"; fi
if "$FM" plot --E2 4e6 --profile paper --out "$tmp/m.svg" 2>"$tmp/err" && content svg "$tmp/m.svg" $W $H; then ok; else bad "plot SVG: $(cat "$tmp/err")"; fi
# plot_content.py itself refuses a blank figure of the right size.
if convert -size ${W}x$H xc:white "$tmp/blank.png" && ! content png "$tmp/blank.png" $W $H safe 2>/dev/null; then ok; else bad "plot_content.py accepts a blank PNG"; fi
expect_usage "--out FILE.png|FILE.svg is required" plot
expect_usage "must end in .png or .svg" plot --out "$tmp/m.pdf"
expect_usage "cannot write" plot --out "$tmp/no/such/dir/m.png"
expect_usage "--modulus-min -1" plot --out "$tmp/m.png" --modulus-min -1
expect_usage "--modulus-max must be above --modulus-min" plot --out "$tmp/m.png" --modulus-max 1e6
expect_usage "--R2" plot --out "$tmp/m.png" --R2 -1
expect_usage "unknown flag '--frob'" plot --out "$tmp/m.png" --frob 1

summary test_plot
