#!/usr/bin/env bash
# firmness_model paper --quick: every figure (Figs. 2-8 under both profiles,
# PNG and SVG) and doc/paper.md with a verdict for every claim under both
# profiles and the designer's comparison; bad input exits 2.
source "$(dirname "$0")/harness.sh" "$@"

if "$FM" paper --quick --out "$tmp/doc" >"$tmp/out" 2>"$tmp/err"; then ok; else bad "paper: $(cat "$tmp/err")"; fi
for fig in 2 3 4 5 6 7 8; do
  for prof in paper default; do
    png="$tmp/doc/paper/fig${fig}_${prof}.png" svg="$tmp/doc/paper/fig${fig}_${prof}.svg"
    if [ "$(head -c 8 "$png" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ]; then ok; else bad "no PNG $png"; fi
    if grep -q "<svg" "$svg" 2>/dev/null; then ok; else bad "no SVG $svg"; fi
    if grep -q "(paper/fig${fig}_${prof}.png)" "$tmp/doc/paper.md"; then ok; else bad "paper.md does not link fig${fig}_${prof}"; fi
  done
done
md="$tmp/doc/paper.md"
verdict='\*\*(reproduces|reproduces with a different number|does not reproduce)\*\*'
for claim in "Harder" "E2 2–12 MPa" "R2 ≳ 31 mm" "R2 sensitivity" "e below 0.8" "e barely changes" "ν negligible"; do
  # The claim's section: its heading, then one verdict row per profile.
  section=$(awk -v c="$claim" 'index($0, "### ") == 1 { on = index($0, c) > 0 } on' "$md")
  if [ -n "$section" ]; then ok; else bad "no section for '$claim'"; fi
  for prof in "paper-literal" "shipped default"; do
    if grep -Eq "^\| $prof \| .+ \| $verdict \| .+ \|$" <<<"$section"; then ok; else bad "no verdict for '$claim' under $prof"; fi
  done
done
if grep -q "the paper's optimum: hammer 10.0 g at 1.40 m/s" "$md" && grep -Eq "gives up [0-9]+ of [0-9]+ apples" "$md"; then ok; else bad "no designer comparison"; fi
expect_usage "unknown flag '--frob'" paper --frob
expect_usage "--out needs a value: DIR" paper --out
expect_usage "cannot create" paper --out "$tmp/no/such/dir"

summary test_paper
