#!/usr/bin/env bash
# firmness_model paper --quick: every figure (Figs. 2-8 under both profiles,
# PNG and SVG) and doc/paper.md with a verdict for every claim under both
# profiles and the designer's comparison; bad input exits 2. Each claim's
# verdict is the one PHYSICS.md §7 predicts and its key figure agrees with the
# closed forms of PHYSICS.md §2, §3 and §5 (or, for the 31 mm threshold, with
# the paper's printed value): see the tolerances below.
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
verdict='\*\*(reproduces|reproduces with a different number|does not reproduce|calibrated to 31 mm)\*\*'
for claim in "Harder" "E2 2–12 MPa" "R2 ≳ 31 mm" "R2 sensitivity" "e below 0.8" "e barely changes" "ν negligible"; do
  # The claim's section: its heading, then one verdict row per profile.
  section=$(awk -v c="$claim" 'index($0, "### ") == 1 { on = index($0, c) > 0 } on' "$md")
  if [ -n "$section" ]; then ok; else bad "no section for '$claim'"; fi
  for prof in "paper-literal" "shipped default"; do
    if grep -Eq "^\| $prof \| .+ \| $verdict \| .+ \|$" <<<"$section"; then ok; else bad "no verdict for '$claim' under $prof"; fi
  done
done
# Each claim's verdict under each profile, and its key figure against the
# closed forms of PHYSICS.md (or, where only the paper has a number, against
# the paper's printed value). One line per failure; exit 1 if any.
"$PY" - "$md" <<'PYEOF' || bad "claims' verdicts or key figures (above)"
import math, re, sys
md = open(sys.argv[1], encoding='utf-8').read()
fails = []
def check(cond, what):
    if not cond:
        fails.append(what)

# The rows of each claim: {claim number: {profile: (figure, verdict)}}.
rows = {}
for sec in re.split(r'^### ', md, flags=re.M)[1:]:
    m = re.match(r'(\d+)\. ', sec)
    if not m:
        continue
    for prof, fig, verdict in re.findall(r'^\| (paper-literal|shipped default) \| (.+?) \| \*\*(.+?)\*\* \| .+ \|$', sec, flags=re.M):
        rows.setdefault(int(m.group(1)), {})[prof] = (fig, verdict)
P, D = 'paper-literal', 'shipped default'
R, RD, NR, CAL = 'reproduces', 'reproduces with a different number', 'does not reproduce', 'calibrated to 31 mm'
# The expected verdicts (PHYSICS.md §7): the paper's lobe 2 never holds the
# Lamb 0S2 (f t_c 0.72-1.25 lies in the main lobe), so every claim that needs
# the 0S2 inside the band fails under the paper-literal profile (2, 3, 5); the
# shipped profile meets the 31 mm threshold (3) only because its yield law was
# calibrated there (so the verdict says so, not "reproduces"), but not the whole grid
# (2, 5: light firm apples' 0S2 above the band); exact damping lengthens the
# pulse at low e (6: a different number); Hertz gives 1 and 4, and ν enters
# only through 1/(1 - ν²) (7).
expect = {1: (R, R), 2: (NR, NR), 3: (NR, CAL), 4: (R, R), 5: (NR, NR), 6: (R, RD), 7: (R, R)}
for n, (vp, vd) in expect.items():
    got = rows.get(n, {})
    for prof, v in ((P, vp), (D, vd)):
        check(prof in got, 'claim %d: no %s row' % (n, prof))
        if prof in got:
            check(got[prof][1] == v, 'claim %d %s: verdict %r, expected %r' % (n, prof, got[prof][1], v))
def fig(n, prof):
    return rows.get(n, {}).get(prof, ('', ''))[0]
def nums(pattern, text, what):
    m = re.search(pattern, text)
    check(m is not None, 'no %s in %r' % (what, text[:120]))
    return [float(x) for x in m.groups()] if m else None
def near(got, want, rel, what):
    check(abs(got - want) <= rel * abs(want), '%s: %g, expected %g within %g %%' % (what, got, want, 100 * rel))

