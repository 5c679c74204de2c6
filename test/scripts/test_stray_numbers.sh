#!/usr/bin/env bash
# The parameter table (src/core/params/settings_table.c) is the only source of the
# lane's numbers: the shipped defaults below may appear only in
# the table and in what is generated from it (config/station.yaml,
# config/jonagold.yaml and doc/parameters.md's generated part, which
# scripts_doc_parameters checks; doc/paper.md, written by `firmness_model
# paper`). The values looked for are the table's CURRENT ones, read from the
# generated YAML files. Any other line of src/, config/, launch/, doc/, msg/
# or README.md that states one fails, unless the allow-list below names it
# with its reason; and an allow-list entry that no longer matches fails too,
# so that a changed default fails every line still quoting the old one (a
# quote cannot drift). Then the scanner is run on a scratch tree with a
# planted stray, which it must report (so this test can fail). Registered in
# ctest as scripts_stray_numbers.
#   bash test/scripts/test_stray_numbers.sh
set -euo pipefail
source "$(dirname "$0")/harness.sh"

# The allow-list: "path | a fixed part of the line", one per line; '#' starts
# a comment. An entry that matches no line of its file where a default is
# stated fails.
cat >"$tmp/allow" <<'ALLOW'
# not a default: what the table's rows document (the rig's value, YAML syntax)
src/core/params/settings.h | e.g. 0.010 for hammer_mass_kg [kg]
# the rig itself: its URDF (test_urdf checks it equals the table's rig value)
config/rig.urdf | <mass value="0.010"/>
# quotes of the paper: its claim and its deviations (doc/deviations.md)
src/tools/paper_claims.c | "below the yield at 10 g, 1.4 m/s",
doc/deviations.md | 0.536 = 0.75/1.4 is the Lankarani
doc/deviations.md | shipped 0.0414 × 8 MPa × (E2/8 MPa)^0.70
doc/deviations.md | 0.0414 with exponent 0.70 in the c
doc/figures.md | elastic contact time (m1 10 g, v0 1.4 m/s
# prose quoting the shipped value: the doc pages the lead merges (README.md
# is rewritten by another helper); to be cited from the table, then dropped
doc/model.md | Shipped: **0.0414 × 8 MPa × (E2/8 MPa)^0.70**
doc/model.md | p = 0.70 below the computed shear's
doc/model.md | R2 40 mm, 10 g at 1.4 m/s) the shipped profile
doc/model.md | law shipped now (0.0414 × 8 MPa × (E2/8 MPa)^0.70
doc/model.md | the shipped exponent 0.70, below
doc/cli.md | (calibration) [-] (default 0.0414, range
# the paper's strike's energy worked by hand, and design's printed example
doc/model.md | over a contact that ends where it began). The paper's strike, 10 g at 1.4 m/s
doc/model.md | `hammer_mass_kg`'s rig value and `strike_velocity_m_s`), delivers 0.5 × 0.010 × 1.4² =
doc/model.md | the paper's optimum: hammer 10.0 g at 1.40 m/s, tip flat
# not a default: the tap SNR of test_onset's weaker taps, not the 0S2 threshold
doc/tap_only.md | - At 15 dB, 198 of 200 are found
doc/tap_only.md | 200 taps at 18 and 15 dB
# not defaults: the test signals of the response's benchmark
doc/performance.md | | hum: comb plus 50 Hz hum, 5 harmonics
doc/cli.md | 15 dB none of 2e4) [dB] (default 15
doc/cli.md | (default 0.0414, range [0.001, 1]
doc/cli.md | config/rig.urdf: 10 g,
doc/cli.md | The paper's 10 g at 1.4 m/s is not feasible
doc/parameters.md | The shipped rig's hammer (10 g, a flat face)
doc/report.md | the shipped rig's hammer (10 g, flat face)
doc/tests.md | (the value stays 15 dB;
# example output: printed by the tools from the table (scripts_doc_examples
# re-runs each and compares)
doc/cli.md | contact velocity [m/s] (default 1.4, range
doc/cli.md | hammer mass [kg] (default 0.01, range
doc/cli.md | yield law exponent p, tau_y ~ E2^p (1 = ratio law) [-] (default 0.7, range
doc/cli.md | strike: hammer 10.0 g at 1.40 m/s on E2 8.00 MPa
doc/cli.md | overrides the URDF's hammer mass [kg] (default 0.01, range
doc/cli.md | the paper's optimum: hammer 10.0 g at 1.40 m/s, tip flat
doc/cli.md | contact velocity (the paper's optimum) [m/s] (default 1.4, range
doc/lane.md | 'measure_snr_threshold_db': 15.0
doc/shift.md | 1.4616 from the impulse (mean of 20 clean strikes, SD 0.0044, +4.40 % of strike_velocity_m_s 1.4
doc/shift.md | outside strike_velocity_m_s 1.4 m/s
doc/shift.md | +4.46 % of strike_velocity_m_s 1.4, band
doc/report.md | -0.09 % of strike_velocity_m_s 1.4, band
# a measured figure against strike_bag's truth (its v0 is the table's)
doc/shift.md | window v0 1.39915 m/s against the truth 1.4 (-0.061 %)
ALLOW

# scan ROOT ALLOW: prints each stray as "path:line: default (text)"; exit 1
# when there is one.
scan() {
  /usr/bin/python3 - "$1" "$2" "${3:-$AF_ROOT}" <<'PY'
import os, re, sys
root, allow_path = sys.argv[1], sys.argv[2]
# Each default: its name and a regex of a line stating it (case-insensitive):
# the number in a context that makes it that default (a bare "1.4" may be
# anything; "1.4 m/s" or "velocity ... 1.4" is the strike velocity).
def table_values(root):
    """The shipped defaults, as the generated YAML files state them (the
    hammer's rig mass is the station file's commented optional row)."""
    want = {'yield_ratio', 'yield_exponent', 'measure_snr_threshold_db', 'measure_hum_hz',
            'strike_velocity_m_s', 'hammer_mass_kg'}
    v = {}
    for name in ('station.yaml', 'jonagold.yaml'):
        for line in open(os.path.join(root, 'config', name), encoding='utf-8'):
            m = re.match(r'#?\s*(\w+):\s*([-+0-9.eE]+)\s', line)
            if m and m.group(1) in want and m.group(1) not in v:
                v[m.group(1)] = m.group(2)
    missing = want - set(v)
    if missing:
        sys.exit('test_stray_numbers: no value of %s in config/*.yaml' % sorted(missing))
    return v

def num(text):
    """A regex of a number as written (1.4, 15.0 or 15, 0.70, 0.010)."""
    x = float(text)
    forms = {text, repr(x), '%g' % x}
    if x == int(x):
        forms.add('%d' % x)
    return '(?:%s)' % '|'.join(re.escape(f) for f in sorted(forms, key=len, reverse=True))

def defaults(v):
    """Each default: its name and a regex of a line stating it (case-
    insensitive): the number in a context that makes it that default (a bare
    "1.4" may be anything; "1.4 m/s" or "velocity ... 1.4" is the strike
    velocity)."""
    g = num('%g' % (float(v['hammer_mass_kg']) * 1000.0))
    kg = num(v['hammer_mass_kg'])
    snr, hum, vel = num(v['measure_snr_threshold_db']), num(v['measure_hum_hz']), num(
        v['strike_velocity_m_s'])
    return [
        ('yield_ratio ' + v['yield_ratio'], r'(?<![.\d])%s(?![\d])' % num(v['yield_ratio'])),
        ('yield_exponent ' + v['yield_exponent'],
         r'(yield|exponent|\^|\bp\b).*(?<![.\d])%s(?![.\d])|(?<![.\d])%s(?![.\d]).*(yield|exponent)'
         % (num(v['yield_exponent']), num(v['yield_exponent']))),
        ('hammer_mass_kg %s (%s g)' % (v['hammer_mass_kg'], '%g' % (float(v['hammer_mass_kg']) * 1e3)),
         r'(hammer|\bm1\b|\brig\b|mass).{0,40}((?<![.\d])%s(?![.\d])|\b%s ?g\b)|((?<![.\d])%s(?![.\d])|\b%s ?g\b).{0,20}(hammer|\bkg\b)'
         % (kg, g, kg, g)),
        ('measure_snr_threshold_db ' + v['measure_snr_threshold_db'],
         r'(?<![.\d])%s ?dB\b|snr\w*\W?\s*[:=]\s*%s(?![.\d])' % (snr, snr)),
        ('measure_hum_hz ' + v['measure_hum_hz'],
         r'(?<![.\d])%s ?Hz\b|hum_hz\W?\s*[:=]\s*%s(?![.\d])' % (hum, hum)),
        ('strike_velocity_m_s ' + v['strike_velocity_m_s'],
         r'(?<![.\d])%s ?m/s\b|(velocity|\bv0).{0,40}(?<![.\d])%s(?![.\d]| ?ms)' % (vel, vel)),
    ]

DEFAULTS = defaults(table_values(sys.argv[3]))
# The table and what is generated from it (checked by scripts_doc_parameters
# and cli_test_paper): not scanned.
SKIP = {'src/core/params/settings.c', 'src/core/params/settings_table.c', 'config/station.yaml',
        'config/jonagold.yaml', 'doc/paper.md'}
GEN_BEGIN = '<!-- generated by af_settings_doc (scripts/docs.sh): do not edit -->'
GEN_END = '<!-- end of generated -->'
allow = []
for line in open(allow_path, encoding='utf-8'):
    line = line.strip()
    if line and not line.startswith('#'):
        path, _, part = line.partition(' | ')
        allow.append([path.strip(), part, 0])
files = []
for top in ('src', 'config', 'launch', 'doc', 'msg'):
    for d, _, names in os.walk(os.path.join(root, top)):
        files += [os.path.join(d, n) for n in names]
if os.path.exists(os.path.join(root, 'README.md')):
    files.append(os.path.join(root, 'README.md'))
strays = 0
for f in sorted(files):
    rel = os.path.relpath(f, root)
    if rel in SKIP or rel.startswith('doc/notes/'):
        continue
    try:
        lines = open(f, encoding='utf-8').read().split('\n')
    except (UnicodeDecodeError, OSError):
        continue  # figures (png), not text
    generated = False
    for k, text in enumerate(lines, 1):
        if text.strip() == GEN_BEGIN: generated = True
        if text.strip() == GEN_END: generated = False
        if generated:
            continue
        for name, regex in DEFAULTS:
            if not re.search(regex, text, re.I):
                continue
            hit = [a for a in allow if a[0] == rel and a[1] in text]
            for a in hit:
                a[2] += 1
            if not hit:
                strays += 1
                print('%s:%d: %s typed outside the table: %s' % (rel, k, name, text.strip()[:160]))
for path, part, used in allow:
    if not used and os.path.exists(os.path.join(root, path)):
        strays += 1
        print('%s: allow-list entry matches no line stating a default (the default changed, or '
              'the line did: update or drop it): %s' % (path, part))
sys.exit(1 if strays else 0)
PY
}

if scan "$AF_ROOT" "$tmp/allow" >"$tmp/out"; then
  echo "test_stray_numbers: no default outside the table ($(grep -cv '^#\|^$' "$tmp/allow") allowed lines)"
else
  cat "$tmp/out" >&2
  bad "defaults typed outside the parameter table (take them from it, or allow-list with a reason)"
fi

# The scanner must see a planted stray: a tool starting from its own 1.4 m/s.
mkdir -p "$tmp/plant/src/tools"
printf 'static const double v0 = 1.4; /* strike velocity [m/s] */\n' >"$tmp/plant/src/tools/planted.c"
if scan "$tmp/plant" /dev/null >"$tmp/plant.out"; then
  bad "a planted 1.4 m/s in src/tools/planted.c was not reported"
else
  grep -q '^src/tools/planted.c:1: strike_velocity_m_s' "$tmp/plant.out" ||
    bad "the planted stray was reported wrongly: $(cat "$tmp/plant.out")"
fi

# And a quote allow-listed for the old default must fail once the table's
# default changes: a scratch config with strike_velocity_m_s 1.5.
mkdir -p "$tmp/stale/doc" "$tmp/stale/config"
cp "$AF_ROOT/config/station.yaml" "$AF_ROOT/config/jonagold.yaml" "$tmp/stale/config/"
sed -i 's/^strike_velocity_m_s: 1.4 /strike_velocity_m_s: 1.5 /' "$tmp/stale/config/station.yaml"
grep -q '^strike_velocity_m_s: 1.5 ' "$tmp/stale/config/station.yaml" || bad "no strike_velocity_m_s line to change"
printf 'The strike runs at 1.4 m/s.\n' >"$tmp/stale/doc/page.md"
printf 'doc/page.md | runs at 1.4 m/s\n' >"$tmp/stale/allow"
if scan "$tmp/stale" "$tmp/stale/allow" "$tmp/stale" >"$tmp/stale.out"; then
  bad "a quote of the old default (1.4 m/s, table now 1.5) was not reported"
else
  grep -q '^doc/page.md: allow-list entry matches no line' "$tmp/stale.out" ||
    bad "the stale quote was reported wrongly: $(cat "$tmp/stale.out")"
fi
exit "$fail"