# 1. Hertz (PHYSICS.md §3): t_c ∝ E*^-2/5 and F_max ∝ E*^2/5 whatever the
# damping (χ is dimensionless), so 2 -> 12 MPa scales them by 6^0.4 = 2.048;
# 2 % covers the printed rounding (3 digits) and gravity (0.1 %). The
# paper-literal figures against PHYSICS.md §7 (2.41 -> 1.17 ms, 20 -> 42 N,
# independent solvers): 1 % on t_c, 3 % on F_max (printed to 2 digits).
for prof in (P, D):
    v = nums(r't_c ([\d.]+) → ([\d.]+) ms, F_max ([\d.]+) → ([\d.]+) N', fig(1, prof), 'claim 1 t_c, F_max')
    if v:
        near(v[0] / v[1], 6 ** 0.4, 0.02, 'claim 1 %s t_c(2)/t_c(12)' % prof)
        near(v[3] / v[2], 6 ** 0.4, 0.02, 'claim 1 %s F_max(12)/F_max(2)' % prof)
        if prof == P:
            near(v[0], 2.41, 0.01, 'claim 1 t_c at 2 MPa')
            near(v[1], 1.17, 0.01, 'claim 1 t_c at 12 MPa')
            near(v[2], 20, 0.03, 'claim 1 F_max at 2 MPa')
            near(v[3], 42, 0.03, 'claim 1 F_max at 12 MPa')
# 2. Paper-literal: lobe 2 never holds the 0S2 (§7), so 0 of 12. Shipped: the
# Lamb 0S2 of §5 (2/8/12 MPa x 100/175/250 g; 4 MPa = 2 MPa x sqrt 2) against
# the main lobe's amplitude-half edge, which scales as 1/t_c ∝ E2^0.4 from
# claim 1's printed 2 MPa edge: the apples above it are the ones not reliable.
v = nums(r'(\d+) of 12 reliable; (\d+) outside', fig(2, P), 'claim 2 paper-literal counts')
if v:
    check(v == [0, 12], 'claim 2 paper-literal: %d reliable, %d outside; expected 0, 12' % tuple(v))
lamb = {2: (411, 341, 303), 8: (821, 682, 605), 12: (1006, 835, 741)}
lamb[4] = tuple(f * math.sqrt(2) for f in lamb[2])
edge = nums(r'amplitude-half edge ([\d.]+) → ([\d.]+) Hz', fig(1, D), 'claim 1 shipped edge')
if edge:
    above = sum(f > edge[0] * (E / 2) ** 0.4 for E, fs in lamb.items() for f in fs)
    v = nums(r'(\d+) of 12 reliable; (\d+) outside', fig(2, D), 'claim 2 shipped counts')
    if v:
        check(v == [12 - above, above], 'claim 2 shipped: %d reliable, %d outside; Lamb gives %d outside' % (v[0], v[1], above))
# 3. Paper-literal: no R2 makes it reliable (§7). Shipped: the paper prints
# 31 mm and gives no tolerance; PHYSICS.md §7 puts the crossing between 31 and
# 40 mm; 3 mm is the verdict's own tolerance (only the paper's value checks it).
check('min strike radius none' in fig(3, P), 'claim 3 paper-literal: a min strike radius: %r' % fig(3, P)[:160])
v = nums(r'min strike radius ([\d.]+) mm', fig(3, D), 'claim 3 shipped radius')
if v:
    near(v[0], 31.0, 3 / 31, 'claim 3 shipped min strike radius [mm]')
# 4. t_c ∝ R^-1/5 (§3): the log slope -0.200 (printed to 3 digits), and the
# per-millimetre slopes 20-40 vs 40-60 mm in the ratio
# (2^0.2 - 1) / (1 - 1.5^-0.2) = 1.909; 2 % for the rounding of 0.0103 etc.
for prof in (P, D):
    v = nums(r'slope 20–40 mm ([\d.]+) ms/mm, 40–60 mm ([\d.]+) ms/mm', fig(4, prof), 'claim 4 slopes')
    if v:
        near(v[0] / v[1], (2 ** 0.2 - 1) / (1 - 1.5 ** -0.2), 0.02, 'claim 4 %s slope ratio' % prof)
    v = nums(r'log slope d ln t_c/d ln R2 (-[\d.]+) vs (-[\d.]+)', fig(4, prof), 'claim 4 log slopes')
    if v:
        near(v[0], -0.2, 0.01, 'claim 4 %s log slope below 40 mm' % prof)
        near(v[1], -0.2, 0.01, 'claim 4 %s log slope above 40 mm' % prof)
# 5. Paper-literal: 0 reliable at every e (§7). Shipped: at e 0.6 the grid is
# claim 2's (the same strike), so its counts must agree with claim 2.
grid = dict(re.findall(r'([\d.]+): (\d+/\d+/\d+)', fig(5, P)))
check(len(grid) == 11 and all(g.startswith('0/') for g in grid.values()), 'claim 5 paper-literal: a reliable apple: %r' % grid)
grid = dict(re.findall(r'([\d.]+): (\d+/\d+/\d+)', fig(5, D)))
v = nums(r'(\d+) of 12 reliable; (\d+) outside', fig(2, D), 'claim 2 shipped counts')
if v:
    check(grid.get('0.6') == '%d/%d/0' % (v[0], v[1]), 'claim 5 shipped at e 0.6: %s, claim 2 gives %d/%d/0' % (grid.get('0.6'), v[0], v[1]))
# 6. The delivered e (§2: LN 0.702/0.756/0.847 for 0.4/0.6/0.8; exact damping
# the asked e) within 0.01: the printed 2 digits (0.005) and gravity, which
# the table leaves out (a few 0.001); t_c at e = 1 against the closed form
# with gravity, 1.33217 ms (§3), to 0.1 % (printed to 4 digits).
for prof, delivered in ((P, (0.702, 0.756, 0.847, 1.0)), (D, (0.4, 0.6, 0.8, 1.0))):
    v = nums(r'delivered ([\d.]+)/([\d.]+)/([\d.]+)/([\d.]+)\): t_c [\d.]+/[\d.]+/[\d.]+/([\d.]+) ms', fig(6, prof), 'claim 6 figures')
    if v:
        for got, want in zip(v[:4], delivered):
            check(abs(got - want) <= 0.01, 'claim 6 %s delivered e %g, expected %g (PHYSICS.md §2)' % (prof, got, want))
        near(v[4], 1.33217, 0.001, 'claim 6 %s t_c at e 1 [ms]' % prof)
# 7. t_c ∝ (1 - ν²)^(2/5) (§3, E* = E2 / (1 - ν²)): each t_c over the ν 0.35
# one, 0.2 % (printed to 4 digits), and the ± spread 4.7 % of the printed one.
nu = (0.2, 0.3, 0.35, 0.4, 0.49)
law = [(1 - n * n) ** 0.4 for n in nu]
for prof in (P, D):
    v = nums(r't_c ([\d.]+)/([\d.]+)/([\d.]+)/([\d.]+)/([\d.]+) ms \(±([\d.]+) %\)', fig(7, prof), 'claim 7 t_c')
    if v:
        for k in range(5):
            near(v[k] / v[2], law[k] / law[2], 0.002, 'claim 7 %s t_c(ν %g)/t_c(0.35)' % (prof, nu[k]))
        near(v[5], 100 * (max(law) - min(law)) / (max(law) + min(law)), 0.03, 'claim 7 %s ± spread [%%]' % prof)
for f in fails:
    print('FAIL: ' + f, file=sys.stderr)
sys.exit(1 if fails else 0)
PYEOF
if grep -q "the paper's optimum: hammer 10.0 g at 1.40 m/s" "$md" && grep -Eq "gives up [0-9]+ of [0-9]+ apples" "$md"; then ok; else bad "no designer comparison"; fi
expect_usage "unknown flag '--frob'" paper --frob
expect_usage "--out needs a value: DIR" paper --out
expect_usage "cannot create" paper --out "$tmp/no/such/dir"

summary test_paper
